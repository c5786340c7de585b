//! Acceptance: on a noisy hyperbolic paraboloid the Greiner method has no stripe artifacts —
//! the spread of |K − K_exact| after fairing is at most half that of target-curvature fairing.

mod common;

use common::*;
use fair_curvature::{GreinerFairing, GreinerParams, GreinerTarget, TargetCurvatureFairing};
use nurbs_core::{BSplineSurface, ControlMask, Frame, SurfaceFairing};

/// Standard deviation of |K − K_exact| over an inner grid (K_exact at the faired point's x, y).
fn spread(s: &BSplineSurface) -> f64 {
    let mut e = s.evaluator();
    let errs: Vec<f64> = inner_grid(s, 30, 0.05)
        .iter()
        .map(|&(u, v)| {
            let d = e.derivatives(u, v);
            let k = d.gaussian_curvature().expect("regular");
            (k - saddle_gauss(d.point.x, d.point.y)).abs()
        })
        .collect();
    variance(&errs).sqrt()
}

fn faired_spread(method: &dyn SurfaceFairing) -> (f64, f64) {
    let exact = saddle(12);
    let mask = ControlMask::with_boundary_frame(&exact, Frame::Tangential);
    let noise = 0.005 * exact.size();
    let s = noisy(&exact, &mask, noise, 11);
    let (out, report) = run(method, &s, &mask, 3.0 * noise);
    assert!(report.max_deviation <= 3.0 * noise);
    (spread(&s), spread(&out))
}

#[test]
#[ignore = "open (issue 5): target curvature 0.1025; Greiner (normal rows) Hessian 0.0898, MeanCurvature 0.0734 — needs ≤ 0.051; the smoothed targets and the noisy reference (normals, Christoffel terms) set the floor"]
fn greiner_spread_is_at_most_half_of_target_curvature() {
    let (noisy_spread, target) = faired_spread(&TargetCurvatureFairing::default());
    for g in [GreinerTarget::Hessian, GreinerTarget::MeanCurvature] {
        let method = GreinerFairing {
            params: GreinerParams {
                target: g,
                ..GreinerParams::default()
            },
        };
        let (_, greiner) = faired_spread(&method);
        println!(
            "noisy {noisy_spread:.4}, target curvature {target:.4}, greiner {g:?} {greiner:.4}"
        );
        assert!(greiner <= 0.5 * target, "{g:?}: {greiner} vs {target}");
    }
}

/// The normal rows (default) do not tie the faired surface to the noisy reference's
/// parametrization: on the saddle they beat the three coordinate rows of each Hessian entry.
#[test]
fn normal_rows_beat_coordinate_rows_on_the_saddle() {
    let spread_of = |normal_rows: bool| {
        faired_spread(&GreinerFairing {
            params: GreinerParams {
                normal_rows,
                ..GreinerParams::default()
            },
        })
        .1
    };
    let (normal, full) = (spread_of(true), spread_of(false));
    println!("normal rows {normal:.4}, coordinate rows {full:.4}");
    assert!(normal < 0.9 * full, "{normal} vs {full}");
}
