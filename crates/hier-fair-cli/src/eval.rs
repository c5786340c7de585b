//! `hier-fair eval SURFACE.json (--grid NU,NV | --params PARAMS.json) [--summary]`
//! (cli-contract.md): point, derivatives, normal and curvatures at parameters.

use std::fmt::Write as _;
use std::time::Instant;

use anyhow::{Result, bail};
use nurbs_core::{BSplineSurface, GridOrder, SurfaceDerivatives};
use serde::Deserialize;

/// One evaluated sample.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Sample {
    /// parameters
    pub u: f64,
    /// parameters
    pub v: f64,
    /// derivatives
    pub d: SurfaceDerivatives,
    /// unit normal S_u × S_v, `None` at singular points
    pub normal: Option<[f64; 3]>,
    /// k1 ≥ k2, mean, gauss, `None` at singular points
    pub curvatures: Option<[f64; 4]>,
}

impl Sample {
    fn new(u: f64, v: f64, d: &SurfaceDerivatives) -> Self {
        let pc = d.curvature_values();
        Self {
            u,
            v,
            d: *d,
            normal: pc.map(|c| c.normal.into()),
            curvatures: pc.map(|c| [c.k1, c.k2, c.mean, c.gauss]),
        }
    }
}

/// Where the parameters come from.
#[derive(Debug, Clone, PartialEq)]
pub enum Params {
    /// NU × NV uniform grid over the domain, both ends included, u slowest
    Grid(usize, usize),
    /// explicit (u, v) pairs
    List(Vec<(f64, f64)>),
}

#[derive(Deserialize)]
struct ParamsFile {
    params: Vec<[f64; 2]>,
}

/// Largest grid `eval --grid --summary` evaluates: 10⁸ samples, streamed in blocks of grid
/// rows, so memory stays a few megabytes whatever the grid (cli-contract.md).
pub const MAX_GRID_SAMPLES: usize = 100_000_000;

/// Largest number of samples `eval` lists in full: about 270 bytes each in memory and 500 in
/// JSON, so 4·10⁶ samples are about 1 GB of memory and 2 GB of output (cli-contract.md).
pub(crate) const MAX_LISTED_SAMPLES: usize = 4_000_000;

/// Grid rows per block of the streamed summary.
const SUMMARY_BLOCK_ROWS: usize = 64;

/// Parses `NU,NV` (each ≥ 1, NU·NV ≤ [`MAX_GRID_SAMPLES`]).
pub fn parse_grid(text: &str) -> Result<Params> {
    let parts: Vec<&str> = text.split(',').collect();
    let parse = |s: &str| s.trim().parse::<usize>().ok().filter(|&n| n >= 1);
    match (
        parts.as_slice(),
        parts.first().and_then(|s| parse(s)),
        parts.get(1).and_then(|s| parse(s)),
    ) {
        ([_, _], Some(nu), Some(nv)) => match nu.checked_mul(nv) {
            Some(n) if n <= MAX_GRID_SAMPLES => Ok(Params::Grid(nu, nv)),
            _ => bail!(
                "--grid {nu},{nv} asks for more than {MAX_GRID_SAMPLES} samples, the bound of eval"
            ),
        },
        _ => bail!("--grid expects NU,NV with two positive integers, got {text:?}"),
    }
}

/// Parses a PARAMS.json text `{"params": [[u, v], ...]}`.
pub fn parse_params(text: &str, origin: &str) -> Result<Params> {
    let file: ParamsFile = serde_json::from_str(text)
        .map_err(|e| anyhow::anyhow!("{origin}: malformed params file: {e}"))?;
    Ok(Params::List(
        file.params.into_iter().map(|[u, v]| (u, v)).collect(),
    ))
}

