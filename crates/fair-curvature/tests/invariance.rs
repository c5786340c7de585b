//! Greiner fairing does not depend on the parametric directions: swapping the roles of u and v
//! gives the same faired surface up to rounding.

mod common;

use common::*;
use fair_curvature::{GreinerParams, GreinerTarget, Sampling, fair_surface_greiner};
use nurbs_core::{ControlMask, Frame};

#[test]
fn swapping_u_and_v_gives_the_same_surface() {
    // a non-square net with different knots per direction and a one-sided mask
    let base = nurbs_core::testing::random_surface(21, 3..=3, 11, false);
    for rational in [false, true] {
        let s = if rational {
            nurbs_core::testing::random_surface(22, 2..=3, 10, true)
        } else {
            base.clone()
        };
        let mut mask = ControlMask::for_surface(&s);
        mask.fix_frame(nurbs_core::Side::U0, Frame::Tangential);
        mask.fix_frame(nurbs_core::Side::V1, Frame::Positional);
        for target in [GreinerTarget::Hessian, GreinerTarget::MeanCurvature] {
            for sampling in [Sampling::PerSpan(3), Sampling::Uniform(17, 23)] {
                let params = GreinerParams {
                    target,
                    sampling,
                    ..GreinerParams::default()
                };
                let swapped_sampling = match sampling {
                    Sampling::Uniform(a, b) => Sampling::Uniform(b, a),
                    other => other,
                };
                let tol = 0.05 * s.size();
                let (a, ra) = fair_surface_greiner(&s, &mask, tol, &params).unwrap();
                let (b, _) = fair_surface_greiner(
                    &swap_uv(&s),
                    &swap_mask(&mask),
                    tol,
                    &GreinerParams {
                        sampling: swapped_sampling,
                        ..params
                    },
                )
                .unwrap();
                let back = swap_uv(&b);
                let diff = nurbs_core::max_displacement(a.control_points(), back.control_points());
                println!(
                    "rational {rational} {target:?} {sampling:?}: move {:.3e}, swap diff {diff:.2e}",
                    ra.max_control_move
                );
                assert!(ra.max_control_move > 1e-4 * s.size(), "nothing moved");
                assert!(diff <= 1e-9 * s.size(), "{diff:e}");
            }
        }
    }
}
