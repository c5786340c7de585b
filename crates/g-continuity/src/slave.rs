//! Setting continuity of one slave to all its masters: C0, then G1, then G2, side by side with
//! consistent twists ([SV] §3.3, §4), knot insertion when the tolerances are missed.
//!
//! Order ([SV] §3.1): the cross derivative of order r on a clamped side depends on rows 0..=r
//! only, so C0 (row 0) is set first on every linked side, then G1 (row 1), then G2 (row 2); a
//! later step never touches the rows of an earlier one, which therefore stay bit-identical.
//!
//! Row k of a side, at along index e from one end, is row e of the neighbouring side at that end.
//! Such a point is
//! - *fixed* when e < k and the neighbour is linked with a target ≥ G_e (its frame is set);
//! - *shared* (a twist, [SV] §3.3; for k = 0 a common corner) when e = k and the neighbour's
//!   target is ≥ G_k: both sides propose a position, the candidates are averaged, and every side
//!   is solved again with the shared points pinned;
//! - *free* otherwise (for an unlinked neighbour with e = 0 only when
//!   [`SetParams::move_unlinked_boundaries`] allows it).
//!
//! More freedom ([SV] §3.2 step 1): a slave whose degree across a G_r side is below r is degree
//! elevated; one with too few control rows for the frames of two opposite sides gets knots across.
//! A rational slave keeps its weights: with the weights fixed it is linear in its control points
//! through the rational basis, so the row equations stay linear ([`crate::sampling::SideBasis`]),
//! and knot insertion and degree elevation are exact in homogeneous coordinates.
//! When a side misses the tolerances after setting, the knot spans along it that hold failing
//! samples are halved and the whole slave is set again, up to
//! [`ConnectParams::max_refinements`] rounds.
//!
//! # Tolerance
//! [`C0_CONVERGED`]: the C0 passes stop when no row point moves by more than this times the
//! slave size; [`C0_EXACT`]: a row already this close to its master is not refitted.

use std::collections::BTreeMap;

use nurbs_core::{BSplineSurface, Continuity, Direction, Point3, Side, Vector3};
use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::measure::{LinkMeasure, MeasureParams, is_collapsed};
/// The default net bound lives with [`ConnectParams`] (params.rs), re-exported here.
pub use crate::params::MAX_CONTROL_POINTS;
use crate::params::{ConnectParams, SetParams};
use crate::rows::{RowMove, row_of, solve_row_at};
use crate::sampling::along_knots;

/// C0 passes stop when the largest row movement is below this fraction of the slave size.
pub const C0_CONVERGED: f64 = 1e-12;

/// A row whose samples all lie within this fraction of the slave size from the master is left
/// alone in the C0 step (bit-identical): gaps of this size are rounding from knot insertion or
/// extraction (~1e4 units of 1e-16), not geometry.
pub const C0_EXACT: f64 = 1e-11;

/// The end point of a row k ≥ 1 on an unlinked neighbouring side stays fixed (the free boundary
/// bit-identical) when the correction its corner sample alone asks for is below this fraction of
/// the slave size: the corner is continuous already, up to rounding of the construction.
pub const END_CONTINUOUS: f64 = 1e-9;

/// One linked side of a slave: which side, onto which master, with what target.
#[derive(Debug, Clone, Copy)]
pub struct SideLink<'a> {
    /// the slave's side
    pub side: Side,
    /// the master surface (never modified)
    pub master: &'a BSplineSurface,
    /// the continuity to reach
    pub target: Continuity,
    /// the part of the side the link holds on, as an interval of the along-side parameter
    /// (`None`: the whole side). A trimmed face's side lies on the surface it meets only up to
    /// the trim; the row equations, measures and refinement then use samples of that part only,
    /// and the control points whose along-side support misses it do not move.
    pub range: Option<(f64, f64)>,
}

impl SideLink<'_> {
    /// The along-side parameter interval the link holds on: its [`SideLink::range`] clipped to
    /// the side's domain, or the whole domain.
    pub fn domain(&self, slave: &BSplineSurface) -> (f64, f64) {
        crate::sampling::side_part(slave, self.side, self.range)
    }

    /// Measures the link on `slave` (over its range).
    pub fn measure(&self, slave: &BSplineSurface, params: &MeasureParams) -> Result<LinkMeasure> {
        crate::measure::measure_link_on(self.master, slave, self.side, self.range, params)
    }
}

/// Before/after of one linked side.
#[derive(Debug, Clone, PartialEq)]
pub struct SideReport {
    /// the side
    pub side: Side,
    /// its target
    pub target: Continuity,
    /// continuity of the input slave
    pub before: LinkMeasure,
    /// continuity of the result
    pub after: LinkMeasure,
    /// whether `after` meets the tolerances up to the target
    pub met: bool,
}

/// What [`connect_slave`] did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ConnectReport {
    /// per linked side
    pub sides: Vec<SideReport>,
    /// knots inserted in total (across for row room, along for accuracy)
    pub knots_inserted: usize,
    /// rounds of knot insertion along failing sides
    pub refinements: usize,
    /// degree elevation (u, v)
    pub degree_elevation: (usize, usize),
    /// whether the slave's weights were all equal and were dropped (exact; a rational slave
    /// with unequal weights stays rational)
    pub made_polynomial: bool,
    /// twist (and shared corner) points set by averaging
    pub twists_averaged: usize,
    /// largest control point movement against the input refined the same way (model units)
    pub max_control_movement: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Status {
    Free,
    Shared,
    /// end point of a row k ≥ 1 on an unlinked neighbouring side: it lies on that free boundary,
    /// so it moves only by what its own corner sample needs
    End,
    /// end point of a row k ≥ 1 on a neighbouring side linked G0 only (e.g. a fillet's end on a
    /// face it meets at a sharp edge): it lies on that side's boundary, so it moves only within
    /// the G0 master's tangent plane at the corner, which keeps that join C0 (exactly on a plane
    /// master, to first order on a curved one) while the corner takes part in the G1/G2 solve
    Sliding,
    Fixed,
}

