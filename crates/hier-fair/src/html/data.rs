//! The data of the HTML report: every surface sampled on a parameter grid (points, unit normals,
//! mean and Gaussian curvature, the normal curvatures along both iso-directions, the distance
//! from the input), its control net, its knot lines and its trim, and the curvature combs
//! across every link — before and, for a faired model, after.
//!
//! Arrays travel as base64 of little-endian `f32` (a quarter of their JSON text); the viewer
//! decodes them with `Float32Array`. Lengths stay in model units: the page scales them by the
//! model's millimetres per unit for display, so its figures are millimetres whatever the file's
//! unit.

use base64::Engine as _;
use g_continuity::{LinkMeasure, MeasureParams};
use nurbs_core::{BSplineSurface, Point3, ProjectionParams, Side, SurfaceProjector, Vector3};
use serde_json::{Value, json};

use crate::model::{Model, ModelSurface};

/// Grid samples of all surfaces of one state together: what keeps a report of a 100-surface
/// model under 10 MB. A sample costs 32 bytes before and 36 after (eight and nine `f32`),
/// 4/3 of that as base64, so a faired report spends about 3.6 MB on its grids at this budget
/// (the minimum grid of [`GRID_MIN`] lets a model of more than 138 surfaces spend more, 8.7 MB
/// at 300); nets, knot lines, combs and the viewer are the rest.
pub const GRID_BUDGET: usize = 40_000;

/// Samples per direction of a surface's grid: at least this many, so that a fillet's lead-ins
/// show on a 100-surface model (16 intervals put about 3 samples on a lead-in of a fifth).
pub const GRID_MIN: usize = 17;

/// At most this many samples per direction: a single surface shown at 81 × 81 is smooth at any
/// window size a report is read in (6 400 quads), and its indices fit the 16 bits WebGL 1 draws.
pub const GRID_MAX: usize = 81;

/// Samples along each knot line.
pub const KNOT_LINE_SAMPLES: usize = 33;

/// Samples of a link's curvature comb (as `check` measures a link).
pub const COMB_SAMPLES: usize = 41;

/// A trim loop whose projected parameters jump by more than this share of the domain between
/// two neighbouring points crosses a seam: its parameter polygon does not bound the face, so
/// the surface is shown untrimmed (and the loop drawn) rather than cut wrongly.
pub const SEAM_JUMP: f64 = 0.5;

/// `values` as base64 of little-endian `f32`.
pub fn f32_base64(values: &[f64]) -> String {
    let bytes: Vec<u8> = values
        .iter()
        .flat_map(|&x| (x as f32).to_le_bytes())
        .collect();
    base64::engine::general_purpose::STANDARD.encode(bytes)
}

/// Samples per direction for each of `count` surfaces: the budget shared equally, within
/// [`GRID_MIN`], [`GRID_MAX`].
pub fn grid_size(count: usize) -> usize {
    let per = GRID_BUDGET / count.max(1);
    ((per as f64).sqrt().floor() as usize).clamp(GRID_MIN, GRID_MAX)
}

/// `n` parameters from `a` to `b`, both included.
fn params(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| a + (b - a) * k as f64 / (n - 1) as f64)
        .collect()
}

/// Normal curvatures along S_u and S_v (L/E, N/G; 1/unit), `None` at a singular point.
fn iso_curvatures(d: &nurbs_core::SurfaceDerivatives) -> Option<(f64, f64)> {
    let ff = d.fundamental_forms()?;
    (ff.e > 0.0 && ff.g > 0.0).then(|| (ff.l / ff.e, ff.n / ff.g))
}

/// One state of a surface on an n × n grid (u slowest): `points`, `normals`, `mean`, `gauss`,
/// `k_u`, `k_v`, and `deviation` from `reference` where given. Values undefined at a sample (a
/// pole) are NaN; a normal undefined there is the mean of its neighbours' (so that shading
/// stays smooth into a pole).
pub fn grid_json(s: &BSplineSurface, n: usize, reference: Option<&BSplineSurface>) -> Value {
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    let (us, vs) = (params(u0, u1, n), params(v0, v1, n));
    let ders = s.eval_grid_derivatives(&us, &vs);
    let mut normals: Vec<Option<Vector3>> = Vec::with_capacity(n * n);
    let (mut pts, mut mean, mut gauss, mut ku, mut kv) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for d in &ders {
        pts.extend([d.point.x, d.point.y, d.point.z]);
        let c = d.curvature_values();
        normals.push(c.map(|c| c.normal));
        mean.push(c.map_or(f64::NAN, |c| c.mean));
        gauss.push(c.map_or(f64::NAN, |c| c.gauss));
        let iso = iso_curvatures(d);
        ku.push(iso.map_or(f64::NAN, |k| k.0));
        kv.push(iso.map_or(f64::NAN, |k| k.1));
    }
    let normals = fill_normals(&normals, n);
    let mut out = json!({
        "points": f32_base64(&pts),
        "normals": f32_base64(&normals),
        "mean": f32_base64(&mean),
        "gauss": f32_base64(&gauss),
        "k_u": f32_base64(&ku),
        "k_v": f32_base64(&kv),
    });
    if let Some(r) = reference {
        out["deviation"] = json!(f32_base64(&deviations(r, &ders, &us, &vs)));
    }
    out
}

