//! The public steps: every step on a prepared slave ([`set_rows`]), one step on one side
//! ([`set_g0`], [`set_g1`], [`set_g2`]), and one step of the staged framework on all sides with
//! its refinement rounds ([`set_step`], \[SV\] §3.2 steps 3 and 5).
//!
//! # Tolerance
//! [`C0_FOR_G1_SHARE`]: the share of the G0 tolerance the C0 step of [`set_step`] aims at when
//! a link of the slave targets G1 or G2.

use nurbs_core::{BSplineSurface, Continuity, Side};

use super::refine::{Refiner, RoundRank, insert_along};
use super::step::{step_all, step_all_with};
use super::{C0_CONVERGED, SideLink, check_links, measure_links};
use crate::error::Result;
use crate::knots::new_breakpoints;
use crate::measure::LinkMeasure;
use crate::params::{ConnectParams, SetParams, Tolerances};

/// Share of the G0 tolerance that [`set_step`]'s C0 step aims at (knots inserted until reached)
/// when a link of the slave targets G1 or G2: a boundary off its master by a gap g that varies
/// along it over a length λ tilts its tangent out of the master's tangent plane by about
/// 2πg/λ, and no cross derivative makes the normals agree better than that tilt. On the car
/// shell a gap of 6.4e-4 (within the 1e-3 G0 tolerance) left G1 at 0.16° after the G1 step;
/// `connect` (all rows at once, refined for the highest target) reached gaps of 1–4e-5.
pub const C0_FOR_G1_SHARE: f64 = 0.05;

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

/// One step on one side, C0 in passes until it converges; returns the largest movement.
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
        g2_zones: [0.0; 2],
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

/// Sets G1 across `side` by moving its tangential row (\[SV\] §4.1); the positional row is not
/// touched. Returns the largest movement.
pub fn set_g1(
    master: &BSplineSurface,
    slave: &mut BSplineSurface,
    side: Side,
    params: &SetParams,
) -> Result<f64> {
    single(master, slave, side, Continuity::G1, params)
}

/// Sets G2 across `side` by moving its curvature row (\[SV\] §4.2); rows 0–1 are not touched.
/// Returns the largest movement.
pub fn set_g2(
    master: &BSplineSurface,
    slave: &mut BSplineSurface,
    side: Side,
    params: &SetParams,
) -> Result<f64> {
    single(master, slave, side, Continuity::G2, params)
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
    ///
    /// [`RowMove::g2_slack`]: crate::rows::RowMove::g2_slack
    pub g2_slack: f64,
}

/// One step of the alternation (\[SV\] §3.2 steps 3 and 5, and the C0 re-attachment to faired
/// masters): sets continuity `step` on every link whose target is at least `step`, moving only
/// row `step` of those sides (rows of earlier steps stay bit-identical unless knots are inserted,
/// which keeps their shape). Sides that miss the tolerances get their failing knot spans halved
/// and the step is repeated — after the rows of the lower steps are solved again with the new
/// knots — up to [`ConnectParams::max_refinements`] rounds; the best round (`RoundRank`: the
/// most links met, then the smallest worst excess up to where a row takes hold) is returned. The C0
/// step of a slave with G1/G2 links aims at [`C0_FOR_G1_SHARE`] × the G0 tolerance (not below
/// [`ConnectParams::c0_floor`]). The slave must be prepared ([`prepare_slave`]).
///
/// [`prepare_slave`]: super::prepare_slave
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
    // the best round so far: (its rank, surface, report)
    let mut best: Option<(RoundRank, BSplineSurface, StepReport)> = None;
    let tolerances = step_tolerances(links, step, params);
    loop {
        let mut s = work.clone();
        report.max_move = solve_round(&mut s, links, step, &params.set, &mut report)?;
        if step == Continuity::G0 && params.set.spread_boundary_move {
            let linked = Side::ALL.map(|side| links.iter().any(|l| l.side == side));
            super::spread::spread_boundary_move(&work, &mut s, linked, params.set.kept_sides);
        }
        let after = measure_links(links, &s, &params.measure)?;
        let rank = RoundRank::new(links, &after, step, &tolerances);
        report.after = after;
        if best.as_ref().is_none_or(|b| rank.beats(&b.0)) {
            best = Some((rank, s.clone(), report.clone()));
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
            let (_, s, report) = best.unwrap_or((rank, s, report));
            return Ok((s, report));
        }
        report.refinements += 1;
    }
}

/// The tolerances [`set_step`] aims at: those of `params`, but for the C0 step of a slave with
/// G1/G2 links a G0 tolerance of [`C0_FOR_G1_SHARE`] of theirs (not below
/// [`ConnectParams::c0_floor`]): a boundary that will carry G1 must lie closer to its master
/// than the G0 tolerance.
fn step_tolerances(links: &[SideLink], step: Continuity, params: &ConnectParams) -> Tolerances {
    if step == Continuity::G0 && links.iter().any(|l| l.target > step) {
        Tolerances {
            g0: (C0_FOR_G1_SHARE * params.tolerances.g0)
                .max(params.c0_floor)
                .min(params.tolerances.g0),
            ..params.tolerances
        }
    } else {
        params.tolerances
    }
}

/// One round of [`set_step`] on `s`: after knots were inserted the rows of the lower steps
/// first, then the rows of `step` (C0 in passes until it converges); the twists and the G2
/// slack go into `report`. Returns the largest movement.
fn solve_round(
    s: &mut BSplineSurface,
    links: &[SideLink],
    step: Continuity,
    params: &SetParams,
    report: &mut StepReport,
) -> Result<f64> {
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
            params.c0_iterations.max(1)
        } else {
            1
        };
        for _ in 0..passes {
            // the C0 rows solved again inside a G2 step carry the corner curvatures the G2
            // sides ask of them ([`crate::rows::solve_row_with`])
            let corners = step == Continuity::G2 && level == Continuity::G0;
            if level == Continuity::G2 {
                moved = moved.max(super::pole::set_pole_curvature(s, links, params));
            }
            let o = step_all_with(s, links, level, params, corners)?;
            report.twists_averaged = report.twists_averaged.max(o.twists);
            report.g2_slack = report.g2_slack.min(o.g2_slack);
            moved = moved.max(o.max_move);
            if o.max_move <= C0_CONVERGED * s.size() {
                break;
            }
        }
    }
    Ok(moved)
}
