//! # nside-discrete
//!
//! The first stage of n-sided corner patches ([SV] §3.4): the corner is faired as one triangle
//! mesh by Kobbelt's discrete fairing ([K97]) before its quadrilaterals are refitted. This crate
//! holds the discrete fairing (umbrella² thin-plate energy, fixed boundary rings, one sparse
//! symmetric solve) and the mesh checks it needs.

pub mod error;
pub mod fairing;
pub mod split;
pub mod topology;

pub use error::NsideError;
pub use fairing::{DiscreteFairingParams, DiscreteFairingReport, fair_mesh};
pub use split::{CentralSplitParams, CentralSplitReport, central_split};
pub use topology::{MeshTopology, ring_distance};
