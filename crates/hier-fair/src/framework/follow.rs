//! One-hump sections a slave could not follow, withdrawn. A master fillet that takes its
//! one-hump section ([`super::section`]) changes the curves its slaves are set against; the
//! slaves' C0 steps spread that move over their interiors ([`super::spread`]), and on the
//! kernel models they follow. Where a slave still misses a link after such a change (measured
//! by default on a box whose B-spline corner missed all four of its links against a changed
//! fillet), the run is made again with the sections of that slave's masters
//! withdrawn — those masters keep their input section — and the run that misses fewer links
//! is kept, its report naming each withdrawn section.

use std::sync::atomic::AtomicBool;

use super::report::link_reports;
use super::{FairModelReport, LinkFair, Plan, Problem, ProblemKind, Progress, measure_links};
use crate::error::Result;
use crate::model::Model;

impl Plan<'_> {
    /// Runs the plan from `start` ([`Plan::run`]), and again with sections withdrawn where a
    /// slave could not follow them (module docs): the output model, its report (the `slivers`
    /// problems first) and its links.
    pub(super) fn run_following(
        &self,
        start: &Model,
        slivers: &[Problem],
        tolerance: f64,
        progress: &(dyn Fn(Progress<'_>) + Sync),
    ) -> Result<(Model, FairModelReport, Vec<LinkFair>)> {
        let attempt = |plan: &Plan<'_>| -> Result<(Model, FairModelReport, Vec<LinkFair>)> {
            let flags: Vec<AtomicBool> = (0..start.surfaces.len())
                .map(|_| AtomicBool::new(false))
                .collect();
            let plan = Plan {
                sectioned: &flags,
                ..*plan
            };
            let mut out = start.clone();
            let mut report = FairModelReport {
                tolerance,
                problems: slivers.to_vec(),
                ..FairModelReport::default()
            };
            plan.run(&mut out, &mut report, progress)?;
            let after = measure_links(&out, self.ranges, self.connect);
            let links = link_reports(self.model, self.before, after, self.cap);
            Ok((out, report, links))
        };
        let first = attempt(self)?;
        let Some(withdrawn) = self.sections_to_withdraw(&first.1, &first.2) else {
            return Ok(first);
        };
        let again = Plan {
            no_section: &withdrawn,
            ..*self
        };
        let (out, mut report, links) = attempt(&again)?;
        let (with, without) = (missed(&first.2), missed(&links));
        if without >= with {
            return Ok(first);
        }
        report
            .problems
            .extend(self.withdrawn_notes(&withdrawn, with, without));
        Ok((out, report, links))
    }

    /// Per surface, whether its one-hump section is to be withdrawn: every master, with a
    /// section in `report`, of a slave that misses one of `links`; `None` where there is none.
    pub(super) fn sections_to_withdraw(
        &self,
        report: &FairModelReport,
        links: &[LinkFair],
    ) -> Option<Vec<bool>> {
        let model = self.model;
        let sectioned = |m: usize| {
            report.surfaces.iter().any(|s| {
                s.surface == m && s.stages.first().is_some_and(|st| st.section_ramp.is_some())
            })
        };
        let mut out = vec![false; model.surfaces.len()];
        for l in links.iter().filter(|l| !l.met) {
            let slave = model.links[l.link].slave;
            for k in model.links_of_slave(slave) {
                let m = model.links[k].master;
                out[m] |= sectioned(m) && !self.no_section.get(m).copied().unwrap_or(false);
            }
        }
        out.iter().any(|&w| w).then_some(out)
    }

    /// The problems that name the withdrawn sections of `withdrawn`, with the links missed
    /// with them (`with`) and without (`without`).
    pub(super) fn withdrawn_notes(
        &self,
        withdrawn: &[bool],
        with: usize,
        without: usize,
    ) -> Vec<Problem> {
        (0..withdrawn.len())
            .filter(|&m| withdrawn[m])
            .map(|m| Problem {
                kind: ProblemKind::Limited,
                surface: self.model.surfaces[m].name.clone(),
                link: None,
                message: format!(
                    "its one-hump section was withdrawn (it keeps its input's section): with it a slave of it could not follow, and {with} link(s) of the model missed; without it {without}"
                ),
                amount: None,
            })
            .collect()
    }
}

/// How many of `links` are missed.
pub(super) fn missed(links: &[LinkFair]) -> usize {
    links.iter().filter(|l| !l.met).count()
}
