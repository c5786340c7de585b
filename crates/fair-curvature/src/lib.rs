//! # fair-curvature
//!
//! Two curvature-driven fairing methods of \[SV\] §5 as [`nurbs_core::SurfaceFairing`]
//! implementations that move only the control points a [`nurbs_core::ControlMask`] frees
//! (fixed frames come back bit-identical) and stay within the deviation tolerance:
//!
//! ```
//! use fair_curvature::TargetCurvatureFairing;
//! use nurbs_core::{BSplineSurface, ControlMask, FairingProblem, KnotVector, Point3};
//! // a bicubic 8 × 8 net with a zig-zag of ±0.02 on a plane, faired through the checked
//! // runner (fixed points bit-identical, every move within ε)
//! let k = KnotVector::clamped_uniform(3, 8).unwrap();
//! let bump = |i: usize, j: usize| if (i + j) % 2 == 0 { 0.02 } else { -0.02 };
//! let pts = (0..64).map(|r| Point3::new((r / 8) as f64, (r % 8) as f64, bump(r / 8, r % 8)));
//! let s = BSplineSurface::new(k.clone(), k, pts.collect(), None).unwrap();
//! let mask = ControlMask::all_free(8, 8);
//! let problem = FairingProblem::new(&s, &mask, 0.05);
//! let (_faired, report) = problem.solve(&TargetCurvatureFairing::default()).unwrap();
//! assert!(report.energy_after < report.energy_before);
//! ```
//!
//! The same on a surface read from the JSON format of `docs/model-format.md` (a biquadratic
//! 4 × 4 patch whose four middle points are lifted unevenly), through nurbs-core's checked
//! runner (the `greiner` method):
//!
//! ```
//! use fair_curvature::GreinerFairing;
//! use nurbs_core::{ControlMask, FairingProblem, Frame};
//! let json = r#"{"degree_u": 2, "degree_v": 2,
//!     "knots_u": [0, 0, 0, 0.5, 1, 1, 1], "knots_v": [0, 0, 0, 0.5, 1, 1, 1],
//!     "control_points": [
//!       [[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 3, 0]],
//!       [[1, 0, 0], [1, 1, 0.3], [1, 2, -0.1], [1, 3, 0]],
//!       [[2, 0, 0], [2, 1, -0.2], [2, 2, 0.25], [2, 3, 0]],
//!       [[3, 0, 0], [3, 1, 0], [3, 2, 0], [3, 3, 0]]]}"#;
//! let s = &nurbs_core::io::surfaces_from_json(json).unwrap()[0];
//! let mask = ControlMask::with_boundary_frame(s, Frame::Positional);
//! let (faired, report) = FairingProblem::new(s, &mask, 0.1).solve(&GreinerFairing::default()).unwrap();
//! assert!(report.energy_after < report.energy_before);
//! assert_eq!(faired.control_points()[0], s.control_points()[0]); // the boundary stays
//! ```
//!
//! - [`TargetCurvatureFairing`] (`curvature`, \[SV\] §5.2 after \[SSV08\]): the curvature of the
//!   isocurves of a sample grid is smoothed ([`polyline`]), the samples follow it in one
//!   least-squares integration from both ends with a soft pull towards the original
//!   (`integrate`), and the surface is refitted by constrained least squares ([`target`]);
//!   curves by [`fair_curve`] ([`curve`]).
//! - [`GreinerFairing`] (`greiner`, \[SV\] §5.3 after \[G96\]): the Hessian of the faired
//!   surface's coordinates on the original as reference surface is linear in the control points
//!   ([`hessian`]); it is fitted to smoothed curvature targets in sparse least squares
//!   ([`greiner`]), independent of the parametric directions.
//!
//! Both handle rational surfaces with their weights held fixed (then S is still linear in the
//! control points). References (keys in brackets) are listed in `docs/references.md`.

mod coupled;
pub mod curve;
pub mod error;
pub mod greiner;
pub mod hessian;
mod integrate;
mod normal;
pub mod polyline;
pub mod quadric;
pub mod sampling;
pub mod smooth;
pub mod target;

pub use curve::{CurveParams, CurveReport, arc_length_params, fair_curve};
pub use error::{CurvatureError, Result};
pub use greiner::{
    DEFAULT_HALF_WINDOW_SPANS, GREINER_METHOD, GreinerFairing, GreinerParams, GreinerReport,
    GreinerTarget, TargetSmoothing, fair_surface_greiner,
};
pub use normal::SCALE_MARGIN;
pub use polyline::{EndCurvature, PolylineParams, fair_polyline};
pub use sampling::Sampling;
pub use target::{
    TARGET_METHOD, TargetCurvatureFairing, TargetCurvatureParams, TargetCurvatureReport,
    fair_surface_target,
};
