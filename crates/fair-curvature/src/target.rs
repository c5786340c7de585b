//! Target-curvature fairing of surfaces (\[SV\] §5.2, \[SSV08\]): the [`SurfaceFairing`] method
//! `curvature`.
//!
//! 1. Sample the surface on the grid S(u_a, v_b) of [`Sampling`].
//! 2. Every u-isocurve polyline (a fixed, b running) and every v-isocurve polyline gets its
//!    target curvature: curvature vectors smoothed along the polyline
//!    ([`crate::polyline`]; the values next to the ends are smoothed too, since the control
//!    mask, not the polyline, decides what the boundary keeps). All samples then follow the
//!    wanted curvature changes of both families in one least-squares integration with a soft
//!    pull to the originals and within D of them (`crate::integrate`); samples that only
//!    fixed control points reach stay where they are.
//! 3. Refit: least squares over the free control points only (`crate::normal`),
//!    min Σ_ab |S(u_a, v_b) − X_ab|² + λ Σ_free |P − O|², with the weights of a rational surface
//!    held fixed. Fixed control points are never written, so the frames the mask fixes stay
//!    bit-identical and the refit cannot harm the continuity already set.
//! 4. If a control point moved farther than the tolerance, all displacements are scaled back
//!    (by the convex hull property the surface then stays within the tolerance).
//!
//! \[SV\] §5.2 notes that fairing isocurves may leave artifacts on saddle-like surfaces: the
//! targets come from the isocurves alone, so the curvature is smoothed along two directions
//! only, which flattens curvature peaks that the isocurves cross.
//!
//! # Deviation from the paper
//! \[SV\] and \[SSV08\] fair the u- and v-isocurves one by one and average the two faired
//! positions of each sample. An average of two fairings keeps half of the noise that only one
//! family sees (a wave along u is invisible to the v-isocurves), and on a noisy sphere patch it
//! removed less than a fifth of the mean-curvature variance; integrating the targets of both
//! families in one least-squares problem weighs them instead of averaging their results.
//!
//! # Tolerance
//! D = `pull_tolerance_fraction` × the tolerance (model units) bounds each sample's move; the
//! final control displacements are bounded by the tolerance itself.

use nurbs_core::{
    BSplineSurface, ControlMask, Faired, FairingProblem, Point3, SurfaceBasis,
    SurfaceBasisEvaluator, SurfaceFairing,
};

use crate::error::{Result, check_fraction, check_param, check_tolerance};
use crate::integrate::{Integration, Line};
use crate::normal::{NormalSystem, apply, limit_to_tolerance, max_norm};
use crate::polyline::{CurvatureWork, PolylineParams, SmoothedEnds, curvature_change};
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
    let fixed = fixed_samples(surface, mask, &us, &vs);
    let targets = fair_isocurves(&grid, mu, mv, &fixed, d, &params.curve)?;
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

/// Samples that only fixed control points reach: the refit cannot move them.
fn fixed_samples(
    surface: &BSplineSurface,
    mask: &ControlMask,
    us: &[f64],
    vs: &[f64],
) -> Vec<bool> {
    let mut basis = SurfaceBasis::new(surface);
    let mut eval = SurfaceBasisEvaluator::new(surface);
    let mut out = Vec::with_capacity(us.len() * vs.len());
    for &u in us {
        for &v in vs {
            eval.eval(u, v, &mut basis);
            out.push((0..basis.len()).all(|k| {
                let (i, j) = basis.control_index(k);
                basis.value[k] == 0.0 || !mask.is_free(i, j)
            }));
        }
    }
    out
}

/// Step 2: the u- and v-isocurves of the `mu × mv` grid get their curvature targets, and all
/// samples follow them in one least-squares integration (samples with `fixed` stay).
fn fair_isocurves(
    grid: &[Point3],
    mu: usize,
    mv: usize,
    fixed: &[bool],
    d: f64,
    params: &PolylineParams,
) -> Result<Vec<Point3>> {
    let mut lines = Vec::with_capacity(mu + mv);
    for a in 0..mu {
        lines.push(Line {
            start: a * mv,
            stride: 1,
            len: mv,
            delta: Vec::new(),
        });
    }
    for b in 0..mv {
        lines.push(Line {
            start: b,
            stride: mv,
            len: mu,
            delta: Vec::new(),
        });
    }
    let mut work = CurvatureWork::default();
    let mut buffer = Vec::with_capacity(mu.max(mv));
    // half the chords on either side of each sample along its two lines
    let mut along = [vec![0.0; mu * mv], vec![0.0; mu * mv]];
    for (k, line) in lines.iter_mut().enumerate() {
        buffer.clear();
        buffer.extend((0..line.len).map(|i| grid[line.index(i)]));
        let half = &mut along[usize::from(k >= mu)];
        for i in 0..line.len - 1 {
            let l = (buffer[i + 1] - buffer[i]).norm() / 2.0;
            half[line.index(i)] += l;
            half[line.index(i + 1)] += l;
        }
        curvature_change(
            &buffer,
            params,
            SmoothedEnds::Free,
            &mut work,
            &mut line.delta,
        );
    }
    let measure: Vec<f64> = along[0].iter().zip(&along[1]).map(|(a, b)| a * b).collect();
    Integration {
        points: grid,
        original: grid,
        fixed,
        measure: &measure,
        radius: d,
        rho: params.pull,
    }
    .solve(&lines)
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

    /// A direct solve: `max_iterations` does not apply.
    fn fair(&self, problem: &FairingProblem<'_>) -> nurbs_core::Result<Faired> {
        let (out, _) = fair_surface_target(
            problem.surface,
            problem.mask,
            problem.tolerance,
            &self.params,
        )
        .map_err(|e| e.into_core(TARGET_METHOD))?;
        Ok(Faired::new(out, 1))
    }
}
