//! The curvature lead-in of a G2 side: the freedom G2 needs, placed next to the boundary.
//!
//! Setting G2 on a side moves control row 2 only (\[SV\] §4.2): rows 0–1 keep position and
//! tangent plane, row 2 bends the cross-boundary curvature to the master's. How far the surface
//! moves depends on how far row 2 reaches into it. For a clamped knot vector of degree p with
//! interior knots k₁ < k₂ < k₃ next to the side, row 2's basis function lives on [c, k₃], and
//! the move it needs is the distance of row 2 from the osculating parabola of the master, about
//! |Δκ|/2 · (3ℓ/p)² for a lead-in of length ℓ = k₃ − c (times the parametric speed): the
//! deviation grows with the *square* of the lead-in width, and a narrow lead-in always fits a
//! small deviation budget. A wide one is fairer (the curvature changes over a longer stretch),
//! so the framework takes the widest width whose deviation fits its budget
//! (`hier-fair`'s framework searches it); this module builds the surface for one width.
//!
//! For a rolling-ball fillet of radius R (a quarter circle, κ = 1/R) on a plane (κ = 0) the row
//! move is |Δκ|/2 · (3ℓ/p)², so with p = 5 a lead-in of a tenth of the arc (ℓ ≈ 0.16 R) moves
//! row 2 by ≈ 0.005 R.
//!
//! # Degree
//! The cross direction of a G2 side is raised to at least [`LEAD_IN_DEGREE`] (exactly, in
//! homogeneous coordinates: a rational conic stays the same conic).

use nurbs_core::{BSplineSurface, Continuity, Direction, Side};

use crate::error::Result;
use crate::knots::new_knots;
use crate::link::SideLink;
use crate::measure::is_collapsed;

/// Least degree across a G2 side. Quintic: inside a span the curvature of a degree-p curve is
/// a rational function whose numerator has degree 2p − 3 at most, and at a simple knot the
/// curve is C^{p−1}, so its curvature is C^{p−3}. Degree 5 keeps the curvature C² across the
/// lead-in knots — smooth curvature plots and reflection lines (the Class-A norm, where the
/// curvature's own derivative must not jump); a cubic would leave the curvature only C⁰ there.
pub const LEAD_IN_DEGREE: usize = 5;

/// Knots placed in a lead-in: three, at ℓ/3, 2ℓ/3 and ℓ from the side, so that rows 0, 1 and 2
/// each end inside the lead-in (row r lives on [c, k_{r+1}]) and every row beyond is free for
/// fairing.
pub const LEAD_IN_KNOTS: usize = 3;

/// Widest lead-in, as a fraction of the cross domain: below one half, so that the lead-ins of
/// two opposite G2 sides never overlap and at least one free row remains between them.
pub const MAX_LEAD_IN: f64 = 0.45;

/// What [`with_lead_in`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LeadInReport {
    /// degree elevation (u, v)
    pub degree_elevation: (usize, usize),
    /// knots inserted
    pub knots_inserted: usize,
}

/// The slave with a lead-in of `width` (fraction of the cross domain, clamped to
/// (0, [`MAX_LEAD_IN`]]) at every linked side whose target is G2 and that is not collapsed to a
/// point: the cross direction raised to [`LEAD_IN_DEGREE`] and [`LEAD_IN_KNOTS`] knots inserted
/// within `width` of the side (knots that are there already are kept). The surface is the same
/// (knot insertion and degree elevation are exact, rational or not).
pub fn with_lead_in(
    slave: &BSplineSurface,
    links: &[SideLink],
    width: f64,
) -> Result<(BSplineSurface, LeadInReport)> {
    let width = if width.is_finite() && width > 0.0 {
        width.min(MAX_LEAD_IN)
    } else {
        MAX_LEAD_IN
    };
    let mut s = slave.clone();
    let mut report = LeadInReport::default();
    let g2: Vec<Side> = links
        .iter()
        .filter(|l| l.target >= Continuity::G2 && !is_collapsed(slave, l.side))
        .map(|l| l.side)
        .collect();
    for dir in [Direction::U, Direction::V] {
        if !g2.iter().any(|side| side.cross_direction() == dir) {
            continue;
        }
        let degree = match dir {
            Direction::U => s.degree_u(),
            Direction::V => s.degree_v(),
        };
        if degree < LEAD_IN_DEGREE {
            let by = LEAD_IN_DEGREE - degree;
            s = s.elevate_degree(dir, by)?;
            match dir {
                Direction::U => report.degree_elevation.0 += by,
                Direction::V => report.degree_elevation.1 += by,
            }
        }
    }
    for dir in [Direction::U, Direction::V] {
        let (a, b) = match dir {
            Direction::U => s.domain_u(),
            Direction::V => s.domain_v(),
        };
        let mut xs = Vec::new();
        for side in g2.iter().filter(|side| side.cross_direction() == dir) {
            for k in 1..=LEAD_IN_KNOTS {
                let d = width * (b - a) * k as f64 / LEAD_IN_KNOTS as f64;
                xs.push(if side.is_start() { a + d } else { b - d });
            }
        }
        // a lead-in knot that is a knot already needs no insertion (a repeated knot would
        // only lower the continuity inside the lead-in)
        let kv = match dir {
            Direction::U => s.knots_u(),
            Direction::V => s.knots_v(),
        };
        let close = nurbs_core::knots::KNOT_MERGE_RELATIVE * (b - a);
        xs.retain(|&x| kv.knots().iter().all(|&k| (k - x).abs() > close));
        let xs = new_knots(&s, dir, &xs);
        if !xs.is_empty() {
            s = s.refine(dir, &xs)?;
            report.knots_inserted += xs.len();
        }
    }
    Ok((s, report))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs_core::energy::max_deviation;

    #[test]
    fn lead_in_keeps_a_rational_cylinder_exact() {
        let cyl = nurbs_core::shapes::cylinder(2.0, 1.0).unwrap();
        let plane = cyl.clone();
        let links = [
            SideLink {
                side: Side::U0,
                master: &plane,
                target: Continuity::G2,
                range: None,
                g2_zones: [0.0; 2],
            },
            SideLink {
                side: Side::U1,
                master: &plane,
                target: Continuity::G2,
                range: None,
                g2_zones: [0.0; 2],
            },
        ];
        let (s, r) = with_lead_in(&cyl, &links, 0.2).unwrap();
        assert!(s.is_rational());
        assert_eq!(s.degree_u(), LEAD_IN_DEGREE.max(cyl.degree_u()));
        assert_eq!(r.knots_inserted, 2 * LEAD_IN_KNOTS);
        assert!(max_deviation(&cyl, &s, 21) < 1e-12);
        // every lead-in knot within 0.2 of its side
        let (a, b) = s.domain_u();
        let inner: Vec<f64> = s
            .knots_u()
            .interior_knots()
            .iter()
            .map(|&(k, _)| k)
            .collect();
        assert!(
            inner
                .iter()
                .all(|&k| k - a <= 0.2 * (b - a) + 1e-12 || b - k <= 0.2 * (b - a) + 1e-12)
        );
    }
}
