//! The continuity steps alone (\[SV\] §3.2 steps 1, 3, 5 without fairing), run before the stages:
//! their deviation decides the highest level the tolerance allows, and the width of a G2
//! lead-in is searched here ([`g_continuity::lead_in`]).

use g_continuity::{ConnectParams, LinkMeasure, SideLink, prepare_slave, set_step};
use nurbs_core::energy::max_deviation;
use nurbs_core::{BSplineSurface, Continuity};

use super::error::{StageError, StageResult};
use super::masks::free_rows;
use super::{DryRun, Job};

/// Relative margin of the dry run's slack test: a variant's larger G2 move bound is skipped
/// only when every weight the previous run rejected moved more than the bound by more than
/// this (a few roundings of the move quotient, so the skip stays exact).
pub const SLACK_ROUNDING: f64 = 1e-12;

/// One continuity step of the dry run ([`Job::dry_step`]): the result, whether it met every
/// link up to its step, the settings that gave it, and the links' measures on it.
type StepResult = (
    BSplineSurface,
    bool,
    g_continuity::SetParams,
    Vec<LinkMeasure>,
);

/// Trials of the lead-in width search: the first at the widest lead-in, each next one scaled by
/// √((budget − d₀)/(d − d₀)), d₀ the C0 step's deviation (following the masters, which no
/// lead-in changes; where d₀ alone exceeds the budget the search stops); the error of the
/// square law shrinks with the width, so the third trial is usually within the budget and six
/// are a bound, not a typical count.
pub const LEAD_IN_TRIALS: usize = 6;

/// Factor applied to each predicted width: 0.9, so a prediction that is 20 % optimistic on the
/// deviation (0.9² ≈ 0.81) still lands within the budget.
pub const LEAD_IN_MARGIN: f64 = 0.9;

/// After a trial that misses a link within the budget, the next lead-in is this factor
/// narrower: its three knots at half the distance from the side, one level of the span halving
/// the refinement rounds use.
pub(crate) const LEAD_IN_MISS_NARROWING: f64 = 2.0;

/// A trial narrows the lead-in by at most this factor (the square law is a local estimate).
pub const LEAD_IN_MAX_NARROWING: f64 = 8.0;

/// Narrowest lead-in tried, as a fraction of the cross domain: 1/64, where the three lead-in
/// knots are 1/192 of the domain apart and the curvature ramp is steeper than any fairing
/// would keep.
pub const MIN_LEAD_IN: f64 = 1.0 / 64.0;

/// The lead-in width to try after a trial at width `w` whose C0 step deviated `d0` and whose
/// last step `d` (the budget `budget`; `met`: it met every link), or `None` to stop.
fn next_width(w: f64, d0: f64, d: f64, budget: f64, met: bool) -> Option<f64> {
    let next = if d <= budget {
        w / LEAD_IN_MISS_NARROWING
    } else if d0 >= budget {
        // the C0 step alone takes the budget, so no narrower lead-in brings the result within
        // it; once the links are met there is nothing a narrower one can give (a box's
        // sphere corners per role: 0.281 mm at every width), else another width may meet them
        // (its refinement places other knots: a box's B-spline corner per role met at the
        // fourth)
        if met {
            return None;
        }
        let next = w * (budget / d).sqrt() * LEAD_IN_MARGIN;
        next.clamp(w / LEAD_IN_MAX_NARROWING, w * LEAD_IN_MARGIN)
    } else {
        // the square law on the lead-in's own share of the deviation
        let next = w * ((budget - d0) / (d - d0)).sqrt() * LEAD_IN_MARGIN;
        next.clamp(w / LEAD_IN_MAX_NARROWING, w * LEAD_IN_MARGIN)
    };
    (next >= MIN_LEAD_IN).then_some(next)
}

impl DryRun {
    /// The deviation of the last step (0 without steps).
    pub(super) fn deviation(&self) -> f64 {
        self.steps.last().map_or(0.0, |s| s.2)
    }
}

