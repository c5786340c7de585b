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
