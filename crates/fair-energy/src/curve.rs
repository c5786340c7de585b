//! Local energy fairing of B-spline curves: the scheme of \[H\] in one variable.
//!
//! Functional ∫ |x''|² dt (+ β ∫ |x'''|² dt) = Σ_c x_cᵀ (G²² + β G³³) x_c; each step moves the free
//! control point with the largest energy decrease to its optimum, clamped to the ball of radius ε
//! around its original (see [`crate::local`]).

use nurbs_core::BSplineCurve;

use crate::error::{EnergyError, Result, check_tolerance};
use crate::local::{LocalOutcome, LocalSettings, run_local};
use crate::stiffness::SeparableStiffness;

/// Settings of the local curve scheme.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveEnergyParams {
    /// Largest number of single-point moves. Default 10,000, as for surfaces (\[H\] "Examples (1)").
    pub max_iterations: usize,
    /// Stop when the best energy decrease falls below this fraction of the starting energy
    /// (unit-free). Default 1e-12.
    pub min_relative_decrease: f64,
    /// β, weight of ∫ |x'''|² (parameter² units relative to ∫ |x''|²). Default 0: bending energy
    /// only.
    pub third_derivative_weight: f64,
}

impl Default for CurveEnergyParams {
    fn default() -> Self {
        Self {
            max_iterations: 10_000,
            min_relative_decrease: 1e-12,
            third_derivative_weight: 0.0,
        }
    }
}

/// Fairs `curve` moving only points with `free[i]`, each within `tolerance` (model units) of its
/// original.
pub fn fair_curve(
    curve: &BSplineCurve,
    free: &[bool],
    tolerance: f64,
    params: &CurveEnergyParams,
) -> Result<(BSplineCurve, LocalOutcome)> {
    check_tolerance(tolerance)?;
    if !(params.min_relative_decrease.is_finite() && params.min_relative_decrease >= 0.0) {
        return Err(EnergyError::InvalidParameter {
            name: "min_relative_decrease",
            value: params.min_relative_decrease,
            expected: "finite and ≥ 0",
        });
    }
    if free.len() != curve.control_points().len() {
        return Err(EnergyError::MaskLength {
            flags: free.len(),
            points: curve.control_points().len(),
        });
    }
    if curve.is_rational() {
        return Err(EnergyError::Rational { what: "curve" });
    }
    let k = SeparableStiffness::curve(curve.knots(), params.third_derivative_weight)?;
    let mut out = curve.clone();
    let settings = LocalSettings {
        tolerance,
        max_iterations: params.max_iterations,
        min_relative_decrease: params.min_relative_decrease,
    };
    let outcome = run_local(
        &k,
        curve.control_points(),
        out.control_points_mut(),
        free,
        settings,
    );
    Ok((out, outcome))
}
