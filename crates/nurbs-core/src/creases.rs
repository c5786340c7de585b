//! Knot lines where a surface is only C⁰ in its parameters, and the normal jump across them.
//!
//! An interior knot of multiplicity m ≥ p in a direction of degree p joins the spans on either
//! side with C⁰ continuity only (\[NB\] §2.2): the iso-curve at that knot passes through the
//! control column P_k (k = r − p, r the last index of the knot), and the surface is tangent
//! continuous across it exactly when the columns P_{k−1}, P_k, P_{k+1} are collinear row by row
//! with P_k between. Kernels write rational arcs of more than 90° so (a full circle as three
//! 120° arcs joined by double knots), and a knot inserted into a degree-1 direction is one. A
//! method that moves the points of those columns one by one turns the join into a crease.
//!
//! [`knot_lines`] lists them, [`crease_deg`] measures the largest angle between the normals on
//! either side of a line (one-sided limits, sampled along it), and [`largest_crease_deg`] the
//! worst over a surface — what `hier-fair check` reports per surface beside the links.

use crate::Direction;
use crate::surface::BSplineSurface;

/// Samples along a knot line (both ends included): one every 2.5 % of it.
pub const CREASE_SAMPLES: usize = 41;

/// Offset of the one-sided evaluations from the knot, relative to the domain length: the normal
/// a side gives there differs from its limit by about this times the domain length times the
/// normal's rate of turn (≤ 1e-7° for any surface a radius of 1e-3 of its parameter range can
/// bend), and it stays far above the spacing of doubles near the knot.
pub(crate) const ONE_SIDED_OFFSET: f64 = 1e-8;

/// An interior knot of multiplicity at least the degree: the surface is C⁰ across its iso-line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KnotLine {
    /// the parameter direction of the knot (a `U` line is u = knot, running along v)
    pub direction: Direction,
    /// the knot value
    pub knot: f64,
    /// index k of the control column the iso-line passes through (P_k: row k for `U`,
    /// column k for `V`); the tangent plane across it rests on k − 1, k and k + 1
    pub column: usize,
}

/// The interior knots of `s` whose multiplicity equals the degree (C⁰ joins with a column of
/// points on the surface); higher multiplicities (a gap) are not joins and are left out.
pub fn knot_lines(s: &BSplineSurface) -> Vec<KnotLine> {
    let mut out = Vec::new();
    for direction in [Direction::U, Direction::V] {
        let kv = match direction {
            Direction::U => s.knots_u(),
            Direction::V => s.knots_v(),
        };
        let p = kv.degree();
        let knots = kv.knots();
        for (knot, m) in kv.interior_knots() {
            if m != p {
                continue;
            }
            let last = knots.partition_point(|&t| t <= knot) - 1;
            out.push(KnotLine {
                direction,
                knot,
                column: last - p,
            });
        }
    }
    out
}

/// Largest angle (degrees) between the normals on either side of `line`, over
/// [`CREASE_SAMPLES`] points along it; `None` when no sample has a normal on both sides (a line
/// that runs into a pole has one only off the pole). Only the line's direction and parameter
/// are used: it may come from another surface of the same parametrization (the input of a
/// fairing, to ask whether a join of the result was smooth there before).
pub fn crease_deg(s: &BSplineSurface, line: &KnotLine) -> Option<f64> {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let mut eval = s.evaluator();
    let mut worst: Option<f64> = None;
    for i in 0..CREASE_SAMPLES {
        let f = i as f64 / (CREASE_SAMPLES - 1) as f64;
        let (a, b) = match line.direction {
            Direction::U => {
                let h = ONE_SIDED_OFFSET * (u1 - u0);
                let v = v0 + f * (v1 - v0);
                ((line.knot - h, v), (line.knot + h, v))
            }
            Direction::V => {
                let h = ONE_SIDED_OFFSET * (v1 - v0);
                let u = u0 + f * (u1 - u0);
                ((u, line.knot - h), (u, line.knot + h))
            }
        };
        let na = eval.derivatives(a.0, a.1).normal();
        let nb = eval.derivatives(b.0, b.1).normal();
        if let (Some(na), Some(nb)) = (na, nb) {
            let angle = na.cross(&nb).norm().atan2(na.dot(&nb)).to_degrees();
            worst = Some(worst.map_or(angle, |w: f64| w.max(angle)));
        }
    }
    worst
}

