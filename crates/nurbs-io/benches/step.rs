//! Reading the kernel models' STEP files (`fixtures/occt/`): the 449 kB loft (18 faces, rational
//! degree-13 fillets and trimmed freeform faces; goal ≤ 100 ms) and the 62 kB filleted box.
//! Run: `cargo bench -p nurbs-io --bench step`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nurbs_io::read_step;

fn step(c: &mut Criterion) {
    let mut g = c.benchmark_group("step");
    g.sample_size(20);
    for name in ["occt_loft_block", "occt_box12_r5"] {
        let path = format!(
            "{}/../../fixtures/occt/{name}.step",
            env!("CARGO_MANIFEST_DIR")
        );
        let text = std::fs::read_to_string(&path).expect("the fixture is in the repository");
        g.bench_function(format!("read_{name}"), |b| {
            b.iter(|| black_box(read_step(&text).expect("reads")))
        });
    }
    g.finish();
}

criterion_group!(benches, step);
criterion_main!(benches);
