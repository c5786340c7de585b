//! The interface every fairing method implements, and the report it returns.
//!
//! A method receives a surface, a [`ControlMask`] (only free control points may move: the fixed
//! frames of [SV] §3.1 must come back bit-identical) and the deviation tolerance, and returns
//! the faired surface with a [`FairingReport`]. [`FairingReport::measure`] fills the figures
//! every method reports the same way.

use crate::Point3;
use crate::energy::{max_deviation, thin_plate_energy};
use crate::error::Result;
use crate::frames::ControlMask;
use crate::surface::BSplineSurface;

/// Samples per direction of the sampled deviation in reports.
pub const REPORT_DEVIATION_SAMPLES: usize = 41;

/// Factor (just below 1) applied to ε when a fairing method puts a point onto its tolerance
/// sphere, so that the stored point is within ε despite rounding (one value for every method).
pub const BALL_SHRINK: f64 = 1.0 - 1e-12;

/// Largest distance between corresponding points of two equally long lists (the largest
/// control-point or vertex move of a run; 0 for empty lists).
pub fn max_displacement(before: &[Point3], after: &[Point3]) -> f64 {
    before
        .iter()
        .zip(after)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max)
}

/// What a fairing run achieved.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FairingReport {
    /// the method's name
    pub method: String,
    /// iterations (steps, sweeps or solves) performed
    pub iterations: usize,
    /// thin-plate energy before
    pub energy_before: f64,
    /// thin-plate energy after
    pub energy_after: f64,
    /// largest control-point displacement (model units)
    pub max_control_move: f64,
    /// largest sampled distance of the result from the original surface (model units)
    pub max_deviation: f64,
    /// wall-clock seconds
    pub seconds: f64,
}

impl FairingReport {
    /// Measures energies, control moves and the sampled deviation of `faired` against
    /// `original`.
    pub fn measure(
        method: &str,
        original: &BSplineSurface,
        faired: &BSplineSurface,
        iterations: usize,
        seconds: f64,
    ) -> Self {
        let max_control_move =
            if original.num_u() == faired.num_u() && original.num_v() == faired.num_v() {
                max_displacement(original.control_points(), faired.control_points())
            } else {
                f64::NAN
            };
        Self {
            method: method.to_string(),
            iterations,
            energy_before: thin_plate_energy(original),
            energy_after: thin_plate_energy(faired),
            max_control_move,
            max_deviation: max_deviation(original, faired, REPORT_DEVIATION_SAMPLES),
            seconds,
        }
    }
}

/// A surface fairing method, pluggable into the framework.
pub trait SurfaceFairing: Send + Sync {
    /// Short name, e.g. "energy".
    fn name(&self) -> &str;

    /// Fairs `surface` moving only the control points `mask` frees, keeping the result within
    /// `tolerance` (model units) of the original. Method failures are returned as
    /// [`crate::Error::FairingFailed`].
    fn fair(
        &self,
        surface: &BSplineSurface,
        mask: &ControlMask,
        tolerance: f64,
    ) -> Result<(BSplineSurface, FairingReport)>;
}
