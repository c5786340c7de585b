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
use nurbs_core::{BSplineSurface, ProjectionParams, Side, SurfaceProjector, Vector3};
use serde_json::{Value, json};

use crate::model::{Model, ModelSurface};

/// Grid samples of all surfaces of one state together: what keeps a report of a 100-surface
/// model under 10 MB. A sample costs 32 bytes before and 36 after (eight and nine `f32`),
/// 4/3 of that as base64, so a faired report spends about 3.6 MB on its grids at this budget
/// (the minimum grid of [`GRID_MIN`] lets a model of more than 138 surfaces spend more, 8.7 MB
/// at 300); nets, knot lines, combs and the viewer are the rest.
pub(crate) const GRID_BUDGET: usize = 40_000;

/// Samples per direction of a surface's grid: at least this many, so that a fillet's lead-ins
/// show on a 100-surface model (16 intervals put about 3 samples on a lead-in of a fifth).
pub const GRID_MIN: usize = 17;

/// At most this many samples per direction: a single surface shown at 81 × 81 is smooth at any
/// window size a report is read in (6 400 quads), and its indices fit the 16 bits WebGL 1 draws.
pub const GRID_MAX: usize = 81;

/// Samples of a link's curvature comb (as `check` measures a link).
pub const COMB_SAMPLES: usize = 41;

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
    let (us, vs) = (s.knots_u().uniform_params(n), s.knots_v().uniform_params(n));
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
                if a >= 0
                    && b >= 0
                    && (a as usize) < n
                    && (b as usize) < n
                    && let Some(m) = normals[a as usize * n + b as usize]
                {
                    sum += m;
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

/// The distinct interior knots as shares of the domain (`u`, `v`): the viewer draws their
/// iso-lines on the grid it shows (a line across the grid's cells, interpolated), so that
/// they lie on the surface as drawn and cost a number each.
fn knot_lines_json(s: &BSplineSurface) -> Value {
    let share = |knots: &nurbs_core::KnotVector| -> Vec<f64> {
        let (a, b) = knots.domain();
        knots
            .interior_knots()
            .iter()
            .map(|&(t, _)| (t - a) / (b - a))
            .collect()
    };
    json!({"u": share(s.knots_u()), "v": share(s.knots_v())})
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
/// loops bound a region of the parameter square cleanly, the grid cells inside it
/// ([`crate::trim::cell_mask`]; `cells`, one byte each, base64); `null` without trim.
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
    if let Some(cells) = crate::trim::cell_mask(&m.surface, &m.trim, n) {
        let cells: Vec<u8> = cells.into_iter().map(u8::from).collect();
        out["cells"] = json!(base64::engine::general_purpose::STANDARD.encode(cells));
    }
    out
}

/// The curvature comb of a link in one state: at each sample of the slave side its point,
/// the slave's unit normal, and the slave's and master's normal curvatures across the boundary
/// (direction n × T, as `check` measures G2), flat arrays; NaN where undefined. `null` for a
/// side collapsed to a point (no direction across it).
pub fn comb_json(slave: &BSplineSurface, side: Side, m: &LinkMeasure) -> Value {
    if m.collapsed {
        return Value::Null;
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs_core::{Point3, shapes};

    fn decode(v: &Value) -> Vec<f32> {
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(v.as_str().expect("base64 text"))
            .expect("base64");
        bytes
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    }

    #[test]
    fn base64_holds_the_values_as_f32() {
        let values = [0.0, -1.5, 1e-7, 123_456.789, f64::NAN];
        let back = decode(&json!(f32_base64(&values)));
        for (a, b) in values.iter().zip(&back) {
            assert!(a.is_nan() && b.is_nan() || (*a as f32) == *b, "{a} {b}");
        }
    }

    #[test]
    fn grid_size_shares_the_budget_within_its_bounds() {
        assert_eq!(grid_size(1), GRID_MAX);
        assert_eq!(grid_size(100), 20);
        assert_eq!(grid_size(10_000), GRID_MIN);
        for count in 1..400 {
            let n = grid_size(count);
            assert!(
                n * n * count <= GRID_BUDGET || n == GRID_MIN,
                "{count}: {n}"
            );
        }
    }

    /// An exact sphere patch (radius 2): mean curvature 1/2, Gaussian 1/4, both iso-curvatures
    /// 1/2 with respect to its (inward) normal, unit normals pointing to the centre; a sphere of
    /// radius 2.1 lies 0.1 from it everywhere.
    #[test]
    fn sphere_grid_has_closed_form_curvatures_and_deviation() {
        let (r, n) = (2.0, 9);
        let s = shapes::sphere_patch(r).expect("sphere");
        let bigger = shapes::sphere_patch(r + 0.1).expect("sphere");
        let g = grid_json(&bigger, n, Some(&s));
        let pts = decode(&g["points"]);
        let nrm = decode(&g["normals"]);
        let r2 = r + 0.1;
        for (field, want) in [
            ("mean", 1.0 / r2),
            ("gauss", 1.0 / (r2 * r2)),
            ("k_u", 1.0 / r2),
            ("k_v", 1.0 / r2),
        ] {
            for x in decode(&g[field]) {
                assert!((f64::from(x) - want).abs() < 1e-5, "{field}: {x} vs {want}");
            }
        }
        for x in decode(&g["deviation"]) {
            assert!((f64::from(x) - 0.1).abs() < 1e-5, "deviation {x}");
        }
        for (p, m) in pts.chunks_exact(3).zip(nrm.chunks_exact(3)) {
            let p = Vector3::new(p[0].into(), p[1].into(), p[2].into());
            let m = Vector3::new(m[0].into(), m[1].into(), m[2].into());
            assert!((m + p / r2).norm() < 1e-5, "normal {m} at {p}");
        }
    }

    /// An exact cylinder (radius 3, u along the axis): the iso-curvature along the axis is 0,
    /// around it 1/3, mean 1/6, Gaussian 0.
    #[test]
    fn cylinder_grid_has_closed_form_curvatures() {
        let s = shapes::cylinder(3.0, 5.0).expect("cylinder");
        let g = grid_json(&s, 7, None);
        assert!(g.get("deviation").is_none());
        let along = decode(&g["k_u"]);
        let around = decode(&g["k_v"]);
        let mean = decode(&g["mean"]);
        let gauss = decode(&g["gauss"]);
        for k in 0..along.len() {
            assert!(along[k].abs() < 1e-6, "along {}", along[k]);
            assert!(
                (around[k].abs() - 1.0 / 3.0).abs() < 1e-5,
                "around {}",
                around[k]
            );
            assert!((mean[k].abs() - 1.0 / 6.0).abs() < 1e-5, "mean {}", mean[k]);
            assert!(gauss[k].abs() < 1e-6, "gauss {}", gauss[k]);
        }
    }

    /// A pole (the sphere octant's collapsed side) has no curvature there (NaN) but a normal:
    /// that of its neighbours, so that shading runs into it smoothly.
    #[test]
    fn a_pole_gets_its_neighbours_normal() {
        let s = shapes::sphere_octant(1.0).expect("octant");
        let n = 5;
        let g = grid_json(&s, n, None);
        let mean = decode(&g["mean"]);
        let nrm = decode(&g["normals"]);
        for j in 0..n {
            let m = &nrm[3 * j..3 * j + 3];
            let len = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-5, "pole normal {m:?}");
            assert!(m[2].abs() > 0.9, "the pole's normal is the axis: {m:?}");
        }
        assert!(mean[n..].iter().all(|x| x.is_finite()));
    }

    /// A square trim loop over the middle quarter of a plane keeps the cells whose centre lies
    /// inside it, and the loops travel as 3D points; a face without trim has none.
    #[test]
    fn trim_cells_are_the_cells_inside_the_loop() {
        let plane = shapes::plane_patch(
            Point3::origin(),
            Vector3::x(),
            Vector3::y(),
            (0.0, 4.0),
            (0.0, 4.0),
        )
        .expect("plane");
        let square = vec![
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(3.0, 1.0, 0.0),
            Point3::new(3.0, 3.0, 0.0),
            Point3::new(1.0, 3.0, 0.0),
        ];
        let mut m = crate::model::Model::from_primaries(vec![plane])
            .surfaces
            .remove(0);
        assert_eq!(trim_json(&m, 9), Value::Null);
        m.trim = vec![square];
        let t = trim_json(&m, 9);
        let cells = base64::engine::general_purpose::STANDARD
            .decode(t["cells"].as_str().expect("cells"))
            .expect("base64");
        assert_eq!(cells.len(), 64);
        // cells of width 0.5: centres 0.25 … 3.75; inside (1, 3): 1.25 … 2.75, four per row
        assert_eq!(cells.iter().filter(|&&c| c == 1).count(), 16);
        assert_eq!(cells[3 * 8 + 3], 1);
        assert_eq!(cells[0], 0);
        assert_eq!(decode(&t["loops"]).len(), 12);
        assert_eq!(t["lengths"], json!([4]));
    }

    /// A loop that runs across a closed surface's seam does not bound a region of the parameter
    /// square: no cells (the face is shown whole, its loop drawn), never a wrong cut.
    #[test]
    fn a_loop_across_a_seam_cuts_nothing() {
        let s = shapes::full_cylinder(1.0, 2.0).expect("cylinder");
        let ring: Vec<Point3> = (0..12)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 12.0;
                Point3::new(a.cos(), a.sin(), 1.0)
            })
            .collect();
        let mut m = crate::model::Model::from_primaries(vec![s])
            .surfaces
            .remove(0);
        m.trim = vec![ring];
        let t = trim_json(&m, 9);
        assert!(t.get("cells").is_none(), "{t}");
        assert!(t["loops"].is_string());
    }
}
