//! The error type of fair-energy: bad input kept apart from numerical failure.

use thiserror::Error;

/// Everything that can go wrong in energy fairing.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum EnergyError {
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
    /// The energy is quadratic in the control points only for polynomial geometry.
    #[error("energy fairing needs a polynomial (non-rational) {what}")]
    Rational {
        /// "surface" or "curve"
        what: &'static str,
    },
    /// The sparse Cholesky factorization of the global system failed.
    #[error("sparse Cholesky ({solver}) failed: {reason}")]
    SolveFailed {
        /// which solver
        solver: &'static str,
        /// what it reported
        reason: String,
    },
    /// An error of the kernel.
    #[error(transparent)]
    Core(#[from] nurbs_core::Error),
}

impl EnergyError {
    /// The error at the [`nurbs_core::SurfaceFairing`] boundary: kernel errors pass through,
    /// ours become [`nurbs_core::Error::FairingFailed`] naming `method`.
    pub fn into_core(self, method: &str) -> nurbs_core::Error {
        match self {
            EnergyError::Core(e) => e,
            other => nurbs_core::Error::FairingFailed {
                method: method.to_string(),
                message: other.to_string(),
            },
        }
    }
}

/// Result alias of the crate.
pub type Result<T, E = EnergyError> = std::result::Result<T, E>;

/// Checks a distance tolerance ε (model units): finite and > 0.
pub(crate) fn check_tolerance(value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(EnergyError::InvalidTolerance { value })
    }
}
