//! `hier-fair fair` on a bare surface file: every surface is a primary surface with no links, its
//! boundary frames fixed (\[SV\] §3.1), faired by one [`SurfaceFairing`] method.
//!
//! The model-level driver (hierarchy, links, continuity) lives in the `hier-fair` crate; this file
//! only builds masks and methods from command-line options and writes the result and report.

use std::path::Path;
use std::time::Instant;

use anyhow::{Result, bail};
use nurbs_core::{BSplineSurface, Continuity, ControlMask, FairingReport, SurfaceFairing};
use serde::Serialize;

use crate::files;

/// Options of `fair`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FairOptions {
    /// the method's name in the program's registry ([`crate::methods`])
    pub method: &'static str,
    /// ε: largest control-point move (model units)
    pub tolerance: f64,
    /// iteration limit (local methods: moves; energy-global: polishing moves); `None` = the
    /// method's default
    pub iterations: Option<usize>,
    /// boundary data kept on all four sides: G0 fixes the boundary rows, G1 two rows, G2 three
    pub keep: Continuity,
}

/// The mask that fixes the frame of `keep` on all four sides; an error when no control point
/// would be left free ([`hier_fair::bare::boundary_mask`]).
pub fn boundary_mask(surface: &BSplineSurface, keep: Continuity) -> Result<ControlMask> {
    Ok(hier_fair::bare::boundary_mask(surface, keep)?)
}

/// The method object for `options`, from the program's registry ([`crate::methods`]).
pub fn method(options: &FairOptions) -> Result<Box<dyn SurfaceFairing>> {
    Ok(crate::methods().build(options.method, options.iterations)?)
}

/// One surface's line of the report (cli-contract.md).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SurfaceLine {
    /// surface name
    pub name: String,
    /// "primary" for a bare surface
    pub role: String,
    /// method name
    pub method: String,
    /// thin-plate energy before
    pub energy_before: f64,
    /// thin-plate energy after
    pub energy_after: f64,
    /// largest sampled distance from the original (model units)
    pub max_deviation: f64,
    /// iterations performed
    pub iterations: usize,
    /// seconds of this surface
    pub seconds: f64,
    /// why the surface was kept as it was (the method raised its energy); absent otherwise
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kept: Option<String>,
}

/// The `--report` JSON of `fair` (cli-contract.md); `links` is empty for bare surfaces.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FairRunReport {
    /// wall-clock seconds of the whole run
    pub seconds_total: f64,
    /// one line per surface
    pub surfaces: Vec<SurfaceLine>,
    /// links (none for bare surfaces)
    pub links: Vec<serde_json::Value>,
}

/// Free rows a patch of a multi-patch file gets besides the frames it keeps (knots inserted
/// where it has fewer), as the framework's `min_free_rows`.
pub(crate) const PATCH_FREE_ROWS: usize = 2;

/// Fairs every surface of a bare surface file; returns the faired surfaces and the report. A
/// file of several patches keeps every shared edge's continuity ([`hier_fair::patches`]).
pub fn fair_surfaces(
    surfaces: &[BSplineSurface],
    options: &FairOptions,
) -> Result<(Vec<BSplineSurface>, FairRunReport)> {
    if !(options.tolerance.is_finite() && options.tolerance > 0.0) {
        bail!(
            "--tolerance must be a finite length > 0, got {}",
            options.tolerance
        );
    }
    let start = Instant::now();
    let method = method(options)?;
    let mut out = Vec::with_capacity(surfaces.len());
    let mut lines = Vec::with_capacity(surfaces.len());
    // several patches: each keeps the continuity of the edges it shares with the others
    let shared = (surfaces.len() > 1).then(|| hier_fair::patches::shared_sides(surfaces));
    for (k, s) in surfaces.iter().enumerate() {
        let name = if surfaces.len() == 1 {
            "surface".to_string()
        } else {
            format!("surface{k}")
        };
        let (s, mask) = prepared_surface(s, shared.as_ref().map(|shared| &shared[k]), options)
            .map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        // checked against the contract: a result that moves a fixed point or leaves the
        // tolerance is an error, never an output
        let alone = hier_fair::bare::fair_alone(&s, &mask, options.tolerance, method.as_ref())
            .map_err(|e| anyhow::anyhow!("{name}: {e}"))?;
        lines.push(surface_line(name, alone.report, alone.kept));
        out.push(alone.surface);
    }
    Ok((
        out,
        FairRunReport {
            seconds_total: start.elapsed().as_secs_f64(),
            surfaces: lines,
            links: Vec::new(),
        },
    ))
}

