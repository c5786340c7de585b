//! The row equations of one side: C0 (row 0), G1 (row 1, \[SV\] §4.1) and G2 (row 2, \[SV\] §4.2).
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

/// A row whose samples all lie within this fraction of the slave size from the master is left
/// alone in the C0 step (bit-identical): gaps of this size are rounding from knot insertion or
/// extraction (~1e4 units of 1e-16), not geometry.
pub const C0_EXACT: f64 = 1e-11;

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
    solve_row_with(
        master,
        slave,
        side,
        (range, [0.0; 2]),
        step,
        movable,
        params,
        &[],
    )
}

/// A corner of a side's boundary where the neighbouring side carries G2: the boundary curve's
/// normal curvature there is that of the neighbour's master in the curve's direction (see
/// [`solve_row_with`]).
#[derive(Clone, Copy)]
pub(crate) struct CornerCurvature<'a> {
    /// the end's parameter along the side
    pub(crate) t: f64,
    /// the neighbouring side's master
    pub(crate) master: &'a BSplineSurface,
}

/// [`solve_row_in`] with, for the C0 step, one more equation per corner of `corners`: at a corner
/// where the neighbouring side B carries G2, B's condition there asks the slave's normal curvature
/// in B's cross direction — the direction of this side's boundary curve C — to be that of B's
/// master, and that curvature is n · C''/|C'|² (Meusnier, \[DC\] §3-2), set by this side's boundary
/// row alone (\[SV\] §3.3: the corner compatibility of two sides' frames, one order up). Fitted to
/// its own master by positions only, the boundary's end curvature is off by its fit error over the
/// span squared (1e-6 mm over a 0.1 mm span: 1e-4 /mm, far above the flatness cut-off of a blend
/// between faired fillets), which no row of B can take back; and where the two masters disagree a
/// little in that direction (fillets faired G2 to their faces, flat at the corner to 1e-4), B's G2
/// is what the tolerances ask for, while the boundary may leave its own master by the little that
/// costs (a curvature change Δκ over a length L moves it Δκ L²/2 and turns it Δκ L). The equation
/// prescribes C''(t) with its tangential part as it is and its normal part from B's master; it is
/// scaled to a position (× h²/(q(q−1)), h the end span: the size of a position change that makes
/// that curvature change) and weighted by √K, as much as the K samples of the side together.
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_row_with(
    master: &BSplineSurface,
    slave: &BSplineSurface,
    side: Side,
    (range, zones): (Option<(f64, f64)>, [f64; 2]),
    step: Continuity,
    movable: &[bool],
    params: &SetParams,
    corners: &[CornerCurvature<'_>],
) -> Result<RowMove> {
    // the G2 rows leave out the samples of the link's vertex zones ([`crate::SideLink::g2_zones`])
    let zoned = step == Continuity::G2 && zones.iter().any(|&z| z > 0.0);
    let ranged: Option<Vec<f64>> = (range.is_some() || zoned).then(|| {
        let (x, y) = crate::sampling::side_part(slave, side, range);
        let mut ts: Vec<f64> = vec![x];
        ts.extend(
            solve_side_params(slave, side, params.samples_per_span, params.min_samples)
                .into_iter()
                .filter(|&t| t > x && t < y),
        );
        ts.push(y);
        if zoned {
            let outside: Vec<f64> = ts
                .iter()
                .copied()
                .filter(|&t| !crate::sampling::in_zones(t, (x, y), zones))
                .collect();
            // zones that leave no sample relax nothing (the caller keeps them short)
            if !outside.is_empty() {
                ts = outside;
            }
        }
        ts
    });
    let samples = ranged.as_deref();
    let once = Once {
        master,
        side,
        step,
        movable,
        samples,
        params,
        corners,
    };
    let mut total = once.solve(slave)?;
    if step != Continuity::G1 || total.indices.is_empty() {
        return Ok(total);
    }
    let mut work = slave.clone();
    total.apply(&mut work);
    let mut pass_params = *params;
    let first_move = total.max_displacement();
    for _ in 1..params.g1_passes.max(1) {
        pass_params.g1_tangential_weight *= G1_WEIGHT_STEP;
        let more = Once {
            params: &pass_params,
            ..once
        }
        .solve(&work)?;
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
    let once = Once {
        master,
        side,
        step,
        movable,
        samples: Some(ts),
        params,
        corners: &[],
    };
    once.solve(slave)
}

/// One solve of a row: what stays the same over the passes of [`solve_row_with`] (the slave
/// changes from pass to pass).
#[derive(Clone, Copy)]
struct Once<'a> {
    master: &'a BSplineSurface,
    side: Side,
    step: Continuity,
    movable: &'a [bool],
    samples: Option<&'a [f64]>,
    params: &'a SetParams,
    corners: &'a [CornerCurvature<'a>],
}

