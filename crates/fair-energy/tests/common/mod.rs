//! Narrow helpers shared by the integration tests.
#![allow(dead_code)]

use nurbs_core::{BSplineSurface, ControlMask, KnotVector, Point3};
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

/// Asserts that fixed points are bit-identical and every point stays within `tolerance` of its
/// original; returns the number of points that moved.
#[track_caller]
pub fn assert_mask_and_tolerance(
    original: &BSplineSurface,
    faired: &BSplineSurface,
    mask: &ControlMask,
    tolerance: f64,
) -> usize {
    let mut moved = 0;
    for (r, (a, b)) in original
        .control_points()
        .iter()
        .zip(faired.control_points())
        .enumerate()
    {
        let (i, j) = (r / original.num_v(), r % original.num_v());
        if !mask.is_free(i, j) {
            for c in 0..3 {
                assert_eq!(
                    a[c].to_bits(),
                    b[c].to_bits(),
                    "fixed point ({i}, {j}) changed"
                );
            }
        }
        let d = (a - b).norm();
        assert!(
            d <= tolerance,
            "point ({i}, {j}) moved {d} > tolerance {tolerance}"
        );
        if d > 0.0 {
            moved += 1;
        }
    }
    moved
}