/// Each grid point's distance from `reference`, projected from the same parameters (the faired
/// surface keeps its input's domain, so its point at (u, v) lies near the input's).
fn deviations(
    reference: &BSplineSurface,
    ders: &[nurbs_core::SurfaceDerivatives],
    us: &[f64],
    vs: &[f64],
) -> Vec<f64> {
    let mut projector = SurfaceProjector::new(reference, ProjectionParams::default());
    let n = vs.len();
    ders.iter()
        .enumerate()
        .map(|(k, d)| {
            projector
                .project_from(&d.point, (us[k / n], vs[k % n]))
                .distance
        })
        .collect()
}

/// Normals as flat xyz, an undefined one replaced by the mean of the defined ones among its
/// grid neighbours (a pole's row takes its neighbour row's), (0, 0, 0) where none is defined.
fn fill_normals(normals: &[Option<Vector3>], n: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(3 * normals.len());
    for (k, nrm) in normals.iter().enumerate() {
        let v = nrm.unwrap_or_else(|| {
            let (i, j) = ((k / n) as isize, (k % n) as isize);
            let mut sum = Vector3::zeros();
            for (di, dj) in [
                (-1, 0),
                (1, 0),
                (0, -1),
                (0, 1),
                (-1, -1),
                (1, 1),
                (-1, 1),
                (1, -1),
            ] {
                let (a, b) = (i + di, j + dj);
                if a >= 0 && b >= 0 && (a as usize) < n && (b as usize) < n {
                    if let Some(m) = normals[a as usize * n + b as usize] {
                        sum += m;
                    }
                }
            }
            sum.try_normalize(0.0).unwrap_or_else(Vector3::zeros)
        });
        out.extend([v.x, v.y, v.z]);
    }
    out
}

/// The control net: `size` (rows, columns) and `points` (row-major xyz).
fn net_json(s: &BSplineSurface) -> Value {
    let pts: Vec<f64> = s
        .control_points()
        .iter()
        .flat_map(|p| [p.x, p.y, p.z])
        .collect();
    json!({"size": [s.num_u(), s.num_v()], "points": f32_base64(&pts)})
}

/// The iso-lines at the distinct interior knots, each [`KNOT_LINE_SAMPLES`] points: `u` lines
/// (u fixed) then `v` lines, flat xyz.
fn knot_lines_json(s: &BSplineSurface) -> Value {
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    let along_v = params(v0, v1, KNOT_LINE_SAMPLES);
    let along_u = params(u0, u1, KNOT_LINE_SAMPLES);
    let mut pts = Vec::new();
    let ku = s.knots_u().interior_knots();
    let kv = s.knots_v().interior_knots();
    for &(u, _) in &ku {
        for &v in &along_v {
            let p = s.point(u, v);
            pts.extend([p.x, p.y, p.z]);
        }
    }
    for &(v, _) in &kv {
        for &u in &along_u {
            let p = s.point(u, v);
            pts.extend([p.x, p.y, p.z]);
        }
    }
    json!({"u": ku.len(), "v": kv.len(), "samples": KNOT_LINE_SAMPLES, "points": f32_base64(&pts)})
}

/// One state of a surface: its grid, net and knot lines, `n` samples per direction.
pub fn state_json(s: &BSplineSurface, n: usize, reference: Option<&BSplineSurface>) -> Value {
    json!({
        "grid": grid_json(s, n, reference),
        "net": net_json(s),
        "knots": knot_lines_json(s),
        "degree": [s.degree_u(), s.degree_v()],
    })
}

