//! Grid and scattered evaluation of the 20×20 non-uniform bicubic of `fixtures/third_party/bench`.
//!
//! Run: `cargo bench -p nurbs-core --bench eval`. Goals (issue "Foundation"): 1000×1000 grid,
//! single thread — points ≤ 15 ms, with first and second derivatives ≤ 40 ms, with normal and
//! principal curvatures ≤ 70 ms; scattered evaluation with second derivatives ≥ 8 M points/s;
//! parallel grid ≥ 1.8× the single-thread speed on 2 cores.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use nurbs_core::{BSplineSurface, GridOrder};
use rand::{Rng, SeedableRng};

fn bench_surface() -> BSplineSurface {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/third_party/bench/bicubic_20x20_nonuniform.json"
    );
    match std::fs::read_to_string(path) {
        Ok(text) => nurbs_core::io::surfaces_from_json(&text)
            .expect("bench surface parses")
            .remove(0),
        Err(_) => {
            eprintln!("{path} not found: benchmarking a generated 20×20 bicubic instead");
            nurbs_core::testing::random_surface(20, 3..=3, 20, false)
        }
    }
}

fn single_thread<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    thread_local_pool().install(f)
}

fn thread_local_pool() -> &'static rayon::ThreadPool {
    static POOL: std::sync::OnceLock<rayon::ThreadPool> = std::sync::OnceLock::new();
    POOL.get_or_init(|| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("pool")
    })
}

/// What "point with normal and principal curvatures" returns per sample (read only through
/// `black_box`).
#[allow(dead_code)]
#[derive(Clone, Copy, Default)]
struct CurvatureSample {
    point: nurbs_core::Point3,
    normal: nurbs_core::Vector3,
    k1: f64,
    k2: f64,
}

fn curvature_sample(d: &nurbs_core::SurfaceDerivatives) -> CurvatureSample {
    match d.curvature_values() {
        Some(c) => CurvatureSample {
            point: d.point,
            normal: c.normal,
            k1: c.k1,
            k2: c.k2,
        },
        None => CurvatureSample {
            point: d.point,
            normal: nurbs_core::Vector3::zeros(),
            k1: f64::NAN,
            k2: f64::NAN,
        },
    }
}

fn grid(c: &mut Criterion) {
    let s = bench_surface();
    let us = s.knots_u().uniform_params(1000);
    let vs = s.knots_v().uniform_params(1000);
    let mut g = c.benchmark_group("grid_1000x1000");
    g.sample_size(20);
    g.throughput(Throughput::Elements(1_000_000));
    // results go into buffers reused across iterations, as a caller evaluating repeatedly would
    let mut points = Vec::new();
    g.bench_function("points", |b| {
        b.iter(|| s.eval_grid_into(&us, &vs, GridOrder::Points, &mut points, |d| d.point))
    });
    let mut derivs = Vec::new();
    g.bench_function("second_derivatives", |b| {
        b.iter(|| s.eval_grid_into(&us, &vs, GridOrder::Second, &mut derivs, |d| *d))
    });
    let mut batched = Vec::new();
    g.bench_function("normal_and_principal_curvatures", |b| {
        b.iter(|| s.eval_grid_curvatures_into(&us, &vs, &mut batched))
    });
    let mut curv = Vec::new();
    g.bench_function("normal_and_principal_curvatures_pointwise", |b| {
        b.iter(|| s.eval_grid_into(&us, &vs, GridOrder::Second, &mut curv, curvature_sample))
    });
    g.bench_function("par_second_derivatives_all_threads", |b| {
        b.iter(|| s.par_eval_grid_into(&us, &vs, GridOrder::Second, &mut derivs, |d| *d))
    });
    g.bench_function("par_second_derivatives_1_thread", |b| {
        b.iter(|| {
            single_thread(|| s.par_eval_grid_into(&us, &vs, GridOrder::Second, &mut derivs, |d| *d))
        })
    });
    g.bench_function("par_curvatures_all_threads", |b| {
        b.iter(|| s.par_eval_grid_into(&us, &vs, GridOrder::Second, &mut curv, curvature_sample))
    });
    g.bench_function("par_curvatures_1_thread", |b| {
        b.iter(|| {
            single_thread(|| {
                s.par_eval_grid_into(&us, &vs, GridOrder::Second, &mut curv, curvature_sample)
            })
        })
    });
    black_box((&points, &derivs, &curv, &batched));
    g.finish();
}

fn scattered(c: &mut Criterion) {
    let s = bench_surface();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let params: Vec<(f64, f64)> = (0..1_000_000)
        .map(|_| (rng.random_range(0.0..=1.0), rng.random_range(0.0..=1.0)))
        .collect();
    let mut g = c.benchmark_group("scattered_1M");
    g.sample_size(20);
    g.throughput(Throughput::Elements(params.len() as u64));
    g.bench_function("points", |b| {
        b.iter(|| {
            let mut eval = s.evaluator();
            let mut acc = 0.0;
            for &(u, v) in &params {
                acc += eval.point(u, v).x;
            }
            black_box(acc)
        })
    });
    g.bench_function("second_derivatives", |b| {
        b.iter(|| {
            let mut eval = s.evaluator();
            let mut acc = 0.0;
            for &(u, v) in &params {
                let d = eval.derivatives(u, v);
                acc += d.point.x + d.duu.y + d.dvv.z;
            }
            black_box(acc)
        })
    });
    g.finish();
}

/// Thin-plate energy of a rational degree-5 net (the size a vertex blend reaches after knot
/// transfer and G2 refinement): the grid quadrature against the node-by-node reference.
fn thin_plate(c: &mut Criterion) {
    // the first seed whose net is at least 50 × 50 (deterministic)
    let s = (0..)
        .map(|seed| nurbs_core::testing::random_surface(seed, 5..=5, 64, true))
        .find(|s| s.num_u() >= 50 && s.num_v() >= 50)
        .expect("some seed gives a large net");
    let mut g = c.benchmark_group(format!(
        "thin_plate_{}x{}_rational_deg5",
        s.num_u(),
        s.num_v()
    ));
    g.sample_size(20);
    g.bench_function("grid", |b| {
        b.iter(|| black_box(nurbs_core::energy::thin_plate_energy(&s)))
    });
    g.bench_function("pointwise", |b| {
        b.iter(|| black_box(nurbs_core::energy::thin_plate_energy_pointwise(&s)))
    });
    g.finish();
}

criterion_group!(benches, grid, scattered, thin_plate);
criterion_main!(benches);
