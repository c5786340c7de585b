//! One step (row k: C0, G1 or G2) on every linked side of a slave at once (\[SV\] §3.3, §4):
//! every side's row solved on its own, the candidates of shared points (twists, common corners)
//! averaged and the sides solved again with those pinned; sliding end points kept in their G0
//! master's tangent plane, and on request the corner tangents turned after the C0 rows.

use std::collections::BTreeMap;

use nurbs_core::{BSplineSurface, Continuity, Side, Vector3};
use rayon::prelude::*;

use super::status::{Status, degenerate_corner_blocks, row_statuses};
use super::{PART_SHARE, SideLink};
use crate::error::Result;
use crate::measure::is_collapsed;
use crate::params::SetParams;
use crate::rows::{RowMove, row_of};

/// Outcome of one step over all sides.
#[derive(Debug, Clone, Copy)]
pub(super) struct StepOutcome {
    /// shared points (twists, common corners) averaged
    pub(super) twists: usize,
    /// largest control point movement (model units)
    pub(super) max_move: f64,
    /// the least [`RowMove::g2_slack`] of the rows solved
    pub(super) g2_slack: f64,
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

/// The least [`RowMove::g2_slack`] of `moves` (∞ for none).
fn least_slack(moves: &[RowMove]) -> f64 {
    moves
        .iter()
        .map(|m| m.g2_slack)
        .fold(f64::INFINITY, f64::min)
}

/// The summed candidate displacement of each shared point and the number of sides proposing it.
type SharedCandidates = BTreeMap<(usize, usize), (Vector3, usize)>;

/// The sides one step solves, with the status of every point of their rows.
struct StepSides<'a> {
    /// the linked sides with target ≥ the step, none collapsed
    active: Vec<&'a SideLink<'a>>,
    /// per active side, the status of each point of its row
    statuses: Vec<Vec<Status>>,
    /// every link of the slave (the neighbours' masters)
    links: &'a [SideLink<'a>],
    /// the step's continuity
    step: Continuity,
    /// the settings of the row solves
    params: &'a SetParams,
    /// whether the C0 rows also set the normal curvature at corners with a G2 neighbour
    corner_curvature: bool,
}

impl StepSides<'_> {
    /// The row moves of every active side on `surface`, the points whose status passes `movable`
    /// free. The sides' systems are independent (each reads `surface` only): they are solved in
    /// parallel and collected in side order, the first error in side order winning, so the
    /// result does not depend on the thread count.
    fn solve(
        &self,
        surface: &BSplineSurface,
        movable: impl Fn(Status) -> bool + Sync,
    ) -> Result<Vec<RowMove>> {
        let (step, params) = (self.step, self.params);
        let k = row_of(step);
        self.active
            .par_iter()
            .zip(&self.statuses)
            .map(|(l, status)| {
                let mut free: Vec<bool> = status.iter().map(|&s| movable(s)).collect();
                if l.range.is_some() {
                    within_part(&mut free, l, surface);
                }
                let corners = if step == Continuity::G0 && self.corner_curvature {
                    corner_curvatures(l, self.links, surface)
                } else {
                    Vec::new()
                };
                let mut mv = crate::rows::solve_row_with(
                    l.master,
                    surface,
                    l.side,
                    (l.range, l.g2_zones),
                    step,
                    &free,
                    params,
                    &corners,
                )?;
                slide(&mut mv, k, status, l.side, self.links, surface, params);
                Ok(mv)
            })
            .collect::<Vec<Result<RowMove>>>()
            .into_iter()
            .collect()
    }

    /// The candidates of the shared points in `moves` (one per active side), summed in side
    /// order.
    fn shared_candidates(&self, moves: &[RowMove], nu: usize, nv: usize) -> SharedCandidates {
        let k = row_of(self.step);
        let mut shared = SharedCandidates::new();
        for (l, (status, mv)) in self.active.iter().zip(self.statuses.iter().zip(moves)) {
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
        shared
    }

    /// `base` with every shared point moved by the mean of its candidates, then every side
    /// solved again with those points pinned (only free and sliding points move); the moves
    /// and the G2 slack go into `outcome`.
    fn solve_pinned(
        &self,
        base: BSplineSurface,
        shared: &SharedCandidates,
        outcome: &mut StepOutcome,
    ) -> Result<BSplineSurface> {
        let mut pinned = base;
        for (&(i, j), &(sum, count)) in shared {
            let idx = pinned.index(i, j);
            let d = sum / count as f64;
            pinned.control_points_mut()[idx] += d;
            outcome.max_move = outcome.max_move.max(d.norm());
        }
        let second = self.solve(&pinned, |s| matches!(s, Status::Free | Status::Sliding))?;
        outcome.g2_slack = outcome.g2_slack.min(least_slack(&second));
        for mv in &second {
            mv.apply(&mut pinned);
            outcome.max_move = outcome.max_move.max(mv.max_displacement());
        }
        Ok(pinned)
    }
}