/// A surface's trim: its loops as 3D polylines (`loops`, flat xyz, and `lengths`), and where its
/// loops bound a region of the parameter square cleanly, the grid cells (`(n−1)²`, u slowest)
/// whose centre lies inside that region (`cells`, one byte each, base64); `null` without trim.
pub fn trim_json(m: &ModelSurface, n: usize) -> Value {
    if m.trim.is_empty() {
        return Value::Null;
    }
    let pts: Vec<f64> = m
        .trim
        .iter()
        .flatten()
        .flat_map(|p| [p.x, p.y, p.z])
        .collect();
    let lengths: Vec<usize> = m.trim.iter().map(Vec::len).collect();
    let mut out = json!({"loops": f32_base64(&pts), "lengths": lengths});
    if let Some(polys) = parameter_loops(&m.surface, &m.trim) {
        let cells: Vec<u8> = (0..(n - 1) * (n - 1))
            .map(|k| {
                let c = (
                    ((k / (n - 1)) as f64 + 0.5) / (n - 1) as f64,
                    ((k % (n - 1)) as f64 + 0.5) / (n - 1) as f64,
                );
                u8::from(inside(&polys, c))
            })
            .collect();
        out["cells"] = json!(base64::engine::general_purpose::STANDARD.encode(cells));
    }
    out
}

/// The trim loops projected into the unit parameter square, `None` when a loop crosses a seam
/// ([`SEAM_JUMP`]) or a point does not project.
fn parameter_loops(s: &BSplineSurface, loops: &[Vec<Point3>]) -> Option<Vec<Vec<(f64, f64)>>> {
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    let mut projector = SurfaceProjector::new(s, ProjectionParams::default());
    let tol = 1e-3 * s.size();
    let mut out = Vec::with_capacity(loops.len());
    for l in loops {
        let mut poly = Vec::with_capacity(l.len());
        for p in l {
            let f = projector.project(p);
            if !(f.distance <= tol) {
                return None;
            }
            poly.push(((f.u - u0) / (u1 - u0), (f.v - v0) / (v1 - v0)));
        }
        let jumps = poly
            .iter()
            .zip(poly.iter().cycle().skip(1))
            .any(|(a, b)| (a.0 - b.0).abs() > SEAM_JUMP || (a.1 - b.1).abs() > SEAM_JUMP);
        if jumps {
            return None;
        }
        out.push(poly);
    }
    Some(out)
}

/// Even–odd rule over all loops (outer and holes alike).
fn inside(polys: &[Vec<(f64, f64)>], (x, y): (f64, f64)) -> bool {
    let mut odd = false;
    for poly in polys {
        for (a, b) in poly.iter().zip(poly.iter().cycle().skip(1)) {
            if (a.1 > y) != (b.1 > y) && x < a.0 + (y - a.1) * (b.0 - a.0) / (b.1 - a.1) {
                odd = !odd;
            }
        }
    }
    odd
}

/// The curvature comb of a link in one state: at each sample of the slave side its point,
/// the slave's unit normal, and the slave's and master's normal curvatures across the boundary
/// (direction n × T, as `check` measures G2), flat arrays; NaN where undefined.
pub fn comb_json(slave: &BSplineSurface, side: Side, m: &LinkMeasure) -> Value {
    let (mut pts, mut nrm, mut ks, mut km) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for d in &m.detail {
        let (u, v) = side.params(slave, d.t);
        let der = slave.derivatives(u, v);
        let n = der
            .du
            .cross(&der.dv)
            .try_normalize(0.0)
            .unwrap_or_else(Vector3::zeros);
        pts.extend([der.point.x, der.point.y, der.point.z]);
        nrm.extend([n.x, n.y, n.z]);
        ks.push(d.kappa_slave_across.unwrap_or(f64::NAN));
        km.push(d.kappa_master_across.unwrap_or(f64::NAN));
    }
    json!({
        "points": f32_base64(&pts),
        "normals": f32_base64(&nrm),
        "slave": f32_base64(&ks),
        "master": f32_base64(&km),
    })
}

/// Measures every link of `model` as `check` does, with [`COMB_SAMPLES`] samples for the combs;
/// an empty list where measuring failed (the page then shows no combs, the tables their own
/// figures).
pub fn link_measures(model: &Model) -> Vec<LinkMeasure> {
    let params = MeasureParams {
        samples: COMB_SAMPLES,
        ..MeasureParams::default()
    };
    crate::check::measure_model(model, &params)
        .map(|checks| checks.into_iter().map(|c| c.measure).collect())
        .unwrap_or_default()
}
