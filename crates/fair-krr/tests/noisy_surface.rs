//! Issue 4 acceptance for KRR: seeded noise on a smooth bicubic loses ≥ 90 % of its excess
//! thin-plate energy within ε.

use fair_krr::{KrrDirection, KrrParams, fair_surface};
use nurbs_core::energy::thin_plate_energy;
use nurbs_core::testing::rng;
use nurbs_core::{BSplineSurface, ControlMask, Frame, KnotVector, Point3, Vector3};
use rand::Rng;

/// A smooth n×n bicubic (points sampled from a smooth height field) and the same with seeded
/// noise of `amplitude` on every coordinate of every point.
fn smooth_and_noisy(seed: u64, n: usize, amplitude: f64) -> (BSplineSurface, BSplineSurface) {
    let k = KnotVector::clamped_uniform(3, n).expect("knots");
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
    let mut r = rng(seed);
    let noisy: Vec<Point3> = smooth
        .iter()
        .map(|p| {
            p + Vector3::new(
                r.random_range(-1.0..1.0),
                r.random_range(-1.0..1.0),
                r.random_range(-1.0..1.0),
            ) * amplitude
        })
        .collect();
    (
        BSplineSurface::new(k.clone(), k.clone(), smooth, None).expect("smooth"),
        BSplineSurface::new(k.clone(), k, noisy, None).expect("noisy"),
    )
}

#[test]
fn noisy_surface_loses_ninety_percent_of_its_excess_energy() {
    // default settings: u/v average ([SV] §5.1), taboo 2, 10,000 moves (≈ 25 per point)
    let params = KrrParams::default();
    assert_eq!(params.direction, KrrDirection::Average);
    for seed in [42, 7] {
        let amplitude = 0.004;
        let (smooth, noisy) = smooth_and_noisy(seed, 20, amplitude);
        let mask = ControlMask::with_boundary_frame(&noisy, Frame::Positional);
        // generous: 3 × the noise amplitude per coordinate (the noise itself is ≤ √3 × amplitude)
        let eps = 3.0 * amplitude;
        let (out, report) = fair_surface(&noisy, &mask, eps, &params).expect("fairs");
        for (r, (a, b)) in noisy
            .control_points()
            .iter()
            .zip(out.control_points())
            .enumerate()
        {
            if !mask.as_slice()[r] {
                for c in 0..3 {
                    assert_eq!(a[c].to_bits(), b[c].to_bits(), "fixed point {r} changed");
                }
            }
            assert!((a - b).norm() <= eps, "point {r} moved {}", (a - b).norm());
        }
        let (e_smooth, e_noisy, e_out) = (
            thin_plate_energy(&smooth),
            thin_plate_energy(&noisy),
            thin_plate_energy(&out),
        );
        let excess = e_noisy - e_smooth;
        assert!(excess > 0.0);
        let loss = (e_noisy - e_out) / excess;
        eprintln!(
            "seed {seed}: energy {e_noisy:.4} -> {e_out:.4} (smooth {e_smooth:.4}), excess loss {:.0} %, {report:?}",
            100.0 * loss
        );
        assert!(
            e_out - e_smooth <= 0.1 * excess,
            "seed {seed}: energy {e_noisy} -> {e_out}, smooth {e_smooth} ({report:?})"
        );
    }
}
