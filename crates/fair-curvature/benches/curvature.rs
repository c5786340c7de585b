//! Criterion benchmarks of the curvature methods: a 30×30 bicubic sampled on a 60×60 grid, Greiner fairing
//! (goal ≤ 150 ms) and target-curvature fairing (goal ≤ 50 ms).

use criterion::{Criterion, criterion_group, criterion_main};
use fair_curvature::{
    GreinerFairing, GreinerParams, Sampling, TargetCurvatureFairing, TargetCurvatureParams,
};
use nurbs_core::{
    BSplineSurface, ControlMask, FairingProblem, Frame, KnotVector, Point3, SurfaceFairing,
};
use rand::Rng;

fn wavy(n: usize) -> BSplineSurface {
    let kv = KnotVector::clamped_uniform(3, n).unwrap();
    let mut r = nurbs_core::testing::rng(5);
    let mut pts = Vec::with_capacity(n * n);
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64);
            let z = 0.2 * (3.0 * x).sin() * (2.0 * y).cos() + r.random_range(-0.005..0.005);
            pts.push(Point3::new(x, y, z));
        }
    }
    BSplineSurface::new(kv.clone(), kv, pts, None).unwrap()
}

fn bench(c: &mut Criterion) {
    let s = wavy(30);
    let mask = ControlMask::with_boundary_frame(&s, Frame::Curvature);
    let greiner = GreinerFairing {
        params: GreinerParams {
            sampling: Sampling::Uniform(60, 60),
            ..GreinerParams::default()
        },
    };
    let target = TargetCurvatureFairing {
        params: TargetCurvatureParams {
            sampling: Sampling::Uniform(60, 60),
            ..TargetCurvatureParams::default()
        },
    };
    c.bench_function("greiner 30x30 on 60x60", |b| {
        b.iter(|| greiner.fair(&FairingProblem::new(&s, &mask, 0.01)).unwrap())
    });
    c.bench_function("target curvature 30x30 on 60x60", |b| {
        b.iter(|| target.fair(&FairingProblem::new(&s, &mask, 0.01)).unwrap())
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
