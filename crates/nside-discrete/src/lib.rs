//! # nside-discrete
//!
//! The first stage of n-sided corner patches ([SV] §3.4): the corner is faired as one triangle
//! mesh by Kobbelt's discrete fairing ([K97]) before its quadrilaterals are refitted. This crate
//! holds the discrete fairing (umbrella² thin-plate energy, fixed boundary rings, one sparse
//! symmetric solve) and the mesh checks it needs, and the n-sided corner around it: the central
//! split of an n-sided hole into n bicubic quads ([`split`]), their sampling into one welded mesh
//! with the neighbours' wings ([`sampling`]), the refit with shared internal curves ([`refit`])
//! and the whole stage in one call ([`corner`]).

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
