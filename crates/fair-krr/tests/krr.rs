//! KRR: closed-form truth (C^p at the faired knot), masks, tolerance, bad input.

use fair_krr::{
    KnotJumps, KrrCurveParams, KrrDirection, KrrError, KrrFairing, KrrParams, KrrSolve, KrrStop,
    cubic_closed_form, fair_curve, fair_surface,
};
use nurbs_core::energy::thin_plate_energy;
use nurbs_core::testing::{assert_close, rng};
use nurbs_core::{
    BSplineCurve, BSplineSurface, ControlMask, FairingProblem, Frame, KnotVector, Point3,
    SurfaceFairing, Vector3,
};
use rand::Rng;

/// A curve of degree p with n points, simple non-uniform interior knots and noisy points.
fn noisy_curve(seed: u64, p: usize, n: usize) -> BSplineCurve {
    let mut r = rng(seed);
    let mut interior: Vec<f64> = Vec::new();
    let mut t = 0.0;
    for _ in 0..n - p - 1 {
        t += r.random_range(0.5..1.5);
        interior.push(t);
    }
    let end = t + r.random_range(0.5..1.5);
    let mut knots = vec![0.0; p + 1];
    knots.extend(interior);
    knots.extend(std::iter::repeat_n(end, p + 1));
    let kv = KnotVector::new(p, knots).expect("knots");
    let points = (0..n)
        .map(|i| {
            Point3::new(
                i as f64,
                (i as f64 * 0.7).sin() + r.random_range(-0.1..0.1),
                r.random_range(-0.1..0.1),
            )
        })
        .collect();
    BSplineCurve::new(kv, points, None).expect("curve")
}

/// The p-th derivative just left and right of knot index c (constant on each span: evaluate at
/// the span midpoints).
fn pth_derivative_jump(curve: &BSplineCurve, c: usize) -> (Vector3, Vector3) {
    let t = curve.knots().knots();
    let p = curve.degree().min(3);
    let left = curve.derivatives(0.5 * (t[c - 1] + t[c]), p).d[p];
    let right = curve.derivatives(0.5 * (t[c] + t[c + 1]), p).d[p];
    (left, right)
}

#[test]
fn cubic_closed_form_agrees_with_the_single_point_solve() {
    for seed in 0..8 {
        let c = noisy_curve(seed, 3, 12);
        let jumps = KnotJumps::new(c.knots());
        let p = c.control_points();
        let mut checked = 0;
        for j in 0..p.len() {
            if let (Some(a), Some(b)) = (
                cubic_closed_form(c.knots().knots(), p, j),
                jumps.target(j, |k| p[k]),
            ) {
                assert!(
                    (a - b).norm() <= 1e-9 * (1.0 + a.coords.norm()),
                    "seed {seed} j {j}: {a:?} vs {b:?}"
                );
                checked += 1;
            }
        }
        assert_eq!(
            checked,
            p.len() - 4,
            "every point but the two at each end has a knot"
        );
    }
    // uniform knots: P_j = (−P_{j−2} + 4P_{j−1} + 4P_{j+1} − P_{j+2}) / 6
    let kv = KnotVector::clamped_uniform(3, 10).expect("knots");
    let p: Vec<Point3> = (0..10)
        .map(|i| Point3::new(i as f64, ((i * i) % 7) as f64, 0.0))
        .collect();
    let j = 5;
    let expected =
        (-p[j - 2].coords + 4.0 * p[j - 1].coords + 4.0 * p[j + 1].coords - p[j + 2].coords) / 6.0;
    let got = KnotJumps::new(&kv).target(j, |k| p[k]).expect("target");
    assert!((got.coords - expected).norm() < 1e-12);
}

#[test]
fn one_krr_step_makes_the_curve_c_p_at_its_knot() {
    for (seed, p) in [(1, 3), (2, 3), (3, 2), (4, 4), (5, 5)] {
        let c = noisy_curve(seed, p, 14);
        let j = 6;
        let knot = j + (p + 2) / 2;
        let (l0, r0) = pth_derivative_jump(&c, knot);
        let mut free = vec![false; 14];
        free[j] = true;
        let params = KrrCurveParams {
            max_iterations: 1,
            ..KrrCurveParams::default()
        };
        let (out, report) = fair_curve(&c, &free, 1e3, &params).expect("fairs");
        assert_eq!(report.iterations, 1);
        let (l1, r1) = pth_derivative_jump(&out, knot);
        if p <= 3 {
            assert!(
                (l0 - r0).norm() > 1e-3,
                "degree {p}: the test curve has a jump to remove"
            );
            assert!(
                (l1 - r1).norm() <= 1e-9 * l1.norm().max(1.0),
                "degree {p}: jump {:e} left",
                (l1 - r1).norm()
            );
        }
        assert!(
            report.max_jump_after <= 1e-9 * report.max_jump_before.max(1.0),
            "degree {p}: {report:?}"
        );
        for k in (0..14).filter(|&k| k != j) {
            assert_eq!(out.control_points()[k], c.control_points()[k]);
        }
    }
}