fn side_index(side: Side) -> usize {
    match side {
        Side::U0 => 0,
        Side::U1 => 1,
        Side::V0 => 2,
        Side::V1 => 3,
    }
}

fn classify(
    side: Side,
    k: usize,
    m: usize,
    levels: &[Option<usize>; 4],
    move_unlinked: bool,
    kept: &[bool; 4],
) -> Vec<Status> {
    let (start, end) = side.neighbours();
    (0..m)
        .map(|j| {
            let mut status = Status::Free;
            for (e, adj) in [(j, start), (m - 1 - j, end)] {
                let s = match levels[side_index(adj)] {
                    // on a kept side's boundary row or the row next to it
                    None if kept[side_index(adj)] && e <= 1 => Status::Fixed,
                    Some(0) if e == 0 && k > 0 => Status::Sliding,
                    Some(la) if e < k && la >= e => Status::Fixed,
                    Some(la) if e == k && la >= k => Status::Shared,
                    None if e == 0 && k > 0 && !move_unlinked => Status::Fixed,
                    None if e == 0 && k > 0 => Status::End,
                    _ => Status::Free,
                };
                status = match (status, s) {
                    (Status::Fixed, _) | (_, Status::Fixed) => Status::Fixed,
                    (Status::Shared, _) | (_, Status::Shared) => Status::Shared,
                    (Status::Sliding, _) | (_, Status::Sliding) => Status::Sliding,
                    (Status::End, _) | (_, Status::End) => Status::End,
                    _ => Status::Free,
                };
            }
            status
        })
        .collect()
}

fn level(c: Continuity) -> usize {
    row_of(c)
}

fn levels_of(links: &[SideLink]) -> [Option<usize>; 4] {
    let mut levels = [None; 4];
    for l in links {
        levels[side_index(l.side)] = Some(level(l.target));
    }
    levels
}

/// Outcome of one step over all sides.
#[derive(Debug, Clone, Copy)]
struct StepOutcome {
    twists: usize,
    max_move: f64,
    /// the least [`RowMove::g2_slack`] of the rows solved
    g2_slack: f64,
}

impl Default for StepOutcome {
    fn default() -> Self {
        Self {
            twists: 0,
            max_move: 0.0,
            g2_slack: f64::INFINITY,
        }
    }
}

fn least_slack(moves: &[RowMove]) -> f64 {
    moves
        .iter()
        .map(|m| m.g2_slack)
        .fold(f64::INFINITY, f64::min)
}

/// The row moves of every active side on `surface`, the points whose status passes `movable`
/// free. The sides' systems are independent (each reads `surface` only): they are solved in
/// parallel and collected in side order, the first error in side order winning, so the result
/// does not depend on the thread count.
fn solve_sides(
    active: &[&SideLink],
    statuses: &[Vec<Status>],
    surface: &BSplineSurface,
    links: &[SideLink],
    step: Continuity,
    params: &SetParams,
    movable: impl Fn(Status) -> bool + Sync,
) -> Result<Vec<RowMove>> {
    let k = row_of(step);
    active
        .par_iter()
        .zip(statuses)
        .map(|(l, status)| {
            let mut free: Vec<bool> = status.iter().map(|&s| movable(s)).collect();
            if l.range.is_some() {
                // a point whose along-side support misses the link's part has no equation
                let (a, b) = l.domain(surface);
                let kv = crate::sampling::along_knots(surface, l.side);
                let (q, t) = (kv.degree(), kv.knots());
                for (j, f) in free.iter_mut().enumerate() {
                    *f &= t[j] < b && t[j + q + 1] > a;
                }
            }
            let mut mv =
                crate::rows::solve_row_in(l.master, surface, l.side, l.range, step, &free, params)?;
            slide(&mut mv, k, status, l.side, links, surface, params);
            Ok(mv)
        })
        .collect::<Vec<Result<RowMove>>>()
        .into_iter()
        .collect()
}

