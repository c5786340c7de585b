//! Discrete fairing of noisy paraboloid caps with the boundary and 2 rings fixed: the 10k-vertex
//! mesh of `fixtures/third_party/bench` (goal ≤ 30 ms) and a generated 100k-vertex one (goal ≤ 0.8 s),
//! with each sparse solver/ordering (`faer_nd` is the default of `DiscreteFairingParams`).
//! Run: `cargo bench -p nside-discrete`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nside_discrete::{DiscreteFairingParams, fair_mesh};
use nurbs_core::TriMesh;
use nurbs_core::sparse::{FillOrdering, SpdSolver};
use rand::Rng;

fn noisy_cap(n: usize) -> TriMesh {
    let s = nurbs_core::shapes::paraboloid_bicubic(&[0.5]).expect("paraboloid");
    let mut m = TriMesh::from_surface(&s, n, n);
    let mut r = nurbs_core::testing::rng(3);
    for p in &mut m.positions {
        p.z += r.random_range(-0.01..0.01);
    }
    m
}

fn discrete(c: &mut Criterion) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/third_party/bench/disk_paraboloid_10k.obj"
    );
    let small = std::fs::read_to_string(path)
        .ok()
        .and_then(|t| TriMesh::from_obj_str(&t).ok())
        .unwrap_or_else(|| noisy_cap(100));
    let big = noisy_cap(317);
    let mut g = c.benchmark_group("discrete_fairing");
    g.sample_size(10);
    for (name, solver) in [
        ("faer_nd", SpdSolver::Faer(FillOrdering::NestedDissection)),
        ("faer_amd", SpdSolver::Faer(FillOrdering::Amd)),
        ("faer_natural", SpdSolver::Faer(FillOrdering::Natural)),
        ("nalgebra_sparse", SpdSolver::NalgebraSparse),
    ] {
        let params = DiscreteFairingParams {
            fixed_rings: 2,
            solver,
            ..Default::default()
        };
        g.bench_function(format!("10k_{name}"), |b| {
            b.iter(|| black_box(fair_mesh(&small, &[], &params).expect("fairs")))
        });
    }
    for (name, solver) in [
        ("faer_nd", SpdSolver::Faer(FillOrdering::NestedDissection)),
        ("faer_amd", SpdSolver::Faer(FillOrdering::Amd)),
    ] {
        let params = DiscreteFairingParams {
            fixed_rings: 2,
            solver,
            ..Default::default()
        };
        g.bench_function(format!("100k_{name}"), |b| {
            b.iter(|| black_box(fair_mesh(&big, &[], &params).expect("fairs")))
        });
    }
    g.finish();
}

criterion_group!(benches, discrete);
criterion_main!(benches);
