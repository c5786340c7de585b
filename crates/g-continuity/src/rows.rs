//! The row equations of one side: C0 (row 0), G1 (row 1, [SV] §4.1) and G2 (row 2, [SV] §4.2).
//! This module solves one row (and repeats the G1 passes); the systems are built per sample in
//! `system.rs` (a C0, G1 and G2 builder) and the G2 weight ladder is solved in `ladder.rs`.
//!
//! Notation for a side `u0` (the other sides are the same with u/v and the row order swapped):
//! samples t_k along the side, along-side basis M_j(t), row coefficients a_r = N_r^{(r)}(c)
//! ([`crate::sampling::SideBasis`]), master foot point with unit normal n_k (from projection).
//! - **C0**: Σ_j a_0 M_j(t_k) δ_j = Q_k − S(c, t_k) with Q_k the master point: three right-hand
//!   sides of one K × m matrix, solved by QR. The foot points move with the row, so the callers
//!   repeat this step a few times.
//! - **G1**, eq. (1)–(3): moving row 1 by w_j changes the cross derivative e_k = S_u(c, t_k) by
//!   a_1 Σ_j M_j(t_k) w_j; we require n_k · ê_k = 0, scaled by 1/|e_k| so that the residual is
//!   the sine of the remaining angle: (a_1/|e_k|) Σ_j M_j(t_k) n_k · w_j = −n_k · e_k / |e_k|,
//!   and, with the small weight [`G1_TANGENTIAL_WEIGHT`], that the tangential part of e_k stays:
//!   (a_1/|e_k|) Σ_j M_j(t_k) τ · w_j = 0 for the master's unit tangents τ = t1, t2. QR, repeated
//!   from the updated row with smaller weights while the moves stay plausible ([`G1_PASSES`],
//!   [`G1_POLISH_MOVE_FACTOR`]).
//! - **G2**, eq. (4)–(5): with rows 0–1 fixed the slave normal n_k and E_k = |e_k|² are fixed and
//!   κ_s = S_uu · n_k / E_k is linear in row 2: (a_2/E_k) Σ_j M_j(t_k) n_k · d_j = κ_k^M − κ_k^S,
//!   where κ^M is the master's normal curvature in the 3D direction e_k, signed w.r.t. n_k.
//!   *Fixed directions*: d_j = χ_j D_j with D_j the slave normal at the Greville abscissa of j
//!   (the paper's first choice), a K × m system solved by QR. *Minimal deviation*: d_j free in 3D.
//!
//! # Deviation from the paper
//! The paper's G1 system prescribes the whole displacement vector −n_k (e_k · n_k) of every
//! cross derivative (3K equations), and its minimal-deviation G2 system the vector β_k n_k. These
//! vectors are generally not in the spline space, so the fit leaves a residual even when an exact
//! G1/G2 solution exists. We impose the scalar conditions that define G1/G2 with full weight.
//! For G1 the paper's tangential rows stay, down-weighted (the scalar condition alone would
//! allow the cross derivative to collapse). For G2 the paper's tangential rows stay too (weight
//! 1 first: the paper's system), then are relaxed step by step towards the scalar condition alone
//! while the moves stay of the size of the first solution's ([`G2_WEIGHT_LADDER`],
//! [`G2_MOVE_FACTOR`]): exact where an exact join needs comparable moves, never the huge
//! tangential moves the scalar condition alone asks for when its right-hand side is not in the
//! spline space (its tangential directions are determined only through the variation of n_k).

use nurbs_core::{BSplineSurface, Continuity, Side, Vector3};

use crate::error::{Error, Result};
/// The weight ladder lives with its solver (ladder.rs), re-exported here.
pub use crate::ladder::G2_WEIGHT_LADDER;
/// The defaults of [`SetParams`] live with it (params.rs), re-exported here where the row solves use them.
pub use crate::params::{G1_PASSES, G1_TANGENTIAL_WEIGHT, G2_MOVE_FACTOR, G2_TANGENTIAL_WEIGHT};
use crate::params::{G2Method, SetParams};
use crate::sampling::{SideBasis, solve_side_params};
use crate::system::{RowContext, RowSystem, fixed_directions, movable_columns, point_moves};

