//! Errors of the n-sided / discrete fairing crate.

use thiserror::Error;

/// What can go wrong.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NsideError {
    /// A mesh that is not a manifold region with boundary.
    #[error("mesh is not a manifold region: {detail}")]
    NotManifold {
        /// what is wrong, naming the edge or vertex
        detail: String,
    },
    /// A face that names a vertex that does not exist, or repeats one.
    #[error("face {face} is invalid: {detail}")]
    BadFace {
        /// face index
        face: usize,
        /// what is wrong
        detail: String,
    },
    /// A fixed-vertex index outside the mesh.
    #[error("fixed vertex index {index} is outside the mesh ({count} vertices)")]
    FixedIndex {
        /// the index
        index: usize,
        /// number of vertices
        count: usize,
    },
    /// A coordinate that is NaN or infinite.
    #[error("vertex {index} has a non-finite coordinate")]
    NonFinite {
        /// the vertex
        index: usize,
    },
    /// Nothing is fixed, so the thin-plate problem has no unique solution.
    #[error(
        "no vertex is fixed: fix the boundary or some rings so that the fairing problem is determined"
    )]
    NothingFixed,
    /// The kernel failed (e.g. a singular system).
    #[error(transparent)]
    Core(#[from] nurbs_core::Error),
}

/// Result alias.
pub type Result<T, E = NsideError> = std::result::Result<T, E>;
