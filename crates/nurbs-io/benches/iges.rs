//! Reading the impeller (`fixtures/third_party/impeller.igs`, 4 MB, 247 surfaces, 2342 curves) — goal
//! ≤ 0.5 s — and writing it back. Run: `cargo bench -p nurbs-io`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nurbs_io::{IgesWriteParams, read_iges, write_iges};

fn iges(c: &mut Criterion) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/third_party/impeller.igs"
    );
    let Ok(bytes) = std::fs::read(path) else {
        eprintln!("{path} not found: nothing to benchmark");
        return;
    };
    let mut g = c.benchmark_group("iges");
    g.sample_size(10);
    g.bench_function("read_impeller", |b| {
        b.iter(|| black_box(read_iges(&bytes).expect("reads")))
    });
    let file = read_iges(&bytes).expect("reads");
    let surfaces: Vec<(&str, &nurbs_core::BSplineSurface)> = file
        .surfaces
        .iter()
        .map(|s| (s.name.as_str(), &s.surface))
        .collect();
    let curves: Vec<(&str, &nurbs_core::BSplineCurve)> = file
        .curves
        .iter()
        .map(|c| (c.name.as_str(), &c.curve))
        .collect();
    g.bench_function("write_impeller_geometry", |b| {
        b.iter(|| {
            black_box(write_iges(&surfaces, &curves, &IgesWriteParams::default()).expect("writes"))
        })
    });
    g.finish();
}

criterion_group!(benches, iges);
criterion_main!(benches);
