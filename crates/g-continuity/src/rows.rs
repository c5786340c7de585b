//! The row equations of one side: C0 (row 0), G1 (row 1, [SV] §4.1) and G2 (row 2, [SV] §4.2).
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

use nalgebra::DMatrix;
use nurbs_core::{BSplineSurface, BandedQr, Continuity, Side, Vector3};

use crate::error::{Error, Result};
use crate::lsq::{
    SINGULAR_RELATIVE, banded_factor, banded_solve_with, solve_least_squares, solve_min_norm,
};
use crate::measure::cross_derivative;
use crate::params::{G2Method, SetParams};
use crate::sampling::{MasterTracker, SideBasis, solve_side_params};

/// Weight of the G1 rows that keep the tangential part of the cross derivative, relative to the
/// rows of the G1 condition itself. The condition n·ê = 0 alone admits ê = 0 (a collapsed
/// cross derivative); the paper keeps the tangential part exactly ([SV] eq. (3)). A small weight
/// keeps it as far as the condition allows: the remaining normal residual is of order
/// weight² × the tangential change an exact join needs. Too small a weight lets the solve fit
/// noise with huge tangential moves (1e-6 moved a car-shell row by 3 units); 1e-2 is safe, and
/// the later passes shrink it where the moves stay plausible.
pub const G1_TANGENTIAL_WEIGHT: f64 = 1e-2;

/// Weight of the minimal-deviation G2 rows that keep the tangential part of the change of the
/// curvature row at each sample, relative to the rows of the G2 condition (default of
/// [`SetParams::g2_tangential_weight`]). With weight 1 the system is the paper's ([SV] §4.2):
/// the change Σ_j M_j(t_k) d_j is to be the normal vector β_k n_k, a well-conditioned fit.
pub const G2_TANGENTIAL_WEIGHT: f64 = 1.0;

/// Factors applied to [`SetParams::g2_tangential_weight`] after the first G2 solve, from the
/// heaviest to the lightest: each lets the tangential components help the scalar condition more,
/// with less conditioning. The lightest, 1e-8, stands for the scalar condition alone: its
/// remaining scalar residual is of order weight² (1e-16) times the tangential change, and among
/// the solutions of the scalar rows it picks the one with the least tangential change (where
/// the scalar rows leave directions free, as the minimum-norm solution would, but without an SVD).
pub const G2_WEIGHT_LADDER: [f64; 6] = [1e-1, 1e-2, 1e-3, 1e-4, 1e-6, 1e-8];

/// Default of [`SetParams::g2_move_factor`]: a lighter-weighted G2 solution is accepted only while
/// no point moves more than this factor times the largest move of the first (weight 1) solution.
pub const G2_MOVE_FACTOR: f64 = 2.0;

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

