//! Narrow helpers shared by the integration tests.
#![allow(dead_code)]

use nurbs_core::{
    BSplineSurface, ControlMask, Direction, FairingReport, KnotVector, Point3, SurfaceFairing,
    Vector3,
};
use rand::Rng;

/// Interior knots k/(m+1), k = 1..=m.
pub fn interior(m: usize) -> Vec<f64> {
    (1..=m).map(|k| k as f64 / (m + 1) as f64).collect()
}

/// The exact sphere patch of nurbs-core (rational biquadratic) refined with `m` interior knots
/// per direction: the same surface with more control points.
pub fn sphere(radius: f64, m: usize) -> BSplineSurface {
    let s = nurbs_core::shapes::sphere_patch(radius).expect("sphere");
    s.refine(Direction::U, &interior(m))
        .and_then(|s| s.refine(Direction::V, &interior(m)))
        .expect("refine")
}

/// The exact quarter cylinder of nurbs-core refined with `m` interior knots per direction
/// (degree raised to 2 along the axis so both directions have inner rows).
pub fn cylinder(radius: f64, height: f64, m: usize) -> BSplineSurface {
    let s = nurbs_core::shapes::cylinder(radius, height).expect("cylinder");
    s.elevate_degree(Direction::U, 1)
        .and_then(|s| s.refine(Direction::U, &interior(m)))
        .and_then(|s| s.refine(Direction::V, &interior(m)))
        .expect("refine")
}

/// The hyperbolic paraboloid z = x² − y² over [−1, 1]² as an exact polynomial bicubic with `m`
/// interior knots per direction (x = 2u − 1, y = 2v − 1).
pub fn saddle(m: usize) -> BSplineSurface {
    let xs = [-1.0, 0.0, 1.0];
    let cz = [1.0, -1.0, 1.0];
    let mut points = Vec::new();
    for i in 0..3 {
        for j in 0..3 {
            points.push(Point3::new(xs[i], xs[j], cz[i] - cz[j]));
        }
    }
    let b = KnotVector::bezier(2).expect("knots");
    BSplineSurface::new(b.clone(), b, points, None)
        .and_then(|s| s.elevate_degree(Direction::U, 1))
        .and_then(|s| s.elevate_degree(Direction::V, 1))
        .and_then(|s| s.refine(Direction::U, &interior(m)))
        .and_then(|s| s.refine(Direction::V, &interior(m)))
        .expect("saddle")
}

/// Gaussian curvature of z = x² − y² at (x, y).
pub fn saddle_gauss(x: f64, y: f64) -> f64 {
    -4.0 / (1.0 + 4.0 * x * x + 4.0 * y * y).powi(2)
}

/// `surface` with seeded noise on the points `mask` frees: each gets a random direction times
/// `amplitude` (model units).
pub fn noisy(
    surface: &BSplineSurface,
    mask: &ControlMask,
    amplitude: f64,
    seed: u64,
) -> BSplineSurface {
    let mut rng = nurbs_core::testing::rng(seed);
    let mut out = surface.clone();
    for (k, p) in out.control_points_mut().iter_mut().enumerate() {
        let d = loop {
            let d = Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            );
            let n = d.norm();
            if n > 0.1 && n <= 1.0 {
                break d / n;
            }
        };
        if mask.as_slice()[k] {
            *p += amplitude * d;
        }
    }
    out
}

/// The surface with the roles of u and v exchanged (P'_ji = P_ij, knots swapped).
pub fn swap_uv(s: &BSplineSurface) -> BSplineSurface {
    let (nu, nv) = (s.num_u(), s.num_v());
    let mut pts = Vec::with_capacity(nu * nv);
    let mut w = Vec::with_capacity(nu * nv);
    for j in 0..nv {
        for i in 0..nu {
            pts.push(s.control_point(i, j));
            w.push(s.weight(i, j));
        }
    }
    BSplineSurface::new(
        s.knots_v().clone(),
        s.knots_u().clone(),
        pts,
        s.is_rational().then_some(w),
    )
    .expect("swap")
}

/// A mask with the rows swapped like [`swap_uv`].
pub fn swap_mask(m: &ControlMask) -> ControlMask {
    let mut out = ControlMask::all_free(m.num_v(), m.num_u());
    for i in 0..m.num_u() {
        for j in 0..m.num_v() {
            out.set_free(j, i, m.is_free(i, j));
        }
    }
    out
}

/// Parameters of an n × n grid strictly inside the domain (margin `inset` of the domain length
/// on each side).
pub fn inner_grid(s: &BSplineSurface, n: usize, inset: f64) -> Vec<(f64, f64)> {
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    let mut out = Vec::new();
    for a in 0..n {
        for b in 0..n {
            let fa = inset + (1.0 - 2.0 * inset) * a as f64 / (n - 1) as f64;
            let fb = inset + (1.0 - 2.0 * inset) * b as f64 / (n - 1) as f64;
            out.push((u0 + fa * (u1 - u0), v0 + fb * (v1 - v0)));
        }
    }
    out
}

/// Mean curvatures at `params`.
pub fn mean_curvatures(s: &BSplineSurface, params: &[(f64, f64)]) -> Vec<f64> {
    let mut e = s.evaluator();
    params
        .iter()
        .map(|&(u, v)| e.derivatives(u, v).mean_curvature().expect("regular"))
        .collect()
}

/// Population variance.
pub fn variance(xs: &[f64]) -> f64 {
    let m = xs.iter().sum::<f64>() / xs.len() as f64;
    xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / xs.len() as f64
}

// (not every test crate that includes this module asserts the contract)
#[allow(unused_imports)]
pub use nurbs_core::testing::assert_contract;

/// Runs a method through the trait, its result checked against the contract.
pub fn run(
    method: &dyn SurfaceFairing,
    s: &BSplineSurface,
    mask: &ControlMask,
    tolerance: f64,
) -> (BSplineSurface, FairingReport) {
    nurbs_core::FairingProblem::new(s, mask, tolerance)
        .solve(method)
        .expect("fairing")
}