/// One step (row k) on every linked side with target ≥ `step`, with twist averaging.
fn step_all(
    slave: &mut BSplineSurface,
    links: &[SideLink],
    step: Continuity,
    params: &SetParams,
) -> Result<StepOutcome> {
    let k = row_of(step);
    let levels = levels_of(links);
    let active: Vec<&SideLink> = links
        .iter()
        .filter(|l| l.target >= step && !is_collapsed(slave, l.side))
        .collect();
    if active.is_empty() {
        return Ok(StepOutcome::default());
    }
    let (nu, nv) = (slave.num_u(), slave.num_v());
    let base = slave.clone();
    let degenerate = degenerate_corner_blocks(&base);
    let mut statuses: Vec<Vec<Status>> = Vec::with_capacity(active.len());
    // the weight searches of the corner samples decide statuses: their slack counts too
    let mut end_slack = f64::INFINITY;
    for l in &active {
        let m = l.side.row(k, nu, nv).len();
        let mut status = classify(
            l.side,
            k,
            m,
            &levels,
            params.move_unlinked_boundaries,
            &params.kept_sides,
        );
        // the end point on a neighbouring side collapsed to a point (a pole) is that point: it
        // never moves, so the pole stays one point and the rows next to it stay consistent
        let (start, end) = l.side.neighbours();
        if is_collapsed(&base, start) {
            status[0] = Status::Fixed;
        }
        if is_collapsed(&base, end) {
            status[m - 1] = Status::Fixed;
        }
        // a degenerate corner — a corner point and its neighbour along one side coincide, a
        // zero end tangent, how kernels close a vertex blend's side — has a normal only as the
        // limit S_u × S_uv: it depends on the corner's 2 × 2 block, twist included, and moving
        // any of them turns the normal there (0.7° on box12_variable's freeform vertex blend).
        // The block stays as it is, as a pole does.
        let row = l.side.row(k, nu, nv);
        for (j, ij) in row.iter().enumerate() {
            if degenerate.contains(ij) {
                status[j] = Status::Fixed;
            }
        }
        // an end point on an unlinked side lies on that free boundary: it stays where it is when
        // its corner is already continuous (the corner sample alone asks for no move), and is
        // free otherwise (the boundary has to change for the corner anyway)
        let (t0, t1) = l.side.along_domain(slave);
        let (r0, r1) = l.domain(slave);
        for (j, t) in [(0, t0), (m - 1, t1)] {
            if status[j] != Status::End {
                continue;
            }
            // an end the link's part does not reach is no corner of this join
            if (j == 0 && r0 > t0) || (j == m - 1 && r1 < t1) {
                status[j] = Status::Fixed;
                continue;
            }
            let mut only = vec![false; m];
            only[j] = true;
            let corner = solve_row_at(l.master, &base, l.side, step, &only, &[t], params)?;
            end_slack = end_slack.min(corner.g2_slack);
            status[j] = if corner.max_displacement() <= END_CONTINUOUS * slave.size() {
                Status::Fixed
            } else {
                Status::Free
            };
        }
        statuses.push(status);
    }
    let moves = solve_sides(&active, &statuses, &base, links, step, params, |s| {
        s != Status::Fixed
    })?;
    // average the candidates of shared points
    let mut shared: BTreeMap<(usize, usize), (Vector3, usize)> = BTreeMap::new();
    for (l, (status, mv)) in active.iter().zip(statuses.iter().zip(&moves)) {
        let row = l.side.row(k, nu, nv);
        for (ij, d) in mv.indices.iter().zip(&mv.displacements) {
            let j = row.iter().position(|x| x == ij).unwrap_or(0);
            if status[j] == Status::Shared {
                let e = shared.entry(*ij).or_insert((Vector3::zeros(), 0));
                e.0 += d;
                e.1 += 1;
            }
        }
    }
    let mut outcome = StepOutcome {
        twists: shared.len(),
        max_move: 0.0,
        g2_slack: least_slack(&moves).min(end_slack),
    };
    if shared.is_empty() {
        for mv in &moves {
            mv.apply(slave);
            outcome.max_move = outcome.max_move.max(mv.max_displacement());
        }
        if step == Continuity::G0 && params.tangent_corners {
            let t = tangent_corners(slave, links, &active, params);
            outcome.max_move = outcome.max_move.max(t);
        }
        return Ok(outcome);
    }
    let mut pinned = base;
    for (&(i, j), &(sum, count)) in &shared {
        let idx = pinned.index(i, j);
        let d = sum / count as f64;
        pinned.control_points_mut()[idx] += d;
        outcome.max_move = outcome.max_move.max(d.norm());
    }
    let second = solve_sides(&active, &statuses, &pinned, links, step, params, |s| {
        matches!(s, Status::Free | Status::Sliding)
    })?;
    outcome.g2_slack = outcome.g2_slack.min(least_slack(&second));
    for mv in &second {
        mv.apply(&mut pinned);
        outcome.max_move = outcome.max_move.max(mv.max_displacement());
    }
    *slave = pinned;
    if step == Continuity::G0 && params.tangent_corners {
        let t = tangent_corners(slave, links, &active, params);
        outcome.max_move = outcome.max_move.max(t);
    }
    Ok(outcome)
}

/// After the C0 rows: at a corner where the neighbouring side carries G1 or more, the second
/// point of this side's boundary row moves into the tangent plane of that neighbour's master
/// at the corner ([`SetParams::tangent_corners`]). The corner's normal is
/// (P₁₀ − P₀₀) × (P₀₁ − P₀₀) and each edge lies on one side's boundary: fitted to its own master
/// by positions only, an edge's end tangent misses the other master's tangent plane by the
/// fit's slope error (1.5e-4 rad on a kernel's freeform vertex blend), which no later G1 row
/// can take back — at the corner the G1 rows keep the block the C0 rows made. Where the two
/// masters share their tangent plane (they are G1 there) the moved point stays on its own
/// master to first order; the move does change the boundary's end curvature, the neighbour's
/// G2 at the corner, which is why the correction is not the default. Returns the largest move.
fn tangent_corners(
    slave: &mut BSplineSurface,
    links: &[SideLink],
    active: &[&SideLink],
    params: &SetParams,
) -> f64 {
    let (nu, nv) = (slave.num_u(), slave.num_v());
    let fixed = degenerate_corner_blocks(slave);
    let mut largest: f64 = 0.0;
    for l in active {
        let row = l.side.row(0, nu, nv);
        let m = row.len();
        if m < 3 {
            continue;
        }
        let (start, end) = l.side.neighbours();
        for (c, j, adj) in [(0, 1, start), (m - 1, m - 2, end)] {
            let Some(nb) = links
                .iter()
                .find(|x| x.side == adj && x.target >= Continuity::G1 && x.range.is_none())
            else {
                continue;
            };
            let (corner, second) = (row[c], row[j]);
            if is_collapsed(slave, adj) || fixed.contains(&corner) || fixed.contains(&second) {
                continue;
            }
            let p0 = slave.control_point(corner.0, corner.1);
            let foot = nurbs_core::project_to_surface(nb.master, &p0, &params.projection);
            let Some(n) = nb.master.derivatives(foot.u, foot.v).normal() else {
                continue;
            };
            let idx = slave.index(second.0, second.1);
            let d = n * n.dot(&(slave.control_points()[idx] - p0));
            slave.control_points_mut()[idx] -= d;
            largest = largest.max(d.norm());
        }
    }
    largest
}

