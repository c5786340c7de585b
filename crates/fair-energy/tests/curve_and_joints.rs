//! Curve fairing and the Bézier-spline extension (\[H\] part ②).

mod common;

use common::{assert_contract, c0_joined};
use fair_energy::{CurveEnergyParams, EnergyParams, SeparableStiffness, fair_curve, fair_surface};
use nurbs_core::testing::{assert_close, random_curve, rng};
use nurbs_core::{BSplineSurface, ControlMask, Frame, KnotVector, Point3};
use rand::Rng;

fn bending(curve: &nurbs_core::BSplineCurve, third: f64) -> f64 {
    SeparableStiffness::curve(curve.knots(), third)
        .expect("stiffness")
        .energy(curve.control_points())
}

#[test]
fn curve_energy_matches_quadrature_and_reaches_the_single_point_optimum() {
    for seed in 0..5 {
        let c = random_curve(seed, 3..=5, 14, false);
        // ∫|x''|² by Gauss–Legendre on every span
        let rule = nurbs_core::quadrature::GaussLegendre::new(c.degree() + 1);
        let t = c.knots().knots();
        let mut e = 0.0;
        for s in c.knots().spans() {
            for (x, w) in rule.on(t[s], t[s + 1]) {
                e += w * c.derivatives(x, 2).d[2].norm_squared();
            }
        }
        assert_close(
            bending(&c, 0.0),
            e,
            1e-9 * e.max(1.0),
            "x^T G22 x vs quadrature",
        );
        let n = c.control_points().len();
        let mut free = vec![false; n];
        free[n / 2] = true;
        let (out, _) = fair_curve(&c, &free, 1e3, &CurveEnergyParams::default()).expect("fairs");
        let h = 1e-3;
        for k in 0..3 {
            let mut plus = out.clone();
            let mut minus = out.clone();
            plus.control_points_mut()[n / 2][k] += h;
            minus.control_points_mut()[n / 2][k] -= h;
            let slope = (bending(&plus, 0.0) - bending(&minus, 0.0)) / (2.0 * h);
            assert!(
                slope.abs() <= 1e-6 * e.max(1.0),
                "seed {seed}: slope {slope}"
            );
        }
    }
}

#[test]
fn noisy_curve_loses_ninety_percent_of_its_excess_energy() {
    // noise on the free points only: the smooth polygon is then reachable within ε
    for third in [0.0, 1e-3] {
        let n = 30;
        let free: Vec<bool> = (0..n).map(|i| i >= 2 && i + 2 < n).collect();
        let mut r = rng(7);
        let kv = KnotVector::clamped_uniform(3, n).expect("knots");
        let smooth: Vec<Point3> = (0..n)
            .map(|i| i as f64 / (n - 1) as f64)
            .map(|x| Point3::new(x, 0.3 * (4.0 * x).sin(), 0.1 * x * x))
            .collect();
        let noisy: Vec<Point3> = smooth
            .iter()
            .zip(&free)
            .map(|(p, &f)| {
                if f {
                    p + nurbs_core::Vector3::new(
                        0.0,
                        r.random_range(-0.01..0.01),
                        r.random_range(-0.01..0.01),
                    )
                } else {
                    *p
                }
            })
            .collect();
        let smooth = nurbs_core::BSplineCurve::new(kv.clone(), smooth, None).expect("curve");
        let c = nurbs_core::BSplineCurve::new(kv, noisy, None).expect("curve");
        let eps = 0.03;
        let params = CurveEnergyParams {
            third_derivative_weight: third,
            max_iterations: 20_000,
            ..CurveEnergyParams::default()
        };
        let (out, report) = fair_curve(&c, &free, eps, &params).expect("fairs");
        for i in 0..n {
            let (a, b) = (c.control_points()[i], out.control_points()[i]);
            if !free[i] {
                assert_eq!(a, b);
            }
            assert!((a - b).norm() <= eps);
        }
        let (e_smooth, e_noisy, e_out) = (
            bending(&smooth, third),
            bending(&c, third),
            bending(&out, third),
        );
        assert!(
            e_out - e_smooth <= 0.1 * (e_noisy - e_smooth),
            "third {third}: {e_noisy} -> {e_out}, smooth {e_smooth}"
        );
        assert_close(report.energy_after, e_out, 1e-9 * e_out, "reported energy");
    }
}

/// Largest |X_u(u⁻) − X_u(u⁺)| over samples along the u-joints (and likewise in v).
fn max_cross_jump(s: &BSplineSurface, params: &[f64]) -> f64 {
    let h = 1e-7;
    let mut worst: f64 = 0.0;
    for &t in params {
        for k in 0..=20 {
            let w = k as f64 / 20.0;
            let ju = s.derivatives(t - h, w).du - s.derivatives(t + h, w).du;
            let jv = s.derivatives(w, t - h).dv - s.derivatives(w, t + h).dv;
            worst = worst.max(ju.norm()).max(jv.norm());
        }
    }
    worst
}

#[test]
fn bezier_spline_extension_smooths_the_joints() {
    let (s, _, _) = c0_joined();
    let joints = [s.knots_u().knots()[4], s.knots_u().knots()[7]];
    assert_eq!(s.knots_u().multiplicity(joints[0]), 3, "full multiplicity");
    let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
    let eps = 0.1;
    let before = max_cross_jump(&s, &joints);
    let plain = EnergyParams {
        max_iterations: 20_000,
        ..EnergyParams::default()
    };
    let joined = EnergyParams {
        joint_weight: 0.95,
        ..plain
    };
    let (a, _) = fair_surface(&s, &mask, eps, &plain).expect("fairs");
    let (b, report) = fair_surface(&s, &mask, eps, &joined).expect("fairs");
    assert_contract(&s, &b, &mask, eps);
    assert!(report.energy_after < report.energy_before);
    let (ja, jb) = (max_cross_jump(&a, &joints), max_cross_jump(&b, &joints));
    assert!(before > 0.1, "the test surface has kinks ({before})");
    assert!(
        jb < 0.2 * before,
        "joint jumps {before} -> {jb} (plain thin plate: {ja})"
    );
    assert!(
        jb < 0.5 * ja,
        "the extension beats plain thin plate at the joints: {jb} vs {ja}"
    );
}
