//! # fair-energy
//!
//! Hadenfeld's local energy fairing of B-spline curves and surfaces (\[H\]), frame-preserving
//! (\[SV\] §3.1, §5.2), and a global variant that solves for all free points at once.
//!
//! ```
//! use fair_energy::{EnergyParams, fair_surface};
//! use nurbs_core::{BSplineSurface, ControlMask, KnotVector, Point3};
//! // a bicubic 8 × 8 net on the plane z = 0 with a zig-zag of ±0.05 inside its boundary ring,
//! // which is kept; x and y at the Greville abscissae, so that (u, v) ↦ (x, y) is linear
//! let k = KnotVector::clamped_uniform(3, 8).unwrap();
//! let g: Vec<f64> = (0..8).map(|i| 7.0 * k.knots()[i + 1..i + 4].iter().sum::<f64>() / 3.0).collect();
//! let inside = |i: usize, j: usize| (1..7).contains(&i) && (1..7).contains(&j);
//! let bump = |i, j| if !inside(i, j) { 0.0 } else if (i + j) % 2 == 0 { 0.05 } else { -0.05 };
//! let pts = (0..64).map(|r| Point3::new(g[r / 8], g[r % 8], bump(r / 8, r % 8)));
//! let s = BSplineSurface::new(k.clone(), k, pts.collect(), None).unwrap();
//! let mut mask = ControlMask::all_free(8, 8);
//! for t in 0..8 {
//!     for (i, j) in [(0, t), (7, t), (t, 0), (t, 7)] {
//!         mask.set_free(i, j, false);
//!     }
//! }
//! let (faired, report) = fair_surface(&s, &mask, 0.1, &EnergyParams::default()).unwrap();
//! nurbs_core::check_contract("energy", &s, &faired, &mask, 0.1).unwrap();
//! // closed form: the flat net has zero thin-plate energy (the map is linear) and lies inside
//! // every ε-ball, so it is the minimum — the zig-zag is gone, not just reduced
//! assert!(report.energy_after < 1e-6 * report.energy_before);
//! assert!(faired.control_points().iter().all(|p| p.z.abs() < 1e-5));
//! ```
//!
//! The same on a surface read from the JSON format of `docs/model-format.md` (a biquadratic
//! 4 × 4 patch whose four middle points are lifted unevenly), through nurbs-core's checked
//! runner (the `energy` method):
//!
//! ```
//! use fair_energy::LocalEnergyFairing;
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
//! let (faired, report) = FairingProblem::new(s, &mask, 0.1).solve(&LocalEnergyFairing::default()).unwrap();
//! assert!(report.energy_after < report.energy_before);
//! assert_eq!(faired.control_points()[0], s.control_points()[0]); // the boundary stays
//! ```
//!
//! The functional is the linearized thin-plate energy Π = ∬ |X_uu|² + 2|X_uv|² + |X_vv|² du dv
//! (curves ∫ |x''|² + β |x'''|²), a quadratic form in the control points built from nurbs-core's
//! Gram integrals ([`stiffness`]). The local scheme ([`local`]) repeatedly moves the free control
//! point with the largest energy decrease to its optimal position, clamped to a ball of radius ε
//! around its original. [`global`] minimizes Π + w Σ |d − d_orig|² over all free points with a
//! sparse Cholesky factorization, holds the points that left their ε-balls on the balls and
//! solves the others again (active-set rounds, [`ACTIVE_SET_ROUNDS`]).
//!
//! Rational surfaces: the local scheme and the global variant take them with their weights held
//! fixed — the thin plate is then a quadratic form through the rational basis functions
//! ([`rational`], [`RationalStiffness`]). The Bézier-spline flow and curve fairing need
//! polynomial input and return [`EnergyError::Rational`] otherwise.
//!
//! Bézier-spline surfaces (interior knots of full multiplicity, \[H\] part ②): [`bezier`] runs the
//! seed's flow — remove the knots that are C¹ already, fair with the jump-weighted functional,
//! then project the joints to exact C¹ inside the ε-balls ([`C1_JUMP_REL`]) and optionally remove
//! those knots too.
//!
//! Entry points: [`fair_surface`], [`fair_curve`], [`fair_surface_global`],
//! [`fair_bezier_spline`] and the [`nurbs_core::SurfaceFairing`] methods [`LocalEnergyFairing`]
//! (`energy`), [`GlobalEnergyFairing`] (`energy-global`) and [`BezierSplineFairing`]
//! (`energy-bezier`).

pub mod error;
pub mod local;
pub mod rational;
pub mod stiffness;
pub mod surface;

pub use error::{EnergyError, Result};
pub use local::{LocalOutcome, StopReason};
pub use rational::RationalStiffness;
pub use stiffness::SeparableStiffness;
pub use surface::{
    EnergyParams, EnergyReport, LOCAL_METHOD, LocalEnergyFairing, LocalStart, fair_surface,
};
pub mod bezier;
pub mod c1_finish;
pub mod curve;
pub mod global;
pub mod joints;
mod ordering;
pub mod start;

pub use bezier::{
    BEZIER_METHOD, BezierSplineFairing, BezierSplineParams, BezierSplineReport, JointGap,
    KnotRemoval, fair_bezier_spline,
};
pub use joints::C1_JUMP_REL;

pub use curve::{CurveEnergyParams, fair_curve};
pub use global::{
    ACTIVE_SET_ROUNDS, GLOBAL_METHOD, GlobalEnergyFairing, GlobalParams, GlobalReport,
    SparseSolver, fair_surface_global,
};