/// The control points of the 2 × 2 corner blocks of `s` at its degenerate corners: those where
/// the corner point coincides with its neighbour along u or along v (within
/// [`crate::measure::COLLAPSED_SIDE_RELATIVE`] of the size). The two corners of a side collapsed
/// to a point (a pole) count too — there the corner coincides with its neighbour along the
/// collapsed side, and the normal at the pole is the same kind of limit, set by the row next to
/// it. A corner that coincides with both neighbours has no such limit and is left to the other
/// rules.
pub fn degenerate_corner_blocks(s: &BSplineSurface) -> Vec<(usize, usize)> {
    let (nu, nv) = (s.num_u(), s.num_v());
    let mut out = Vec::new();
    if nu < 3 || nv < 3 {
        return out;
    }
    let tiny = crate::measure::COLLAPSED_SIDE_RELATIVE * s.size();
    let at = |i: usize, j: usize| s.control_points()[s.index(i, j)];
    for (i0, i1, j0, j1) in [
        (0, 1, 0, 1),
        (nu - 1, nu - 2, 0, 1),
        (0, 1, nv - 1, nv - 2),
        (nu - 1, nu - 2, nv - 1, nv - 2),
    ] {
        let corner = at(i0, j0);
        let along_u = (at(i1, j0) - corner).norm() <= tiny;
        let along_v = (at(i0, j1) - corner).norm() <= tiny;
        // exactly one neighbour coincides: a zero end tangent along one side
        if along_u != along_v {
            out.extend([(i0, j0), (i1, j0), (i0, j1), (i1, j1)]);
        }
    }
    out
}

/// Restricts the moves of [`Status::Sliding`] end points of `side`'s row to the tangent plane of
/// the G0 master of the neighbouring side at that corner.
fn slide(
    mv: &mut RowMove,
    k: usize,
    status: &[Status],
    side: Side,
    links: &[SideLink],
    slave: &BSplineSurface,
    params: &SetParams,
) {
    let m = status.len();
    let (start, end) = side.neighbours();
    let (t0, t1) = side.along_domain(slave);
    let (nu, nv) = (slave.num_u(), slave.num_v());
    let row = side.row(k, nu, nv);
    for (j, adj, t) in [(0, start, t0), (m - 1, end, t1)] {
        if status.get(j) != Some(&Status::Sliding) {
            continue;
        }
        let Some(link) = links.iter().find(|l| l.side == adj) else {
            continue;
        };
        let (u, v) = side.params(slave, t);
        let corner = slave.point(u, v);
        let foot = nurbs_core::project_to_surface(link.master, &corner, &params.projection);
        let Some(n) = link.master.derivatives(foot.u, foot.v).normal() else {
            continue;
        };
        for (ij, d) in mv.indices.iter().zip(mv.displacements.iter_mut()) {
            if *ij == row[j] {
                *d -= n * n.dot(d);
            }
        }
    }
}

/// Sets C0, then G1, then G2 (as far as each link's target asks) on a prepared slave (clamped,
/// enough rows); returns the number of averaged twists.
pub fn set_rows(
    slave: &mut BSplineSurface,
    links: &[SideLink],
    params: &SetParams,
) -> Result<usize> {
    check_links(links)?;
    let mut twists = 0;
    let size = slave.size();
    for _ in 0..params.c0_iterations.max(1) {
        let o = step_all(slave, links, Continuity::G0, params)?;
        twists = twists.max(o.twists);
        if o.max_move <= C0_CONVERGED * size {
            break;
        }
    }
    twists += step_all(slave, links, Continuity::G1, params)?.twists;
    twists += step_all(slave, links, Continuity::G2, params)?.twists;
    Ok(twists)
}

fn check_links(links: &[SideLink]) -> Result<()> {
    for (a, la) in links.iter().enumerate() {
        if links[..a].iter().any(|lb| lb.side == la.side) {
            return Err(Error::DuplicateSide { side: la.side });
        }
    }
    Ok(())
}

fn single(
    master: &BSplineSurface,
    slave: &mut BSplineSurface,
    side: Side,
    step: Continuity,
    params: &SetParams,
) -> Result<f64> {
    let links = [SideLink {
        side,
        master,
        target: step,
        range: None,
    }];
    if step == Continuity::G0 {
        let mut moved = 0.0f64;
        for _ in 0..params.c0_iterations.max(1) {
            let o = step_all(slave, &links, step, params)?;
            moved = moved.max(o.max_move);
            if o.max_move <= C0_CONVERGED * slave.size() {
                break;
            }
        }
        Ok(moved)
    } else {
        Ok(step_all(slave, &links, step, params)?.max_move)
    }
}

/// Fits the positional row of `side` to the master (C0); returns the largest row movement. The
/// slave must be clamped.
pub fn set_g0(
    master: &BSplineSurface,
    slave: &mut BSplineSurface,
    side: Side,
    params: &SetParams,
) -> Result<f64> {
    single(master, slave, side, Continuity::G0, params)
}

/// Sets G1 across `side` by moving its tangential row ([SV] §4.1); the positional row is not
/// touched. Returns the largest movement.
pub fn set_g1(
    master: &BSplineSurface,
    slave: &mut BSplineSurface,
    side: Side,
    params: &SetParams,
) -> Result<f64> {
    single(master, slave, side, Continuity::G1, params)
}

