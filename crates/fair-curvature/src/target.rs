//! Target-curvature fairing of surfaces ([SV] §5.2, [SSV08]): the [`SurfaceFairing`] method
//! `curvature`.
//!
//! 1. Sample the surface on the grid S(u_a, v_b) of [`Sampling`].
//! 2. Fair every u-isocurve polyline (a fixed, b running) and every v-isocurve polyline with
//!    [`crate::polyline::fair_polyline`] (ends and end curvatures kept, samples within D of the
//!    original), and average the two faired positions of each sample.
//! 3. Refit: least squares over the free control points only ([`crate::normal`]),
//!    min Σ_ab |S(u_a, v_b) − X_ab|² + λ Σ_free |P − O|², with the weights of a rational surface
//!    held fixed. Fixed control points are never written, so the frames the mask fixes stay
//!    bit-identical and the refit cannot harm the continuity already set.
//! 4. If a control point moved farther than the tolerance, all displacements are scaled back
//!    (by the convex hull property the surface then stays within the tolerance).
//!
//! [SV] §5.2 notes that fairing isocurves may leave artifacts on saddle-like surfaces: the u and
//! v fairings disagree where the directions bend opposite ways.
//!
//! # Tolerance
//! D = `pull_tolerance_fraction` × the tolerance (model units) bounds each sample's move; the
//! final control displacements are bounded by the tolerance itself.

use std::time::Instant;

use nurbs_core::{
    BSplineSurface, ControlMask, FairingReport, Point3, SurfaceBasis, SurfaceBasisEvaluator,
    SurfaceFairing,
};

use crate::error::{Result, check_fraction, check_param, check_tolerance};
use crate::normal::{NormalSystem, apply, limit_to_tolerance, max_norm};
use crate::polyline::{EndCurvature, PolylineParams, fair_polyline};
use crate::sampling::Sampling;

/// Name of the target-curvature method.
pub const TARGET_METHOD: &str = "curvature";

/// Settings of target-curvature surface fairing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TargetCurvatureParams {
    /// The sample grid. Default [`Sampling::PerSpan`]`(3)`.
    pub sampling: Sampling,
    /// Smoothing and integration of each isocurve. Default [`PolylineParams::default`].
    pub curve: PolylineParams,
    /// D / tolerance ∈ (0, 1] (unit-free): how far a faired sample may move. Default 0.9,
    /// leaving a tenth of the budget to the refit.
    pub pull_tolerance_fraction: f64,
    /// ρ of the refit's pull towards the original control points (unit-free, relative to the
    /// mean diagonal of the fit's normal matrix, ≥ 0). Default 1e-6: it only keeps points
    /// that few samples see determined and changes a well-posed fit by ~1e-6 relative.
    pub fit_regularization: f64,
}

impl Default for TargetCurvatureParams {
    fn default() -> Self {
        Self {
            sampling: Sampling::default(),
            curve: PolylineParams::default(),
            pull_tolerance_fraction: 0.9,
            fit_regularization: 1e-6,
        }
    }
}

impl TargetCurvatureParams {
    fn check(&self) -> Result<()> {
        self.sampling.check()?;
        self.curve.check()?;
        check_fraction("pull_tolerance_fraction", self.pull_tolerance_fraction)?;
        check_param(
            "fit_regularization",
            self.fit_regularization,
            0.0,
            false,
            "finite and ≥ 0",
        )
    }
}

/// What a target-curvature surface run achieved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TargetCurvatureReport {
    /// samples in u and v
    pub samples: (usize, usize),
    /// number of free control points
    pub free_points: usize,
    /// largest move of a faired sample from its original (model units)
    pub max_sample_move: f64,
    /// largest distance between the refitted surface and the faired samples (model units)
    pub refit_max_error: f64,
    /// root mean square of those distances (model units)
    pub refit_rms_error: f64,
    /// factor the control displacements were scaled by to respect the tolerance (1 = none)
    pub scale: f64,
    /// largest control-point displacement (model units)
    pub max_control_move: f64,
}

