//! The error type of fair-curvature: bad input kept apart from numerical failure.

use thiserror::Error;

/// Everything that can go wrong in curvature fairing.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CurvatureError {
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
    /// A NaN or infinite value where geometry was expected.
    #[error("{what} {index} is not finite")]
    NonFinite {
        /// which kind of value
        what: &'static str,
        /// its position
        index: usize,
    },
    /// The least-squares system could not be solved.
    #[error("singular system in {stage}: {reason}")]
    SingularSystem {
        /// which solve
        stage: &'static str,
        /// what the solver reported
        reason: String,
    },
    /// An error of the kernel.
    #[error(transparent)]
    Core(#[from] nurbs_core::Error),
}

impl CurvatureError {
    /// The error at the [`nurbs_core::SurfaceFairing`] boundary: a
    /// [`nurbs_core::Error::FairingFailed`] naming `method`.
    pub fn into_core(self, method: &str) -> nurbs_core::Error {
        nurbs_core::Error::FairingFailed {
            method: method.to_string(),
            message: self.to_string(),
        }
    }
}

/// Result alias of the crate.
pub type Result<T, E = CurvatureError> = std::result::Result<T, E>;

/// Checks a distance tolerance (model units): finite and > 0.
pub(crate) fn check_tolerance(value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(CurvatureError::InvalidTolerance { value })
    }
}

/// Checks that `value` is finite and ≥ `min` (or > `min` when `strict`).
pub(crate) fn check_param(
    name: &'static str,
    value: f64,
    min: f64,
    strict: bool,
    expected: &'static str,
) -> Result<()> {
    let ok = value.is_finite() && if strict { value > min } else { value >= min };
    if ok {
        Ok(())
    } else {
        Err(CurvatureError::InvalidParameter {
            name,
            value,
            expected,
        })
    }
}

/// Checks that a named fraction lies in (0, 1] (and is finite).
pub(crate) fn check_fraction(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 && value <= 1.0 {
        Ok(())
    } else {
        Err(CurvatureError::InvalidParameter {
            name,
            value,
            expected: "in (0, 1]",
        })
    }
}
