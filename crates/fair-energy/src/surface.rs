//! Local energy fairing of B-spline surfaces (\[H\] part ①, and part ② with `joint_weight` > 0):
//! the [`SurfaceFairing`] method `energy`.
//!
//! Only control points the [`ControlMask`] frees move; fixed points are never written, so the
//! frames of \[SV\] §3.1 come back bit-identical. Every moved point stays within the tolerance ε of
//! its original, which by the convex hull property bounds the surface deviation by ε (\[H\] slide
//! "Distance tolerance").
//!
//! Rational surfaces are faired with their weights held fixed (the weights come back
//! bit-identical): S = Σ R_ij P_ij is then linear in the control points, the thin plate is the
//! quadratic form of [`RationalStiffness`], and since R_ij ≥ 0 with Σ R_ij = 1 the surface still
//! moves by at most ε. The Bézier-spline extension (`joint_weight` > 0) needs a polynomial
//! surface.

use nurbs_core::{BSplineSurface, ControlMask, Faired, FairingProblem, SurfaceFairing};

use crate::error::{EnergyError, Result, check_tolerance};
use crate::local::{LocalOutcome, LocalSettings, run_local};
use crate::rational::RationalStiffness;
use crate::start::solved_start;
use crate::stiffness::SeparableStiffness;

/// Settings of the local surface scheme.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyParams {
    /// Largest number of single-point moves. Default 10,000: \[H\]'s 52×52 example (\[H\] slide
    /// "Examples (1)").
    pub max_iterations: usize,
    /// Least number of moves per free control point: the limit is
    /// max(`max_iterations`, this × free points), so that a large net (e.g. after knot
    /// insertion) is not stopped after a few moves per point. Default 0 (the fixed limit alone).
    pub min_iterations_per_free_point: usize,
    /// Stop when the best energy decrease falls below this fraction of the starting energy
    /// (unit-free). Default 1e-12: far below any visible change, so the iteration limit usually
    /// decides.
    pub min_relative_decrease: f64,
    /// λ of the Bézier-spline extension (\[H\] part ②): weight of the cross-derivative jumps at
    /// interior knots of full multiplicity, 0 ≤ λ < 1. Default 0 (plain thin plate); \[H\]'s
    /// examples use 0.85–0.95.
    pub joint_weight: f64,
    /// Where the moves start. Default [`LocalStart::Solved`]: the same minimizer, reached in
    /// a fraction of the moves ([`crate::start`]).
    pub start: LocalStart,
}

/// Where the local scheme starts ([`EnergyParams::start`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LocalStart {
    /// at the original net, as \[H\] has it
    Original,
    /// at the free points' unconstrained thin-plate optimum of one sparse solve where that lies
    /// inside every ε-ball (it is then the constrained minimizer), else at the original net
    /// ([`crate::start`])
    #[default]
    Solved,
}

impl Default for EnergyParams {
    fn default() -> Self {
        Self {
            max_iterations: 10_000,
            min_iterations_per_free_point: 0,
            min_relative_decrease: 1e-12,
            joint_weight: 0.0,
            start: LocalStart::default(),
        }
    }
}

impl EnergyParams {
    pub(crate) fn check(&self) -> Result<()> {
        if !(self.min_relative_decrease.is_finite() && self.min_relative_decrease >= 0.0) {
            return Err(EnergyError::InvalidParameter {
                name: "min_relative_decrease",
                value: self.min_relative_decrease,
                expected: "finite and ≥ 0",
            });
        }
        if !(0.0..1.0).contains(&self.joint_weight) {
            return Err(EnergyError::InvalidParameter {
                name: "joint_weight",
                value: self.joint_weight,
                expected: "in [0, 1)",
            });
        }
        Ok(())
    }
}

/// What a local surface run achieved. Energies are values of the minimized functional: the
/// thin-plate energy when `joint_weight` = 0.
pub type EnergyReport = LocalOutcome;

