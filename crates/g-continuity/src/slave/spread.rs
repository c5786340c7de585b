//! The boundary's move spread into the interior (\[F02\], the bilinearly blended Coons
//! patch). The C0 step moves the boundary rows of the linked sides onto their masters. Where a
//! master changed shape before its slave is set (a fillet whose section was made one-hump, a
//! master faired first), that move is up to the deviation budget. Moving only the boundary row
//! turns it into a strip of curvature one span wide beside the side, which the G1 and G2 steps
//! then fix in place — a sphere corner bounded by three re-sectioned fillets peaked at 11× its
//! curvature that way.
//!
//! The interior points move with the boundary instead: the displacement field is the Boolean
//! sum of the linear blends across the net of the four boundary rows' moves, taken at the
//! Greville fractions of the control points. A side with no link has no move of its own to
//! give: its row enters the blend as the straight interpolation of its two corners' moves (the
//! row itself is not moved), so that where one side moved the field decays linearly across to
//! the opposite side, and where two opposite sides moved it is their ruled blend. The field
//! reproduces every linked side's move (the C0 result is unchanged) and is zero where nothing
//! moved, so a slave whose boundary already lies on its masters is left bit-identical.

use nurbs_core::{BSplineSurface, Side, Vector3};

/// Moves the interior control points of `after` by the Coons blend of its boundary points'
/// moves from `before` (module docs); `linked[k]` tells whether side `Side::ALL[k]` has a link,
/// `kept[k]` whether it keeps its frame ([`crate::SetParams::kept_sides`]: its row enters the
/// blend as it is, and its rows 1 and 2 do not move). `before` and `after` must have the same
/// net; otherwise `after` is left as it is.
pub(crate) fn spread_boundary_move(
    before: &BSplineSurface,
    after: &mut BSplineSurface,
    linked: [bool; 4],
    kept: [bool; 4],
) {
    let (nu, nv) = (after.num_u(), after.num_v());
    if before.num_u() != nu || before.num_v() != nv || nu < 3 || nv < 3 {
        return;
    }
    let (last_u, last_v) = (nu - 1, nv - 1);
    let actual = |i: usize, j: usize| after.control_point(i, j) - before.control_point(i, j);
    let corners = [
        actual(0, 0),
        actual(last_u, 0),
        actual(0, last_v),
        actual(last_u, last_v),
    ];
    let (su, sv) = (
        after.knots_u().greville_fractions(),
        after.knots_v().greville_fractions(),
    );
    let at = Side::index;
    let is = |side: Side| linked[at(side)] || kept[at(side)];
    // a kept side's frame: rows 1 and 2 (the G1 and G2 rows) beside it
    let frozen = |i: usize, j: usize| {
        (kept[at(Side::U0)] && i <= 2)
            || (kept[at(Side::U1)] && i + 2 >= last_u)
            || (kept[at(Side::V0)] && j <= 2)
            || (kept[at(Side::V1)] && j + 2 >= last_v)
    };
    // the move a side's row gives the blend at its k-th point: its own where it is linked, the
    // interpolation of its corners' moves where it is not
    let row = |side: Side, k: usize| -> Vector3 {
        match side {
            Side::U0 if is(side) => actual(0, k),
            Side::U1 if is(side) => actual(last_u, k),
            Side::V0 if is(side) => actual(k, 0),
            Side::V1 if is(side) => actual(k, last_v),
            Side::U0 => corners[0] * (1.0 - sv[k]) + corners[2] * sv[k],
            Side::U1 => corners[1] * (1.0 - sv[k]) + corners[3] * sv[k],
            Side::V0 => corners[0] * (1.0 - su[k]) + corners[1] * su[k],
            Side::V1 => corners[2] * (1.0 - su[k]) + corners[3] * su[k],
        }
    };
    let moved = |side: Side, len: usize| (0..len).any(|k| row(side, k) != Vector3::zeros());
    if !(moved(Side::U0, nv) || moved(Side::U1, nv) || moved(Side::V0, nu) || moved(Side::V1, nu)) {
        return;
    }
    let mut moves = Vec::with_capacity((nu - 2) * (nv - 2));
    for i in 1..last_u {
        for j in (1..last_v).filter(|&j| !frozen(i, j)) {
            let (s, t) = (su[i], sv[j]);
            let across_u = row(Side::U0, j) * (1.0 - s) + row(Side::U1, j) * s;
            let across_v = row(Side::V0, i) * (1.0 - t) + row(Side::V1, i) * t;
            let bilinear = (corners[0] * (1.0 - s) + corners[1] * s) * (1.0 - t)
                + (corners[2] * (1.0 - s) + corners[3] * s) * t;
            moves.push((after.index(i, j), across_u + across_v - bilinear));
        }
    }
    for (k, m) in moves {
        after.control_points_mut()[k] += m;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs_core::{KnotVector, Point3};

    /// A flat bicubic 5 × 6 net over [0, 4] × [0, 3] with one interior knot in u, two in v.
    fn plate() -> BSplineSurface {
        let ku = KnotVector::new(3, vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0]).unwrap();
        let kv =
            KnotVector::new(3, vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.7, 1.0, 1.0, 1.0, 1.0]).unwrap();
        let (gu, gv) = (ku.greville_fractions(), kv.greville_fractions());
        let pts = gu
            .iter()
            .flat_map(|&s| gv.iter().map(move |&t| Point3::new(4.0 * s, 3.0 * t, 0.0)))
            .collect();
        BSplineSurface::new(ku, kv, pts, None).unwrap()
    }

    /// Adds `f(s, t)` (Greville fractions) to the boundary points of `s`.
    fn move_boundary(s: &BSplineSurface, f: impl Fn(f64, f64) -> Vector3) -> BSplineSurface {
        let mut out = s.clone();
        let (gu, gv) = (
            s.knots_u().greville_fractions(),
            s.knots_v().greville_fractions(),
        );
        for i in 0..s.num_u() {
            for j in 0..s.num_v() {
                if i == 0 || j == 0 || i + 1 == s.num_u() || j + 1 == s.num_v() {
                    let k = s.index(i, j);
                    out.control_points_mut()[k] += f(gu[i], gv[j]);
                }
            }
        }
        out
    }

    #[test]
    fn a_bilinear_move_is_reproduced_everywhere() {
        // the Coons patch reproduces any bilinear field exactly: the interior moves as the
        // boundary would have moved it had the whole net been moved by that field
        let s = plate();
        let field = |a: f64, b: f64| Vector3::new(0.1 * a * b, -0.2 * b, 0.3 + 0.05 * a);
        let mut moved = move_boundary(&s, field);
        spread_boundary_move(&s, &mut moved, [true; 4], [false; 4]);
        let (gu, gv) = (
            s.knots_u().greville_fractions(),
            s.knots_v().greville_fractions(),
        );
        for i in 0..s.num_u() {
            for j in 0..s.num_v() {
                let want = s.control_point(i, j) + field(gu[i], gv[j]);
                assert!(
                    (moved.control_point(i, j) - want).norm() < 1e-14,
                    "({i}, {j})"
                );
            }
        }
    }

    #[test]
    fn one_side_moved_decays_linearly_across() {
        let s = plate();
        let up = Vector3::new(0.0, 0.0, 0.25);
        let mut moved = move_boundary(&s, |a, _| if a == 0.0 { up } else { Vector3::zeros() });
        spread_boundary_move(&s, &mut moved, [true, false, false, false], [false; 4]);
        let gu = s.knots_u().greville_fractions();
        for i in 1..s.num_u() - 1 {
            for j in 1..s.num_v() - 1 {
                let dz = moved.control_point(i, j).z - s.control_point(i, j).z;
                assert!(
                    (dz - 0.25 * (1.0 - gu[i])).abs() < 1e-15,
                    "({i}, {j}): {dz}"
                );
            }
        }
        // the boundary rows of the other sides keep their own (zero) moves
        assert_eq!(moved.control_point(4, 2), s.control_point(4, 2));
    }

    #[test]
    fn two_opposite_sides_give_their_ruled_blend_and_a_kept_frame_stays() {
        let s = plate();
        let (a, b) = (Vector3::new(0.0, 0.0, 0.2), Vector3::new(0.1, 0.0, -0.3));
        let side_moves = |x: f64, _: f64| match x {
            0.0 => a,
            1.0 => b,
            _ => Vector3::zeros(),
        };
        let mut moved = move_boundary(&s, side_moves);
        spread_boundary_move(&s, &mut moved, [true, true, false, false], [false; 4]);
        let gu = s.knots_u().greville_fractions();
        for i in 1..s.num_u() - 1 {
            for j in 1..s.num_v() - 1 {
                let d = moved.control_point(i, j) - s.control_point(i, j);
                assert!(
                    (d - (a * (1.0 - gu[i]) + b * gu[i])).norm() < 1e-15,
                    "({i}, {j})"
                );
            }
        }
        // side v0 kept: its rows 1 and 2 stay, row 3 still follows the u sides
        let mut kept = move_boundary(&s, side_moves);
        spread_boundary_move(
            &s,
            &mut kept,
            [true, true, false, false],
            [false, false, true, false],
        );
        for i in 1..s.num_u() - 1 {
            for j in 1..=2 {
                assert_eq!(
                    kept.control_point(i, j),
                    s.control_point(i, j),
                    "({i}, {j})"
                );
            }
            assert_ne!(kept.control_point(i, 3), s.control_point(i, 3), "({i}, 3)");
        }
    }

    #[test]
    fn an_unmoved_boundary_leaves_the_net_bit_identical() {
        let s = plate();
        let mut same = s.clone();
        spread_boundary_move(&s, &mut same, [true; 4], [false; 4]);
        assert_eq!(same.control_points(), s.control_points());
    }
}
