//! The global variant `energy-global`: all free control points at once.
//!
//! Minimize E(d) + w Σ_{r free} |d_r − o_r|² with E(d) = Σ_c x_cᵀ K x_c (the thin plate of
//! [`crate::stiffness`]) and o the original points. Writing d = o + δ (δ = 0 on fixed points) and
//! g = K o, the normal equations are (K_ff + w I) δ_f = −g_f, one right-hand side per coordinate,
//! symmetric positive definite for w > 0, solved by a sparse Cholesky factorization with a
//! fill-reducing order ([`SparseSolver`]).
//!
//! A rational surface keeps its weights: K is then the quadratic form of [`RationalStiffness`]
//! (not separable; assembled from its stencils), as in the local scheme.
//!
//! Points whose solved displacement leaves the ball of radius ε are held on it (in the
//! direction they moved) and the others solved again ([`GlobalParams::active_set_rounds`]).
//! Afterwards every displacement is within the ball of radius ε, and a line search along
//! d(t) = o + t Δ (Δ the clamped displacement; E(t) = E₀ + 2t Δ·g + t² ΔᵀKΔ is a parabola,
//! t ∈ [0, 1] keeps every point in its ball) makes sure the energy never exceeds the original.
//! Optionally the local scheme of [`crate::local`] polishes the result inside the same balls.
//!
//! # Deviation from the paper
//! \[SV\] §5.2 minimizes the energy of all free points at once without the deviation term; w
//! keeps the system definite when the mask frees whole regions and pulls the result towards the
//! original, so that clamping to ε changes it less.
//!
//! # Tolerance
//! w = `deviation_weight` × the mean diagonal entry of K_ff: a relative, unit-free weight.

use nalgebra::DMatrix;
use nurbs_core::{
    BSplineSurface, ControlMask, Faired, FairingProblem, Point3, SurfaceFairing, Vector3,
};

use crate::error::{EnergyError, Result, check_tolerance};
use crate::local::{
    BALL_SHRINK, LocalSettings, LocalStiffness, NULL_DIAGONAL_REL, StopReason, run_local,
};
use crate::ordering::nested_dissection;
use crate::rational::RationalStiffness;
use crate::stiffness::SeparableStiffness;

/// The sparse Cholesky implementation of the global solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SparseSolver {
    /// nalgebra-sparse's left-looking Cholesky after our nested-dissection order
    /// (`crate::ordering`)
    NalgebraSparse,
    /// faer's supernodal/simplicial Cholesky with its AMD order (feature `faer`)
    #[cfg(feature = "faer")]
    Faer,
}

impl SparseSolver {
    /// The faster solver on the benchmarks of `docs/benchmarks.md`.
    pub const FASTEST: SparseSolver = {
        #[cfg(feature = "faer")]
        {
            SparseSolver::Faer
        }
        #[cfg(not(feature = "faer"))]
        {
            SparseSolver::NalgebraSparse
        }
    };

    fn name(self) -> &'static str {
        match self {
            SparseSolver::NalgebraSparse => "nalgebra-sparse",
            #[cfg(feature = "faer")]
            SparseSolver::Faer => "faer",
        }
    }
}

/// Settings of the global variant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlobalParams {
    /// w relative to the mean diagonal of K_ff (unit-free, > 0). Default 1e-3: small enough that
    /// noise at the control-point scale is smoothed away, large enough to keep the overall shape;
    /// on \[H\]'s 52×52 example (ε = 0.02) no move needs clamping (`docs/benchmarks.md`).
    pub deviation_weight: f64,
    /// Which sparse Cholesky. Default: [`SparseSolver::FASTEST`].
    pub solver: SparseSolver,
    /// Local-scheme moves after the solve (inside the same ε-balls). Default 0.
    pub polish_iterations: usize,
    /// Active-set rounds: after a solve, the points that left their ε-ball are held on its
    /// surface (in the direction they moved) and the others solved again, until no further
    /// point leaves or the rounds are spent. Default [`ACTIVE_SET_ROUNDS`]; 0 clamps the first
    /// solve alone (the scheme before the rounds).
    pub active_set_rounds: usize,
}

/// Default [`GlobalParams::active_set_rounds`]: 8. Clamping a solution that left its balls
/// shortens each offending move on its own, so where the balls bind over a region the clamped
/// net keeps the unconstrained solve's shape at the region's edge, where the held and the free
/// points meet. Re-solving the free points against the held ones lets them take the held
/// points' places into account: the result is the minimum with those points held, its energy
/// no higher than the single clamp's on the tests' noisy nets (`tests/global.rs`). Each round
/// holds at least one more point, so the rounds end; eight bounds the cost (one sparse
/// factorization each).
pub const ACTIVE_SET_ROUNDS: usize = 8;