/// The surface to fair and its mask: the boundary frames of `options.keep` on a single
/// surface; on a patch of several (`shared`: its sides shared with the others) the frames its
/// edges keep, with knots inserted where it has too few free rows; the surface's own
/// tangent-continuous C0 knot lines (rational arcs joined by double knots) keep their three
/// columns, as in the framework's stages.
fn prepared_surface(
    surface: &BSplineSurface,
    shared: Option<&nurbs_core::PerSide<Option<hier_fair::patches::SharedSide>>>,
    options: &FairOptions,
) -> Result<(BSplineSurface, ControlMask)> {
    let (s, mut mask) = match shared {
        None => (surface.clone(), boundary_mask(surface, options.keep)?),
        Some(shared) => {
            let frames = hier_fair::patches::kept_frames(surface, shared, options.keep.frame());
            let (prepared, mask, _) =
                hier_fair::patches::prepared_patch(surface, frames, PATCH_FREE_ROWS)?;
            (prepared, mask)
        }
    };
    hier_fair::bare::fix_smooth_joins(surface, &s, &mut mask);
    Ok((s, mask))
}

/// The report line of surface `name` faired as `r`, kept as it was for the reason `kept` (the
/// fairing raised its energy) where that is given.
fn surface_line(name: String, r: FairingReport, kept: Option<String>) -> SurfaceLine {
    let raised = kept.is_some();
    SurfaceLine {
        name,
        role: "primary".into(),
        kept,
        method: r.method,
        energy_before: r.energy_before,
        energy_after: if raised {
            r.energy_before
        } else {
            r.energy_after
        },
        max_deviation: if raised { 0.0 } else { r.max_deviation },
        iterations: r.iterations,
        seconds: r.seconds,
    }
}

/// JSON of the faired surfaces: one record for one surface, `{"surfaces": [...]}` for several.
pub fn surfaces_json(surfaces: &[BSplineSurface]) -> Result<String> {
    if let [one] = surfaces {
        return Ok(nurbs_core::io::surface_to_json(one));
    }
    let records: Vec<_> = surfaces
        .iter()
        .map(nurbs_core::io::SurfaceRecord::from_surface)
        .collect();
    Ok(serde_json::to_string(
        &serde_json::json!({ "surfaces": records }),
    )?)
}

/// The whole subcommand: read, fair, write the output (and report, and quality report page)
/// atomically; returns the one-line-per-surface summary to print.
pub fn run(
    input: &Path,
    output: &Path,
    report: Option<&Path>,
    html: Option<&Path>,
    options: &FairOptions,
) -> Result<String> {
    files::refuse_overwrite(output, &[input])?;
    if let Some(r) = report {
        files::refuse_overwrite(r, &[input])?;
        if std::fs::canonicalize(r)
            .ok()
            .is_some_and(|c| std::fs::canonicalize(output).ok() == Some(c))
            || r == output
        {
            bail!("--report and -o name the same file {}", r.display());
        }
    }
    let surfaces = files::read_surfaces(input)?;
    let (faired, run) = fair_surfaces(&surfaces, options)?;
    files::write_atomic(output, surfaces_json(&faired)?.as_bytes())?;
    if let Some(r) = report {
        files::write_atomic(r, serde_json::to_string_pretty(&run)?.as_bytes())?;
    }
    if let Some(h) = html {
        // the surfaces as a model of primaries without links, named as the report names them
        let before = hier_fair::Model::from_primaries(surfaces.clone());
        let after = hier_fair::Model::from_primaries(faired.clone());
        let json = serde_json::to_value(&run)?;
        let page = hier_fair::html::html_report(&hier_fair::html::HtmlReport {
            title: &format!("hier-fair fair {}", input.display()),
            model: &before,
            faired: Some(&after),
            report: Some(&json),
            checks: None,
        });
        files::write_atomic(h, page.as_bytes())?;
    }
    Ok(surface_lines(&run, options.tolerance) + &verdict(&run, options.tolerance, output))
}

