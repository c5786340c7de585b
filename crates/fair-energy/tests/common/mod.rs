//! Narrow helpers shared by the integration tests.
#![allow(dead_code)]

use nurbs_core::{BSplineSurface, Direction, KnotVector, Point3};
use rand::Rng;

/// A smooth n×n surface of degree p with uniform knots (control points sampled from a smooth
/// height field) and the same surface with seeded noise of `amplitude` on every coordinate of
/// every point.
pub fn smooth_and_noisy(
    seed: u64,
    n: usize,
    p: usize,
    amplitude: f64,
) -> (BSplineSurface, BSplineSurface) {
    let k = KnotVector::clamped_uniform(p, n).expect("knots");
    let smooth: Vec<Point3> = (0..n * n)
        .map(|r| {
            let (u, v) = (
                (r / n) as f64 / (n - 1) as f64,
                (r % n) as f64 / (n - 1) as f64,
            );
            Point3::new(
                u,
                v,
                0.3 * (2.0 * u).sin() * (1.5 * v + 0.3).cos() + 0.2 * u * v,
            )
        })
        .collect();
    let mut rng = nurbs_core::testing::rng(seed);
    let noisy: Vec<Point3> = smooth
        .iter()
        .map(|p| {
            p + nurbs_core::Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            ) * amplitude
        })
        .collect();
    let s = BSplineSurface::new(k.clone(), k.clone(), smooth, None).expect("smooth");
    let t = BSplineSurface::new(k.clone(), k, noisy, None).expect("noisy");
    (s, t)
}

// (not every test crate that includes this module asserts the contract)
#[allow(unused_imports)]
pub use nurbs_core::testing::assert_contract;

/// A bicubic made of C0-joined Bézier patches: a smooth surface with the knots 1/3 and 2/3 raised
/// to full multiplicity in both directions, then the joint rows displaced so that the cross
/// derivatives jump there.
pub fn c0_joined() -> (BSplineSurface, Vec<usize>, Vec<usize>) {
    let joints = vec![3, 6];
    (joined_bicubic(0.03), joints.clone(), joints)
}

/// The 3 × 3 Bézier patches of [`c0_joined`] with the interior points of the joint rows and
/// columns (3 and 6) raised by `kink` in z; `kink` = 0 gives a surface that is C² everywhere.
pub fn joined_bicubic(kink: f64) -> BSplineSurface {
    let k = KnotVector::clamped_uniform(3, 6).expect("knots");
    let mut r = nurbs_core::testing::rng(4);
    let points = (0..36)
        .map(|q| {
            let (u, v) = ((q / 6) as f64 / 5.0, (q % 6) as f64 / 5.0);
            Point3::new(
                u,
                v,
                0.2 * (u * 3.0).sin() * v + r.random_range(-0.002..0.002),
            )
        })
        .collect();
    let s = BSplineSurface::new(k.clone(), k, points, None).expect("surface");
    let (a, b) = (s.knots_u().knots()[4], s.knots_u().knots()[5]);
    let s = s
        .insert_knot(Direction::U, a, 2)
        .and_then(|s| s.insert_knot(Direction::U, b, 2))
        .expect("insert u");
    let s = s
        .insert_knot(Direction::V, a, 2)
        .and_then(|s| s.insert_knot(Direction::V, b, 2))
        .expect("insert v");
    let mut s = s;
    let nv = s.num_v();
    // the joint rows are the points where the patches meet: index 3 and 6
    let joints = [3, 6];
    for q in 0..s.control_points().len() {
        let (i, j) = (q / nv, q % nv);
        let interior = i > 0 && j > 0 && i + 1 < s.num_u() && j + 1 < nv;
        if interior && (joints.contains(&i) || joints.contains(&j)) {
            s.control_points_mut()[q].z += kink;
        }
    }
    s
}

/// `s` with seeded noise of `amplitude` on every coordinate of its interior control points.
pub fn with_interior_noise(s: &BSplineSurface, seed: u64, amplitude: f64) -> BSplineSurface {
    let mut r = nurbs_core::testing::rng(seed);
    let (nu, nv) = (s.num_u(), s.num_v());
    let mut out = s.clone();
    for (q, p) in out.control_points_mut().iter_mut().enumerate() {
        let (i, j) = (q / nv, q % nv);
        if i > 0 && j > 0 && i + 1 < nu && j + 1 < nv {
            *p += nurbs_core::Vector3::new(
                r.random_range(-1.0..1.0),
                r.random_range(-1.0..1.0),
                r.random_range(-1.0..1.0),
            ) * amplitude;
        }
    }
    out
}