impl Default for GlobalParams {
    fn default() -> Self {
        Self {
            deviation_weight: 1e-3,
            solver: SparseSolver::FASTEST,
            polish_iterations: 0,
            active_set_rounds: ACTIVE_SET_ROUNDS,
        }
    }
}

impl GlobalParams {
    /// Bad input unless `deviation_weight` is finite and > 0.
    fn check(&self) -> Result<()> {
        if !(self.deviation_weight.is_finite() && self.deviation_weight > 0.0) {
            return Err(EnergyError::InvalidParameter {
                name: "deviation_weight",
                value: self.deviation_weight,
                expected: "finite and > 0",
            });
        }
        Ok(())
    }
}

/// What a global run achieved (thin-plate energies).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlobalReport {
    /// number of unknown control points
    pub free_points: usize,
    /// energy before
    pub energy_before: f64,
    /// energy after clamping, line search and polishing
    pub energy_after: f64,
    /// how many points the ε-clamp moved back (held on their balls by the active-set rounds,
    /// or shortened after the last solve)
    pub clamped_points: usize,
    /// solves made (1 + the active-set rounds that found a point leaving its ball)
    pub solves: usize,
    /// the line-search step t ∈ [0, 1] (1 = clamped solution kept as is)
    pub step: f64,
    /// local moves made while polishing
    pub polish_iterations: usize,
    /// largest control-point displacement (model units)
    pub max_control_move: f64,
}

/// A symmetric matrix in compressed sparse columns (both triangles, rows sorted per column).
pub(crate) struct Csc {
    pub(crate) n: usize,
    pub(crate) col_ptr: Vec<usize>,
    pub(crate) row_idx: Vec<usize>,
    pub(crate) values: Vec<f64>,
}

/// Solves A x = b (A symmetric positive definite, unknowns already in elimination order) with
/// the shared sparse Cholesky of nurbs-core.
pub(crate) fn solve(solver: SparseSolver, a: Csc, rhs: DMatrix<f64>) -> Result<DMatrix<f64>> {
    use nurbs_core::sparse::{SparseSpd, SpdSolver};
    let failed = |e: nurbs_core::Error| EnergyError::SolveFailed {
        solver: solver.name(),
        reason: e.to_string(),
    };
    let matrix = SparseSpd::from_csc(a.n, a.col_ptr, a.row_idx, a.values).map_err(failed)?;
    let backend = match solver {
        SparseSolver::NalgebraSparse => SpdSolver::NalgebraSparse,
        #[cfg(feature = "faer")]
        SparseSolver::Faer => {
            use nurbs_core::sparse::FillOrdering;
            SpdSolver::Faer(if FAER_ORDERING_AMD {
                FillOrdering::Amd
            } else {
                FillOrdering::Natural
            })
        }
    };
    matrix.solve(&rhs, backend).map_err(failed)
}

/// Whether faer reorders with AMD (true) or keeps our nested-dissection order (false); see
/// `docs/benchmarks.md` for the measurement that chose it.
#[cfg(feature = "faer")]
const FAER_ORDERING_AMD: bool = false;

/// Fairs `surface` by one global solve, moving only points `mask` frees, each within `tolerance`
/// (model units) of its original; energy never increases. A rational surface keeps its weights
/// (the functional is then the quadratic form of [`RationalStiffness`], as for the local
/// scheme).
pub fn fair_surface_global(
    surface: &BSplineSurface,
    mask: &ControlMask,
    tolerance: f64,
    params: &GlobalParams,
) -> Result<(BSplineSurface, GlobalReport)> {
    check_tolerance(tolerance)?;
    params.check()?;
    mask.check_shape(surface)?;
    if surface.is_rational() {
        let k = RationalStiffness::thin_plate_shared(surface);
        global_with(k.as_ref(), surface, mask, tolerance, params)
    } else {
        let k = SeparableStiffness::thin_plate(surface.knots_u(), surface.knots_v())?;
        global_with(&k, surface, mask, tolerance, params)
    }
}

