//! Masked rows stay bit-identical; the report's deviation is a sampled surface distance; bad
//! input is an error, never a panic.

mod common;

use common::*;
use fair_curvature::{
    CurveParams, GREINER_METHOD, GreinerFairing, GreinerParams, TARGET_METHOD,
    TargetCurvatureFairing, TargetCurvatureParams, fair_curve, fair_surface_target,
};
use nurbs_core::{ControlMask, Error, FairingProblem, Frame, SurfaceFairing};

fn methods() -> Vec<Box<dyn SurfaceFairing>> {
    vec![
        Box::new(TargetCurvatureFairing::default()),
        Box::new(GreinerFairing::default()),
    ]
}

#[test]
fn names() {
    assert_eq!(TargetCurvatureFairing::default().name(), TARGET_METHOD);
    assert_eq!(TARGET_METHOD, "curvature");
    assert_eq!(GreinerFairing::default().name(), GREINER_METHOD);
    assert_eq!(GREINER_METHOD, "greiner");
}

#[test]
fn masked_rows_are_bit_identical_and_moves_within_tolerance() {
    let exact = sphere(5.0, 8);
    for frame in [Frame::Positional, Frame::Tangential, Frame::Curvature] {
        let mask = ControlMask::with_boundary_frame(&exact, frame);
        // noise on every point, fixed ones included: the fixed rows must come back as given
        let s = noisy(&exact, &ControlMask::for_surface(&exact), 0.05, 3);
        for m in methods() {
            let (out, _) = run(m.as_ref(), &s, &mask, 0.1);
            let moved = assert_contract(&s, &out, &mask, 0.1);
            assert!(moved > 0, "{} moved nothing", m.name());
        }
    }
}

#[test]
fn report_deviation_is_a_sampled_surface_distance() {
    let exact = sphere(5.0, 8);
    let mask = ControlMask::with_boundary_frame(&exact, Frame::Tangential);
    let s = noisy(&exact, &mask, 0.05, 4);
    for m in methods() {
        let (out, report) = run(m.as_ref(), &s, &mask, 0.1);
        let sampled = nurbs_core::energy::max_deviation(
            &s,
            &out,
            nurbs_core::fairing::REPORT_DEVIATION_SAMPLES,
        );
        assert_eq!(report.max_deviation, sampled);
        // a distance between surfaces, not the control move, and never above it
        assert!(report.max_deviation > 0.0);
        assert!(report.max_deviation < report.max_control_move);
        assert_eq!(report.method, m.name());
    }
}

#[test]
fn target_report_names_the_refit_error() {
    let exact = sphere(5.0, 8);
    let mask = ControlMask::with_boundary_frame(&exact, Frame::Tangential);
    let s = noisy(&exact, &mask, 0.05, 5);
    let (_, report) =
        fair_surface_target(&s, &mask, 0.1, &TargetCurvatureParams::default()).unwrap();
    assert!(report.refit_max_error > 0.0 && report.refit_max_error < 0.1);
    assert!(report.refit_rms_error <= report.refit_max_error);
    assert!(report.max_sample_move <= 0.9 * 0.1 * (1.0 + 1e-12));
}

#[test]
fn bad_input_is_a_fairing_error() {
    let s = sphere(5.0, 4);
    let mask = ControlMask::for_surface(&s);
    for m in methods() {
        for tol in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = m.fair(&FairingProblem::new(&s, &mask, tol)).unwrap_err();
            assert!(matches!(e, Error::FairingFailed { .. }), "{e}");
        }
        let wrong = ControlMask::all_free(3, 3);
        assert!(matches!(
            m.fair(&FairingProblem::new(&s, &wrong, 0.1)),
            Err(Error::FairingFailed { .. })
        ));
    }
    let bad = GreinerFairing {
        params: GreinerParams {
            deviation_weight: f64::NAN,
            ..GreinerParams::default()
        },
    };
    let e = bad.fair(&FairingProblem::new(&s, &mask, 0.1)).unwrap_err();
    assert!(e.to_string().contains("deviation_weight"), "{e}");
    let bad = TargetCurvatureFairing {
        params: TargetCurvatureParams {
            pull_tolerance_fraction: 2.0,
            ..TargetCurvatureParams::default()
        },
    };
    assert!(bad.fair(&FairingProblem::new(&s, &mask, 0.1)).is_err());
    // nothing free: returned unchanged
    for m in methods() {
        let fixed = ControlMask::all_fixed(s.num_u(), s.num_v());
        let out = m
            .fair(&FairingProblem::new(&s, &fixed, 0.1))
            .unwrap()
            .surface;
        assert_eq!(out, s);
    }
    // curves: wrong flag count, rational curve
    let c = nurbs_core::testing::random_curve(1, 3..=3, 12, false);
    assert!(fair_curve(&c, &[true; 2], 0.1, &CurveParams::default()).is_err());
    let r = nurbs_core::shapes::circle(1.0).unwrap();
    let free = vec![true; r.control_points().len()];
    assert!(fair_curve(&r, &free, 0.1, &CurveParams::default()).is_err());
}
