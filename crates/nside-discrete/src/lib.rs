//! # nside-discrete
//!
//! The first stage of n-sided corner patches (\[SV\] §3.4): the corner is faired as one triangle
//! mesh by Kobbelt's discrete fairing (\[K97\]) before its quadrilaterals are refitted. This crate
//! holds the discrete fairing (umbrella² thin-plate energy, fixed boundary rings, one sparse
//! symmetric solve) and the mesh checks it needs, and the n-sided corner around it: the central
//! split of an n-sided hole into n bicubic quads ([`split`]), their sampling into one welded mesh
//! with the neighbours' wings ([`sampling`]), the refit with shared internal curves ([`refit`])
//! and the whole stage in one call ([`corner`]).
//!
//! ```
//! use nside_discrete::{CentralSplitParams, central_split};
//! use nurbs_core::{BSplineCurve, KnotVector, Point3};
//! // a three-sided hole bounded by cubic Bézier curves (a curved triangle, one closed loop)
//! let corners = [Point3::new(0.0, 0.0, 0.0), Point3::new(4.0, 0.0, 0.0), Point3::new(2.0, 3.5, 0.0)];
//! let side = |a: Point3, b: Point3| {
//!     let lift = |t: f64| a + (b - a) * t + nurbs_core::Vector3::z() * 0.5;
//!     BSplineCurve::new(KnotVector::bezier(3).unwrap(), vec![a, lift(1.0 / 3.0), lift(2.0 / 3.0), b], None)
//!         .unwrap()
//! };
//! let sides = [side(corners[0], corners[1]), side(corners[1], corners[2]), side(corners[2], corners[0])];
//! // the central split ([SV] §3.4): one quad per side, meeting at a centre point
//! let (quads, report) = central_split(&sides, None, &CentralSplitParams::default()).unwrap();
//! assert_eq!(quads.len(), 3);
//! assert!(report.closure_gap < 1e-12);
//! ```
//!
//! A neighbour surface from your own control points: a square hole in the plane z = 0 whose
//! first side borders a flat bilinear strip (a 2 × 2 net, i over u, its side v = 0 on the hole's
//! side); the whole stage in one call keeps the filling in the plane and tangent to the strip.
//!
//! ```
//! use nside_discrete::{Neighbour, NsidedParams, fill_corner};
//! use nurbs_core::{BSplineCurve, BSplineSurface, KnotVector, Point3, Side};
//! let c = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]].map(|[x, y]| Point3::new(x, y, 0.0));
//! // the sides: straight cubic Bézier curves, counter-clockwise around the hole
//! let side = |a: Point3, b: Point3| {
//!     let pts = (0..4).map(|i| a + (b - a) * (i as f64 / 3.0)).collect();
//!     BSplineCurve::new(KnotVector::bezier(3).unwrap(), pts, None).unwrap()
//! };
//! let sides: Vec<_> = (0..4).map(|k| side(c[k], c[(k + 1) % 4])).collect();
//! // the strip below the first side (y ∈ [−0.3, 0]): P(0,0), P(0,1), P(1,0), P(1,1)
//! let out = nurbs_core::Vector3::new(0.0, -0.3, 0.0);
//! let bilinear = KnotVector::bezier(1).unwrap();
//! let strip = BSplineSurface::new(bilinear.clone(), bilinear, vec![c[0], c[0] + out, c[1], c[1] + out], None)
//!     .unwrap();
//! let neighbours = [Some(Neighbour { surface: &strip, side: Side::V0 }), None, None, None];
//! let (quads, report) = fill_corner(&sides, &neighbours, &NsidedParams::default()).unwrap();
//! assert_eq!(quads.len(), 4);
//! assert!(quads.iter().flat_map(|q| q.control_points()).all(|p| p.z.abs() < 1e-9));
//! assert!(report.refit.max_boundary_angle_deg.unwrap() < 1e-6);
//! ```
//!
//! The same strip read from the JSON format of `docs/model-format.md` (knot vectors left out
//! make a Bézier patch), here tilted: z = 0.5·y, and the hole's sides on that plane.
//!
//! ```
//! use nside_discrete::{Neighbour, NsidedParams, fill_corner};
//! use nurbs_core::{BSplineCurve, KnotVector, Point3, Side};
//! let json = r#"{"degree_u": 1, "degree_v": 1,
//!     "control_points": [[[0, 0, 0], [0, -0.3, -0.15]], [[1, 0, 0], [1, -0.3, -0.15]]]}"#;
//! let strip = &nurbs_core::io::surfaces_from_json(json).unwrap()[0];
//! let c = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]].map(|[x, y]| Point3::new(x, y, 0.5 * y));
//! let side = |a: Point3, b: Point3| {
//!     let pts = (0..4).map(|i| a + (b - a) * (i as f64 / 3.0)).collect();
//!     BSplineCurve::new(KnotVector::bezier(3).unwrap(), pts, None).unwrap()
//! };
//! let sides: Vec<_> = (0..4).map(|k| side(c[k], c[(k + 1) % 4])).collect();
//! let neighbours = [Some(Neighbour { surface: strip, side: Side::V0 }), None, None, None];
//! let (quads, report) = fill_corner(&sides, &neighbours, &NsidedParams::default()).unwrap();
//! // every control point of the filling on the plane z = 0.5·y, tangent to the strip
//! assert!(quads.iter().flat_map(|q| q.control_points()).all(|p| (p.z - 0.5 * p.y).abs() < 1e-9));
//! assert!(report.refit.max_boundary_angle_deg.unwrap() < 1e-6);
//! ```

pub mod corner;
pub mod error;
pub mod fairing;
pub mod refit;
pub mod sampling;
pub mod split;
pub mod topology;

pub use corner::{NsidedParams, NsidedReport, cross_tangents, fair_corner, fill_corner};
pub use error::NsideError;
pub use fairing::{
    DiscreteFairingParams, DiscreteFairingReport, UmbrellaWeights, fair_mesh,
    fair_mesh_with_layout, fair_mesh_within,
};
pub use refit::{RefitReport, boundary_angle_deg, internal_angle_deg, refit_quads};
pub use sampling::{
    Neighbour, QuadGrid, SampledCorner, SamplingParams, VertexOrigin, check_quads, sample_quads,
};
pub use split::{CentralSplitParams, CentralSplitReport, central_split};
pub use topology::{MeshTopology, ring_distance};
