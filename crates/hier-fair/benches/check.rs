//! Criterion bench of hier-fair: `check` on a model with 100 links (issue 3 target ≤ 100 ms).

use criterion::{Criterion, criterion_group, criterion_main};
use g_continuity::MeasureParams;
use hier_fair::{Model, check_model};
use nurbs_core::io::SurfaceRecord;
use nurbs_core::{BSplineSurface, KnotVector, Point3};
use serde_json::json;
use std::hint::black_box;

/// 101 strips cut from one wavy bicubic surface: even strips primary, odd strips connecting and
/// linked on both long sides to their neighbours: 100 links.
fn model() -> Model {
    let n = (40, 12);
    let ku = KnotVector::clamped_uniform(3, n.0).unwrap();
    let kv = KnotVector::clamped_uniform(3, n.1).unwrap();
    let pts = (0..n.0)
        .flat_map(|i| (0..n.1).map(move |j| (i, j)))
        .map(|(i, j)| {
            let (x, y) = (
                20.0 * i as f64 / (n.0 - 1) as f64,
                2.0 * j as f64 / (n.1 - 1) as f64,
            );
            Point3::new(x, y, 0.5 * (0.7 * x).sin() * (1.3 * y).cos())
        })
        .collect();
    let w = BSplineSurface::new(ku, kv, pts, None).unwrap();
    let count = 101;
    let mut surfaces = Vec::new();
    let mut links = Vec::new();
    for k in 0..count {
        let piece = w
            .extract(
                (k as f64 / count as f64, (k + 1) as f64 / count as f64),
                (0.0, 1.0),
            )
            .unwrap();
        let role = if k % 2 == 0 { "primary" } else { "connecting" };
        surfaces.push(json!({"name": format!("s{k}"), "role": role, "surface": SurfaceRecord::from_surface(&piece)}));
        if k % 2 == 1 {
            links.push(json!({"slave": format!("s{k}"), "side": "u0", "master": format!("s{}", k - 1), "continuity": "G2"}));
            links.push(json!({"slave": format!("s{k}"), "side": "u1", "master": format!("s{}", k + 1), "continuity": "G2"}));
        }
    }
    Model::from_json(&json!({"units": "mm", "surfaces": surfaces, "links": links}).to_string())
        .unwrap()
}

fn benches(c: &mut Criterion) {
    let m = model();
    assert_eq!(m.links.len(), 100);
    c.bench_function("check_100_links_k101", |b| {
        b.iter(|| black_box(check_model(&m, &MeasureParams::default()).unwrap()))
    });
}

criterion_group!(group, benches);
criterion_main!(group);
