//! The error type of nurbs-core: bad input kept apart from numerical failure.

use thiserror::Error;

/// Everything that can go wrong in the kernel.
///
/// Input errors (`Invalid…`, `…Mismatch`, `NonFinite…`) name the offending value; numerical
/// failures (`SingularSystem`, `RemovalFailed`, …) say what could not be solved.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Error {
    /// A degree below 1 (or above what an operation supports).
    #[error("degree must be at least 1, got {degree}")]
    InvalidDegree {
        /// the degree given
        degree: usize,
    },
    /// A knot that is NaN or infinite.
    #[error("knot {index} is not finite ({value})")]
    NonFiniteKnot {
        /// position in the knot vector
        index: usize,
        /// the value found
        value: f64,
    },
    /// Knots that decrease.
    #[error("knots decrease at index {index}: {previous} > {value}")]
    DecreasingKnots {
        /// position of the smaller knot
        index: usize,
        /// the knot before it
        previous: f64,
        /// the knot at `index`
        value: f64,
    },
    /// Fewer knots than the degree needs.
    #[error("{len} knots are too few for degree {degree} (at least {min} needed)")]
    TooFewKnots {
        /// number of knots given
        len: usize,
        /// the degree
        degree: usize,
        /// the minimum, 2·(degree + 1)
        min: usize,
    },
    /// The parameter domain `[t_p, t_{n+1}]` has zero length.
    #[error("the parameter domain [{start}, {end}] is empty")]
    EmptyDomain {
        /// t_p
        start: f64,
        /// t_{n+1}
        end: f64,
    },
    /// A knot repeated more often than the degree allows.
    #[error(
        "knot {value} has multiplicity {multiplicity}, more than {max} allowed for degree {degree}"
    )]
    KnotMultiplicity {
        /// the knot value
        value: f64,
        /// how often it occurs
        multiplicity: usize,
        /// the largest multiplicity allowed there
        max: usize,
        /// the degree
        degree: usize,
    },
    /// Knot count does not match degree and number of control points.
    #[error(
        "{direction} knot vector has {len} knots, but degree {degree} with {count} control points needs {expected}"
    )]
    KnotCountMismatch {
        /// "u", "v" or "curve"
        direction: &'static str,
        /// number of knots given
        len: usize,
        /// the degree
        degree: usize,
        /// number of control points in that direction
        count: usize,
        /// count + degree + 1
        expected: usize,
    },
    /// Control net whose size is not nu × nv, or a ragged row.
    #[error("control net shape: {detail}")]
    ControlNetShape {
        /// what is wrong, with the numbers
        detail: String,
    },
    /// A control point coordinate that is NaN or infinite.
    #[error("control point [{i}][{j}] is not finite")]
    NonFiniteControlPoint {
        /// u index (or curve index)
        i: usize,
        /// v index (0 for curves)
        j: usize,
    },
    /// A weight that is not finite or not positive.
    #[error("weight [{i}][{j}] is {value}; weights must be finite and > 0")]
    InvalidWeight {
        /// u index (or curve index)
        i: usize,
        /// v index (0 for curves)
        j: usize,
        /// the weight found
        value: f64,
    },
    /// A value of an input beyond a documented bound of the readers (see [`crate::io`]).
    #[error("{what} is {value:e}, beyond the bound of {bound:e}")]
    BeyondBound {
        /// what was measured, with its place
        what: String,
        /// the value found
        value: f64,
        /// the bound
        bound: f64,
    },
    /// A parameter that is not finite or lies outside the domain.
    #[error("parameter {value} is outside the domain [{start}, {end}]")]
    ParameterOutOfDomain {
        /// the parameter
        value: f64,
        /// domain start
        start: f64,
        /// domain end
        end: f64,
    },
    /// A knot operation asked for more than the knot vector allows.
    #[error(
        "cannot insert knot {value} {times} time(s): multiplicity {multiplicity} would exceed degree {degree}"
    )]
    InsertionOverflow {
        /// the knot
        value: f64,
        /// requested insertions
        times: usize,
        /// present multiplicity
        multiplicity: usize,
        /// the degree
        degree: usize,
    },
    /// An operation that needs clamped knot vectors got an unclamped one.
    #[error("{operation} needs a clamped knot vector")]
    NotClamped {
        /// the operation
        operation: &'static str,
    },
    /// An operation that is defined for polynomial (non-rational) geometry only.
    #[error("{operation} needs a polynomial (non-rational) surface or curve")]
    RationalNotSupported {
        /// the operation
        operation: &'static str,
    },
    /// Lengths of parallel inputs differ.
    #[error("{what}: {left} vs {right} entries")]
    LengthMismatch {
        /// which inputs
        what: &'static str,
        /// first length
        left: usize,
        /// second length
        right: usize,
    },
    /// A row of a banded system that does not fit its window.
    #[error(
        "banded row at column {start} with {len} values exceeds the width {width} or the {unknowns} unknowns"
    )]
    BandOverflow {
        /// first column of the row
        start: usize,
        /// number of values
        len: usize,
        /// the system's band width
        width: usize,
        /// the system's number of unknowns
        unknowns: usize,
    },
    /// A linear system without a unique solution.
    #[error("singular system: {reason}")]
    SingularSystem {
        /// why, e.g. which control point has no data
        reason: String,
    },
    /// Exact knot removal that should succeed failed numerically.
    #[error("removing knot {value} failed: deviation above tolerance {tolerance}")]
    RemovalFailed {
        /// the knot
        value: f64,
        /// the tolerance used
        tolerance: f64,
    },
    /// A fairing method failed.
    #[error("fairing method {method} failed: {message}")]
    FairingFailed {
        /// the method's name
        method: String,
        /// what went wrong
        message: String,
    },
    /// A fairing method returned a result that breaks the contract of
    /// [`crate::SurfaceFairing`] (a fixed control point moved, a point beyond the tolerance,
    /// another net or other weights).
    #[error("fairing method {method} broke its contract: {detail}")]
    ContractBroken {
        /// the method's name
        method: String,
        /// the first violation found
        detail: String,
    },
    /// An error with the place it happened (a surface, a field).
    #[error("{context}: {source}")]
    Context {
        /// where, e.g. "surface 2 (knots_u)"
        context: String,
        /// the error
        source: Box<Error>,
    },
    /// Malformed input data (a file format).
    #[error("{detail}")]
    Format {
        /// what is wrong, naming the field
        detail: String,
    },
    /// Degenerate input geometry (zero-size domain, collapsed data).
    #[error("degenerate geometry: {detail}")]
    Degenerate {
        /// what is degenerate
        detail: String,
    },
}

impl Error {
    /// Wraps the error with the place it happened.
    pub fn context(self, context: impl Into<String>) -> Self {
        Error::Context {
            context: context.into(),
            source: Box::new(self),
        }
    }
}

/// Result alias of the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;
