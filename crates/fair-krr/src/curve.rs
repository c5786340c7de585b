//! KRR fairing of curves (\[SV\] §5.1; \[FS\] for cubics, \[HK\] for general order).
//!
//! Each iteration picks the free control point (single-point solve) or the knot (least squares)
//! with the largest jump |J| of the p-th derivative (the third for cubics), removes the jump by
//! the solves of [`crate::jump`], and clamps every move to the ball of radius ε around the
//! original point. The last `taboo` choices are skipped, which stops the method from cycling
//! between neighbours. The stencils are short, so a full scan per iteration (O(n p)) is cheap for
//! curves; surfaces keep ranks in a priority tree ([`crate::surface`]).
//!
//! # Tolerance
//! A candidate whose clamped move is shorter than [`MIN_MOVE_REL`] × ε is skipped (it sits on
//! its tolerance sphere with the target outside); the run stops when the largest jump falls
//! below `min_relative_jump` × the largest jump at the start.

use nurbs_core::{BSplineCurve, Point3};

use crate::error::{KrrError, Result, check_tolerance};
use crate::jump::KnotJumps;

/// Moves shorter than this fraction of ε count as no move.
pub const MIN_MOVE_REL: f64 = 1e-9;

/// Factor (just below 1) applied to ε when a point is clamped onto its tolerance sphere, so that
/// rounding never puts it outside (the kernel's value).
pub use nurbs_core::fairing::BALL_SHRINK;

/// How the jump at a knot is removed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KrrSolve {
    /// only the point in the middle of the knot's stencil moves (exact)
    SinglePoint,
    /// every free point of the stencil moves, by the least-squares (minimum-norm) correction
    LeastSquares,
}

/// Why a KRR run stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KrrStop {
    /// `max_iterations` moves were made
    IterationLimit,
    /// the largest jump fell below the threshold, or no candidate could move any more
    Converged,
    /// no free point has a knot to fair: nothing could move
    NothingFree,
}

/// Settings of curve KRR.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KrrCurveParams {
    /// Largest number of knot fairing steps. Default 1,000 (curves have few knots).
    pub max_iterations: usize,
    /// Exact single-point solve (default, \[FS\]) or least squares (\[HK\]).
    pub solve: KrrSolve,
    /// How many of the last chosen points (or knots) are skipped. Default 2: enough to stop two
    /// neighbours from trading the same jump back and forth.
    pub taboo: usize,
    /// Stop when the largest jump falls below this fraction of the largest jump at the start
    /// (unit-free). Default 1e-6.
    pub min_relative_jump: f64,
}

impl Default for KrrCurveParams {
    fn default() -> Self {
        Self {
            max_iterations: 1_000,
            solve: KrrSolve::SinglePoint,
            taboo: 2,
            min_relative_jump: 1e-6,
        }
    }
}

/// What a KRR run achieved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KrrReport {
    /// steps made
    pub iterations: usize,
    /// largest |jump| over the faired knots before (length / parameter^p)
    pub max_jump_before: f64,
    /// the same after
    pub max_jump_after: f64,
    /// largest distance of a control point from its original (model units)
    pub max_control_move: f64,
    /// why the run stopped
    pub stop: KrrStop,
}

pub(crate) fn clamp_to_ball(target: Point3, origin: &Point3, eps: f64) -> Point3 {
    let w = target - origin;
    let d = w.norm();
    if d <= eps {
        target
    } else {
        origin + w * (eps * BALL_SHRINK / d)
    }
}

pub(crate) fn check_params(min_relative_jump: f64) -> Result<()> {
    if min_relative_jump.is_finite() && min_relative_jump >= 0.0 {
        Ok(())
    } else {
        Err(KrrError::InvalidParameter {
            name: "min_relative_jump",
            value: min_relative_jump,
            expected: "finite and ≥ 0",
        })
    }
}

fn max_jump(jumps: &KnotJumps, p: &[Point3], free: &[bool]) -> f64 {
    (0..p.len())
        .filter(|&j| free[j])
        .filter_map(|j| jumps.jump(j, |k| p[k]))
        .map(|v| v.norm())
        .fold(0.0, f64::max)
}

/// The least-squares step at the knot of point j: P_i ← P_i − β_i J / Σ_{free} β_k² on the free
/// points of the stencil, each clamped to its ball; applied only when `apply`. Returns whether
/// some point moves by more than [`MIN_MOVE_REL`] × ε.
fn least_squares_step(
    jumps: &KnotJumps,
    j: usize,
    p: &mut [Point3],
    free: &[bool],
    origin: &[Point3],
    tolerance: f64,
    apply: bool,
) -> bool {
    let Some((first, b)) = jumps.stencil(j) else {
        return false;
    };
    let Some(jump) = jumps.jump(j, |k| p[k]) else {
        return false;
    };
    let norm2: f64 = b
        .iter()
        .enumerate()
        .filter(|(k, _)| free[first + k])
        .map(|(_, v)| v * v)
        .sum();
    if !(norm2 > 0.0) {
        return false;
    }
    let mut moved = false;
    for (k, &bk) in b.iter().enumerate() {
        let i = first + k;
        if free[i] && bk != 0.0 {
            let new = clamp_to_ball(p[i] - jump * (bk / norm2), &origin[i], tolerance);
            moved |= (new - p[i]).norm() > MIN_MOVE_REL * tolerance;
            if apply {
                p[i] = new;
            }
        }
    }
    moved
}

