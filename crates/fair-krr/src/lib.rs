//! # fair-krr
//!
//! Knot removal and reinsertion (KRR) fairing of B-spline curves and surfaces ([SV] §5.1;
//! [FS] for cubic curves, [HK] for general order and surfaces).
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