impl Job<'_> {
    /// Runs the continuity steps alone (no fairing) from `prepared`: every step up to the
    /// highest target, each with its sampled deviation from the original.
    /// `spread`: [`g_continuity::SetParams::spread_boundary_move`] in the C0 step.
    pub(super) fn dry_run(
        &self,
        prepared: &BSplineSurface,
        links: &[SideLink<'_>],
        spread: bool,
    ) -> StageResult<DryRun> {
        let original = &self.model.surfaces[self.surface].surface;
        let mut steps = Vec::new();
        let mut params = self.set_params();
        params.set.spread_boundary_move = spread;
        let Some(top) = links.iter().map(|l| l.target).max() else {
            return Ok(DryRun {
                steps,
                met: true,
                met_steps: Vec::new(),
                after: Vec::new(),
                prepared: prepared.clone(),
                tangent_corners: false,
                section_ramp: None,
                spread,
            });
        };
        let mut s = prepared.clone();
        let mut met = false;
        let mut met_steps = Vec::new();
        let mut after = Vec::new();
        // the step settings in use; a variant that met a step stays for the steps after it (a
        // G2 step solves the C0 and G1 rows again after refining)
        let mut set = params.set;
        for step in [Continuity::G0, Continuity::G1, Continuity::G2] {
            if step > top {
                break;
            }
            let next;
            (next, met, set, after) = self.dry_step(&s, links, step, &params, set)?;
            let d = max_deviation(original, &next, self.params.deviation_grid);
            steps.push((step, next.clone(), d));
            met_steps.push(met);
            s = next;
        }
        Ok(DryRun {
            steps,
            met,
            met_steps,
            after,
            prepared: prepared.clone(),
            tangent_corners: set.tangent_corners,
            section_ramp: None,
            spread,
        })
    }

    /// One continuity step of the dry run from `s` with the settings `set`, and where it
    /// misses, its variants in order ([`step_variants`]) until one meets: the result, whether
    /// it met every link up to `step`, the settings that gave it, and its links' measures.
    fn dry_step(
        &self,
        s: &BSplineSurface,
        links: &[SideLink<'_>],
        step: Continuity,
        params: &ConnectParams,
        set: g_continuity::SetParams,
    ) -> StageResult<StepResult> {
        let name = &self.model.surfaces[self.surface].name;
        let t = &params.tolerances;
        let meets = |after: &[g_continuity::LinkMeasure]| {
            links
                .iter()
                .zip(after)
                .all(|(l, m)| m.meets(l.target.min(step), t.g0, t.g1_deg, t.g2_rel))
        };
        let run = |set: g_continuity::SetParams| {
            set_step(s, links, step, &ConnectParams { set, ..*params }).map_err(|source| {
                StageError::Set {
                    level: step,
                    surface: name.clone(),
                    source,
                }
            })
        };
        let (next, report) = run(set)?;
        if meets(&report.after) {
            return Ok((next, true, set, report.after));
        }
        for variant in step_variants(set, step) {
            // a variant that only raises the G2 move bound to below the slack of the run with
            // the step's own bound would repeat that run bit for bit (the slack is a quotient
            // of moves, the test a product: the margin keeps a ratio one rounding above the
            // bound from counting as beyond it); nor is it run where the G2 rows did not take
            // hold ([`took_hold`])
            if variant.g2_move_factor > set.g2_move_factor
                && (report.g2_slack > variant.g2_move_factor * (1.0 + SLACK_ROUNDING)
                    || !took_hold(links, &report.after))
            {
                continue;
            }
            let (other, again) = run(variant)?;
            if meets(&again.after) {
                return Ok((other, true, variant, again.after));
            }
        }
        Ok((next, false, set, report.after))
    }

    /// Prepares the surface and runs the continuity steps alone, with the widest curvature
    /// lead-in at its G2 sides whose deviation fits [`LEAD_IN_SHARE`] of the tolerance
    /// ([`g_continuity::lead_in`]): the deviation of the G2 step grows with the square of the
    /// lead-in width, so after a trial the next width is w·√(budget/d), narrowed by
    /// [`LEAD_IN_MARGIN`] against the neglected higher-order terms. A trial within the budget
    /// that misses a link is followed by one [`LEAD_IN_MISS_NARROWING`] times narrower, while
    /// its misses are of accuracy ([`Job::excess`]), narrowing brings the worst link nearer its
    /// tolerances, and no corner's masters disagree beyond ρ ([`super::vertex`]): the least
    /// deviation at which G2 holds is searched before a link is called missed. Returns the
    /// chosen trial and the smallest deviation any trial that met every link needed (the honest
    /// figure of a conflict).
    ///
    /// With `spread` the search runs with the C0 step's boundary move spread into the interior
    /// ([`g_continuity::SetParams::spread_boundary_move`]); where its pick misses a link, it
    /// runs again without, and that pick is taken where it meets every link.
    pub(super) fn prepare_and_dry_run(
        &self,
        links: &[SideLink<'_>],
        spread: bool,
    ) -> StageResult<(DryRun, Option<f64>)> {
        let (mut pick, mut needed) = self.lead_in_search(links, spread)?;
        if spread && !pick.met {
            let (other, other_needed) = self.lead_in_search(links, false)?;
            if other.met {
                (pick, needed) = (other, other_needed);
            }
        }
        let budget = self.params.budget.lead_in(self.tolerance);
        Ok((self.with_section(links, budget, pick)?, needed))
    }

    /// The lead-in width search of [`Job::prepare_and_dry_run`] with `spread` in its C0 steps:
    /// the chosen trial and the smallest deviation any trial that met every link needed.
    fn lead_in_search(
        &self,
        links: &[SideLink<'_>],
        spread: bool,
    ) -> StageResult<(DryRun, Option<f64>)> {
        let name = &self.model.surfaces[self.surface].name;
        let g2 = links.iter().any(|l| {
            l.target >= Continuity::G2 && !g_continuity::measure::is_collapsed(self.start, l.side)
        });
        let budget = self.params.budget.lead_in(self.tolerance);
        let mut width = g2.then_some(g_continuity::MAX_LEAD_IN);
        let rho = self.set_params().tolerances.g2_rel;
        let hopeless = g2 && super::vertex::incompatible_corner(links, self.start, rho);
        let mut trials: Vec<(DryRun, f64)> = Vec::new();
        for _ in 0..LEAD_IN_TRIALS {
            let connect = ConnectParams {
                lead_in: width,
                ..*self.connect
            };
            let (prepared, _) = prepare_slave(self.start, links, &connect).map_err(|source| {
                StageError::Prepare {
                    surface: name.clone(),
                    source,
                }
            })?;
            let (prepared, _) =
                free_rows(prepared, links, self.params.min_free_rows).map_err(|source| {
                    StageError::Knots {
                        surface: name.clone(),
                        source,
                    }
                })?;
            let dry = self.dry_run(&prepared, links, spread)?;
            let (d, met) = (dry.deviation(), dry.met);
            // the C0 step's deviation: following the masters' sides, whatever the lead-in
            let d0 = dry.steps.first().map_or(0.0, |s| s.2);
            let (excess, narrowable) = if met {
                (0.0, false)
            } else {
                self.excess(&dry, links)
            };
            // a narrower lead-in is tried after a miss within the budget only where the miss is
            // one of accuracy ([`Job::excess`]), no corner's masters disagree beyond ρ, and
            // while narrowing helps (the worst link comes nearer its tolerances)
            let helped = narrowable && trials.last().is_none_or(|(_, e)| excess < *e);
            trials.push((dry, excess));
            let Some(w) = width else { break };
            let within = d <= budget;
            if within && (met || hopeless || !helped) {
                break;
            }
            let Some(next) = next_width(w, d0, d, budget, met) else {
                break;
            };
            width = Some(next);
        }
        let needed = trials
            .iter()
            .filter(|(t, _)| t.met)
            .map(|(t, _)| t.deviation())
            .fold(None, |a: Option<f64>, d| Some(a.map_or(d, |a| a.min(d))));
        // the widest trial that met its links within the budget; else the one that met them
        // with the least deviation; else the one within the budget that came nearest its
        // tolerances; else the one with the least deviation
        let least = |keep: &dyn Fn(&(DryRun, f64)) -> bool, key: &dyn Fn(&(DryRun, f64)) -> f64| {
            (0..trials.len())
                .filter(|&k| keep(&trials[k]))
                .min_by(|&a, &b| key(&trials[a]).total_cmp(&key(&trials[b])))
        };
        let pick = trials
            .iter()
            .position(|(t, _)| t.met && t.deviation() <= budget)
            .or_else(|| least(&|(t, _)| t.met, &|(t, _)| t.deviation()))
            .or_else(|| least(&|(t, _)| t.deviation() <= budget, &|(_, e)| *e))
            .or_else(|| least(&|_| true, &|(t, _)| t.deviation()))
            .unwrap_or(0);
        Ok((trials.swap_remove(pick).0, needed))
    }
}

impl Job<'_> {
    /// How far the last step of `dry` is from meeting its links: the largest ratio of a
    /// measure (gap, angle, relative curvature, up to each link's target) to its tolerance over
    /// every link (≤ 1 where all are met), from the measures the step took; and whether the
    /// misses are of accuracy only — every gap and angle within its tolerance and every relative
    /// curvature figure below 1, i.e. the slave bends the same way as its master all along each
    /// side — which a narrower curvature lead-in can improve. A figure of 1 or more (curvatures
    /// of opposite signs, or one of them 0) means the G2 rows did not take hold there at all (a
    /// corner conflict, the end of a partial link), which the width of the transition does not
    /// change.
    fn excess(&self, dry: &DryRun, links: &[SideLink<'_>]) -> (f64, bool) {
        let Some((step, _, _)) = dry.steps.last() else {
            return (0.0, false);
        };
        let t = &self.set_params().tolerances;
        let mut narrowable = true;
        let mut worst = 0.0f64;
        for (l, m) in links.iter().zip(&dry.after) {
            let target = l.target.min(*step);
            let g1 = m.g1_deg.unwrap_or(0.0);
            narrowable &= m.g0 <= t.g0 && (target < Continuity::G1 || g1 <= t.g1_deg);
            if target >= Continuity::G2 {
                narrowable &= m.g2_rel.unwrap_or(0.0) < 1.0;
            }
            worst = worst.max(m.excess(target, t.g0, t.g1_deg, t.g2_rel));
        }
        (worst, narrowable)
    }
}

/// Whether the G2 rows took hold on every G2 side of a step's result: each relative curvature
/// figure below 1. A figure of 1 or more means that somewhere along a side the slave's normal
/// curvature is 0 or of the other sign than its master's — the rows are not near a solution there
/// (two sides asking a corner for different curvatures, the end of a partial link), and a larger
/// move bound only lets the ladder take lighter tangential weights for the same rows: on the 36
/// runs of the eighteen kernel models (six and twelve variants, per role and by default) the
/// variant met its links only after misses of accuracy (relative figures 0.006–0.011) and never
/// after one of 1 or more (docs/benchmarks.md), so it is not run after those.
fn took_hold(links: &[SideLink<'_>], after: &[g_continuity::LinkMeasure]) -> bool {
    links
        .iter()
        .zip(after)
        .filter(|(l, _)| l.target >= Continuity::G2)
        .all(|(_, m)| m.g2_rel.is_none_or(|r| r < 1.0))
}

/// The variants of a continuity step that missed with `set`, in the order they are tried: at
/// G2 the move bound of `connect`, which exact joins of constructed pairs need (a vertex blend
/// between faired fillets); at G1 the corners' end tangents turned into the neighbouring
/// masters' tangent planes (a corner normal the C0 fit left off by more than the G1 tolerance,
/// `SetParams::tangent_corners`). The turned tangents are not tried at G2 (with and without
/// `connect`'s bound they were two more refined G2 runs per lead-in trial where a link missed
/// G1 in the G2 step): since the stages' result is polished jointly where a G2 link is missed
/// ([`Job::joint_polish`]) they met no link more on the 25 kernel models measured (the six,
/// twelve variants, seven more of the same kinds, per role and by default), at 5–10 % of the
/// lofted block's time (docs/benchmarks.md).
fn step_variants(set: g_continuity::SetParams, step: Continuity) -> Vec<g_continuity::SetParams> {
    let connect_bound = g_continuity::SetParams::default().g2_move_factor;
    match step {
        Continuity::G2 if set.g2_move_factor < connect_bound => vec![g_continuity::SetParams {
            g2_move_factor: connect_bound,
            ..set
        }],
        Continuity::G1 if !set.tangent_corners => vec![g_continuity::SetParams {
            tangent_corners: true,
            ..set
        }],
        _ => Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::{LEAD_IN_MARGIN, LEAD_IN_MAX_NARROWING, MIN_LEAD_IN, next_width};

    #[test]
    fn the_next_lead_in_follows_the_lead_ins_own_deviation() {
        // within the budget but missed: half as wide
        assert_eq!(next_width(0.4, 0.0, 0.1, 0.2, false), Some(0.2));
        // the square law on the share beyond the C0 step: (0.2 − 0.1)/(0.5 − 0.1) = 1/4
        let w = next_width(0.4, 0.1, 0.5, 0.2, false).unwrap();
        assert!((w - 0.4 * 0.5 * LEAD_IN_MARGIN).abs() < 1e-15, "{w}");
        // the C0 step alone beyond the budget: met, nothing to gain; missed, another width
        assert_eq!(next_width(0.4, 0.3, 0.3, 0.2, true), None);
        let w = next_width(0.4, 0.3, 0.3, 0.2, false).unwrap();
        assert!((w - 0.4 * (0.2f64 / 0.3).sqrt() * LEAD_IN_MARGIN).abs() < 1e-15);
        // never narrower than MIN_LEAD_IN, never more than LEAD_IN_MAX_NARROWING at once
        assert_eq!(next_width(1.5 * MIN_LEAD_IN, 0.0, 100.0, 0.2, false), None);
        let w = next_width(0.4, 0.0, 1e6, 0.2, false).unwrap();
        assert_eq!(w, 0.4 / LEAD_IN_MAX_NARROWING);
    }
}
