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
    /// Fewer boundary curves than an n-sided patch needs, or more than it supports.
    #[error("an n-sided patch needs {min}…{max} boundary curves, got {count}")]
    SideCount {
        /// curves given
        count: usize,
        /// fewest supported (3)
        min: usize,
        /// most supported (8)
        max: usize,
    },
    /// Consecutive boundary curves that do not meet end-to-start.
    #[error(
        "boundary curve {curve} ends {gap} away from the start of curve {next} (tolerance {tolerance})"
    )]
    OpenLoop {
        /// the curve whose end is off
        curve: usize,
        /// the curve that should start there
        next: usize,
        /// distance between the end and the start (model units)
        gap: f64,
        /// the closure tolerance (model units)
        tolerance: f64,
    },
    /// A boundary curve the bicubic quads cannot hold exactly.
    #[error("boundary curve {curve} is unsupported: {detail}")]
    UnsupportedCurve {
        /// the curve
        curve: usize,
        /// why (rational, degree above 3, …)
        detail: String,
    },
    /// The boundary loop crosses itself (checked on a polygon in its best-fit plane).
    #[error(
        "the boundary loop intersects itself: curve {curve_a} crosses curve {curve_b} near parameters {t_a} and {t_b}"
    )]
    SelfIntersecting {
        /// first curve
        curve_a: usize,
        /// its parameter near the crossing
        t_a: f64,
        /// second curve
        curve_b: usize,
        /// its parameter near the crossing
        t_b: f64,
    },
    /// A boundary loop that encloses no area (all on a line or a point).
    #[error("the boundary loop is degenerate: enclosed area {area} (size {size})")]
    DegenerateLoop {
        /// area of the loop's polygon in its best-fit plane
        area: f64,
        /// size of the loop (bounding-box diagonal)
        size: f64,
    },
    /// Per-side data (neighbours, quads) whose count does not match the number of sides.
    #[error("{what}: expected {expected}, got {got}")]
    CountMismatch {
        /// which list
        what: &'static str,
        /// number of sides / quads
        expected: usize,
        /// length given
        got: usize,
    },
    /// Quads that do not form a central split (shapes, shared rows or corners disagree).
    #[error("quad {quad} does not fit the central split: {detail}")]
    BadQuad {
        /// the quad
        quad: usize,
        /// what is wrong
        detail: String,
    },
    /// A parameter setting outside its range.
    #[error("parameter {name} = {value} is out of range: {detail}")]
    BadParam {
        /// the field
        name: &'static str,
        /// its value
        value: f64,
        /// the allowed range
        detail: &'static str,
    },
    /// The kernel failed (e.g. a singular system).
    #[error(transparent)]
    Core(#[from] nurbs_core::Error),
}

/// Result alias.
pub type Result<T, E = NsideError> = std::result::Result<T, E>;