/// The corners of side link `l` whose neighbouring side carries G2 to a master along the whole
/// side (neither side collapsed): there the C0 row also sets the boundary's normal curvature
/// ([`crate::rows::solve_row_with`]).
fn corner_curvatures<'a>(
    l: &SideLink<'_>,
    links: &'a [SideLink<'a>],
    surface: &BSplineSurface,
) -> Vec<crate::rows::CornerCurvature<'a>> {
    if l.range.is_some() || is_collapsed(surface, l.side) {
        return Vec::new();
    }
    let (t0, t1) = l.side.along_domain(surface);
    let (start, end) = l.side.neighbours();
    [(t0, start), (t1, end)]
        .into_iter()
        .filter_map(|(t, adj)| {
            let b = links.iter().find(|x| {
                x.side == adj
                    && x.target >= Continuity::G2
                    && x.range.is_none()
                    && !is_collapsed(surface, adj)
            })?;
            Some(crate::rows::CornerCurvature {
                t,
                master: b.master,
            })
        })
        .collect()
}

/// Clears the points of `free` that do not belong to the part of the side link `l` holds on:
/// those whose along-side basis function holds less than [`PART_SHARE`] of its integral inside
/// it (none at all: no equation; a tail: equations of the tail's height).
fn within_part(free: &mut [bool], l: &SideLink, surface: &BSplineSurface) {
    let (a, b) = l.domain(surface);
    let kv = crate::sampling::along_knots(surface, l.side);
    for (j, f) in free.iter_mut().enumerate() {
        let inside = nurbs_core::basis::basis_function_integral(kv, j, a, b);
        let mass = nurbs_core::basis::basis_function_mass(kv, j);
        *f &= inside > 0.0 && inside >= PART_SHARE * mass;
    }
}

/// One step (row k) on every linked side with target ≥ `step`, with twist averaging.
pub(super) fn step_all(
    slave: &mut BSplineSurface,
    links: &[SideLink],
    step: Continuity,
    params: &SetParams,
) -> Result<StepOutcome> {
    step_all_with(slave, links, step, params, false)
}

/// [`step_all`]; with `corner_curvature` the C0 rows also set the boundary's normal curvature
/// at each corner whose neighbouring side carries G2 ([`crate::rows::solve_row_with`]).
pub(super) fn step_all_with(
    slave: &mut BSplineSurface,
    links: &[SideLink],
    step: Continuity,
    params: &SetParams,
    corner_curvature: bool,
) -> Result<StepOutcome> {
    let active: Vec<&SideLink> = links
        .iter()
        .filter(|l| l.target >= step && !is_collapsed(slave, l.side))
        .collect();
    if active.is_empty() {
        return Ok(StepOutcome::default());
    }
    let (nu, nv) = (slave.num_u(), slave.num_v());
    let base = slave.clone();
    let (statuses, end_slack) = row_statuses(&active, links, step, &base, params)?;
    let sides = StepSides {
        active,
        statuses,
        links,
        step,
        params,
        corner_curvature,
    };
    let moves = sides.solve(&base, |s| s != Status::Fixed)?;
    let shared = sides.shared_candidates(&moves, nu, nv);
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
    } else {
        *slave = sides.solve_pinned(base, &shared, &mut outcome)?;
    }
    if step == Continuity::G0 && params.tangent_corners {
        let t = tangent_corners(slave, links, &sides.active, params);
        outcome.max_move = outcome.max_move.max(t);
    }
    if step == Continuity::G0 && params.seam_end_tangents.contains(&true) {
        let t = seam_end_tangents(slave, &sides.active, params);
        outcome.max_move = outcome.max_move.max(t);
    }
    if step == Continuity::G0 && params.contact_lines.iter().flatten().any(Option::is_some) {
        let t = contact_line_tangents(slave, &sides.active, params);
        outcome.max_move = outcome.max_move.max(t);
    }
    Ok(outcome)
}