/// One line per surface: the method, the thin-plate energy before and after, the deviation
/// against the tolerance, the iterations, and why a surface was kept as it was.
fn surface_lines(run: &FairRunReport, tolerance: f64) -> String {
    let mut text = String::new();
    for line in &run.surfaces {
        let note = match (&line.kept, line.iterations) {
            (Some(why), _) => format!(" ({why})"),
            (None, 0) => " (nothing could move)".to_string(),
            (None, _) => String::new(),
        };
        text += &format!(
            "{} ({}): thin-plate energy {:.6e} -> {:.6e}, max deviation {:.3e} (tolerance {tolerance}), {} iterations, {:.3} s{note}\n",
            line.name,
            line.method,
            line.energy_before,
            line.energy_after,
            line.max_deviation,
            line.iterations,
            line.seconds
        );
    }
    text
}

/// The last line of `fair` on a bare surface file: "verdict: S of T surfaces faired (thin-plate
/// energy A -> B), K kept as they were; largest deviation D (tolerance E); wrote OUT".
fn verdict(run: &FairRunReport, tolerance: f64, output: &Path) -> String {
    let kept = run.surfaces.iter().filter(|l| l.kept.is_some()).count();
    let moved = run
        .surfaces
        .iter()
        .filter(|l| l.kept.is_none() && l.iterations > 0)
        .count();
    let (before, after) = run.surfaces.iter().fold((0.0, 0.0), |(b, a), l| {
        (b + l.energy_before, a + l.energy_after)
    });
    let worst = run
        .surfaces
        .iter()
        .map(|l| l.max_deviation)
        .fold(0.0, f64::max);
    format!(
        "verdict: {moved} of {} surfaces faired (thin-plate energy {before:.4e} -> {after:.4e}), {kept} kept as they were; largest deviation {worst:.3e} (tolerance {tolerance}); wrote {}\n",
        run.surfaces.len(),
        output.display()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn surface(n: usize) -> BSplineSurface {
        let k = nurbs_core::KnotVector::clamped_uniform(3, n).expect("knots");
        let points = (0..n * n)
            .map(|r| {
                nurbs_core::Point3::new(
                    (r / n) as f64,
                    (r % n) as f64,
                    ((r * 7919) % 13) as f64 * 0.01,
                )
            })
            .collect();
        BSplineSurface::new(k.clone(), k, points, None).expect("surface")
    }

    #[test]
    fn too_small_for_the_frames_is_an_error() {
        assert!(boundary_mask(&surface(4), Continuity::G1).is_err());
        assert!(boundary_mask(&surface(5), Continuity::G1).is_ok());
        assert_eq!(
            boundary_mask(&surface(7), Continuity::G2)
                .expect("mask")
                .free_count(),
            1
        );
    }

    /// `--method energy-bezier` on a surface stored as C⁰-joined Bézier patches in u (knot 1/3 of
    /// full multiplicity, joint row 3 lifted): the joint comes out C¹ — for equal spans on both
    /// sides the joint point is the midpoint of its neighbours across the joint, in every column.
    #[test]
    fn energy_bezier_makes_the_joints_c1() {
        let k = nurbs_core::KnotVector::clamped_uniform(3, 6).expect("knots");
        let smooth = (0..36)
            .map(|r| {
                let (x, y) = ((r / 6) as f64, (r % 6) as f64);
                nurbs_core::Point3::new(x, y, 0.3 * (0.5 * x).sin() + 0.02 * x * y)
            })
            .collect();
        let s = BSplineSurface::new(k.clone(), k, smooth, None)
            .and_then(|s| s.insert_knot(nurbs_core::Direction::U, 1.0 / 3.0, 2))
            .expect("surface");
        let mut s = s;
        let nv = s.num_v();
        for j in 1..nv - 1 {
            s.control_points_mut()[3 * nv + j].z += 0.05;
        }
        let kink = |s: &BSplineSurface| {
            (0..nv)
                .map(|j| {
                    let p = |i: usize| s.control_point(i, j).coords;
                    (p(3) - (p(2) + p(4)) * 0.5).norm()
                })
                .fold(0.0, f64::max)
        };
        assert!(kink(&s) > 0.04, "the input has kinks");
        let options = FairOptions {
            method: "energy-bezier",
            tolerance: 0.1,
            iterations: None,
            keep: Continuity::G0,
        };
        let (out, report) = fair_surfaces(std::slice::from_ref(&s), &options).expect("fairs");
        // the boundary columns j = 0, nv − 1 are fixed (G0 frame): only the inner ones can join
        let inner = |s: &BSplineSurface| {
            (1..nv - 1)
                .map(|j| {
                    let p = |i: usize| s.control_point(i, j).coords;
                    (p(3) - (p(2) + p(4)) * 0.5).norm()
                })
                .fold(0.0, f64::max)
        };
        assert!(inner(&out[0]) <= 1e-9 * s.size(), "{}", inner(&out[0]));
        assert!(kink(&out[0]) < kink(&s));
        assert_eq!(report.surfaces[0].method, "energy-bezier");
    }

    #[test]
    fn report_has_the_contract_fields() {
        let options = FairOptions {
            method: "energy",
            tolerance: 0.05,
            iterations: Some(100),
            keep: Continuity::G0,
        };
        let (out, report) = fair_surfaces(&[surface(8)], &options).expect("fairs");
        assert_eq!(out.len(), 1);
        let v = serde_json::to_value(&report).expect("json");
        for key in [
            "name",
            "role",
            "method",
            "energy_before",
            "energy_after",
            "max_deviation",
            "iterations",
            "seconds",
        ] {
            assert!(v["surfaces"][0].get(key).is_some(), "missing {key}");
        }
        assert!(
            v["seconds_total"].is_number() && v["links"].as_array().is_some_and(|l| l.is_empty())
        );
        let bad = FairOptions {
            tolerance: 0.0,
            ..options
        };
        assert!(fair_surfaces(&[surface(8)], &bad).is_err());
    }

    #[test]
    fn run_writes_output_and_report_and_never_the_input() {
        let dir = tempfile::tempdir().expect("tempdir");
        let input = dir.path().join("in.json");
        std::fs::write(&input, nurbs_core::io::surface_to_json(&surface(9))).expect("write input");
        let output = dir.path().join("out.json");
        let report = dir.path().join("report.json");
        for method in ["energy", "energy-global", "krr"] {
            let options = FairOptions {
                method,
                tolerance: 0.05,
                iterations: None,
                keep: Continuity::G1,
            };
            let text = run(&input, &output, Some(&report), None, &options).expect("runs");
            assert!(text.contains("wrote"));
            let faired = files::read_surfaces(&output).expect("output parses");
            let original = files::read_surfaces(&input).expect("input parses");
            let mask = boundary_mask(&original[0], Continuity::G1).expect("mask");
            for (r, (a, b)) in original[0]
                .control_points()
                .iter()
                .zip(faired[0].control_points())
                .enumerate()
            {
                if !mask.as_slice()[r] {
                    assert_eq!(a, b, "{method:?}: kept frame point {r} changed");
                }
                assert!((a - b).norm() <= 0.05 + 1e-12);
            }
            let json: serde_json::Value =
                serde_json::from_str(&files::read_text(&report).expect("report"))
                    .expect("report parses");
            assert_eq!(json["surfaces"][0]["role"], "primary");
            if method != "krr" {
                // the energy methods never increase the energy (KRR does not promise it)
                assert!(
                    json["surfaces"][0]["energy_after"].as_f64()
                        <= json["surfaces"][0]["energy_before"].as_f64()
                );
            }
        }
        let options = FairOptions {
            method: "energy",
            tolerance: 0.05,
            iterations: None,
            keep: Continuity::G0,
        };
        let before = std::fs::read(&input).expect("read");
        assert!(run(&input, &input, None, None, &options).is_err());
        assert_eq!(
            std::fs::read(&input).expect("read"),
            before,
            "input untouched"
        );
    }
}
