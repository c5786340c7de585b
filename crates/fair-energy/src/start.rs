//! Where the local scheme starts: the free points' thin-plate optimum of one sparse solve,
//! brought into the ε-balls.
//!
//! The local scheme ([`crate::local`]) minimizes the convex quadratic E(d) over a product of
//! balls |d_r − o_r| ≤ ε; that problem has one minimizer (K_ff positive definite), which the
//! scheme approaches from the original net one point at a time. Its moves spread a change over
//! the net one stencil per sweep, so it needs about as many sweeps as the net is wide: the
//! fairing of a lofted block's vertex blend (37 × 55 points) made 151,900 moves, the limit of
//! 100 per free point. Where the unconstrained minimizer of the free points — one sparse
//! Cholesky solve of K_ff δ_f = −g_f, as in [`crate::global`] without its pull towards the
//! original — lies inside every ball, it is that constrained minimizer (the balls are then not
//! active), and the scheme started there has nothing left to do: the fixed point of \[H\]'s
//! scheme, reached by the solve of the global variant (\[SV\] §5.2). Where a ball holds a point
//! back, the minimizer lies on some balls' boundaries, which one solve does not foresee, and
//! the scheme runs from the original net exactly as \[H\] has it. A line search along the solved
//! displacement (t ∈ [0, 1]) keeps the start's energy at or below the original's against
//! rounding.
//!
//! K_ff is singular where the mask frees a whole net (the thin plate vanishes on affine nets):
//! the factorization then fails or returns moves far beyond any ball, and the scheme starts
//! from the original net.

use nalgebra::DMatrix;
use nurbs_core::{Point3, Vector3};

use crate::global::{Csc, SparseSolver, assemble, solve};
use crate::local::{BALL_SHRINK, LocalStiffness, NULL_DIAGONAL_REL};
use crate::ordering::nested_dissection;

/// Moves the movable points of `current` (equal to `origin` on entry) to the start described
/// in the module doc. `None` (and `current` untouched) when nothing is movable or the solve
/// fails: the local scheme then starts from the original net as \[H\] has it.
pub(crate) fn solved_start<K: LocalStiffness>(
    k: &K,
    origin: &[Point3],
    current: &mut [Point3],
    free: &[bool],
    tolerance: f64,
) -> Option<f64> {
    let (nu, nv) = k.shape();
    let n = nu * nv;
    let mut g = vec![Vector3::zeros(); n];
    k.multiply(origin, &mut g);
    let diag: Vec<f64> = (0..n).map(|r| k.diagonal(r)).collect();
    let cut = NULL_DIAGONAL_REL * diag.iter().cloned().fold(0.0, f64::max);
    let movable: Vec<bool> = (0..n).map(|r| free[r] && diag[r] > cut).collect();
    let order = nested_dissection(nu, nv, &movable, k.half_widths());
    if order.is_empty() {
        return None;
    }
    let (a, rhs) = normal_equations(k, &order, &movable, &g);
    let delta = solve(SparseSolver::FASTEST, a, rhs).ok()?;
    let mut step = vec![Vector3::zeros(); n];
    let reach = tolerance * BALL_SHRINK;
    for (c, &r) in order.iter().enumerate() {
        let v = Vector3::new(delta[(c, 0)], delta[(c, 1)], delta[(c, 2)]);
        // a point its ball holds back: the minimizer lies on some balls' boundaries, where the
        // scheme slides points along them, which one solve does not foresee (a NaN of a failed
        // solve fails the test too)
        if !(v.norm() <= reach) {
            return None;
        }
        step[r] = v;
    }
    // E(o + tΔ) = E₀ + 2t Δ·g + t² ΔᵀKΔ: the best t in [0, 1] (every point stays in its ball)
    let as_points: Vec<Point3> = step.iter().map(|v| Point3::from(*v)).collect();
    let mut kd = vec![Vector3::zeros(); n];
    k.multiply(&as_points, &mut kd);
    let lin: f64 = step.iter().zip(&g).map(|(a, b)| a.dot(b)).sum();
    let quad: f64 = step.iter().zip(&kd).map(|(a, b)| a.dot(b)).sum();
    let t = if quad > 0.0 {
        (-lin / quad).clamp(0.0, 1.0)
    } else {
        0.0
    };
    if t > 0.0 {
        for &r in &order {
            current[r] = origin[r] + t * step[r];
        }
    }
    Some(t)
}

/// K_ff δ_f = −g_f over the movable points, unknowns in `order`.
fn normal_equations<K: LocalStiffness>(
    k: &K,
    order: &[usize],
    movable: &[bool],
    g: &[Vector3],
) -> (Csc, DMatrix<f64>) {
    let (nu, nv) = k.shape();
    let (wu, wv) = k.half_widths();
    assemble(order, movable, g, (wu, wv), |r, emit| {
        let (i, j) = (r / nv, r % nv);
        for si in i.saturating_sub(wu)..=(i + wu).min(nu - 1) {
            for sj in j.saturating_sub(wv)..=(j + wv).min(nv - 1) {
                emit(si * nv + sj, k.entry((i, j), (si, sj)));
            }
        }
    })
}
