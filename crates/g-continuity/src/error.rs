//! The error type of g-continuity: bad input kept apart from numerical failure.

use nurbs_core::{Continuity, Side};
use thiserror::Error;

/// Everything that can go wrong while measuring or setting continuity.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Error {
    /// An error of the kernel (knot operations, evaluation set-up).
    #[error(transparent)]
    Core(#[from] nurbs_core::Error),
    /// Fewer samples than a measurement or solve needs.
    #[error("{samples} samples are too few (at least {min} needed)")]
    TooFewSamples {
        /// samples asked for
        samples: usize,
        /// the minimum
        min: usize,
    },
    /// The same side of the slave appears in two links.
    #[error("side {side} of the slave is linked twice")]
    DuplicateSide {
        /// the side
        side: Side,
    },
    /// A setting parameter outside its range.
    #[error("invalid parameter {name} = {value}: {reason}")]
    InvalidParameter {
        /// the field
        name: &'static str,
        /// the value given
        value: f64,
        /// the allowed range
        reason: &'static str,
    },
    /// A surface has no fillet section to replace ([`crate::section`]).
    #[error("no one-hump section: {reason}")]
    NoSection {
        /// why (the weights, a column, the profile)
        reason: String,
    },
    /// The least-squares system of one side could not be solved.
    #[error("side {side}, {target:?} step: the least-squares system is singular ({reason})")]
    SingularSystem {
        /// the side
        side: Side,
        /// the step (G0 = position row, G1 tangential row, G2 curvature row)
        target: Continuity,
        /// why
        reason: String,
    },
    /// The slave has fewer control rows across a linked side than the link's frame: rows
    /// 0..=r of the side (r = 0, 1, 2 for G0, G1, G2) must exist (an unprepared slave, e.g. a
    /// kernel's 2 × 3 net under a G2 link).
    #[error(
        "side {side}, {target:?}: the slave has {rows} control rows across it, the frame needs {needed}"
    )]
    TooFewRows {
        /// the side
        side: Side,
        /// the link's target
        target: Continuity,
        /// control rows across the side
        rows: usize,
        /// rows the target's frame needs
        needed: usize,
    },
    /// The solution came out non-finite (NaN or infinite control points).
    #[error("side {side}, {target:?} step: the solution is not finite")]
    NonFiniteSolution {
        /// the side
        side: Side,
        /// the step
        target: Continuity,
    },
}

/// Result alias of the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;
