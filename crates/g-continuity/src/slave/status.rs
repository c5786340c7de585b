//! How each control point of a side's row takes part in one step (\[SV\] §3.3): fixed, shared
//! (a twist or a common corner, averaged), sliding, an end on a free boundary, or free — from
//! the targets of the neighbouring sides, poles and degenerate corners (see the parent module).
//!
//! # Tolerance
//! [`END_CONTINUOUS`]: an end point on a free boundary stays where it is when its corner
//! sample alone asks for less than this times the slave size.

use nurbs_core::{BSplineSurface, Continuity, Side};

use super::{END_CONTINUOUS, SideLink};
use crate::error::Result;
use crate::measure::is_collapsed;
use crate::params::SetParams;
use crate::rows::{row_of, solve_row_at};

/// How a point of a side's row takes part in a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Status {
    /// moves with the row's solve
    Free,
    /// a twist or a common corner: both sides propose a position and the mean is kept
    Shared,
    /// end point of a row k ≥ 1 on an unlinked neighbouring side: it lies on that free boundary,
    /// so it moves only by what its own corner sample needs
    End,
    /// end point of a row k ≥ 1 on a neighbouring side linked G0 only (e.g. a fillet's end on a
    /// face it meets at a sharp edge): it lies on that side's boundary, so it moves only within
    /// the G0 master's tangent plane at the corner, which keeps that join C0 (exactly on a plane
    /// master, to first order on a curved one) while the corner takes part in the G1/G2 solve
    Sliding,
    /// does not move
    Fixed,
}

/// The status of each of the `m` points of row `k` of `side`, from the continuity levels of the
/// four sides (`None`: unlinked) and the kept sides.
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
                let s = match levels[adj.index()] {
                    // on a kept side's boundary row or the row next to it
                    None if kept[adj.index()] && e <= 1 => Status::Fixed,
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

/// The row of the frames a target sets (G0: 0, G1: 1, G2: 2).
pub(super) fn level(c: Continuity) -> usize {
    row_of(c)
}

/// The level of each of the four sides (`None`: unlinked).
pub(super) fn levels_of(links: &[SideLink]) -> [Option<usize>; 4] {
    let mut levels = [None; 4];
    for l in links {
        levels[l.side.index()] = Some(level(l.target));
    }
    levels
}

/// The statuses of the row of every active side of `base` that `step` sets, and the least
/// [`RowMove::g2_slack`](crate::rows::RowMove::g2_slack) of the corner solves that decided end
/// points (∞ when none ran).
pub(super) fn row_statuses(
    active: &[&SideLink],
    links: &[SideLink],
    step: Continuity,
    base: &BSplineSurface,
    params: &SetParams,
) -> Result<(Vec<Vec<Status>>, f64)> {
    let k = row_of(step);
    let levels = levels_of(links);
    let degenerate = degenerate_corner_blocks(base);
    let mut statuses: Vec<Vec<Status>> = Vec::with_capacity(active.len());
    // the weight searches of the corner samples decide statuses: their slack counts too
    let mut end_slack = f64::INFINITY;
    for l in active {
        let m = l.side.row(k, base.num_u(), base.num_v()).len();
        let mut status = classify(
            l.side,
            k,
            m,
            &levels,
            params.move_unlinked_boundaries,
            &params.kept_sides,
        );
        fix_poles_and_blocks(&mut status, l.side, k, base, &degenerate);
        settle_ends(&mut status, l, step, base, params, &mut end_slack)?;
        statuses.push(status);
    }
    Ok((statuses, end_slack))
}

/// Fixes the points of row `k` of `side` that never move: an end on a neighbouring side
/// collapsed to a pole, and the points of the `degenerate` corner blocks.
fn fix_poles_and_blocks(
    status: &mut [Status],
    side: Side,
    k: usize,
    base: &BSplineSurface,
    degenerate: &[(usize, usize)],
) {
    let m = status.len();
    // the end point on a neighbouring side collapsed to a point (a pole) is that point: it
    // never moves, so the pole stays one point and the rows next to it stay consistent
    let (start, end) = side.neighbours();
    if is_collapsed(base, start) {
        status[0] = Status::Fixed;
    }
    if is_collapsed(base, end) {
        status[m - 1] = Status::Fixed;
    }
    // a degenerate corner — a corner point and its neighbour along one side coincide, a
    // zero end tangent, how kernels close a vertex blend's side — has a normal only as the
    // limit S_u × S_uv: it depends on the corner's 2 × 2 block, twist included, and moving
    // any of them turns the normal there (0.7° on a variable-radius box's freeform vertex blend).
    // The block stays as it is, as a pole does.
    let row = side.row(k, base.num_u(), base.num_v());
    for (j, ij) in row.iter().enumerate() {
        if degenerate.contains(ij) {
            status[j] = Status::Fixed;
        }
    }
}

/// Decides the [`Status::End`] points of the row of link `l`: an end the link's part does not
/// reach is free (decided by the part's samples); one whose corner sample alone asks for a move
/// within [`END_CONTINUOUS`] of the slave size is fixed; the others are free. The corner solves'
/// least G2 slack goes into `end_slack`.
fn settle_ends(
    status: &mut [Status],
    l: &SideLink,
    step: Continuity,
    base: &BSplineSurface,
    params: &SetParams,
    end_slack: &mut f64,
) -> Result<()> {
    let m = status.len();
    // an end point on an unlinked side lies on that free boundary: it stays where it is when
    // its corner is already continuous (the corner sample alone asks for no move), and is
    // free otherwise (the boundary has to change for the corner anyway)
    let (t0, t1) = l.side.along_domain(base);
    let (r0, r1) = l.domain(base);
    for (j, t) in [(0, t0), (m - 1, t1)] {
        if status[j] != Status::End {
            continue;
        }
        // an end the link's part does not reach is no corner of this join, but its basis
        // function reaches into the part (`within_part` frees only points whose function the
        // part holds at least `PART_SHARE` of): the part's samples decide it with the rest of
        // the row. Kept where it was, it holds the row at
        // its old curvature near the part's end, and a polynomial span cannot follow the master
        // up to that end and keep it: the least-squares error spreads along the whole row (a
        // fillet's side on its face short of its end by 1 % missed G2 by a relative 1.5 along
        // all of it, and met it with the end free)
        if (j == 0 && r0 > t0) || (j == m - 1 && r1 < t1) {
            status[j] = Status::Free;
            continue;
        }
        let mut only = vec![false; m];
        only[j] = true;
        let corner = solve_row_at(l.master, base, l.side, step, &only, &[t], params)?;
        *end_slack = end_slack.min(corner.g2_slack);
        status[j] = if corner.max_displacement() <= END_CONTINUOUS * base.size() {
            Status::Fixed
        } else {
            Status::Free
        };
    }
    Ok(())
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
