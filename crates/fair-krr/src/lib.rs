//! # fair-krr
//!
//! Knot removal and reinsertion (KRR) fairing of B-spline curves and surfaces ([SV] §5.1;
//! [FS] for cubic curves, [HK] for general order and surfaces).
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
