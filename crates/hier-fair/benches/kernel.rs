//! Criterion benches of the six kernel models of `fixtures/occt` (Open CASCADE exports: boxes
//! with filleted edges and vertex blends, three radii at a corner, a plate with a boss, a pipe
//! tee, a lofted block), each faired as `hier-fair fair` does with per-role deviations of
//! 0.05 mm on primaries and 0.5 mm on connecting and corner surfaces. The goal is ≤ 5 s per
//! model on this 2-core machine (docs/benchmarks.md).

use criterion::{Criterion, criterion_group, criterion_main};
use hier_fair::{FairParams, Model, RoleMethods, fair_model};
use std::hint::black_box;
use std::time::Duration;

/// The kernel models, in the order of `fixtures/occt/index.json`.
const MODELS: [&str; 6] = [
    "occt_box12_r5",
    "occt_box12_variable",
    "occt_corner3_radii",
    "occt_plate_boss",
    "occt_pipe_tee",
    "occt_loft_block",
];

fn bench(c: &mut Criterion) {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/occt");
    let params = FairParams {
        role_tolerance: [Some(0.05), Some(0.5), Some(0.5)],
        ..FairParams::default()
    };
    let mut g = c.benchmark_group("kernel");
    g.sample_size(10).measurement_time(Duration::from_secs(30));
    for name in MODELS {
        let text = std::fs::read_to_string(format!("{root}/{name}.json")).expect("fixture");
        let model = Model::from_json(&text).expect("model");
        g.bench_function(name, |b| {
            b.iter(|| {
                let out =
                    fair_model(&model, &RoleMethods::default(), None, &params).expect("model runs");
                black_box(out)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