/// [`fair_surface_global`] with the functional's matrix `k`.
fn global_with<K: LocalStiffness>(
    k: &K,
    surface: &BSplineSurface,
    mask: &ControlMask,
    tolerance: f64,
    params: &GlobalParams,
) -> Result<(BSplineSurface, GlobalReport)> {
    let (nu, nv) = (surface.num_u(), surface.num_v());
    let n = nu * nv;
    let origin = surface.control_points();
    let mut g = vec![Vector3::zeros(); n];
    k.multiply(origin, &mut g);
    let energy_before: f64 = origin.iter().zip(&g).map(|(p, v)| p.coords.dot(v)).sum();
    let free = mask.as_slice();
    let diag: Vec<f64> = (0..n).map(|r| k.diagonal(r)).collect();
    let diag_cut = NULL_DIAGONAL_REL * diag.iter().cloned().fold(0.0, f64::max);
    let movable: Vec<bool> = (0..n).map(|r| free[r] && diag[r] > diag_cut).collect();
    let order = nested_dissection(nu, nv, &movable, k.half_widths());
    let nf = order.len();
    let mut out = surface.clone();
    let mut report = GlobalReport {
        free_points: nf,
        energy_before,
        energy_after: energy_before,
        clamped_points: 0,
        solves: 0,
        step: 0.0,
        polish_iterations: 0,
        max_control_move: 0.0,
    };
    if nf == 0 {
        return Ok((out, report));
    }
    let w = params.deviation_weight * order.iter().map(|&r| diag[r]).sum::<f64>() / nf as f64;
    let step_points = active_set_step(k, (nu, nv), &movable, origin, w, tolerance, params).map(
        |(step, solves, held)| {
            report.solves = solves;
            report.clamped_points = held;
            step
        },
    )?;
    let (t, lin, quad) = line_search(k, &step_points, &g);
    report.step = t;
    {
        let points = out.control_points_mut();
        for &r in &order {
            points[r] = origin[r] + t * step_points[r].coords;
        }
    }
    // E(t) = E₀ + 2t Δ·g + t² ΔᵀKΔ
    report.energy_after = energy_before + 2.0 * t * lin + t * t * quad;
    if params.polish_iterations > 0 {
        let settings = LocalSettings {
            tolerance,
            max_iterations: params.polish_iterations,
            min_relative_decrease: 0.0,
        };
        let outcome = run_local(k, origin, out.control_points_mut(), &movable, settings);
        if outcome.stop != StopReason::NothingFree {
            report.polish_iterations = outcome.iterations;
            report.energy_after = outcome.energy_after;
        }
    }
    report.max_control_move = nurbs_core::fairing::max_displacement(origin, out.control_points());
    Ok((out, report))
}

/// The displacement Δ of every point (zero where fixed) from the solve and its active-set
/// rounds ([`GlobalParams::active_set_rounds`]), each within ε · [`BALL_SHRINK`]; with the
/// number of solves and of points held on their balls. A round solves
/// (K_ff + w I) δ_f = −(K b)_f over the points still free, b the original net with the held
/// points displaced: the minimum of E + w Σ_f |δ_f|² with the held points where they are.
fn active_set_step<K: LocalStiffness>(
    k: &K,
    (nu, nv): (usize, usize),
    movable: &[bool],
    origin: &[Point3],
    w: f64,
    tolerance: f64,
    params: &GlobalParams,
) -> Result<(Vec<Point3>, usize, usize)> {
    let n = movable.len();
    let bound = tolerance * BALL_SHRINK;
    let mut free = movable.to_vec();
    let mut step = vec![Point3::origin(); n];
    let mut held = 0;
    let mut solves = 0;
    loop {
        // b = o + Δ_held, g = K b
        let base: Vec<Point3> = (0..n)
            .map(|r| {
                if free[r] {
                    origin[r]
                } else {
                    origin[r] + step[r].coords
                }
            })
            .collect();
        let mut g = vec![Vector3::zeros(); n];
        k.multiply(&base, &mut g);
        let order = nested_dissection(nu, nv, &free, k.half_widths());
        if order.is_empty() {
            break;
        }
        let (a, rhs) = normal_equations(k, &order, &free, w, &g, nv);
        let delta = solve(params.solver, a, rhs)?;
        solves += 1;
        let last = solves > params.active_set_rounds;
        let mut left = 0;
        for (c, &r) in order.iter().enumerate() {
            let v = Vector3::new(delta[(c, 0)], delta[(c, 1)], delta[(c, 2)]);
            let len = v.norm();
            if len > bound {
                // held on its ball, in the direction it moved
                step[r] = Point3::from(v * (bound / len));
                free[r] = false;
                left += 1;
            } else {
                step[r] = Point3::from(v);
            }
        }
        held += left;
        if left == 0 || last {
            break;
        }
    }
    Ok((step, solves, held))
}

