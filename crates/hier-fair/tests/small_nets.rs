//! Small nets in G2 links: slaves with fewer control points than the frames of their sides
//! need (2 × 2 … 4 × 3, degree 1 to 3) are faired without a panic or an error for the whole
//! model, and no link comes out worse than it came in (a valve's 6-point surface once panicked
//! in the joint polish with an index below zero).

use hier_fair::{FairParams, Model, RoleMethods, fair_model};
use serde_json::json;

#[path = "common/nets.rs"]
mod nets;
use nets::{patch, surface_json};

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

#[test]
fn small_slaves_in_g2_links_are_faired_and_never_worse() {
    let master = patch((3, 3), (6, 6), (0.0, 20.0), &master_height);
    let mut runs = 0;
    for (p, nu) in [(1, 2), (1, 3), (2, 3), (3, 4)] {
        for (q, nv) in [(1, 2), (2, 3), (2, 4)] {
            let slave = patch((p, q), (nu, nv), (20.0, 30.0), &slave_height);
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