/// Sets G2 across `side` by moving its curvature row ([SV] §4.2); rows 0–1 are not touched.
/// Returns the largest movement.
pub fn set_g2(
    master: &BSplineSurface,
    slave: &mut BSplineSurface,
    side: Side,
    params: &SetParams,
) -> Result<f64> {
    single(master, slave, side, Continuity::G2, params)
}

/// Makes the slave clamped, of sufficient degree and with enough control rows. A rational slave
/// stays rational with its weights (the row equations take them, [`crate::sampling::SideBasis`]);
/// only weights that are all equal are dropped, which is exact.
fn prepare(
    slave: &BSplineSurface,
    links: &[SideLink],
    params: &ConnectParams,
    report: &mut ConnectReport,
) -> Result<BSplineSurface> {
    let lead_in = params.lead_in;
    let transfer = params.transfer_knots;
    let max_control_points = params.max_control_points;
    let projection = params.measure.projection;
    let mut s = slave.clamped()?;
    if let Some(w) = s.weights()
        && w.iter().all(|&x| x == w[0])
    {
        s = BSplineSurface::new(
            s.knots_u().clone(),
            s.knots_v().clone(),
            s.control_points().to_vec(),
            None,
        )?;
        report.made_polynomial = true;
    }
    for dir in [Direction::U, Direction::V] {
        let need_degree = links
            .iter()
            .filter(|l| l.side.cross_direction() == dir)
            .map(|l| level(l.target))
            .max()
            .unwrap_or(0);
        let degree = match dir {
            Direction::U => s.degree_u(),
            Direction::V => s.degree_v(),
        };
        if need_degree > degree {
            s = s.elevate_degree(dir, need_degree - degree)?;
            match dir {
                Direction::U => report.degree_elevation.0 += need_degree - degree,
                Direction::V => report.degree_elevation.1 += need_degree - degree,
            }
        }
    }
    // the refinement rounds insert knots along the linked sides ([`Refiner`], the master's
    // knots too): a low-degree along direction (a plane's, a cylinder's axis) is raised first,
    // so that those knots do not become creases once the rows move (nurbs-core's
    // SMOOTH_JOIN_DEGREE)
    for l in links {
        let dir = l.side.along_direction();
        let degree = match dir {
            Direction::U => s.degree_u(),
            Direction::V => s.degree_v(),
        };
        if degree < nurbs_core::ops::SMOOTH_JOIN_DEGREE {
            s = s.with_smooth_joins(dir)?;
            let by = nurbs_core::ops::SMOOTH_JOIN_DEGREE - degree;
            match dir {
                Direction::U => report.degree_elevation.0 += by,
                Direction::V => report.degree_elevation.1 += by,
            }
        }
    }
    if let Some(width) = lead_in {
        let (more, lead) = crate::lead_in::with_lead_in(&s, links, width)?;
        s = more;
        report.knots_inserted += lead.knots_inserted;
        report.degree_elevation.0 += lead.degree_elevation.0;
        report.degree_elevation.1 += lead.degree_elevation.1;
    }
    if transfer {
        let single_piece = [
            slave.knots_u().interior_knots().is_empty(),
            slave.knots_v().interior_knots().is_empty(),
        ];
        let (more, moved) = crate::transfer::with_master_knots(
            &s,
            links,
            single_piece,
            max_control_points,
            projection,
        )?;
        s = more;
        report.knots_inserted += moved.knots_inserted;
        report.degree_elevation.0 += moved.degree_elevation.0;
        report.degree_elevation.1 += moved.degree_elevation.1;
    }
    let levels = levels_of(links);
    for (dir, a, b) in [
        (Direction::U, Side::U0, Side::U1),
        (Direction::V, Side::V0, Side::V1),
    ] {
        let need =
            levels[side_index(a)].map_or(1, |l| l + 1) + levels[side_index(b)].map_or(1, |l| l + 1);
        let (more, inserted) = s.with_smooth_control_count(dir, need)?;
        s = more;
        report.knots_inserted += inserted;
    }
    Ok(s)
}

/// What [`set_step`] did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StepReport {
    /// the step's continuity
    pub step: Option<Continuity>,
    /// twists (or common corners) averaged
    pub twists_averaged: usize,
    /// knots inserted along failing sides
    pub knots_inserted: usize,
    /// rounds of knot insertion
    pub refinements: usize,
    /// largest control point movement of the step (model units)
    pub max_move: f64,
    /// per link (in the order given), measured after the step up to `min(target, step)`
    pub after: Vec<LinkMeasure>,
    /// the least [`RowMove::g2_slack`] over every row the step solved, in every round: a run
    /// with a G2 move factor ([`SetParams::g2_move_factor`]) below it gives the same result
    /// (0 when not measured)
    pub g2_slack: f64,
}

/// Makes a slave ready for the staged framework ([SV] §3.2 step 1): clamped, of sufficient
/// degree and with enough control rows for the frames of all its `links`, with the curvature
/// lead-in of [`ConnectParams::lead_in`] at its G2 sides. The shape is unchanged (rational
/// slaves stay rational).
pub fn prepare_slave(
    slave: &BSplineSurface,
    links: &[SideLink],
    params: &ConnectParams,
) -> Result<(BSplineSurface, ConnectReport)> {
    check_links(links)?;
    let mut report = ConnectReport::default();
    let s = prepare(slave, links, params, &mut report)?;
    Ok((s, report))
}