/// Evaluates `surface` at `params`; returns the samples and the evaluation time in seconds.
/// Explicit parameters must lie in the domain.
pub fn evaluate(surface: &BSplineSurface, params: &Params) -> Result<(Vec<Sample>, f64)> {
    match params {
        Params::Grid(nu, nv) => {
            let us = surface.knots_u().uniform_params(*nu);
            let vs = surface.knots_v().uniform_params(*nv);
            let start = Instant::now();
            let mut samples = surface
                .par_eval_grid_with(&us, &vs, GridOrder::Second, |d| Sample::new(0.0, 0.0, d));
            for (k, s) in samples.iter_mut().enumerate() {
                (s.u, s.v) = (us[k / nv], vs[k % nv]);
            }
            Ok((samples, start.elapsed().as_secs_f64()))
        }
        Params::List(list) => {
            for (k, &(u, v)) in list.iter().enumerate() {
                surface
                    .knots_u()
                    .check_param(u)
                    .map_err(|e| anyhow::anyhow!("params[{k}] u: {e}"))?;
                surface
                    .knots_v()
                    .check_param(v)
                    .map_err(|e| anyhow::anyhow!("params[{k}] v: {e}"))?;
            }
            let start = Instant::now();
            let mut eval = surface.evaluator();
            let samples = list
                .iter()
                .map(|&(u, v)| Sample::new(u, v, &eval.derivatives(u, v)))
                .collect();
            Ok((samples, start.elapsed().as_secs_f64()))
        }
    }
}

/// The summary of `--grid NU,NV --summary` without keeping the samples: the grid is
/// evaluated in blocks of `SUMMARY_BLOCK_ROWS` rows by the batched kernels (points, normals
/// and principal curvatures, [`BSplineSurface::eval_grid_curvatures_into`]); returns the
/// count, the evaluation time and the checksum of [`summary_json`].
pub fn summarize_grid(surface: &BSplineSurface, nu: usize, nv: usize) -> (usize, f64, f64) {
    let us = surface.knots_u().uniform_params(nu);
    let vs = surface.knots_v().uniform_params(nv);
    let start = Instant::now();
    let mut block = Vec::new();
    let mut checksum = 0.0;
    for rows in us.chunks(SUMMARY_BLOCK_ROWS) {
        surface.eval_grid_curvatures_into(rows, &vs, &mut block);
        checksum += block
            .iter()
            .map(|s| s.point.x + s.point.y + s.point.z)
            .sum::<f64>();
    }
    (nu * nv, start.elapsed().as_secs_f64(), checksum)
}

/// `{"count", "seconds", "checksum"}` of already evaluated samples.
pub fn summary_json(samples: &[Sample], seconds: f64) -> String {
    let checksum: f64 = samples
        .iter()
        .map(|s| s.d.point.x + s.d.point.y + s.d.point.z)
        .sum();
    summary_text(samples.len(), seconds, checksum)
}

/// `{"count", "seconds", "checksum"}` with checksum = sum of all point coordinates.
pub fn summary_text(count: usize, seconds: f64, checksum: f64) -> String {
    serde_json::json!({"count": count, "seconds": seconds, "checksum": checksum}).to_string()
}

fn push_num(out: &mut String, x: f64) {
    // JSON has no NaN/inf; evaluation never produces them for valid surfaces
    if x.is_finite() {
        let _ = write!(out, "{x:?}");
    } else {
        out.push_str("null");
    }
}

fn push_vec(out: &mut String, v: &[f64]) {
    out.push('[');
    for (k, x) in v.iter().enumerate() {
        if k > 0 {
            out.push(',');
        }
        push_num(out, *x);
    }
    out.push(']');
}

/// The full `{"results": [...]}` document.
pub fn results_json(samples: &[Sample]) -> String {
    let mut out = String::with_capacity(samples.len() * 400 + 16);
    out.push_str("{\"results\":[");
    for (k, s) in samples.iter().enumerate() {
        if k > 0 {
            out.push(',');
        }
        out.push_str("{\"u\":");
        push_num(&mut out, s.u);
        out.push_str(",\"v\":");
        push_num(&mut out, s.v);
        let d = &s.d;
        for (name, v) in [
            ("point", d.point.coords),
            ("du", d.du),
            ("dv", d.dv),
            ("duu", d.duu),
            ("duv", d.duv),
            ("dvv", d.dvv),
        ] {
            let _ = write!(out, ",\"{name}\":");
            push_vec(&mut out, v.as_slice());
        }
        out.push_str(",\"normal\":");
        match s.normal {
            Some(n) => push_vec(&mut out, &n),
            None => out.push_str("null"),
        }
        for (idx, name) in ["k1", "k2", "mean", "gauss"].iter().enumerate() {
            let _ = write!(out, ",\"{name}\":");
            match s.curvatures {
                Some(c) => push_num(&mut out, c[idx]),
                None => out.push_str("null"),
            }
        }
        out.push('}');
    }
    out.push_str("]}\n");
    out
}