/// The normal equations (K_ff + w I) δ_f = −g_f over the movable points, unknowns in `order`
/// (the elimination order): the matrix in compressed columns and one right-hand side per
/// coordinate.
fn normal_equations<K: LocalStiffness>(
    k: &K,
    order: &[usize],
    movable: &[bool],
    w: f64,
    g: &[Vector3],
    nv: usize,
) -> (Csc, DMatrix<f64>) {
    let (nu, (wu, wv)) = (k.shape().0, k.half_widths());
    let mut stencil = k.new_stencil();
    assemble(order, movable, g, (wu, wv), |r, emit| {
        let (i, j) = (r / nv, r % nv);
        k.load(i, j, &mut stencil);
        let (i0, i1) = (i.saturating_sub(wu), (i + wu).min(nu - 1));
        let (j0, j1) = (j.saturating_sub(wv), (j + wv).min(nv - 1));
        for (a, row_i) in (i0..=i1).enumerate() {
            for (col_j, kij) in (j0..=j1).zip(k.row(&stencil, a)) {
                let s_ = row_i * nv + col_j;
                emit(s_, kij + if s_ == r { w } else { 0.0 });
            }
        }
    })
}

/// The sparse system over the movable points, unknowns in `order`: `column(r, emit)` emits the
/// entries (s, K_rs) of point r's column (any order; entries of fixed points and zeros are
/// dropped here), the right-hand side is −g_f. `half_widths` bounds a column's length.
pub(crate) fn assemble(
    order: &[usize],
    movable: &[bool],
    g: &[Vector3],
    (wu, wv): (usize, usize),
    mut column_of: impl FnMut(usize, &mut dyn FnMut(usize, f64)),
) -> (Csc, DMatrix<f64>) {
    let nf = order.len();
    let mut col = vec![usize::MAX; movable.len()];
    for (c, &r) in order.iter().enumerate() {
        col[r] = c;
    }
    let stencil = (2 * wu + 1) * (2 * wv + 1);
    let mut a = Csc {
        n: nf,
        col_ptr: Vec::with_capacity(nf + 1),
        row_idx: Vec::with_capacity(nf * stencil),
        values: Vec::with_capacity(nf * stencil),
    };
    a.col_ptr.push(0);
    let mut column: Vec<(usize, f64)> = Vec::with_capacity(stencil);
    let mut rhs = DMatrix::zeros(nf, 3);
    for (c, &r) in order.iter().enumerate() {
        column.clear();
        column_of(r, &mut |s_, value| {
            if movable[s_] && value != 0.0 {
                column.push((col[s_], value));
            }
        });
        column.sort_unstable_by_key(|e| e.0);
        for &(row, value) in &column {
            a.row_idx.push(row);
            a.values.push(value);
        }
        a.col_ptr.push(a.row_idx.len());
        for d in 0..3 {
            rhs[(c, d)] = -g[r][d];
        }
    }
    (a, rhs)
}

/// The step t ∈ [0, 1] minimizing E(o + t Δ) = E₀ + 2t Δ·g + t² ΔᵀKΔ, with Δ·g and ΔᵀKΔ.
fn line_search<K: LocalStiffness>(k: &K, step_points: &[Point3], g: &[Vector3]) -> (f64, f64, f64) {
    let mut kd = vec![Vector3::zeros(); step_points.len()];
    k.multiply(step_points, &mut kd);
    let lin: f64 = step_points
        .iter()
        .zip(g)
        .map(|(p, v)| p.coords.dot(v))
        .sum();
    let quad: f64 = step_points
        .iter()
        .zip(&kd)
        .map(|(p, v)| p.coords.dot(v))
        .sum();
    let t = if quad > 0.0 {
        (-lin / quad).clamp(0.0, 1.0)
    } else if lin < 0.0 {
        1.0
    } else {
        0.0
    };
    (t, lin, quad)
}

/// The global energy fairing method (`energy-global`) for the framework.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GlobalEnergyFairing {
    /// its settings
    pub params: GlobalParams,
}

/// Name of the global method.
pub const GLOBAL_METHOD: &str = "energy-global";

impl SurfaceFairing for GlobalEnergyFairing {
    fn name(&self) -> &str {
        GLOBAL_METHOD
    }

    /// `max_iterations` limits the polishing moves after the solve.
    fn fair(&self, problem: &FairingProblem<'_>) -> nurbs_core::Result<Faired> {
        let mut params = self.params;
        if let Some(n) = problem.max_iterations {
            params.polish_iterations = n;
        }
        let (out, r) =
            fair_surface_global(problem.surface, problem.mask, problem.tolerance, &params)
                .map_err(|e| e.into_core(GLOBAL_METHOD))?;
        // one solve plus the polishing moves; nothing free means nothing was done
        let iterations = if r.free_points == 0 {
            0
        } else {
            1 + r.polish_iterations
        };
        Ok(Faired::new(out, iterations))
    }
}