#[test]
fn least_squares_removes_the_jump_with_a_smaller_correction() {
    let c = noisy_curve(9, 3, 12);
    let free = vec![true; 12];
    let single = KrrCurveParams {
        max_iterations: 1,
        taboo: 0,
        ..KrrCurveParams::default()
    };
    let ls = KrrCurveParams {
        solve: KrrSolve::LeastSquares,
        ..single
    };
    let (a, ra) = fair_curve(&c, &free, 1e3, &single).expect("fairs");
    let (b, rb) = fair_curve(&c, &free, 1e3, &ls).expect("fairs");
    let norm = |x: &BSplineCurve| {
        x.control_points()
            .iter()
            .zip(c.control_points())
            .map(|(p, q)| (p - q).norm_squared())
            .sum::<f64>()
    };
    assert!(
        norm(&b) <= norm(&a) + 1e-15,
        "least squares moves less: {} vs {}",
        norm(&b),
        norm(&a)
    );
    assert!(ra.max_jump_after < ra.max_jump_before && rb.max_jump_after < rb.max_jump_before);
}

#[test]
fn curve_moves_respect_mask_and_tolerance() {
    for solve in [KrrSolve::SinglePoint, KrrSolve::LeastSquares] {
        let c = noisy_curve(11, 3, 30);
        let mut free = vec![true; 30];
        free[0] = false;
        free[1] = false;
        free[28] = false;
        free[29] = false;
        free[15] = false;
        let eps = 0.01;
        let params = KrrCurveParams {
            solve,
            ..KrrCurveParams::default()
        };
        let (out, report) = fair_curve(&c, &free, eps, &params).expect("fairs");
        for (k, (a, b)) in c
            .control_points()
            .iter()
            .zip(out.control_points())
            .enumerate()
        {
            if !free[k] {
                assert_eq!(a, b, "fixed point {k}");
            }
            assert!((a - b).norm() <= eps);
        }
        assert!(
            report.iterations > 0 && report.max_jump_after < report.max_jump_before,
            "{report:?}"
        );
    }
}

fn noisy_surface(seed: u64, n: usize) -> BSplineSurface {
    let k = KnotVector::clamped_uniform(3, n).expect("knots");
    let mut r = rng(seed);
    let points = (0..n * n)
        .map(|q| {
            let (u, v) = (
                (q / n) as f64 / (n - 1) as f64,
                (q % n) as f64 / (n - 1) as f64,
            );
            Point3::new(
                u,
                v,
                0.3 * (2.0 * u).sin() * v + r.random_range(-0.01..0.01),
            )
        })
        .collect();
    BSplineSurface::new(k.clone(), k, points, None).expect("surface")
}

#[test]
fn surface_krr_keeps_frames_and_tolerance_and_smooths() {
    let s = noisy_surface(3, 16);
    for direction in [KrrDirection::U, KrrDirection::V, KrrDirection::Average] {
        for frame in [Frame::Positional, Frame::Tangential, Frame::Curvature] {
            let mask = ControlMask::with_boundary_frame(&s, frame);
            let eps = 0.02;
            let params = KrrParams {
                direction,
                max_iterations: 3000,
                ..KrrParams::default()
            };
            let (out, report) = fair_surface(&s, &mask, eps, &params).expect("fairs");
            for (r, (a, b)) in s
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
                assert!((a - b).norm() <= eps);
            }
            assert!(
                report.max_jump_after < report.max_jump_before,
                "{direction:?} {frame:?}: {report:?}"
            );
            let (e0, e1) = (thin_plate_energy(&s), thin_plate_energy(&out));
            eprintln!("{direction:?} {frame:?}: energy {e0} -> {e1}, {report:?}");
            assert!(e1 < e0, "{direction:?} {frame:?}: energy {e0} -> {e1}");
        }
    }
}

#[test]
fn bad_input_is_an_error_or_a_report_that_nothing_moved() {
    let s = noisy_surface(4, 8);
    let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
    for eps in [0.0, -1.0, f64::NAN] {
        assert!(matches!(
            fair_surface(&s, &mask, eps, &KrrParams::default()),
            Err(KrrError::InvalidTolerance { .. })
        ));
    }
    let none = ControlMask::all_fixed(8, 8);
    let (out, report) = fair_surface(&s, &none, 0.1, &KrrParams::default()).expect("not an error");
    assert_eq!((report.iterations, report.stop), (0, KrrStop::NothingFree));
    assert_eq!(out, s);
    let c = noisy_curve(1, 3, 10);
    assert!(matches!(
        fair_curve(&c, &[true; 3], 0.1, &KrrCurveParams::default()),
        Err(KrrError::MaskLength { .. })
    ));
    let method = KrrFairing::default();
    assert!(matches!(
        method.fair(&FairingProblem::new(&s, &mask, 0.0)),
        Err(nurbs_core::Error::FairingFailed { .. })
    ));
    let (_, r) = FairingProblem::new(&s, &mask, 0.01)
        .solve(&method)
        .expect("fairs");
    assert_eq!(r.method, "krr");
    assert_close(
        r.max_control_move.min(0.01),
        r.max_control_move,
        0.0,
        "moves within ε",
    );
}
