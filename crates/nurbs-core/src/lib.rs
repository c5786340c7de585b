//! # nurbs-core
//!
//! The B-spline/NURBS kernel of hier-fair: knot vectors, basis functions (\[NB\] A2.2/A2.3), curves
//! and surfaces (polynomial and rational) with derivatives, differential geometry, knot
//! insertion/removal, degree elevation, extraction and isocurves, Gram integrals, projection,
//! least-squares fitting with control masks, the frames of \[SV\] §3.1, the [`SurfaceFairing`] trait
//! and a small triangle mesh. References (keys in brackets) are listed in `docs/references.md`.
//!
//! ```
//! use nurbs_core::shapes::sphere_octant;
//! // an exact rational sphere octant of radius 2: every point at distance 2 from the centre,
//! // both principal curvatures of magnitude 1/2
//! let s = sphere_octant(2.0).unwrap();
//! let (u, v) = (0.3, 0.7);
//! assert!((s.point(u, v).coords.norm() - 2.0).abs() < 1e-12);
//! let k = s.derivatives(u, v).curvature_values().unwrap();
//! assert!((k.k1.abs() - 0.5).abs() < 1e-9 && (k.k2.abs() - 0.5).abs() < 1e-9);
//! // knot insertion is exact: the surface does not move
//! let finer = s.refine(nurbs_core::Direction::U, &[0.5]).unwrap();
//! assert!((finer.point(u, v) - s.point(u, v)).norm() < 1e-12);
//! ```
//!
//! A surface from your own control points: a biquadratic Bézier patch (no interior knots) over
//! a 3 × 3 net, the net flat with i over u; its corners are its corner control points.
//!
//! ```
//! use nurbs_core::{BSplineSurface, KnotVector, Point3};
//! let net: Vec<Point3> = (0..3)
//!     .flat_map(|i| (0..3).map(move |j| (i, j)))
//!     .map(|(i, j)| Point3::new(i as f64, j as f64, if (i, j) == (1, 1) { 1.0 } else { 0.0 }))
//!     .collect();
//! let bezier = KnotVector::bezier(2).unwrap();
//! let s = BSplineSurface::new(bezier.clone(), bezier, net, None).unwrap();
//! assert_eq!(s.point(1.0, 0.0), Point3::new(2.0, 0.0, 0.0));
//! // the raised middle point lifts the centre by a quarter of its height (B₁²(½)² = ¼)
//! assert!((s.point(0.5, 0.5).z - 0.25).abs() < 1e-15);
//! ```
//!
//! The same surface read from the JSON format of `docs/model-format.md` (feature `serde`, on by
//! default): knot vectors left out make a Bézier patch.
//!
//! ```
//! # #[cfg(feature = "serde")] {
//! let json = r#"{"degree_u": 2, "degree_v": 2, "control_points": [
//!     [[0, 0, 0], [0, 1, 0], [0, 2, 0]],
//!     [[1, 0, 0], [1, 1, 1], [1, 2, 0]],
//!     [[2, 0, 0], [2, 1, 0], [2, 2, 0]]]}"#;
//! let s = &nurbs_core::io::surfaces_from_json(json).unwrap()[0];
//! assert!((s.point(0.5, 0.5).z - 0.25).abs() < 1e-15);
//! // and written back
//! assert!(nurbs_core::io::surface_to_json(s).contains("degree_u"));
//! # }
//! ```
//!
//! Conventions: control nets are flat, `P[i * n_v + j]`, i over u; parameters outside the domain
//! are clamped by evaluators; normals are S_u × S_v normalized and curvatures are signed with
//! respect to them.

pub mod banded;
pub mod basis;
pub mod creases;
pub mod curve;
pub mod diffgeom;
pub mod energy;
pub mod error;
pub mod fairing;
pub mod fairness;
pub mod fit;
pub mod frames;
pub mod gram;
pub mod grid;
pub mod grid_curvature;
pub mod homogeneous;
#[cfg(feature = "serde")]
pub mod io;
pub mod knot_ops;
pub mod knots;
pub mod max_tree;
pub mod mesh;
pub mod ops;
pub mod projection;
pub mod quadrature;
pub mod shapes;
pub mod sparse;
pub mod surface;
pub mod surface_basis;
#[cfg(feature = "testing")]
pub mod testing;

/// A point in 3D (f64).
pub type Point3 = nalgebra::Point3<f64>;
/// A vector in 3D (f64).
pub type Vector3 = nalgebra::Vector3<f64>;

/// Largest absolute coordinate the readers accept (model units; JSON surfaces and OBJ
/// meshes): 10⁹ mm is a thousand kilometres. Beyond it squared distances, energies (second
/// derivatives squared) and their sums leave the range where tolerances of 10⁻³ keep digits.
pub const MAX_COORDINATE: f64 = 1e9;

pub use banded::BandedQr;
pub use basis::BasisEvaluator;
pub use curve::{BSplineCurve, CurveDerivatives};
pub use diffgeom::{CurvatureValues, FundamentalForms, PrincipalCurvatures};
pub use error::{Error, Result};
pub use fairing::{
    Faired, FairingProblem, FairingReport, SurfaceFairing, check_contract, max_displacement,
};
pub use fairness::{Fairness, FairnessParams, fairness};
pub use fit::{FitParams, FitReport, fit_curve, fit_surface};
pub use frames::{Continuity, ControlMask, Frame, PerSide, Side};
pub use gram::{BandedMatrix, ThinPlateGram, gram_matrix};
pub use grid::GridOrder;
pub use grid_curvature::GridCurvature;
pub use knots::KnotVector;
pub use mesh::TriMesh;
pub use ops::Direction;
pub use projection::{
    CurveProjection, ProjectionParams, SurfaceProjection, SurfaceProjector, project_to_curve,
    project_to_surface, project_to_surface_from,
};
pub use surface::{BSplineSurface, SurfaceDerivatives, SurfaceEvaluator};
pub use surface_basis::{SurfaceBasis, SurfaceBasisEvaluator};