/// Passes of the G1 solve (default of [`SetParams::g1_passes`]): the first with the tangential
/// weight of the parameters, each further one from the previous result with the weight divided
/// by [`G1_WEIGHT_STEP`] (a continuation towards the exact G1 condition).
pub const G1_PASSES: usize = 3;

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
    let m = row.len();
    let mut column = vec![usize::MAX; m];
    let mut indices = Vec::new();
    for j in 0..m {
        if movable.get(j).copied().unwrap_or(false) {
            column[j] = indices.len();
            indices.push(row[j]);
        }
    }
    let free = indices.len();
    if free == 0 {
        return Ok(RowMove {
            side,
            indices,
            displacements: Vec::new(),
            needed: 0.0,
            g2_slack: f64::INFINITY,
        });
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
    let q = basis.along_degree();
    let mut mvals = vec![0.0; q + 1];
    let mut tracker = MasterTracker::new(master, params.projection);
    let mut slave_eval = slave.evaluator();
    let mut master_eval = master.evaluator();
    let singular = |reason: String| Error::SingularSystem {
        side,
        target: step,
        reason,
    };

    // fixed directions of the G2 variant: the slave normal at the Greville abscissae
    let directions: Vec<Vector3> =
        if step == Continuity::G2 && params.g2_method == G2Method::FixedDirections {
            (0..m)
                .map(|j| {
                    let (u, v) = side.params(slave, basis.greville(j));
                    slave_eval
                        .derivatives(u, v)
                        .normal()
                        .unwrap_or_else(Vector3::zeros)
                })
                .collect()
        } else {
            Vec::new()
        };

    let unknowns_per_point = match step {
        Continuity::G0 => 1,
        Continuity::G1 => 3,
        Continuity::G2 => {
            if params.g2_method == G2Method::FixedDirections {
                1
            } else {
                3
            }
        }
    };
    let rhs_cols = if step == Continuity::G0 { 3 } else { 1 };
    let rows = ts.len();
    let mut needed = 0.0f64;
    // G1 adds two down-weighted rows per sample that keep the tangential part of e_k
    let g2_tangential = step == Continuity::G2 && unknowns_per_point == 3;
    let total_rows = if step == Continuity::G1 || g2_tangential {
        3 * rows
    } else {
        rows
    };
    let mut a = DMatrix::<f64>::zeros(total_rows, free * unknowns_per_point);
    let mut b = DMatrix::<f64>::zeros(total_rows, rhs_cols);
    for (r, &t) in ts.iter().enumerate() {
        let (u, v) = side.params(slave, t);
        let ds = slave_eval.evaluate(u, v, if step == Continuity::G2 { 2 } else { 1 });
        let proj = tracker.project(&ds.point);
        let first = basis.row_basis(k, t, &mut mvals);
        match step {
            Continuity::G0 => {
                for (l, &mv) in mvals.iter().enumerate() {
                    let c = column[first + l];
                    if c != usize::MAX {
                        a[(r, c)] = a_k * mv;
                    }
                }
                let diff = proj.point - ds.point;
                for d in 0..3 {
                    b[(r, d)] = diff[d];
                }
            }
            Continuity::G1 => {
                let dm = master_eval.evaluate(proj.u, proj.v, 1);
                let (Some(n), e) = (dm.normal(), cross_derivative(&ds, side)) else {
                    continue;
                };
                let len = e.norm();
                if !(len > 0.0) {
                    continue;
                }
                let t1 = (dm.du - n * n.dot(&dm.du)).normalize();
                let t2 = n.cross(&t1);
                let w = params.g1_tangential_weight;
                for (l, &mv) in mvals.iter().enumerate() {
                    let c = column[first + l];
                    if c != usize::MAX {
                        let f = a_k * mv / len;
                        for d in 0..3 {
                            a[(r, 3 * c + d)] = f * n[d];
                            a[(rows + 2 * r, 3 * c + d)] = w * f * t1[d];
                            a[(rows + 2 * r + 1, 3 * c + d)] = w * f * t2[d];
                        }
                    }
                }
                b[(r, 0)] = -n.dot(&e) / len;
                needed = needed.max(n.dot(&e).abs() / a_k.abs());
            }
            Continuity::G2 => {
                let dm = master_eval.derivatives(proj.u, proj.v);
                let e = cross_derivative(&ds, side);
                let (Some(ns), Some(nm)) = (ds.normal(), dm.normal()) else {
                    continue;
                };
                let Some(km) = dm.normal_curvature(&e) else {
                    continue;
                };
                let km = if nm.dot(&ns) < 0.0 { -km } else { km };
                let big_e = e.norm_squared();
                let second = match side.cross_direction() {
                    nurbs_core::Direction::U => ds.duu,
                    nurbs_core::Direction::V => ds.dvv,
                };
                let ks = second.dot(&ns) / big_e;
                // unit tangents of the slave at the sample: the cross direction and the
                // along-side direction (perpendicular to it)
                let (t1, t2) = match (e - ns * ns.dot(&e)).try_normalize(f64::EPSILON) {
                    Some(t1) => (t1, ns.cross(&t1)),
                    None => (Vector3::zeros(), Vector3::zeros()),
                };
                let w = params.g2_tangential_weight;
                for (l, &mv) in mvals.iter().enumerate() {
                    let j = first + l;
                    let c = column[j];
                    if c == usize::MAX {
                        continue;
                    }
                    let coef = a_k * mv / big_e;
                    if unknowns_per_point == 1 {
                        a[(r, c)] = coef * ns.dot(&directions[j]);
                    } else {
                        for d in 0..3 {
                            a[(r, 3 * c + d)] = coef * ns[d];
                            a[(rows + 2 * r, 3 * c + d)] = w * coef * t1[d];
                            a[(rows + 2 * r + 1, 3 * c + d)] = w * coef * t2[d];
                        }
                    }
                }
                b[(r, 0)] = km - ks;
            }
        }
    }
    if step == Continuity::G0 && {
        let exact = crate::slave::C0_EXACT * slave.size();
        b.iter().all(|d| d.abs() <= exact)
    } {
        // already on the master: keep the row bit-identical
        return Ok(RowMove {
            side,
            indices: Vec::new(),
            displacements: Vec::new(),
            needed: 0.0,
            g2_slack: f64::INFINITY,
        });
    }
    let (x, g2_slack) = if g2_tangential {
        solve_g2_ladder(a, &b, rows, params.g2_move_factor)
    } else {
        solve_least_squares(a, &b).map(|x| (x, f64::INFINITY))
    }
    .map_err(singular)?;
    let displacements: Vec<Vector3> = (0..free)
        .map(|c| match (step, unknowns_per_point) {
            (Continuity::G0, _) => Vector3::new(x[(c, 0)], x[(c, 1)], x[(c, 2)]),
            (_, 3) => Vector3::new(x[(3 * c, 0)], x[(3 * c + 1, 0)], x[(3 * c + 2, 0)]),
            _ => {
                let j = row.iter().position(|&ij| ij == indices[c]).unwrap_or(0);
                directions[j] * x[(c, 0)]
            }
        })
        .collect();
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

/// Largest 3D displacement of a stacked solution (x, y, z per point).
fn largest_point_move(x: &DMatrix<f64>) -> f64 {
    (0..x.nrows() / 3)
        .map(|c| {
            (x[(3 * c, 0)].powi(2) + x[(3 * c + 1, 0)].powi(2) + x[(3 * c + 2, 0)].powi(2)).sqrt()
        })
        .fold(0.0, f64::max)
}

/// R factor and Qᵀb of a block (rows beyond the rank dropped): min |A x − b| and
/// min |R x − Qᵀb| differ by a constant.
fn reduce(a: DMatrix<f64>, b: DMatrix<f64>) -> (DMatrix<f64>, DMatrix<f64>) {
    let n = a.nrows().min(a.ncols());
    let qr = a.qr();
    let mut qtb = b;
    qr.q_tr_mul(&mut qtb);
    (qr.r(), qtb.rows(0, n).into_owned())
}

/// The minimal-deviation G2 solve. `a` holds the `rows` scalar G2 rows, then two tangential rows
/// per sample (weight [`SetParams::g2_tangential_weight`]); `b` is zero on the tangential rows.
///
/// The scalar rows alone (the crate's original system) constrain only n_k · d_j: the tangential
/// components of the d_j enter through the variation of the normal n_k along the side, with
/// singular values 1e-2 … 1e-6 of the largest. Whatever part of the right-hand side the spline
/// space cannot follow (a master of other knots, noise in its curvature) is then fitted with
/// tangential moves of 10–1000 times the needed correction: millimetres of movement for a
/// 0.03 mm curvature correction, the surface wrecked while G2 looks met. So the solve starts with
/// the paper's well-conditioned system (weight 1: change β_k n_k, minimal deviation) and then
/// takes the lightest weight of [`G2_WEIGHT_LADDER`] whose largest move stays within
/// `move_factor` times the first one's (tried from the lightest up; the weight-1 solution when
/// none does). Where an exact join exists with comparable moves (the same spline space on both
/// sides) this reaches it; where it does not, the remaining error is left to knot insertion,
/// which adds real freedom.
///
/// Both blocks are banded (a sample touches the q + 1 control points of its span): they are
/// reduced once to banded triangular factors R1, R2 by Givens QR, and each weight costs one
/// banded QR of [R1; w R2]. Systems that are not banded take the dense Householder path.
fn solve_g2_ladder(
    a: DMatrix<f64>,
    b: &DMatrix<f64>,
    rows: usize,
    move_factor: f64,
) -> std::result::Result<(DMatrix<f64>, f64), String> {
    let n = a.ncols();
    let tangential = a.rows(rows, a.nrows() - rows);
    let scalar = a.rows(0, rows);
    let rhs = b.rows(0, rows);
    let zeros = DMatrix::zeros(tangential.nrows(), 1);
    if let (Some(f1), Some(f2)) = (
        banded_factor(&scalar, &rhs),
        banded_factor(&tangential, &zeros.as_view()),
    ) {
        let width = f1.width().max(f2.width());
        return ladder(move_factor, |w| {
            let mut qr = BandedQr::new(n, width, 1);
            let mut scaled = vec![0.0; width];
            for (i, row, rhs) in f1.rows() {
                let len = row.len().min(n - i);
                qr.add_row(i, &row[..len], rhs).map_err(|e| e.to_string())?;
            }
            for (i, row, _) in f2.rows() {
                let len = row.len().min(n - i);
                for (s, r) in scaled.iter_mut().zip(&row[..len]) {
                    *s = w * r;
                }
                qr.add_row(i, &scaled[..len], &[0.0])
                    .map_err(|e| e.to_string())?;
            }
            // [R1; w R2] has full rank for w > 0 (R2 does): only round-off pivots are refused
            match banded_solve_with(&qr, SINGULAR_RELATIVE) {
                Some(x) => Ok(x),
                None => solve_min_norm(dense_r(&qr), &dense_qtb(&qr)),
            }
        });
    }
    let (r1, c1) = reduce(scalar.into_owned(), rhs.into_owned());
    let (r2, _) = reduce(tangential.into_owned(), zeros);
    ladder(move_factor, |w| {
        let (n1, n2) = (r1.nrows(), r2.nrows());
        let mut m = DMatrix::zeros(n1 + n2, n);
        m.rows_mut(0, n1).copy_from(&r1);
        m.rows_mut(n1, n2).copy_from(&(&r2 * w));
        let mut rhs = DMatrix::zeros(n1 + n2, 1);
        rhs.rows_mut(0, n1).copy_from(&c1);
        solve_least_squares(m, &rhs)
    })
}

/// The weight search of [`solve_g2_ladder`] over a solve for a given tangential weight; with
/// the solution, the smallest move ratio of a rejected weight ([`RowMove::g2_slack`]).
fn ladder(
    move_factor: f64,
    mut solve: impl FnMut(f64) -> std::result::Result<DMatrix<f64>, String>,
) -> std::result::Result<(DMatrix<f64>, f64), String> {
    let first = solve(1.0)?;
    let reference = largest_point_move(&first);
    let limit = move_factor * reference;
    let mut slack = f64::INFINITY;
    for &w in G2_WEIGHT_LADDER.iter().rev() {
        let x = solve(w)?;
        let moved = largest_point_move(&x);
        if moved <= limit {
            return Ok((x, slack));
        }
        // (a zero reference rejects every move whatever the factor)
        if reference > 0.0 {
            slack = slack.min(moved / reference);
        }
    }
    Ok((first, slack))
}

/// R of a banded factor as a dense n × n matrix (rows never filled are zero).
fn dense_r(f: &BandedQr) -> DMatrix<f64> {
    let n = f.unknowns();
    let mut r = DMatrix::zeros(n, n);
    for (i, row, _) in f.rows() {
        for (t, v) in row.iter().enumerate().take(n - i) {
            r[(i, i + t)] = *v;
        }
    }
    r
}

/// Qᵀb of a banded factor (one right-hand side) as a dense n × 1 matrix.
fn dense_qtb(f: &BandedQr) -> DMatrix<f64> {
    let mut c = DMatrix::zeros(f.unknowns(), 1);
    for (i, _, rhs) in f.rows() {
        c[(i, 0)] = rhs[0];
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stand-in solve: weight w gives one point moved by `moves(w)` along x.
    fn solve_with(moves: impl Fn(f64) -> f64) -> impl FnMut(f64) -> Result<DMatrix<f64>, String> {
        move |w| Ok(DMatrix::from_column_slice(3, 1, &[moves(w), 0.0, 0.0]))
    }

    #[test]
    fn ladder_slack_is_the_least_rejected_ratio_and_a_factor_below_it_changes_nothing() {
        // lighter weights move more: 1e-8 → 9, 1e-6 → 5, 1e-4 → 3, 1e-3 → 1.5 (× the
        // weight-1 move of 1)
        let moves = |w: f64| match w {
            w if w < 1e-7 => 9.0,
            w if w < 1e-5 => 5.0,
            w if w < 1e-3 * 0.5 => 3.0,
            w if w < 1e-2 * 0.5 => 1.5,
            _ => 1.0,
        };
        let (x, slack) = ladder(2.0, solve_with(moves)).expect("solves");
        assert_eq!(x[(0, 0)], 1.5, "the lightest weight within 2×");
        assert_eq!(slack, 3.0, "the least ratio the search rejected");
        // any factor in [1.5, 3): the same pick; at 3 the search takes the lighter one
        for f in [1.5, 2.5, 2.999] {
            assert_eq!(ladder(f, solve_with(moves)).expect("solves").0, x);
        }
        assert_eq!(
            ladder(3.0, solve_with(moves)).expect("solves").0[(0, 0)],
            3.0
        );
        // nothing rejected: no bound
        let (_, none) = ladder(10.0, solve_with(moves)).expect("solves");
        assert_eq!(none, f64::INFINITY);
    }
}
