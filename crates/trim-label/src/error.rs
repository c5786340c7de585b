//! The error type of trim-label: bad input (mesh, segments, parameters) kept apart from
//! numerical failure (a singular parameterization or fit, which come from nurbs-core).

use thiserror::Error;

/// Everything that can go wrong while labeling or fitting a trimmed region.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LabelError {
    /// The mesh has no faces.
    #[error("the mesh has no faces")]
    EmptyMesh,
    /// A vertex coordinate that is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFiniteVertex {
        /// the vertex (0-based, OBJ order)
        vertex: usize,
    },
    /// A face naming a vertex that does not exist.
    #[error("face {face} names vertex {vertex}, but the mesh has {count} vertices")]
    FaceIndexOutOfRange {
        /// the face
        face: usize,
        /// the vertex index found
        vertex: usize,
        /// number of vertices
        count: usize,
    },
    /// A triangle with a repeated vertex or (almost) zero area.
    #[error("face {face} is degenerate: area {area:e} (threshold {threshold:e}, units length²)")]
    DegenerateTriangle {
        /// the face
        face: usize,
        /// its area
        area: f64,
        /// the area below which a face counts as degenerate
        threshold: f64,
    },
    /// An edge shared by more than two faces.
    #[error("mesh is not manifold: edge ({a}, {b}) is used by {faces} faces")]
    NonManifoldEdge {
        /// one end of the edge
        a: usize,
        /// the other end
        b: usize,
        /// how many faces use it
        faces: usize,
    },
    /// Two faces that traverse an edge in the same direction.
    #[error(
        "mesh is not orientable (or inconsistently oriented): edge ({a}, {b}) is traversed the same way by two faces"
    )]
    NonOrientable {
        /// start of the directed edge
        a: usize,
        /// end of the directed edge
        b: usize,
    },
    /// A vertex where two boundary loops touch (a "bow tie").
    #[error("mesh is not manifold at vertex {vertex}: {boundary_edges} boundary edges leave it")]
    NonManifoldVertex {
        /// the vertex
        vertex: usize,
        /// outgoing boundary edges found (1 expected)
        boundary_edges: usize,
    },
    /// A closed mesh: nothing to label.
    #[error("the mesh has no boundary: a trimmed region needs an outer boundary loop")]
    NoBoundary,
    /// The faces form several pieces.
    #[error("the mesh has {components} connected pieces; a region must be one piece")]
    Disconnected {
        /// number of face-connected components
        components: usize,
    },
    /// A given segment with fewer than two vertices.
    #[error("segment {segment} has {count} vertices; a segment needs at least 2")]
    SegmentTooShort {
        /// the segment (input order)
        segment: usize,
        /// its vertex count
        count: usize,
    },
    /// A given segment vertex that is not on the outer boundary loop.
    #[error("segment {segment}: vertex {vertex} is not on the outer boundary loop")]
    SegmentOffBoundary {
        /// the segment (input order)
        segment: usize,
        /// the vertex
        vertex: usize,
    },
    /// A given segment that does not follow the boundary loop edge by edge.
    #[error(
        "segment {segment}: vertices {from} → {to} are not consecutive along the boundary loop"
    )]
    SegmentNotContiguous {
        /// the segment (input order)
        segment: usize,
        /// a vertex of the segment
        from: usize,
        /// the vertex after it
        to: usize,
    },
    /// Segments that do not tile the outer loop exactly once.
    #[error("segments do not cover the outer boundary loop: {detail}")]
    SegmentsDoNotCoverLoop {
        /// what is wrong, with the numbers
        detail: String,
    },
    /// Segment JSON that cannot be read.
    #[error("segment JSON: {detail}")]
    SegmentFormat {
        /// the parser's message
        detail: String,
    },
    /// A parameter outside its documented range.
    #[error("parameter {name} = {value} is invalid: {expected}")]
    InvalidParameter {
        /// the field name
        name: &'static str,
        /// the value given
        value: f64,
        /// what is expected
        expected: &'static str,
    },
    /// The labeled parameterization came out degenerate.
    #[error("labeled parameterization failed: {detail}")]
    ParameterizationFailed {
        /// what went wrong, with the numbers
        detail: String,
    },
    /// The parameterization or the fit failed numerically (from the kernel).
    #[error(transparent)]
    Core(#[from] nurbs_core::Error),
}

/// Result alias.
pub type Result<T, E = LabelError> = std::result::Result<T, E>;