/// After the C0 rows: where a side's boundary ends at a corner that a contact line of its
/// master leaves ([`SetParams::contact_lines`]: the neighbouring side's master B is linked to
/// this side's master A along a boundary through the corner), the row's second point turns
/// within A's tangent plane so that the boundary leaves the corner along that line, its
/// distance from the corner kept. Third-order compatibility at a corner of two G2 sides (\[SV\]
/// §3.3's corner compatibility two orders up; \[PW\] for G2 along a curve): G2
/// along this side sets the slave's mixed derivative n · S_uvv at the corner to A's, so along
/// the other side the slave's cross curvature starts with the slope A prescribes; B is G2 to A
/// along the contact line, so its curvature across the slave's other side starts with the same
/// slope only in the line's direction (where A is flat both slopes are zero along the line, and
/// a kink θ between the boundary and the line gives B a slope of about sin²θ times the rate at
/// which B's cross curvature grows off the line: at 3.2° on a kernel's vertex blend, a relative
/// curvature figure near 1 next to the corner on B's side). Only a line that continues the
/// boundary (within 45°, nearer its direction than across it) is followed. Returns the largest
/// move.
fn contact_line_tangents(
    slave: &mut BSplineSurface,
    active: &[&SideLink],
    params: &SetParams,
) -> f64 {
    let (nu, nv) = (slave.num_u(), slave.num_v());
    let fixed = degenerate_corner_blocks(slave);
    let mut largest = 0.0f64;
    for l in active.iter().filter(|l| l.range.is_none()) {
        let k = l.side.index();
        let row = l.side.row(0, nu, nv);
        let m = row.len();
        if m < 3 || is_collapsed(slave, l.side) {
            continue;
        }
        for (e, (c, j)) in [(0, 1), (m - 1, m - 2)].into_iter().enumerate() {
            let Some(line) = params.contact_lines[k][e] else {
                continue;
            };
            let (corner, second) = (row[c], row[j]);
            if fixed.contains(&corner) || fixed.contains(&second) {
                continue;
            }
            let p0 = slave.control_point(corner.0, corner.1);
            let foot = nurbs_core::project_to_surface(l.master, &p0, &params.projection);
            let Some(n) = l.master.derivatives(foot.u, foot.v).normal() else {
                continue;
            };
            let idx = slave.index(second.0, second.1);
            let arm = slave.control_points()[idx] - p0;
            let line = Vector3::new(line[0], line[1], line[2]);
            let within = line - n * n.dot(&line);
            let Some(dir) = within.try_normalize(f64::MIN_POSITIVE) else {
                continue;
            };
            // a line that continues the boundary — nearer its direction than across it; one
            // that crosses the corner is another join, which the boundary must not follow
            if dir.dot(&arm).abs() < dir.cross(&arm).norm() {
                continue;
            }
            let dir = if dir.dot(&arm) < 0.0 { -dir } else { dir };
            let moved = p0 + dir * arm.norm();
            largest = largest.max((moved - slave.control_points()[idx]).norm());
            slave.control_points_mut()[idx] = moved;
        }
    }
    largest
}

/// After the C0 rows: where a linked side's boundary row ends on a seam
/// ([`SetParams::seam_end_tangents`]), the row's second point moves into the tangent plane of
/// the side's own master at the corner. Fitted by positions only, the boundary's end tangent
/// misses that plane by the fit's slope error (1.45e-4 rad on a kernel's saddle fillet, with a
/// gap of 7e-9 at the corner and 8e-6 one sample in), which no G1 row can take back (they move
/// the next row, not this one): the corner normal is then tilted by that angle about the cross
/// direction. The two parts of a seam fit their boundaries separately and tilt in opposite
/// senses, so the seam opens by the sum, up to twice a figure that the link alone still meets.
/// Turned into the master's plane, both corner normals are the master's. No link lies across
/// the seam, so the move (the slope error times the control-point spacing, far below the C0
/// tolerance) changes no other link's curvature. Returns the largest move.
fn seam_end_tangents(slave: &mut BSplineSurface, active: &[&SideLink], params: &SetParams) -> f64 {
    turn_end_tangents(slave, active, params, |l, adj| {
        let k = adj.index();
        (params.seam_end_tangents[k] && l.range.is_none()).then_some(l.master)
    })
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
    turn_end_tangents(slave, active, params, |_, adj| {
        links
            .iter()
            .find(|x| x.side == adj && x.target >= Continuity::G1 && x.range.is_none())
            .map(|x| x.master)
    })
}

/// Moves the second point of each boundary row of `active`, at each end, into the tangent
/// plane at the corner of the master `plane` names for that row and the neighbouring side (no
/// master: the end stays); ends on a collapsed side or in a degenerate corner's block stay too.
/// Returns the largest move.
fn turn_end_tangents<'m>(
    slave: &mut BSplineSurface,
    active: &[&SideLink<'m>],
    params: &SetParams,
    plane: impl Fn(&SideLink<'m>, Side) -> Option<&'m BSplineSurface>,
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
            let Some(master) = plane(l, adj) else {
                continue;
            };
            let (corner, second) = (row[c], row[j]);
            if is_collapsed(slave, adj) || fixed.contains(&corner) || fixed.contains(&second) {
                continue;
            }
            let p0 = slave.control_point(corner.0, corner.1);
            let foot = nurbs_core::project_to_surface(master, &p0, &params.projection);
            let Some(n) = master.derivatives(foot.u, foot.v).normal() else {
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
