//! Acceptance: a noisy sphere patch (seeded noise 1 % of the radius) ends with the variance of its
//! mean curvature reduced ≥ 10× while staying within the tolerance.

mod common;

use common::*;
use fair_curvature::{GreinerFairing, GreinerParams, GreinerTarget, TargetCurvatureFairing};
use nurbs_core::{ControlMask, Frame, SurfaceFairing};

const RADIUS: f64 = 10.0;
const NOISE: f64 = 0.01 * RADIUS;
const TOLERANCE: f64 = 2.0 * NOISE;

fn check(method: &dyn SurfaceFairing, frame: Option<Frame>) -> f64 {
    let exact = sphere(RADIUS, 8);
    let mask = match frame {
        Some(f) => ControlMask::with_boundary_frame(&exact, f),
        None => ControlMask::for_surface(&exact),
    };
    let noisy_surface = noisy(&exact, &mask, NOISE, 7);
    let grid = inner_grid(&exact, 25, 0.02);
    let before = variance(&mean_curvatures(&noisy_surface, &grid));
    let (faired, report) = run(method, &noisy_surface, &mask, TOLERANCE);
    let after = variance(&mean_curvatures(&faired, &grid));
    let reduction = before / after;
    println!(
        "{} {frame:?}: var H {before:.3e} -> {after:.3e} ({reduction:.1}x), deviation {:.4}, move {:.4}",
        method.name(),
        report.max_deviation,
        report.max_control_move
    );
    assert_contract(&noisy_surface, &faired, &mask, TOLERANCE);
    assert!(report.max_deviation <= TOLERANCE);
    reduction
}

#[test]
fn greiner_hessian_reduces_mean_curvature_variance_tenfold() {
    let m = GreinerFairing::default();
    assert_eq!(m.params.target, GreinerTarget::Hessian);
    for frame in [None, Some(Frame::Tangential)] {
        assert!(check(&m, frame) >= 10.0);
    }
}

#[test]
fn greiner_mean_curvature_reduces_mean_curvature_variance_tenfold() {
    let m = GreinerFairing {
        params: GreinerParams {
            target: GreinerTarget::MeanCurvature,
            ..GreinerParams::default()
        },
    };
    for frame in [None, Some(Frame::Tangential)] {
        assert!(check(&m, frame) >= 10.0);
    }
}

#[test]
fn target_curvature_reduces_mean_curvature_variance_tenfold() {
    let m = TargetCurvatureFairing::default();
    for frame in [None, Some(Frame::Tangential)] {
        assert!(check(&m, frame) >= 10.0);
    }
}