/// The largest [`crease_deg`] over all [`knot_lines`] of `s` (0 when it has none).
pub fn largest_crease_deg(s: &BSplineSurface) -> f64 {
    knot_lines(s)
        .iter()
        .filter_map(|l| crease_deg(s, l))
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Point3, Vector3, shapes};

    /// A full circle of three 120° rational arcs (double knots), swept into a cylinder: tangent
    /// continuous across both joins; bending the points of one join's column breaks that.
    #[test]
    fn a_three_arc_cylinder_is_smooth_across_its_double_knots_until_a_column_moves() {
        let circle = shapes::arc(
            Point3::origin(),
            Vector3::x(),
            Vector3::y(),
            2.0,
            0.0,
            std::f64::consts::TAU,
        )
        .unwrap();
        let cyl = shapes::extrude_curve(&circle, Vector3::z(), (0.0, 5.0)).unwrap();
        let lines = knot_lines(&cyl);
        assert!(!lines.is_empty(), "the circle has joins");
        for l in &lines {
            let d = crease_deg(&cyl, l).unwrap();
            assert!(d < 1e-5, "join at {} turns by {d}°", l.knot);
        }
        // move the join point of the first line out of its tangent line: a crease
        let l = lines[0];
        let mut bent = cyl.clone();
        let (nu, nv) = (bent.num_u(), bent.num_v());
        for j in 0..match l.direction {
            Direction::U => nv,
            Direction::V => nu,
        } {
            let idx = match l.direction {
                Direction::U => bent.index(l.column, j),
                Direction::V => bent.index(j, l.column),
            };
            let p = bent.control_points()[idx];
            bent.control_points_mut()[idx] = p + (p - Point3::origin()).normalize() * 0.05;
        }
        let d = crease_deg(&bent, &l).unwrap();
        assert!(d > 0.5, "a moved join column shows: {d}°");
        assert!((largest_crease_deg(&bent) - d).abs() < 1e-9);
    }

    /// The bilinear unit square in z = 0 (degree 1 both ways, as kernels write planes).
    fn unit_plane() -> BSplineSurface {
        shapes::plane_patch(
            Point3::origin(),
            Vector3::x(),
            Vector3::y(),
            (0.0, 1.0),
            (0.0, 1.0),
        )
        .unwrap()
    }

    #[test]
    fn simple_knots_are_no_joins() {
        let s = unit_plane()
            .with_smooth_joins(Direction::U)
            .unwrap()
            .refine(Direction::U, &[0.25, 0.5])
            .unwrap();
        assert!(knot_lines(&s).is_empty());
        assert_eq!(largest_crease_deg(&s), 0.0);
    }

    /// A knot inserted into a degree-1 direction is a join: the surface is smooth only while the
    /// points stay collinear.
    #[test]
    fn a_knot_in_a_degree_one_direction_is_a_join() {
        let s = unit_plane().refine(Direction::U, &[0.5]).unwrap();
        let lines = knot_lines(&s);
        assert_eq!(lines.len(), 1);
        assert_eq!(lines[0].column, 1);
        assert!(crease_deg(&s, &lines[0]).unwrap() < 1e-9);
        let mut bent = s.clone();
        for j in 0..bent.num_v() {
            let idx = bent.index(1, j);
            bent.control_points_mut()[idx].z += 0.1;
        }
        // the two halves rise by 0.1 over 0.5: atan(0.2) each way
        let expected = 2.0 * 0.2f64.atan().to_degrees();
        assert!((crease_deg(&bent, &lines[0]).unwrap() - expected).abs() < 1e-6);
    }
}
