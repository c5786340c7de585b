//! The error type of fair-krr: bad input kept apart from failures of the kernel.

use thiserror::Error;

/// Everything that can go wrong in knot removal–reinsertion fairing.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum KrrError {
    /// A distance tolerance that is not a finite positive length.
    #[error("tolerance must be finite and > 0, got {value}")]
    InvalidTolerance {
        /// the tolerance given (model units)
        value: f64,
    },
    /// A setting outside its range.
    #[error("{name} must be {expected}, got {value}")]
    InvalidParameter {
        /// the field of the params struct
        name: &'static str,
        /// the value given
        value: f64,
        /// the allowed range, in words
        expected: &'static str,
    },
    /// A per-point flag list whose length differs from the number of control points.
    #[error("{flags} free flags given for {points} control points")]
    MaskLength {
        /// number of flags
        flags: usize,
        /// number of control points
        points: usize,
    },
    /// KRR acts on the control points of polynomial geometry.
    #[error("knot removal–reinsertion needs a polynomial (non-rational) {what}")]
    Rational {
        /// "surface" or "curve"
        what: &'static str,
    },
    /// An error of the kernel.
    #[error(transparent)]
    Core(#[from] nurbs_core::Error),
}

impl KrrError {
    /// The error at the [`nurbs_core::SurfaceFairing`] boundary: kernel errors pass through, ours
    /// become [`nurbs_core::Error::FairingFailed`] naming `method`.
    pub fn into_core(self, method: &str) -> nurbs_core::Error {
        match self {
            KrrError::Core(e) => e,
            other => nurbs_core::Error::FairingFailed {
                method: method.to_string(),
                message: other.to_string(),
            },
        }
    }
}

/// Result alias of the crate.
pub type Result<T, E = KrrError> = std::result::Result<T, E>;

/// Checks a distance tolerance ε (model units): finite and > 0.
pub(crate) fn check_tolerance(value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(KrrError::InvalidTolerance { value })
    }
}