/// Fairs `surface` by the local scheme, moving only points `mask` frees, each within `tolerance`
/// (model units) of its original. A mask that frees nothing returns the surface unchanged with
/// [`crate::StopReason::NothingFree`]. A rational surface keeps its weights; it must have
/// `joint_weight` = 0 ([`EnergyError::InvalidParameter`] otherwise).
pub fn fair_surface(
    surface: &BSplineSurface,
    mask: &ControlMask,
    tolerance: f64,
    params: &EnergyParams,
) -> Result<(BSplineSurface, EnergyReport)> {
    check_tolerance(tolerance)?;
    params.check()?;
    mask.check_shape(surface)?;
    let mut out = surface.clone();
    let settings = LocalSettings {
        tolerance,
        max_iterations: params
            .max_iterations
            .max(params.min_iterations_per_free_point * mask.free_count()),
        min_relative_decrease: params.min_relative_decrease,
    };
    let (origin, free) = (surface.control_points(), mask.as_slice());
    let outcome = if surface.is_rational() {
        if params.joint_weight != 0.0 {
            return Err(EnergyError::InvalidParameter {
                name: "joint_weight",
                value: params.joint_weight,
                expected: "0 for a rational surface (the joint terms need polynomial geometry)",
            });
        }
        let k = RationalStiffness::thin_plate_shared(surface);
        start_and_run(
            &*k,
            origin,
            out.control_points_mut(),
            free,
            settings,
            params.start,
        )
    } else {
        let k = SeparableStiffness::with_joints(
            surface.knots_u(),
            surface.knots_v(),
            params.joint_weight,
        )?;
        start_and_run(
            &k,
            origin,
            out.control_points_mut(),
            free,
            settings,
            params.start,
        )
    };
    Ok((out, outcome))
}

/// The local run from the start `start` asks for; the outcome's energy before is the
/// original net's, its moves those of the local scheme (the solve is none).
fn start_and_run<K: crate::local::LocalStiffness>(
    k: &K,
    origin: &[nurbs_core::Point3],
    current: &mut [nurbs_core::Point3],
    free: &[bool],
    settings: LocalSettings,
    start: LocalStart,
) -> EnergyReport {
    if start == LocalStart::Original
        || solved_start(k, origin, current, free, settings.tolerance).is_none()
    {
        return run_local(k, origin, current, free, settings);
    }
    // the scheme stops at a decrease below `min_relative_decrease` of the original net's
    // energy, as from the original net (relative to the start's, far lower energy, it would
    // chase rounding)
    let before = crate::local::energy_of(k, origin);
    let at_start = crate::local::energy_of(k, current);
    let settings = LocalSettings {
        min_relative_decrease: if at_start > 0.0 {
            settings.min_relative_decrease * (before / at_start)
        } else {
            settings.min_relative_decrease
        },
        ..settings
    };
    let mut outcome = run_local(k, origin, current, free, settings);
    outcome.energy_before = before;
    outcome
}

/// The local energy fairing method (`energy`) for the framework.
///
/// It takes rational surfaces (weights held fixed, `joint_weight` = 0), as `energy-global`
/// ([`crate::GlobalEnergyFairing`]) does; `energy-bezier` ([`crate::BezierSplineFairing`])
/// refuses them with [`EnergyError::Rational`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LocalEnergyFairing {
    /// its settings
    pub params: EnergyParams,
}

/// Name of the local method.
pub const LOCAL_METHOD: &str = "energy";

impl SurfaceFairing for LocalEnergyFairing {
    fn name(&self) -> &str {
        LOCAL_METHOD
    }

    /// `max_iterations` is the limit of single-point moves (the per-free-point floor then does
    /// not apply).
    fn fair(&self, problem: &FairingProblem<'_>) -> nurbs_core::Result<Faired> {
        let mut params = self.params;
        if let Some(n) = problem.max_iterations {
            params.max_iterations = n;
            params.min_iterations_per_free_point = 0;
        }
        let (out, outcome) =
            fair_surface(problem.surface, problem.mask, problem.tolerance, &params)
                .map_err(|e| e.into_core(LOCAL_METHOD))?;
        Ok(Faired::new(out, outcome.iterations))
    }
}