/// One step of the alternation ([SV] §3.2 steps 3 and 5, and the C0 re-attachment to faired
/// masters): sets continuity `step` on every link whose target is at least `step`, moving only
/// row `step` of those sides (rows of earlier steps stay bit-identical unless knots are inserted,
/// which keeps their shape). Sides that miss the tolerances get their failing knot spans halved
/// and the step is repeated — after the rows of the lower steps are solved again with the new
/// knots — up to [`ConnectParams::max_refinements`] rounds; the best round is returned. The C0
/// step of a slave with G1/G2 links aims at [`C0_FOR_G1_SHARE`] × the G0 tolerance (not below
/// [`ConnectParams::c0_floor`]). The slave must be prepared ([`prepare_slave`]).
pub fn set_step(
    slave: &BSplineSurface,
    links: &[SideLink],
    step: Continuity,
    params: &ConnectParams,
) -> Result<(BSplineSurface, StepReport)> {
    check_links(links)?;
    let mut report = StepReport {
        step: Some(step),
        g2_slack: f64::INFINITY,
        ..StepReport::default()
    };
    let mut work = slave.clone();
    let mut refiner = Refiner::new(slave, links);
    // the best round so far: (worst excess, surface, report)
    let mut best: Option<(f64, BSplineSurface, StepReport)> = None;
    // a boundary that will carry G1 must lie closer to its master than the G0 tolerance
    let tolerances = if step == Continuity::G0 && links.iter().any(|l| l.target > step) {
        crate::params::Tolerances {
            g0: (C0_FOR_G1_SHARE * params.tolerances.g0)
                .max(params.c0_floor)
                .min(params.tolerances.g0),
            ..params.tolerances
        }
    } else {
        params.tolerances
    };
    loop {
        let mut s = work.clone();
        let mut moved = 0.0f64;
        // after knots were inserted the rows of the lower steps are solved again first: the new
        // knots give them freedom too, and a boundary closer to its master lets G1 get closer
        let lower: &[Continuity] = match (report.refinements, step) {
            (0, _) | (_, Continuity::G0) => &[],
            (_, Continuity::G1) => &[Continuity::G0],
            (_, Continuity::G2) => &[Continuity::G0, Continuity::G1],
        };
        for &level in lower.iter().chain(std::iter::once(&step)) {
            let passes = if level == Continuity::G0 {
                params.set.c0_iterations.max(1)
            } else {
                1
            };
            for _ in 0..passes {
                let o = step_all(&mut s, links, level, &params.set)?;
                report.twists_averaged = report.twists_averaged.max(o.twists);
                report.g2_slack = report.g2_slack.min(o.g2_slack);
                moved = moved.max(o.max_move);
                if o.max_move <= C0_CONVERGED * s.size() {
                    break;
                }
            }
        }
        report.max_move = moved;
        let after: Vec<LinkMeasure> = links
            .iter()
            .map(|l| l.measure(&s, &params.measure))
            .collect::<Result<_>>()?;
        let worst = worst_excess(links, &after, step, &tolerances);
        report.after = after;
        if best.as_ref().is_none_or(|b| worst < b.0) {
            best = Some((worst, s.clone(), report.clone()));
        }
        let mut inserted = false;
        if report.refinements < params.max_refinements {
            let knots = refiner.knots(&s, links, &report.after, step, &tolerances);
            let done = insert_along(&mut work, links, knots, params, new_breakpoints, |l| {
                l.target < step
            })?;
            report.knots_inserted += done.iter().map(|(_, xs)| xs.len()).sum::<usize>();
            inserted = !done.is_empty();
        }
        if !inserted {
            let (_, s, report) = best.unwrap_or((0.0, s, report));
            return Ok((s, report));
        }
        report.refinements += 1;
    }
}

/// The knots of `xs` that can be inserted in direction `dir` of `s`: sorted, inside the open
/// domain, and none that would raise a knot's multiplicity above the degree (two links along
/// the same direction ask for the same span midpoints; on a degree-1 direction the second
/// insertion is impossible). A value within [`KNOT_MERGE_RELATIVE`] of the domain of a knot
/// counts as that knot.
pub fn new_knots(s: &BSplineSurface, dir: Direction, xs: &[f64]) -> Vec<f64> {
    insertable(s, dir, xs, true)
}

/// The values of `xs` to insert into direction `dir` of `s`, sorted, inside the open domain, a
/// value within [`KNOT_MERGE_RELATIVE`] of a knot snapped onto it; with `repeat` a knot may be
/// raised up to the degree, without it every value is a new breakpoint.
fn insertable(s: &BSplineSurface, dir: Direction, xs: &[f64], repeat: bool) -> Vec<f64> {
    let kv = match dir {
        Direction::U => s.knots_u(),
        Direction::V => s.knots_v(),
    };
    let (a, b) = kv.domain();
    let close = KNOT_MERGE_RELATIVE * (b - a);
    let p = kv.degree();
    let mut out: Vec<f64> = Vec::new();
    let mut sorted: Vec<f64> = xs.iter().copied().filter(|x| x.is_finite()).collect();
    sorted.sort_by(f64::total_cmp);
    for x in sorted {
        if x - a <= close || b - x <= close {
            continue;
        }
        // snap onto a knot that is there already, so that multiplicities add up exactly
        let known = kv
            .knots()
            .iter()
            .chain(out.iter())
            .copied()
            .find(|&k| (k - x).abs() <= close);
        match known {
            None => out.push(x),
            Some(k) if repeat => {
                let mult = kv.knots().iter().filter(|&&t| t == k).count()
                    + out.iter().filter(|&&t| t == k).count();
                if mult < p {
                    out.push(k);
                }
            }
            Some(_) => {}
        }
    }
    out
}

