//! Setting continuity of a slave to all its masters at once ([`connect_slave`]): prepared, all
//! rows set (C0 → G1 → G2, twists averaged), and the knot spans along failing sides halved
//! round by round, the best round kept.

use nurbs_core::{BSplineSurface, Continuity, Point3};

use super::prepare::prepare;
use super::refine::{Refiner, insert_along, worst_excess};
use super::{ConnectReport, SideLink, SideReport, check_links, measure_links, set_rows};
use crate::error::Result;
use crate::knots::new_knots;
use crate::measure::LinkMeasure;
use crate::params::{ConnectParams, Tolerances};

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
    let before = measure_links(links, slave, &params.measure)?;
    let mut work = prepare(slave, links, params, &mut report)?;
    let mut reference = work.clone();
    let mut refiner = Refiner::new(&work, links);
    let mut best: Option<BestRound> = None;
    let prepared_knots = report.knots_inserted;
    let mut along_knots = 0;
    loop {
        let mut s = work.clone();
        report.twists_averaged = set_rows(&mut s, links, &params.set)?;
        let after = measure_links(links, &s, &params.measure)?;
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
    let Some(best) = best else {
        unreachable!("at least one round ran");
    };
    report.knots_inserted = prepared_knots + best.along_knots;
    report.refinements = best.rounds;
    report.max_control_movement = largest_movement(&best.surface, &best.reference);
    report.sides = side_reports(links, before, best.after, &params.tolerances);
    Ok((best.surface, report))
}

/// The largest distance between the control points of `result` and those of `reference`.
fn largest_movement(result: &BSplineSurface, reference: &BSplineSurface) -> f64 {
    result
        .control_points()
        .iter()
        .zip(reference.control_points())
        .map(|(a, b): (&Point3, &Point3)| (a - b).norm())
        .fold(0.0, f64::max)
}

/// The report of each link from its measures `before` and `after`, whether `after` meets the
/// tolerances up to its target.
fn side_reports(
    links: &[SideLink],
    before: Vec<LinkMeasure>,
    after: Vec<LinkMeasure>,
    t: &Tolerances,
) -> Vec<SideReport> {
    links
        .iter()
        .zip(before.into_iter().zip(after))
        .map(|(l, (before, after))| {
            let met = after.meets(l.target, t.g0, t.g1_deg, t.g2_rel);
            SideReport {
                side: l.side,
                target: l.target,
                before,
                after,
                met,
            }
        })
        .collect()
}
