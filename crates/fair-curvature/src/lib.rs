//! # fair-curvature
//!
//! Two curvature-driven fairing methods of [SV] §5 as [`nurbs_core::SurfaceFairing`]
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
//! - [`TargetCurvatureFairing`] (`curvature`, [SV] §5.2 after [SSV08]): the curvature of the
//!   isocurves of a sample grid is smoothed ([`polyline`]), the samples follow it in one
//!   least-squares integration from both ends with a soft pull towards the original
//!   (`integrate`), and the surface is refitted by constrained least squares ([`target`]);
//!   curves by [`fair_curve`] ([`curve`]).
//! - [`GreinerFairing`] (`greiner`, [SV] §5.3 after [G96]): the Hessian of the faired
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