/// The knots of `xs` that are new breakpoints in direction `dir` of `s`: sorted, inside the open
/// domain, none at a knot that is there already and none twice. [`set_step`] refines with these:
/// it solves the rows of the earlier steps again after each round, and a knot repeated because
/// two sides along the same direction failed in the same span halves nothing but lowers the
/// continuity there — next to a vertex blend's corners the repeated knots left 1.3e-4 of
/// curvature difference against 2e-5 with single ones (box12_r5). [`connect_slave`] solves all
/// rows at once and keeps [`new_knots`]: the X-node centre of the twist tests meets G2 only with
/// the knots its opposite sides repeat.
pub fn new_breakpoints(s: &BSplineSurface, dir: Direction, xs: &[f64]) -> Vec<f64> {
    insertable(s, dir, xs, false)
}

/// Knots closer than this fraction of the domain are one knot (rounding of span midpoints; the
/// kernel's value).
pub use nurbs_core::knots::KNOT_MERGE_RELATIVE;

/// Share of the G0 tolerance that [`set_step`]'s C0 step aims at (knots inserted until reached)
/// when a link of the slave targets G1 or G2: a boundary off its master by a gap g that varies
/// along it over a length λ tilts its tangent out of the master's tangent plane by about
/// 2πg/λ, and no cross derivative makes the normals agree better than that tilt. On the car
/// shell a gap of 6.4e-4 (within the 1e-3 G0 tolerance) left G1 at 0.16° after the G1 step;
/// `connect` (all rows at once, refined for the highest target) reached gaps of 1–4e-5.
pub const C0_FOR_G1_SHARE: f64 = 0.05;

/// A refinement round improves a failing side when it brings the side's worst measure (relative
/// to its tolerance) below this factor times the best value so far. After
/// [`REFINE_PATIENCE`] rounds in a row without improvement that side gets no more knots: the
/// tolerance is then out of reach of knot insertion (e.g. an incompatible corner), and more knots
/// only make the solve slower and the surface wavier.
pub const REFINE_MIN_GAIN: f64 = 0.98;

/// Rounds in a row without improvement after which a side gets no more knots (see
/// [`REFINE_MIN_GAIN`]; the twists of neighbouring sides can make one round worse before the next
/// one helps).
pub const REFINE_PATIENCE: usize = 2;

/// Knots inserted along one side in all refinement rounds together are capped at this factor
/// times the number of control points the side had before (at least [`REFINE_MIN_KNOTS`]).
pub const REFINE_KNOTS_FACTOR: usize = 2;

/// Least cap of knots inserted along one side (see [`REFINE_KNOTS_FACTOR`]).
pub const REFINE_MIN_KNOTS: usize = 16;

/// Worst measure of a link relative to its tolerances, up to `target` (≤ 1: met).
fn excess(m: &LinkMeasure, target: Continuity, tol: &crate::params::Tolerances) -> f64 {
    let mut e = m.g0 / tol.g0;
    if target >= Continuity::G1 {
        e = e.max(m.g1_deg.unwrap_or(0.0) / tol.g1_deg);
    }
    if target >= Continuity::G2 {
        e = e.max(m.g2_rel.unwrap_or(0.0) / tol.g2_rel);
    }
    e
}

/// Knot insertion state of the links of one slave across refinement rounds.
struct Refiner {
    /// the smallest excess of each link so far
    best: Vec<Option<f64>>,
    /// rounds in a row without improvement, per link
    idle: Vec<usize>,
    /// links that get no more knots
    stalled: Vec<bool>,
    /// knots inserted along each link's side so far, and its cap
    inserted: Vec<usize>,
    cap: Vec<usize>,
}

impl Refiner {
    fn new(slave: &BSplineSurface, links: &[SideLink]) -> Self {
        let cap = links
            .iter()
            .map(|l| {
                let count = match l.side.along_direction() {
                    Direction::U => slave.num_u(),
                    Direction::V => slave.num_v(),
                };
                (REFINE_KNOTS_FACTOR * count).max(REFINE_MIN_KNOTS)
            })
            .collect();
        Self {
            best: vec![None; links.len()],
            idle: vec![0; links.len()],
            stalled: vec![false; links.len()],
            inserted: vec![0; links.len()],
            cap,
        }
    }

    /// Knots to insert along each link's side after a round with measures `after` (empty: none).
    fn knots(
        &mut self,
        s: &BSplineSurface,
        links: &[SideLink],
        after: &[LinkMeasure],
        step: Continuity,
        tol: &crate::params::Tolerances,
    ) -> Vec<Vec<f64>> {
        let mut out = vec![Vec::new(); links.len()];
        for (a, (l, m)) in links.iter().zip(after).enumerate() {
            let target = l.target.min(step);
            let e = excess(m, target, tol);
            if self.best[a].is_some_and(|b| e > REFINE_MIN_GAIN * b) {
                self.idle[a] += 1;
                if self.idle[a] >= REFINE_PATIENCE {
                    self.stalled[a] = true;
                }
            } else {
                self.idle[a] = 0;
            }
            self.best[a] = Some(self.best[a].map_or(e, |b| b.min(e)));
            if e <= 1.0 || self.stalled[a] {
                continue;
            }
            let mut mids = failing_spans(s, m, target, tol);
            if self.inserted[a] + mids.len() > self.cap[a] {
                self.stalled[a] = true;
                continue;
            }
            mids.sort_by(f64::total_cmp);
            self.inserted[a] += mids.len();
            out[a] = mids;
        }
        out
    }
}

/// Worst excess over all links (the quality of one round's result).
fn worst_excess(
    links: &[SideLink],
    after: &[LinkMeasure],
    step: Continuity,
    tol: &crate::params::Tolerances,
) -> f64 {
    links
        .iter()
        .zip(after)
        .map(|(l, m)| excess(m, l.target.min(step), tol))
        .fold(0.0, f64::max)
}

