//! Criterion benches of g-continuity: G2 on one side of a 30×30 bicubic with K = 200 samples
//! (issue 3 target ≤ 1 ms), measuring one link with the default K = 101, and the joint polish
//! setting G2 on that side from G1 (all three rows of the side at once).

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use g_continuity::{
    ConnectParams, MeasureParams, SetParams, SideLink, measure_link, polish_joint, set_g2,
};
use nurbs_core::Continuity;
use nurbs_core::{BSplineSurface, KnotVector, Point3, Side};
use std::hint::black_box;

fn bicubic(n: usize, f: impl Fn(f64, f64) -> Point3) -> BSplineSurface {
    let k = KnotVector::clamped_uniform(3, n).unwrap();
    let pts = (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .map(|(i, j)| f(i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64))
        .collect();
    BSplineSurface::new(k.clone(), k, pts, None).unwrap()
}

/// A 30×30 master on x ∈ [−1, 0] and a 30×30 slave on x ∈ [0, 1] sharing the line x = 0, tangent
/// there (G1) but with a different curvature across (not G2).
fn pair() -> (BSplineSurface, BSplineSurface) {
    let master = bicubic(30, |s, t| {
        Point3::new(
            s - 1.0,
            2.0 * t,
            0.3 * (s - 1.0).powi(2) + 0.1 * (3.0 * t).sin(),
        )
    });
    let slave = bicubic(30, |s, t| {
        Point3::new(s, 2.0 * t, 0.8 * s * s + 0.1 * (3.0 * t).sin())
    });
    (master, slave)
}

fn benches(c: &mut Criterion) {
    let (master, slave) = pair();
    let params = SetParams {
        samples_per_span: 1,
        min_samples: 200,
        ..SetParams::default()
    };
    c.bench_function("g2_one_side_30x30_k200", |b| {
        b.iter_batched(
            || slave.clone(),
            |mut s| black_box(set_g2(&master, &mut s, Side::U0, &params).unwrap()),
            BatchSize::SmallInput,
        )
    });
    let fixed = SetParams {
        g2_method: g_continuity::G2Method::FixedDirections,
        ..params
    };
    c.bench_function("g2_fixed_directions_30x30_k200", |b| {
        b.iter_batched(
            || slave.clone(),
            |mut s| black_box(set_g2(&master, &mut s, Side::U0, &fixed).unwrap()),
            BatchSize::SmallInput,
        )
    });
    c.bench_function("measure_link_30x30_k101", |b| {
        b.iter(|| {
            black_box(measure_link(&master, &slave, Side::U0, &MeasureParams::default()).unwrap())
        })
    });
    let link = [SideLink {
        side: Side::U0,
        master: &master,
        target: Continuity::G2,
        range: None,
        g2_zones: [0.0; 2],
    }];
    let connect = ConnectParams::default();
    c.bench_function("joint_polish_one_side_30x30", |b| {
        b.iter(|| black_box(polish_joint(&slave, &link, &connect, f64::INFINITY).unwrap()))
    });
}

criterion_group!(group, benches);
criterion_main!(group);
