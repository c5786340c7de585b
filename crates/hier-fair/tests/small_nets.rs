//! Small nets in G2 links: slaves with fewer control points than the frames of their sides
//! need (2 × 2 … 4 × 3, degree 1 to 3) are faired without a panic or an error for the whole
//! model, and no link comes out worse than it came in (a valve's 6-point surface once panicked
//! in the joint polish with an index below zero).

use hier_fair::{FairParams, Model, RoleMethods, fair_model};
use nurbs_core::{BSplineSurface, KnotVector, Point3};
use serde_json::{Value, json};

/// The height field both surfaces sample: a master over x ∈ [0, 20], the slave over [20, 30]
/// with its own curvature across the join (so that G2 must be set) but the same value and slope
/// at x = 20 (so that the link touches).
fn master_height(x: f64, y: f64) -> f64 {
    0.01 * x * x + 0.002 * y * y
}

fn slave_height(x: f64, y: f64) -> f64 {
    let d = x - 20.0;
    master_height(20.0, y) + 0.4 * d + 0.03 * d * d
}

/// A degree (p, q) net of nu × nv points over [x0, x1] × [0, 20], its points on the height field
/// at the Greville abscissae.
fn patch(
    (p, q): (usize, usize),
    (nu, nv): (usize, usize),
    (x0, x1): (f64, f64),
    h: fn(f64, f64) -> f64,
) -> BSplineSurface {
    let ku = KnotVector::clamped_uniform(p, nu).unwrap();
    let kv = KnotVector::clamped_uniform(q, nv).unwrap();
    let greville = |k: &KnotVector, i: usize, d: usize| {
        k.knots()[i + 1..=i + d].iter().sum::<f64>() / d as f64
    };
    let mut pts = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let x = x0 + (x1 - x0) * greville(&ku, i, p);
            let y = 20.0 * greville(&kv, j, q);
            pts.push(Point3::new(x, y, h(x, y)));
        }
    }
    BSplineSurface::new(ku, kv, pts, None).unwrap()
}

fn surface_json(s: &BSplineSurface) -> Value {
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

#[test]
fn small_slaves_in_g2_links_are_faired_and_never_worse() {
    let master = patch((3, 3), (6, 6), (0.0, 20.0), master_height);
    let mut runs = 0;
    for (p, nu) in [(1, 2), (1, 3), (2, 3), (3, 4)] {
        for (q, nv) in [(1, 2), (2, 3), (2, 4)] {
            let slave = patch((p, q), (nu, nv), (20.0, 30.0), slave_height);
            let model = json!({
                "units": "mm",
                "surfaces": [
                    {"name": "master", "role": "primary", "surface": surface_json(&master)},
                    {"name": "slave", "role": "connecting", "surface": surface_json(&slave)},
                ],
                "links": [{"slave": "slave", "side": "u0", "master": "master", "continuity": "G2"}],
            });
            let model = Model::from_json(&model.to_string()).unwrap();
            let (_, report) = fair_model(
                &model,
                &RoleMethods::default(),
                None,
                &FairParams::default(),
            )
            .unwrap_or_else(|e| panic!("degree ({p}, {q}), net {nu} × {nv}: {e}"));
            let t = model.tolerances;
            for l in &report.links {
                let (Some(b), Some(a)) = (&l.before, &l.after) else {
                    panic!("({p}, {q}) {nu} × {nv}: {} not measured", l.label);
                };
                assert!(
                    a.g0 <= b.g0.max(t.g0),
                    "({p}, {q}) {nu} × {nv}: gap {} > {}",
                    a.g0,
                    b.g0
                );
                if let (Some(x), Some(y)) = (a.g1_deg, b.g1_deg) {
                    assert!(
                        x <= y.max(t.g1_deg),
                        "({p}, {q}) {nu} × {nv}: angle {x} > {y}"
                    );
                }
            }
            runs += 1;
        }
    }
    assert_eq!(runs, 12);
}
