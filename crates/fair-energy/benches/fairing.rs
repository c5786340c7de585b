//! Local and global energy fairing on \[H\]'s example: the 52×52 quartic of `fixtures/third_party/bench`
//! (ε = 0.02, 10,000 iterations, \[H\] slide "Examples (1)"), the local scheme on the same net made
//! rational (smooth weights in [0.75, 1.25], held fixed), and the global variant on 200×200.
//!
//! Run: `cargo bench -p fair-energy` (`FAIR_BENCH_SLOW=1` adds nalgebra-sparse on 200×200). Goals (issue 4): local fairing ≤ 10 ms, global ≤ 20 ms on
//! the 52×52 surface, ≤ 1 s on 200×200 control points.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use fair_energy::{
    EnergyParams, GlobalParams, LocalStart, RationalStiffness, SparseSolver, fair_surface,
    fair_surface_global,
};
use nurbs_core::{BSplineSurface, ControlMask, Frame, KnotVector, Point3};

/// ε of \[H\]'s example (model units).
const SEED_TOLERANCE: f64 = 0.02;

fn seed_surface() -> BSplineSurface {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/third_party/bench/quartic_52x52_noisy.json"
    );
    match std::fs::read_to_string(path) {
        Ok(text) => nurbs_core::io::surfaces_from_json(&text)
            .expect("bench surface parses")
            .remove(0),
        Err(_) => {
            eprintln!("{path} not found: benchmarking a generated 52×52 quartic instead");
            grid_surface(52, 4)
        }
    }
}

/// A wavy n×n surface of degree p with uniform knots and deterministic noise.
fn grid_surface(n: usize, p: usize) -> BSplineSurface {
    let k = KnotVector::clamped_uniform(p, n).expect("knots");
    let mut x: u64 = 7;
    let points = (0..n * n)
        .map(|r| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let noise = ((x >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.02;
            let (u, v) = (
                (r / n) as f64 / (n - 1) as f64,
                (r % n) as f64 / (n - 1) as f64,
            );
            Point3::new(u, v, 0.2 * (3.0 * u).sin() * (2.0 * v).cos() + noise)
        })
        .collect();
    BSplineSurface::new(k.clone(), k, points, None).expect("surface")
}

fn local(c: &mut Criterion) {
    let s = seed_surface();
    let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
    let params = EnergyParams {
        start: LocalStart::Original,
        ..EnergyParams::default()
    };
    let (_, r) = fair_surface(&s, &mask, SEED_TOLERANCE, &params).expect("fairs");
    eprintln!("local 52x52: {r:?}");
    let mut g = c.benchmark_group("energy_local_52x52");
    g.sample_size(20);
    g.bench_function("10000_iterations", |b| {
        b.iter(|| fair_surface(black_box(&s), &mask, SEED_TOLERANCE, &params).expect("fairs"))
    });
    g.finish();
}

/// `s` with the smooth weights w_ij = 1 + 0.25 sin(0.37 i) cos(0.23 j) ∈ [0.75, 1.25].
fn with_weights(s: &BSplineSurface) -> BSplineSurface {
    let nv = s.num_v();
    let weights = (0..s.control_points().len())
        .map(|r| 1.0 + 0.25 * (0.37 * (r / nv) as f64).sin() * (0.23 * (r % nv) as f64).cos())
        .collect();
    BSplineSurface::new(
        s.knots_u().clone(),
        s.knots_v().clone(),
        s.control_points().to_vec(),
        Some(weights),
    )
    .expect("rational surface")
}

fn local_rational(c: &mut Criterion) {
    let s = with_weights(&seed_surface());
    let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
    let params = EnergyParams {
        start: LocalStart::Original,
        ..EnergyParams::default()
    };
    let (_, r) = fair_surface(&s, &mask, SEED_TOLERANCE, &params).expect("fairs");
    eprintln!("local rational 52x52: {r:?}");
    let mut g = c.benchmark_group("energy_local_rational_52x52");
    g.sample_size(20);
    g.bench_function("stiffness", |b| {
        b.iter(|| RationalStiffness::thin_plate(black_box(&s)))
    });
    g.bench_function("10000_iterations", |b| {
        b.iter(|| fair_surface(black_box(&s), &mask, SEED_TOLERANCE, &params).expect("fairs"))
    });
    g.finish();
}

/// The two starts of the local scheme on the rational 52 × 52 net with a tolerance that holds
/// no point back (ε = 1, fifty times the example's 0.02) and the framework's limit of 100
/// moves per free point: from the original net the scheme runs to its limit, from the solved
/// start it has nothing left to do (`crate::start` in fair-energy).
fn local_start(c: &mut Criterion) {
    let s = with_weights(&seed_surface());
    let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
    let mut g = c.benchmark_group("energy_local_start_rational_52x52");
    g.sample_size(10);
    for start in [LocalStart::Original, LocalStart::Solved] {
        let params = EnergyParams {
            start,
            min_iterations_per_free_point: 100,
            ..EnergyParams::default()
        };
        let (_, r) = fair_surface(&s, &mask, 1.0, &params).expect("fairs");
        eprintln!("local start {start:?}: {r:?}");
        g.bench_function(format!("{start:?}"), |b| {
            b.iter(|| fair_surface(black_box(&s), &mask, 1.0, &params).expect("fairs"))
        });
    }
    g.finish();
}

fn global(c: &mut Criterion) {
    #[allow(unused_mut)]
    let mut solvers = vec![SparseSolver::NalgebraSparse];
    #[cfg(feature = "faer")]
    solvers.push(SparseSolver::Faer);
    // nalgebra-sparse needs ~11 s per solve on 200×200: measured only on request
    let slow = std::env::var_os("FAIR_BENCH_SLOW").is_some();
    for (name, s) in [("52x52", seed_surface()), ("200x200", grid_surface(200, 4))] {
        let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
        let mut g = c.benchmark_group(format!("energy_global_{name}"));
        g.sample_size(10);
        for &solver in &solvers {
            if name == "200x200"
                && solver == SparseSolver::NalgebraSparse
                && !slow
                && solvers.len() > 1
            {
                continue;
            }
            let params = GlobalParams {
                solver,
                ..GlobalParams::default()
            };
            let (_, r) = fair_surface_global(&s, &mask, SEED_TOLERANCE, &params).expect("fairs");
            eprintln!("global {name} {solver:?}: {r:?}");
            g.bench_function(format!("{solver:?}"), |b| {
                b.iter(|| {
                    fair_surface_global(black_box(&s), &mask, SEED_TOLERANCE, &params)
                        .expect("fairs")
                })
            });
        }
        g.finish();
    }
}

criterion_group!(benches, local, local_rational, local_start, global);
criterion_main!(benches);
