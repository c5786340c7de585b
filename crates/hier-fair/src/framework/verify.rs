//! The deviation an unmet link needs, verified by a run (\[SV\] §1.1: connections and corners may
//! deviate more than primaries, so the figure a user would raise is each surface's own).
//!
//! Within one run a link is called a conflict only from the dry run's trials, which set the
//! continuity without the fairing stages; a link those trials miss within the tolerance is not
//! one — yet the stages, the polish and the masters' own fairing all depend on the deviation
//! they may use, and not monotonically (measured on a three-radii corner's blend: all four links
//! met with its master fillet at 0.04 mm, one missed at 0.05, all four at 0.06–0.1 mm;
//! docs/benchmarks.md). A figure that is not run is a guess; this module runs it. Every link
//! the run leaves unmet gets its slave and its master raised to [`VERIFY_FACTOR`] times their
//! own deviation tolerance, the model is faired once more with those per-surface deviations
//! (exactly what a user who sets them in the model file gets: the run is deterministic), and
//! each unmet link is then named either with the deviations under which it was met (a conflict
//! whose figure is verified) or as not reached by that much more deviation.

use super::{FairModelReport, FairParams, LinkFair, Problem, ProblemKind, fair_model_with, report};
use crate::methods::Fairers;
use crate::model::Model;

/// How much more deviation the verification run gives each surface of an unmet link: twice its
/// own tolerance. One run is a whole fairing of the model again, so there is exactly one; twice
/// is the smallest raise that is a different budget for every share the stages plan with
/// ([`DeviationBudget`](super::DeviationBudget)) rather than a rounding of it, and the figure a run meets with is an
/// upper bound of what the link needs, which the report states as such.
pub const VERIFY_FACTOR: f64 = 2.0;

/// The problems that name, for every link `report` leaves unmet, the deviation it needs: one
/// more run of `given` (the model as the caller gave it) with each unmet link's slave and master
/// at [`VERIFY_FACTOR`] times their tolerance; a link met there is a [`ProblemKind::Conflict`]
/// whose amount is the slave's raised figure, one still missed is [`ProblemKind::Limited`] (as
/// is every unmet link where the second run fails). Nothing when every link is met.
pub(super) fn verify_unmet(
    given: &Model,
    fairers: Fairers<'_>,
    params: &FairParams,
    report: &FairModelReport,
) -> Vec<Problem> {
    // a link whose slave met it only with a curvature spike, refused ([`super::polish`]), is
    // not verified: its report names the spike, and the second run (a whole model at twice the
    // deviation) cost the three-radii corner 15 s of a 20 s run
    let refused = |l: &&LinkFair| {
        let slave = &given.surfaces[given.links[l.link].slave].name;
        report
            .problems
            .iter()
            .any(|p| &p.surface == slave && super::polish::is_spike_refusal(p))
    };
    let unmet: Vec<&LinkFair> = report
        .links
        .iter()
        .filter(|l| !l.met && l.after.is_some())
        .filter(|l| !refused(l))
        .collect();
    if unmet.is_empty() {
        return Vec::new();
    }
    let raise = Raise { given, params };
    let mut raised = given.clone();
    for l in &unmet {
        let link = given.links[l.link];
        for k in [link.slave, link.master] {
            raised.surfaces[k].deviation = Some(raise.to(k));
        }
    }
    let again_params = FairParams {
        verify_unmet: false,
        ..*params
    };
    // the first run's result stands whatever the second does
    let again = match fair_model_with(&raised, fairers, &again_params, &|_| {}) {
        Ok((_, again)) => again,
        Err(e) => return unmet.iter().map(|l| raise.failed(l, &e)).collect(),
    };
    let alike = if unmet.len() > 1 {
        " (every unmet link's slave and master raised alike in that run)"
    } else {
        ""
    };
    unmet
        .iter()
        .map(|l| raise.named(l, &again, alike))
        .collect()
}

/// The raise of the verification run: a surface's deviation tolerance in the first run, times
/// [`VERIFY_FACTOR`].
struct Raise<'a> {
    given: &'a Model,
    params: &'a FairParams,
}

impl Raise<'_> {
    /// Surface `k`'s raised deviation.
    fn to(&self, k: usize) -> f64 {
        VERIFY_FACTOR
            * self
                .given
                .deviation_of(k, &self.params.role_tolerance, self.params.tolerance)
    }

    /// Unmet link `l` where the verification run failed with `e`.
    fn failed(&self, l: &LinkFair, e: &crate::error::Error) -> Problem {
        Problem {
            kind: ProblemKind::Limited,
            surface: self.given.surfaces[self.given.links[l.link].slave]
                .name
                .clone(),
            link: Some(l.label.clone()),
            message: format!("the second run that would name the deviation it needs failed: {e}"),
            amount: None,
        }
    }

    /// Unmet link `l` named with what the verification run `again` made of it.
    fn named(&self, l: &LinkFair, again: &FairModelReport, alike: &str) -> Problem {
        let link = self.given.links[l.link];
        let (slave, master) = (
            &self.given.surfaces[link.slave],
            &self.given.surfaces[link.master],
        );
        let (to_slave, to_master) = (self.to(link.slave), self.to(link.master));
        let raise = format!(
            "the deviation of {} raised to {} and of {} to {}{alike}",
            slave.name,
            report::length(to_slave),
            master.name,
            report::length(to_master)
        );
        let deviation_in_again = |name: &str| {
            again
                .surfaces
                .iter()
                .find(|s| s.name == name)
                .map_or(0.0, |s| s.max_deviation)
        };
        if again.links.iter().any(|a| a.link == l.link && a.met) {
            Problem {
                kind: ProblemKind::Conflict,
                surface: slave.name.clone(),
                link: Some(l.label.clone()),
                message: format!(
                    "met in a second run with {raise} (they deviate {} and {} there): the deviation this link needs at most, verified",
                    report::length(deviation_in_again(&slave.name)),
                    report::length(deviation_in_again(&master.name)),
                ),
                amount: Some(to_slave),
            }
        } else {
            Problem {
                kind: ProblemKind::Limited,
                surface: slave.name.clone(),
                link: Some(l.label.clone()),
                message: format!(
                    "not met either in a second run with {raise}: {VERIFY_FACTOR} × the deviation of these two surfaces does not reach it"
                ),
                amount: None,
            }
        }
    }
}
