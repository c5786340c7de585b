//! Criterion benches of the hierarchical framework (issue 9 goals): the demo X-node ≤ 1 s,
//! car_shell1 ≤ 2 s (`fixtures/third_party`), and synthetic grids of
//! filleted blocks with 25, 49 and 99 surfaces (the largest ≤ 5 s, time linear in the count).

use criterion::{Criterion, criterion_group, criterion_main};
use hier_fair::{FairParams, Model, RoleMethods, fair_model, synthetic::block_grid};
use std::hint::black_box;
use std::time::Duration;

fn run(model: &Model) {
    let out = fair_model(model, &RoleMethods::default(), None, &FairParams::default())
        .expect("model runs");
    black_box(out);
}

fn bench(c: &mut Criterion) {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let mut g = c.benchmark_group("framework");
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    let x_node = Model::from_json(
        &std::fs::read_to_string(format!("{root}/fixtures/models/x_node.json")).expect("fixture"),
    )
    .expect("model");
    g.bench_function("demo_x_node", |b| b.iter(|| run(&x_node)));
    let text =
        std::fs::read_to_string(format!("{root}/fixtures/third_party/car_shell1.model.json"))
            .expect("the car shell is in the repository");
    let car = Model::from_json(&text).expect("car shell model");
    g.bench_function("car_shell1", |b| b.iter(|| run(&car)));
    for (c, r) in [(3, 3), (4, 4), (5, 6)] {
        let model = block_grid(c, r).expect("grid");
        let n = model.surfaces.len();
        g.bench_function(format!("block_grid_{n}"), |b| b.iter(|| run(&model)));
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