/// Fairs `curve` by knot removal–reinsertion, moving only points with `free[i]`, each within
/// `tolerance` (model units) of its original.
pub fn fair_curve(
    curve: &BSplineCurve,
    free: &[bool],
    tolerance: f64,
    params: &KrrCurveParams,
) -> Result<(BSplineCurve, KrrReport)> {
    check_tolerance(tolerance)?;
    check_params(params.min_relative_jump)?;
    let n = curve.control_points().len();
    if free.len() != n {
        return Err(KrrError::MaskLength {
            flags: free.len(),
            points: n,
        });
    }
    if curve.is_rational() {
        return Err(KrrError::Rational { what: "curve" });
    }
    let run = CurveRun {
        jumps: KnotJumps::new(curve.knots()),
        origin: curve.control_points(),
        free,
        tolerance,
        solve: params.solve,
    };
    let mut out = curve.clone();
    let mut taboo: Vec<usize> = Vec::with_capacity(params.taboo + 1);
    let before = max_jump(&run.jumps, run.origin, free);
    let threshold = params.min_relative_jump * before;
    let fairable = run.fairable(curve.degree());
    let mut stop = if fairable.is_empty() {
        KrrStop::NothingFree
    } else {
        KrrStop::IterationLimit
    };
    let mut iterations = 0;
    while iterations < params.max_iterations && stop == KrrStop::IterationLimit {
        let p = out.control_points_mut();
        let best = run.best_knot(p, &fairable, &taboo);
        let Some((j, _)) = best.filter(|&(_, s)| s > threshold) else {
            stop = KrrStop::Converged;
            break;
        };
        run.step(p, j);
        iterations += 1;
        taboo.push(j);
        if taboo.len() > params.taboo {
            taboo.remove(0);
        }
    }
    let p = out.control_points();
    let report = KrrReport {
        iterations,
        max_jump_before: before,
        max_jump_after: max_jump(&run.jumps, p, free),
        max_control_move: nurbs_core::fairing::max_displacement(run.origin, p),
        stop,
    };
    Ok((out, report))
}

/// What one curve run works with: the knots' jump solves, the original points, the mask, ε and
/// the solve.
struct CurveRun<'a> {
    jumps: KnotJumps,
    origin: &'a [Point3],
    free: &'a [bool],
    tolerance: f64,
    solve: KrrSolve,
}

impl CurveRun<'_> {
    /// The points whose knot has a free point in its stencil (p + 2 points for degree p).
    fn fairable(&self, degree: usize) -> Vec<usize> {
        (0..self.origin.len())
            .filter(|&j| {
                self.jumps
                    .stencil(j)
                    .is_some_and(|(first, _)| (first..first + degree + 2).any(|k| self.free[k]))
            })
            .collect()
    }

    /// The knot (by its point) with the largest jump at `p` among `fairable` that is not in
    /// `taboo` and whose step moves a point, with that jump's size.
    fn best_knot(
        &self,
        p: &mut [Point3],
        fairable: &[usize],
        taboo: &[usize],
    ) -> Option<(usize, f64)> {
        let mut best: Option<(usize, f64)> = None;
        for &j in fairable {
            if taboo.contains(&j) {
                continue;
            }
            let Some(jump) = self.jumps.jump(j, |k| p[k]) else {
                continue;
            };
            let size = jump.norm();
            if best.is_some_and(|(_, b)| b >= size) {
                continue;
            }
            if self.can_move(p, j) {
                best = Some((j, size));
            }
        }
        best
    }

    /// Whether the step at the knot of point j moves some point by more than
    /// [`MIN_MOVE_REL`] × ε.
    fn can_move(&self, p: &mut [Point3], j: usize) -> bool {
        let (origin, tolerance) = (self.origin, self.tolerance);
        match self.solve {
            KrrSolve::SinglePoint => {
                let min_move = MIN_MOVE_REL * tolerance;
                self.free[j]
                    && self.jumps.target(j, |k| p[k]).is_some_and(|t| {
                        (clamp_to_ball(t, &origin[j], tolerance) - p[j]).norm() > min_move
                    })
            }
            KrrSolve::LeastSquares => {
                least_squares_step(&self.jumps, j, p, self.free, origin, tolerance, false)
            }
        }
    }

    /// Removes the jump at the knot of point j, every move clamped to its ball.
    fn step(&self, p: &mut [Point3], j: usize) {
        let (origin, tolerance) = (self.origin, self.tolerance);
        match self.solve {
            KrrSolve::SinglePoint => {
                let t = self.jumps.target(j, |k| p[k]).unwrap_or(p[j]);
                p[j] = clamp_to_ball(t, &origin[j], tolerance);
            }
            KrrSolve::LeastSquares => {
                least_squares_step(&self.jumps, j, p, self.free, origin, tolerance, true);
            }
        }
    }
}