/// Displacements of some control points of one row.
#[derive(Debug, Clone, PartialEq)]
pub struct RowMove {
    /// the side
    pub side: Side,
    /// control indices (i, j) that move
    pub indices: Vec<(usize, usize)>,
    /// their displacements, in the same order
    pub displacements: Vec<Vector3>,
    /// G1: the largest correction the condition asks for, max_k |n_k · e_k| / |a_1| (model
    /// units); 0 for the other steps
    pub needed: f64,
    /// G2 with tangential moves (the weight search over [`G2_WEIGHT_LADDER`]): the smallest
    /// ratio, to the weight-1 solution's largest move, of a lighter-weighted solution the
    /// search rejected; ∞ when it rejected none and on the other steps. A move factor below
    /// this value picks the same solution.
    pub g2_slack: f64,
}

impl RowMove {
    /// A row that does not move (nothing free, or already in place).
    fn still(side: Side) -> Self {
        Self {
            side,
            indices: Vec::new(),
            displacements: Vec::new(),
            needed: 0.0,
            g2_slack: f64::INFINITY,
        }
    }

    /// Applies the displacements to `surface`.
    pub fn apply(&self, surface: &mut BSplineSurface) {
        let nv = surface.num_v();
        let pts = surface.control_points_mut();
        for (&(i, j), d) in self.indices.iter().zip(&self.displacements) {
            pts[i * nv + j] += d;
        }
    }

    /// Largest displacement length.
    pub fn max_displacement(&self) -> f64 {
        self.displacements
            .iter()
            .map(|d| d.norm())
            .fold(0.0, f64::max)
    }
}

/// Index of the control row a step moves: 0 for G0, 1 for G1, 2 for G2.
pub fn row_of(step: Continuity) -> usize {
    match step {
        Continuity::G0 => 0,
        Continuity::G1 => 1,
        Continuity::G2 => 2,
    }
}

/// Factor by which the tangential weight shrinks from one G1 pass to the next.
pub const G1_WEIGHT_STEP: f64 = 1e-2;

/// A later G1 pass is accepted only when no point moves more than this factor times the largest
/// move of the first pass: larger moves mean the pass fits noise (e.g. the boundary's own C0
/// error) with weakly determined directions instead of polishing the solution.
pub const G1_POLISH_MOVE_FACTOR: f64 = 0.5;

/// Solves the row equations of `step` for `side` of `slave` on `master`, moving only the along
/// indices j with `movable[j]`.
pub fn solve_row(
    master: &BSplineSurface,
    slave: &BSplineSurface,
    side: Side,
    step: Continuity,
    movable: &[bool],
    params: &SetParams,
) -> Result<RowMove> {
    solve_row_in(master, slave, side, None, step, movable, params)
}