impl Once<'_> {
    /// The row's moves on `slave`.
    fn solve(&self, slave: &BSplineSurface) -> Result<RowMove> {
        let (side, step) = (self.side, self.step);
        let row = side.row(row_of(step), slave.num_u(), slave.num_v());
        let (column, indices) = movable_columns(&row, self.movable);
        if indices.is_empty() {
            return Ok(RowMove::still(side));
        }
        let (sys, directions) = self.system(slave, &row, &column, indices.len())?;
        if step == Continuity::G0 && {
            let exact = C0_EXACT * slave.size();
            sys.b.iter().all(|d| d.abs() <= exact)
        } {
            // already on the master: keep the row bit-identical
            return Ok(RowMove::still(side));
        }
        let (needed, unknowns) = (sys.needed, sys.unknowns);
        let (x, g2_slack) =
            sys.solve(self.params.g2_move_factor)
                .map_err(|reason| Error::SingularSystem {
                    side,
                    target: step,
                    reason: reason.to_string(),
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

    /// The least-squares system of the row (`free` movable points, their column blocks in
    /// `column`) with the corner equations of a C0 step, and the fixed G2 directions.
    fn system(
        &self,
        slave: &BSplineSurface,
        row: &[(usize, usize)],
        column: &[Option<usize>],
        free: usize,
    ) -> Result<(RowSystem, Vec<Vector3>)> {
        let Once {
            master,
            side,
            step,
            samples,
            params,
            corners,
            ..
        } = *self;
        let k = row_of(step);
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
        let directions = if step == Continuity::G2 && params.g2_method == G2Method::FixedDirections
        {
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
            column,
            directions: &directions,
            params,
        };
        sys.fill(&ctx, &ts, &mut basis, &mut slave_eval);
        if step == Continuity::G0 {
            for c in corners {
                corner_row(
                    &mut sys,
                    slave,
                    side,
                    c,
                    column,
                    &mut basis,
                    params,
                    ts.len(),
                );
            }
        }
        Ok((sys, directions))
    }
}

/// The equation of corner `c` in the C0 system `sys` of `side` (see [`solve_row_with`]): the
/// boundary's second derivative at the corner with its normal part that of the neighbour's
/// master, scaled to a position and weighted by √`samples`.
#[allow(clippy::too_many_arguments)]
fn corner_row(
    sys: &mut RowSystem,
    slave: &BSplineSurface,
    side: Side,
    c: &CornerCurvature<'_>,
    column: &[Option<usize>],
    basis: &mut SideBasis,
    params: &SetParams,
    samples: usize,
) {
    let (u, v) = side.params(slave, c.t);
    let ds = slave.derivatives(u, v);
    let (d1, d2) = match side.along_direction() {
        nurbs_core::Direction::U => (ds.du, ds.duu),
        nurbs_core::Direction::V => (ds.dv, ds.dvv),
    };
    let foot = nurbs_core::project_to_surface(c.master, &ds.point, &params.projection);
    let dm = c.master.derivatives(foot.u, foot.v);
    let (Some(n), Some(kappa)) = (dm.normal(), dm.normal_curvature(&d1)) else {
        return;
    };
    let tangential = d1 - n * n.dot(&d1);
    let change = n * (kappa * tangential.norm_squared() - n.dot(&d2));
    let q = basis.along_degree();
    let kv = crate::sampling::along_knots(slave, side);
    let span = kv.span(kv.clamp_param(c.t));
    let h = kv.knots()[span + 1] - kv.knots()[span];
    if q < 2 || !(h > 0.0) {
        return;
    }
    let scale = (samples as f64).sqrt() * h * h / (q * (q - 1)) as f64;
    let mut values = vec![0.0; q + 1];
    let first = basis.boundary_second_derivative(c.t, &mut values);
    let a0 = basis.row_coefficient[0];
    let cols: Vec<(usize, f64)> = values
        .iter()
        .enumerate()
        .filter_map(|(l, &m)| column[first + l].map(|col| (col, scale * a0 * m)))
        .collect();
    sys.push_g0_row(&cols, change * scale);
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs_core::shapes::{plane_patch, revolve_curve};
    use nurbs_core::{BSplineCurve, Direction, KnotVector, Point3, ProjectionParams};

    /// A bicubic patch of the plane z = 0 over [0, 1]², four spans along v.
    fn flat_slave() -> BSplineSurface {
        plane_patch(
            Point3::origin(),
            Vector3::x(),
            Vector3::y(),
            (0.0, 1.0),
            (0.0, 1.0),
        )
        .unwrap()
        .elevate_degree(Direction::U, 2)
        .unwrap()
        .elevate_degree(Direction::V, 2)
        .unwrap()
        .refine(Direction::V, &[0.25, 0.5, 0.75])
        .unwrap()
    }

    /// The normal curvature of `s` along its side u = 0 (direction S_v) at v = 0, signed with
    /// respect to `n`.
    fn end_curvature(s: &BSplineSurface, n: &Vector3) -> f64 {
        let d = s.derivatives(0.0, 0.0);
        n.dot(&d.dvv) / d.dv.norm_squared()
    }

    #[test]
    fn a_corner_row_gives_the_boundary_the_neighbours_curvature_at_the_corner() {
        // the side u = 0 lies on the plane z = 0 (its master); the neighbouring side v = 0 is
        // G2 to a cylinder of radius 50 about the line y = 0, z = 50, which touches the plane
        // along the x axis: at the corner its normal curvature along y is 1/50, the plane's 0
        let slave = flat_slave();
        let plane = plane_patch(
            Point3::new(-1.0, 0.0, 0.0),
            Vector3::x(),
            Vector3::y(),
            (0.0, 1.0),
            (0.0, 1.0),
        )
        .unwrap();
        let r = 50.0;
        let axis_line = BSplineCurve::new(
            KnotVector::bezier(1).unwrap(),
            vec![Point3::new(-1.0, 0.0, 0.0), Point3::new(2.0, 0.0, 0.0)],
            None,
        )
        .unwrap();
        let cylinder = revolve_curve(
            &axis_line,
            Point3::new(0.0, 0.0, r),
            Vector3::x(),
            -0.1,
            0.1,
        )
        .unwrap();
        let params = SetParams::default();
        let movable = vec![true; slave.num_v()];
        let solve = |corners: &[CornerCurvature<'_>]| {
            let mv = solve_row_with(
                &plane,
                &slave,
                Side::U0,
                (None, [0.0; 2]),
                Continuity::G0,
                &movable,
                &params,
                corners,
            )
            .unwrap();
            let mut s = slave.clone();
            mv.apply(&mut s);
            s
        };
        let foot = nurbs_core::project_to_surface(
            &cylinder,
            &Point3::origin(),
            &ProjectionParams::default(),
        );
        let dm = cylinder.derivatives(foot.u, foot.v);
        let n = dm.normal().unwrap();
        let target = dm.normal_curvature(&Vector3::y()).unwrap();
        assert!((target.abs() - 1.0 / r).abs() < 1e-12, "{target}");
        // on its master already: without the corner the row stays, flat
        let plain = solve(&[]);
        assert_eq!(plain.control_points(), slave.control_points());
        assert!(end_curvature(&plain, &n).abs() < 1e-12);
        // with it the boundary bends at the corner to the cylinder's curvature (measured
        // 1.9927e-2 against 2e-2: the row weighs as much as the side's samples, not more),
        // leaving the plane by less than κ h²/2 over the first span h = 1/4 (6.3e-4; 5.5e-5)
        let bent = solve(&[CornerCurvature {
            t: 0.0,
            master: &cylinder,
        }]);
        let got = end_curvature(&bent, &n);
        assert!(
            (got - target).abs() < 0.01 * target.abs(),
            "corner curvature {got:.4e} against {target:.4e}"
        );
        let gap = (0..=40)
            .map(|k| bent.point(0.0, f64::from(k) / 40.0).z.abs())
            .fold(0.0, f64::max);
        assert!(
            gap > 0.0 && gap < 0.5 * target.abs() * 0.25 * 0.25,
            "gap {gap:.3e}"
        );
    }
}
