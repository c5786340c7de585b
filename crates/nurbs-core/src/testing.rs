//! Seeded random geometry for property tests (feature `testing`).
//!
//! Every generator takes an explicit seed, so failures reproduce.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::Point3;
use crate::curve::BSplineCurve;
use crate::knots::KnotVector;
use crate::surface::BSplineSurface;

/// The random generator used by tests.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// A random clamped knot vector on [0, 1] for `count` control points: non-uniform interior
/// knots, some repeated (multiplicity ≤ degree − 1 so the result stays C¹, or ≤ degree when
/// `allow_c0`).
pub fn random_knots(
    rng: &mut ChaCha8Rng,
    degree: usize,
    count: usize,
    allow_c0: bool,
) -> KnotVector {
    let interior_count = count - degree - 1;
    let max_mult = if allow_c0 {
        degree
    } else {
        degree.saturating_sub(1).max(1)
    };
    let mut interior = Vec::with_capacity(interior_count);
    while interior.len() < interior_count {
        let t: f64 = rng.random_range(0.05..0.95);
        let mult = rng
            .random_range(1..=max_mult)
            .min(interior_count - interior.len());
        let mult = if rng.random_bool(0.7) { 1 } else { mult };
        interior.extend(std::iter::repeat_n(t, mult));
    }
    interior.sort_by(f64::total_cmp);
    let mut knots = vec![0.0; degree + 1];
    knots.extend(interior);
    knots.extend(std::iter::repeat_n(1.0, degree + 1));
    KnotVector::new(degree, knots).expect("generated knots are valid")
}

/// A random surface: degrees in `degrees`, control nets of up to `max_count` points per direction,
/// a wavy height field plus noise, weights in [0.5, 2] when `rational`.
pub fn random_surface(
    seed: u64,
    degrees: std::ops::RangeInclusive<usize>,
    max_count: usize,
    rational: bool,
) -> BSplineSurface {
    let mut r = rng(seed);
    let p = r.random_range(degrees.clone());
    let q = r.random_range(degrees);
    let nu = r.random_range((p + 1)..=max_count.max(p + 1));
    let nv = r.random_range((q + 1)..=max_count.max(q + 1));
    let ku = random_knots(&mut r, p, nu, true);
    let kv = random_knots(&mut r, q, nv, true);
    let mut points = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            let (x, y) = (i as f64 / (nu - 1) as f64, j as f64 / (nv - 1) as f64);
            let z = 0.3 * (3.0 * x).sin() * (2.0 * y).cos() + r.random_range(-0.05..0.05);
            points.push(Point3::new(
                x + r.random_range(-0.02..0.02),
                y + r.random_range(-0.02..0.02),
                z,
            ));
        }
    }
    let weights = rational.then(|| (0..nu * nv).map(|_| r.random_range(0.5..2.0)).collect());
    BSplineSurface::new(ku, kv, points, weights).expect("generated surface is valid")
}

/// A random curve in the same manner as [`random_surface`].
pub fn random_curve(
    seed: u64,
    degrees: std::ops::RangeInclusive<usize>,
    max_count: usize,
    rational: bool,
) -> BSplineCurve {
    let mut r = rng(seed);
    let p = r.random_range(degrees);
    let n = r.random_range((p + 1)..=max_count.max(p + 1));
    let kv = random_knots(&mut r, p, n, true);
    let points = (0..n)
        .map(|i| {
            let x = i as f64 / (n - 1) as f64;
            Point3::new(
                x,
                (4.0 * x).sin() * 0.3 + r.random_range(-0.05..0.05),
                r.random_range(-0.1..0.1),
            )
        })
        .collect();
    let weights = rational.then(|| (0..n).map(|_| r.random_range(0.5..2.0)).collect());
    BSplineCurve::new(kv, points, weights).expect("generated curve is valid")
}

/// A uniform random parameter in the domain of `knots`.
pub fn random_param(rng: &mut ChaCha8Rng, knots: &KnotVector) -> f64 {
    let (a, b) = knots.domain();
    rng.random_range(a..=b)
}

/// Asserts |a − b| ≤ tol with a message; the one approximate-equality helper of the workspace's
/// tests.
#[track_caller]
pub fn assert_close(a: f64, b: f64, tol: f64, what: &str) {
    assert!(
        (a - b).abs() <= tol,
        "{what}: {a} vs {b} (|diff| = {:e} > {tol:e})",
        (a - b).abs()
    );
}

/// Asserts that two points are within `tol`.
#[track_caller]
pub fn assert_points_close(a: &Point3, b: &Point3, tol: f64, what: &str) {
    let d = (a - b).norm();
    assert!(
        d <= tol,
        "{what}: {a:?} vs {b:?} (distance {d:e} > {tol:e})"
    );
}

/// Asserts that `faired` keeps the contract of [`crate::SurfaceFairing`] against `original`
/// ([`crate::check_contract`]: fixed points bit-identical, every point within `tolerance`, the
/// same knots and weights); returns the number of points that moved.
#[track_caller]
pub fn assert_contract(
    original: &BSplineSurface,
    faired: &BSplineSurface,
    mask: &crate::ControlMask,
    tolerance: f64,
) -> usize {
    crate::check_contract("under test", original, faired, mask, tolerance)
        .unwrap_or_else(|e| panic!("{e}"))
}