/// Fairs `surface` by target curvature, moving only the points `mask` frees, each within
/// `tolerance` (model units) of its original.
pub fn fair_surface_target(
    surface: &BSplineSurface,
    mask: &ControlMask,
    tolerance: f64,
    params: &TargetCurvatureParams,
) -> Result<(BSplineSurface, TargetCurvatureReport)> {
    check_tolerance(tolerance)?;
    params.check()?;
    mask.check_shape(surface)?;
    let us = params.sampling.params(surface.knots_u(), true);
    let vs = params.sampling.params(surface.knots_v(), false);
    let (mu, mv) = (us.len(), vs.len());
    let mut report = TargetCurvatureReport {
        samples: (mu, mv),
        free_points: mask.free_count(),
        max_sample_move: 0.0,
        refit_max_error: 0.0,
        refit_rms_error: 0.0,
        scale: 1.0,
        max_control_move: 0.0,
    };
    if mask.free_count() == 0 {
        return Ok((surface.clone(), report));
    }
    let grid = surface.eval_grid_points(&us, &vs);
    let d = params.pull_tolerance_fraction * tolerance;
    let targets = fair_isocurves(&grid, mu, mv, d, &params.curve)?;
    report.max_sample_move = grid
        .iter()
        .zip(&targets)
        .map(|(g, t)| (g - t).norm())
        .fold(0.0, f64::max);
    let mut system = NormalSystem::new(surface);
    let mut basis = SurfaceBasis::new(surface);
    let mut eval = SurfaceBasisEvaluator::new(surface);
    for (a, &u) in us.iter().enumerate() {
        for (b, &v) in vs.iter().enumerate() {
            eval.eval(u, v, &mut basis);
            system.add_row(&basis, &basis.value, 1.0, targets[a * mv + b].coords);
        }
    }
    let mut solved = system.solve(mask.as_slice(), params.fit_regularization, "refit")?;
    report.scale = limit_to_tolerance(&mut solved.delta, tolerance);
    report.max_control_move = max_norm(&solved.delta);
    let out = apply(surface, mask.as_slice(), &solved.delta);
    let fitted = out.eval_grid_points(&us, &vs);
    let (mut max, mut sq) = (0.0f64, 0.0);
    for (f, t) in fitted.iter().zip(&targets) {
        let e = (f - t).norm();
        max = max.max(e);
        sq += e * e;
    }
    report.refit_max_error = max;
    report.refit_rms_error = (sq / targets.len() as f64).sqrt();
    Ok((out, report))
}

/// One pass of step 2: every u- and v-isocurve polyline of the `mu × mv` grid faired, the two
/// results of each sample averaged.
fn fair_isocurves(
    grid: &[Point3],
    mu: usize,
    mv: usize,
    d: f64,
    params: &PolylineParams,
) -> Result<Vec<Point3>> {
    let mut sum = vec![Point3::origin().coords; mu * mv];
    let mut line = Vec::with_capacity(mu.max(mv));
    for a in 0..mu {
        line.clear();
        line.extend((0..mv).map(|b| grid[a * mv + b]));
        let faired = fair_polyline(&line, d, params, EndCurvature::Keep)?;
        for b in 0..mv {
            sum[a * mv + b] += faired[b].coords;
        }
    }
    for b in 0..mv {
        line.clear();
        line.extend((0..mu).map(|a| grid[a * mv + b]));
        let faired = fair_polyline(&line, d, params, EndCurvature::Keep)?;
        for a in 0..mu {
            sum[a * mv + b] += faired[a].coords;
        }
    }
    Ok(sum.iter().map(|s| Point3::from(s / 2.0)).collect())
}

/// The target-curvature method (`curvature`) for the framework.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TargetCurvatureFairing {
    /// its settings
    pub params: TargetCurvatureParams,
}

impl SurfaceFairing for TargetCurvatureFairing {
    fn name(&self) -> &str {
        TARGET_METHOD
    }

    fn fair(
        &self,
        surface: &BSplineSurface,
        mask: &ControlMask,
        tolerance: f64,
    ) -> nurbs_core::Result<(BSplineSurface, FairingReport)> {
        let start = Instant::now();
        let (out, _) = fair_surface_target(surface, mask, tolerance, &self.params)
            .map_err(|e| e.into_core(TARGET_METHOD))?;
        let seconds = start.elapsed().as_secs_f64();
        Ok((
            out.clone(),
            FairingReport::measure(TARGET_METHOD, surface, &out, 1, seconds),
        ))
    }
}
