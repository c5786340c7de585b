//! What a fairing stage keeps: the rows fixed per side and level, poles and degenerate corners,
//! the columns of smooth C⁰ joins, and the knots that give a surface free rows.

use g_continuity::SideLink;
use nurbs_core::{BSplineSurface, Continuity, ControlMask, Direction, Side};

/// Knots of `after` that `before` lacks, both directions (with multiplicity).
pub(super) fn knots_between(before: &BSplineSurface, after: &BSplineSurface) -> usize {
    missing_knots(before.knots_u().knots(), after.knots_u().knots()).len()
        + missing_knots(before.knots_v().knots(), after.knots_v().knots()).len()
}

/// Rows fixed at `side` when keeping `level`: the link's target (capped by `level`) + 1, or
/// the boundary row for an unlinked side.
fn fixed_rows(links: &[SideLink], side: Side, level: Continuity) -> usize {
    links
        .iter()
        .find(|l| l.side == side)
        .map_or(1, |l| l.target.min(level).frame().rows())
}

/// The mask of a fairing stage keeping `level`.
pub fn stage_mask(surface: &BSplineSurface, links: &[SideLink], level: Continuity) -> ControlMask {
    let mut mask = ControlMask::for_surface(surface);
    for side in Side::ALL {
        let rows = fixed_rows(links, side, level);
        let frame = match rows {
            1 => nurbs_core::Frame::Positional,
            2 => nurbs_core::Frame::Tangential,
            _ => nurbs_core::Frame::Curvature,
        };
        mask.fix_frame(side, frame);
        // a pole: its point and the row next to it (the tangent plane there) stay, as in the
        // continuity steps — a fairing that moves them splits the pole or turns its normal, and
        // the set steps, which keep them, cannot bring the sides that end there back. Where a
        // side kept at G2 ends there, row 2 (the curvature at the pole, which the G2 step sets
        // to the masters') stays too: next to a pole a micrometre of it is a curvature of
        // tenths per millimetre
        if g_continuity::measure::is_collapsed(surface, side) {
            let (a, b) = side.neighbours();
            let g2 = fixed_rows(links, a, level).max(fixed_rows(links, b, level)) >= 3;
            let pole = if g2 {
                nurbs_core::Frame::Curvature
            } else {
                nurbs_core::Frame::Tangential
            };
            mask.fix_frame(side, frame.max(pole));
        }
    }
    // a degenerate corner's 2 × 2 block carries its normal; the set steps keep it, so does fairing
    for (i, j) in g_continuity::degenerate_corner_blocks(surface) {
        mask.set_free(i, j, false);
    }
    mask
}

/// The control points of `s` on the three columns of every C⁰ knot line
/// ([`nurbs_core::creases`]) across which `start` — the surface as it came in, same
/// parametrization — is tangent continuous (normal jump within `g1_deg`, or no normal there):
/// a kernel's rational arcs joined by double knots. The tangent plane across such a line rests
/// on those columns staying collinear, which a fairing method that moves points one by one does
/// not keep (a torus of three arcs came out of the local scheme with 7.4° creases); fixed, the
/// join stays exactly as it came. A line that was already a crease in `start` (C⁰-joined
/// Bézier patches) is left to the method, which may make it C¹ (\[H\] part ②).
pub fn smooth_join_points(
    start: &BSplineSurface,
    s: &BSplineSurface,
    g1_deg: f64,
) -> Vec<(usize, usize)> {
    let (nu, nv) = (s.num_u(), s.num_v());
    let mut out = Vec::new();
    for line in nurbs_core::creases::knot_lines(s) {
        if nurbs_core::creases::crease_deg(start, &line).is_some_and(|d| d > g1_deg) {
            continue;
        }
        let (count, across) = match line.direction {
            Direction::U => (nu, nv),
            Direction::V => (nv, nu),
        };
        let first = line.column.saturating_sub(1);
        let last = (line.column + 1).min(count - 1);
        for k in first..=last {
            for j in 0..across {
                out.push(match line.direction {
                    Direction::U => (k, j),
                    Direction::V => (j, k),
                });
            }
        }
    }
    out
}

/// The knots of the sorted `superset` that the sorted `subset` lacks (with multiplicity).
pub(super) fn missing_knots(subset: &[f64], superset: &[f64]) -> Vec<f64> {
    let mut out = Vec::new();
    let mut i = 0;
    for &k in superset {
        if i < subset.len() && subset[i] == k {
            i += 1;
        } else {
            out.push(k);
        }
    }
    out
}

/// Inserts knots (widest span halved) until every direction has `min_free` rows besides the
/// fixed frames of both ends at the highest level; returns the surface and the knot count.
pub(super) fn free_rows(
    mut s: BSplineSurface,
    links: &[SideLink],
    min_free: usize,
) -> nurbs_core::Result<(BSplineSurface, usize)> {
    let mut inserted = 0;
    for (dir, a, b) in [
        (Direction::U, Side::U0, Side::U1),
        (Direction::V, Side::V0, Side::V1),
    ] {
        let need =
            fixed_rows(links, a, Continuity::G2) + fixed_rows(links, b, Continuity::G2) + min_free;
        let (more, k) = s.with_smooth_control_count(dir, need)?;
        s = more;
        inserted += k;
    }
    Ok((s, inserted))
}
