//! Small test nets over a height field, and their JSON form, shared by the tests that build
//! models of a primary and its slaves (`small_nets.rs`, `never_worse.rs`).

use nurbs_core::{BSplineSurface, KnotVector, Point3};
use serde_json::{Value, json};

/// A degree (p, q) net of nu × nv points over [x0, x1] × [0, 20], its points on `h` at the
/// Greville abscissae.
pub fn patch(
    (p, q): (usize, usize),
    (nu, nv): (usize, usize),
    (x0, x1): (f64, f64),
    h: &dyn Fn(f64, f64) -> f64,
) -> BSplineSurface {
    let ku = KnotVector::clamped_uniform(p, nu).unwrap();
    let kv = KnotVector::clamped_uniform(q, nv).unwrap();
    let (gu, gv) = (ku.greville(), kv.greville());
    let mut pts = Vec::new();
    for &a in &gu {
        for &b in &gv {
            let (x, y) = (x0 + (x1 - x0) * a, 20.0 * b);
            pts.push(Point3::new(x, y, h(x, y)));
        }
    }
    BSplineSurface::new(ku, kv, pts, None).unwrap()
}

/// `s` in the model format's surface JSON.
pub fn surface_json(s: &BSplineSurface) -> Value {
    let nv = s.num_v();
    let rows: Vec<Vec<[f64; 3]>> = s
        .control_points()
        .chunks(nv)
        .map(|r| r.iter().map(|p| [p.x, p.y, p.z]).collect())
        .collect();
    json!({
        "degree_u": s.degree_u(), "degree_v": s.degree_v(),
        "knots_u": s.knots_u().knots(), "knots_v": s.knots_v().knots(),
        "control_points": rows,
    })
}
