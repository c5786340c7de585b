//! # fair-krr
//!
//! Knot removal and reinsertion (KRR) fairing of B-spline curves and surfaces (\[SV\] §5.1;
//! \[FS\] for cubic curves, \[HK\] for general order and surfaces).
//!
//! ```
//! use fair_krr::{KrrParams, fair_surface};
//! use nurbs_core::{BSplineSurface, ControlMask, KnotVector, Point3};
//! // a bicubic 8 × 8 net on a plane with one control point lifted by 0.1: a jump of the third
//! // derivative at the knots around it, which knot removal and reinsertion takes out
//! let k = KnotVector::clamped_uniform(3, 8).unwrap();
//! let lift = |r: usize| if r == 3 * 8 + 4 { 0.1 } else { 0.0 };
//! let pts = (0..64).map(|r| Point3::new((r / 8) as f64, (r % 8) as f64, lift(r)));
//! let s = BSplineSurface::new(k.clone(), k, pts.collect(), None).unwrap();
//! let mask = ControlMask::all_free(8, 8);
//! let (faired, report) = fair_surface(&s, &mask, 0.2, &KrrParams::default()).unwrap();
//! assert!(report.max_jump_after < report.max_jump_before);
//! nurbs_core::check_contract("krr", &s, &faired, &mask, 0.2).unwrap();
//! ```
//!
//! The same on a surface read from the JSON format of `docs/model-format.md` (a biquadratic
//! 4 × 4 patch whose four middle points are lifted unevenly), through nurbs-core's checked
//! runner (the `krr` method):
//!
//! ```
//! use fair_krr::KrrFairing;
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
//! let (faired, report) = FairingProblem::new(s, &mask, 0.1).solve(&KrrFairing::default()).unwrap();
//! assert!(report.energy_after < report.energy_before);
//! assert_eq!(faired.control_points()[0], s.control_points()[0]); // the boundary stays
//! ```
//!
//! At a simple knot a degree-p B-spline is C^{p−1}; the jump of its p-th derivative (the third
//! for cubics) measures the local unfairness. KRR removes the knot and reinserts it, which in
//! closed form moves one control point so that the jump vanishes ([`jump`]). The most offending
//! knot is chosen first, a taboo list stops cycling, every move is clamped to the distance
//! tolerance ε around the original point, and only points a mask frees move.
//!
//! Entry points: [`fair_curve`], [`fair_surface`] and the [`nurbs_core::SurfaceFairing`] method
//! [`KrrFairing`] (`krr`).

pub mod curve;
pub mod error;
pub mod jump;
pub mod surface;

pub use curve::{KrrCurveParams, KrrReport, KrrSolve, KrrStop, fair_curve};
pub use error::{KrrError, Result};
pub use jump::{KnotJumps, cubic_closed_form};
pub use surface::{KRR_METHOD, KrrDirection, KrrFairing, KrrParams, fair_surface};