/// [`solve_row`] with the equations at the samples of the part `range` of the side only (an
/// along-side parameter interval, `None`: the whole side): the solve samples that fall inside
/// it, and its two ends.
pub fn solve_row_in(
    master: &BSplineSurface,
    slave: &BSplineSurface,
    side: Side,
    range: Option<(f64, f64)>,
    step: Continuity,
    movable: &[bool],
    params: &SetParams,
) -> Result<RowMove> {
    let ranged: Option<Vec<f64>> = range.map(|_| {
        let (x, y) = crate::sampling::side_part(slave, side, range);
        let mut ts: Vec<f64> = vec![x];
        ts.extend(
            solve_side_params(slave, side, params.samples_per_span, params.min_samples)
                .into_iter()
                .filter(|&t| t > x && t < y),
        );
        ts.push(y);
        ts
    });
    let samples = ranged.as_deref();
    let mut total = solve_row_once(master, slave, side, step, movable, samples, params)?;
    if step != Continuity::G1 || total.indices.is_empty() {
        return Ok(total);
    }
    let mut work = slave.clone();
    total.apply(&mut work);
    let mut pass_params = *params;
    let first_move = total.max_displacement();
    for _ in 1..params.g1_passes.max(1) {
        pass_params.g1_tangential_weight *= G1_WEIGHT_STEP;
        let more = solve_row_once(master, &work, side, step, movable, samples, &pass_params)?;
        if more.max_displacement() > G1_POLISH_MOVE_FACTOR * first_move {
            break;
        }
        more.apply(&mut work);
        for (d, e) in total.displacements.iter_mut().zip(&more.displacements) {
            *d += e;
        }
    }
    Ok(total)
}

/// Solves the row equations of `step` at the given side parameters `ts` only (e.g. a corner
/// sample), moving only the along indices j with `movable[j]`. Used for the end point of a row on
/// an unlinked neighbouring side: solved at the corner alone, it moves along the slave normal by
/// exactly the correction that corner needs (nothing when the corner is already continuous).
pub fn solve_row_at(
    master: &BSplineSurface,
    slave: &BSplineSurface,
    side: Side,
    step: Continuity,
    movable: &[bool],
    ts: &[f64],
    params: &SetParams,
) -> Result<RowMove> {
    solve_row_once(master, slave, side, step, movable, Some(ts), params)
}

fn solve_row_once(
    master: &BSplineSurface,
    slave: &BSplineSurface,
    side: Side,
    step: Continuity,
    movable: &[bool],
    samples: Option<&[f64]>,
    params: &SetParams,
) -> Result<RowMove> {
    let k = row_of(step);
    let row = side.row(k, slave.num_u(), slave.num_v());
    let (column, indices) = movable_columns(&row, movable);
    let free = indices.len();
    if free == 0 {
        return Ok(RowMove::still(side));
    }
    let mut basis = SideBasis::new(slave, side);
    let a_k = basis.row_coefficient[k];
    if a_k == 0.0 {
        return Err(Error::SingularSystem {
            side,
            target: step,
            reason: format!("the degree across the side is below {k}"),
        });
    }
    let ts = samples.map_or_else(
        || solve_side_params(slave, side, params.samples_per_span, params.min_samples),
        <[f64]>::to_vec,
    );
    let mut slave_eval = slave.evaluator();
    let directions = if step == Continuity::G2 && params.g2_method == G2Method::FixedDirections {
        fixed_directions(slave, side, &basis, row.len(), &mut slave_eval)
    } else {
        Vec::new()
    };
    let mut sys = RowSystem::new(step, params, ts.len(), free, a_k);
    let ctx = RowContext {
        master,
        slave,
        side,
        step,
        k,
        column: &column,
        directions: &directions,
        params,
    };
    sys.fill(&ctx, &ts, &mut basis, &mut slave_eval);
    if step == Continuity::G0 && {
        let exact = crate::slave::C0_EXACT * slave.size();
        sys.b.iter().all(|d| d.abs() <= exact)
    } {
        // already on the master: keep the row bit-identical
        return Ok(RowMove::still(side));
    }
    let (needed, unknowns) = (sys.needed, sys.unknowns);
    let (x, g2_slack) =
        sys.solve(params.g2_move_factor)
            .map_err(|reason| Error::SingularSystem {
                side,
                target: step,
                reason,
            })?;
    let displacements = point_moves(&x, step, unknowns, &row, &indices, &directions);
    if displacements
        .iter()
        .any(|d| !d.iter().all(|x| x.is_finite()))
    {
        return Err(Error::NonFiniteSolution { side, target: step });
    }
    Ok(RowMove {
        side,
        indices,
        displacements,
        needed,
        g2_slack,
    })
}