/// Midpoints of the along-side knot spans that hold a sample above the tolerances.
fn failing_spans(
    surface: &BSplineSurface,
    m: &LinkMeasure,
    target: Continuity,
    tol: &crate::params::Tolerances,
) -> Vec<f64> {
    let kv = along_knots(surface, m.side);
    let k = kv.knots();
    let mut mids: Vec<f64> = Vec::new();
    for s in &m.detail {
        let bad = s.gap > tol.g0
            || (target >= Continuity::G1 && s.angle_deg.is_some_and(|a| a > tol.g1_deg))
            || (target >= Continuity::G2
                && match (s.kappa_slave, s.kappa_master) {
                    (Some(a), Some(b)) => (a - b).abs() > tol.g2_rel * a.abs().max(b.abs()),
                    _ => false,
                });
        if bad {
            let span = kv.span(s.t);
            let mid = 0.5 * (k[span] + k[span + 1]);
            if !mids.contains(&mid) {
                mids.push(mid);
            }
        }
    }
    mids
}

/// The best refinement round of [`connect_slave`] so far.
struct BestRound {
    /// its worst excess over the links (≤ 1: every link met)
    worst: f64,
    /// the slave after the round
    surface: BSplineSurface,
    /// the links measured on it
    after: Vec<LinkMeasure>,
    /// the prepared slave refined the same way (what its moves are measured against)
    reference: BSplineSurface,
    /// knots inserted along the sides before the round
    along_knots: usize,
    /// refinement rounds before it
    rounds: usize,
}

/// Inserts the refiner's `knots` along each link's side of `work`, except for links `skip`
/// names and where the net would pass [`ConnectParams::max_control_points`]; `insertable`
/// picks the values that can go in ([`new_knots`], [`new_breakpoints`]). Returns what went in,
/// in order (the one insertion step of [`set_step`] and [`connect_slave`]).
fn insert_along(
    work: &mut BSplineSurface,
    links: &[SideLink],
    knots: Vec<Vec<f64>>,
    params: &ConnectParams,
    insertable: fn(&BSplineSurface, Direction, &[f64]) -> Vec<f64>,
    skip: impl Fn(&SideLink) -> bool,
) -> Result<Vec<(Direction, Vec<f64>)>> {
    let mut done = Vec::new();
    for (l, xs) in links.iter().zip(knots) {
        if skip(l) || xs.is_empty() {
            continue;
        }
        let dir = l.side.along_direction();
        let count = match dir {
            Direction::U => work.num_u(),
            Direction::V => work.num_v(),
        };
        if count + xs.len() > params.max_control_points {
            continue;
        }
        let xs = insertable(work, dir, &xs);
        if xs.is_empty() {
            continue;
        }
        *work = work.refine(dir, &xs)?;
        done.push((dir, xs));
    }
    Ok(done)
}

/// Sets continuity of `slave` to all its `links` (C0 → G1 → G2, twists averaged), inserting knots
/// along sides that miss the tolerances; returns the new slave and the report. Masters are never
/// modified.
pub fn connect_slave(
    slave: &BSplineSurface,
    links: &[SideLink],
    params: &ConnectParams,
) -> Result<(BSplineSurface, ConnectReport)> {
    check_links(links)?;
    let mut report = ConnectReport::default();
    let before: Vec<LinkMeasure> = links
        .iter()
        .map(|l| l.measure(slave, &params.measure))
        .collect::<Result<_>>()?;
    let mut work = prepare(slave, links, params, &mut report)?;
    let mut reference = work.clone();
    let mut refiner = Refiner::new(&work, links);
    let mut best: Option<BestRound> = None;
    let prepared_knots = report.knots_inserted;
    let mut along_knots = 0;
    loop {
        let mut s = work.clone();
        report.twists_averaged = set_rows(&mut s, links, &params.set)?;
        let after: Vec<LinkMeasure> = links
            .iter()
            .map(|l| l.measure(&s, &params.measure))
            .collect::<Result<_>>()?;
        let worst = worst_excess(links, &after, Continuity::G2, &params.tolerances);
        let rounds = report.refinements;
        let knots = if rounds < params.max_refinements {
            refiner.knots(&s, links, &after, Continuity::G2, &params.tolerances)
        } else {
            Vec::new()
        };
        if best.as_ref().is_none_or(|b| worst < b.worst) {
            best = Some(BestRound {
                worst,
                surface: s,
                after,
                reference: reference.clone(),
                along_knots,
                rounds,
            });
        }
        let done = insert_along(&mut work, links, knots, params, new_knots, |_| false)?;
        for (dir, xs) in &done {
            reference = reference.refine(*dir, xs)?;
            along_knots += xs.len();
        }
        if done.is_empty() {
            break;
        }
        report.refinements += 1;
    }
    let Some(BestRound {
        surface: result,
        after,
        reference,
        along_knots: along,
        rounds,
        ..
    }) = best
    else {
        unreachable!("at least one round ran");
    };
    report.knots_inserted = prepared_knots + along;
    report.refinements = rounds;
    report.max_control_movement = result
        .control_points()
        .iter()
        .zip(reference.control_points())
        .map(|(a, b): (&Point3, &Point3)| (a - b).norm())
        .fold(0.0, f64::max);
    report.sides = links
        .iter()
        .zip(before.into_iter().zip(after))
        .map(|(l, (before, after))| {
            let t = &params.tolerances;
            let met = after.meets(l.target, t.g0, t.g1_deg, t.g2_rel);
            SideReport {
                side: l.side,
                target: l.target,
                before,
                after,
                met,
            }
        })
        .collect();
    Ok((result, report))
}
