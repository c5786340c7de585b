//! The plan of a run: the waves of the hierarchy, masters before slaves (\[SV\] §1.1).

use std::sync::atomic::Ordering;

use nurbs_core::BSplineSurface;
use rayon::prelude::*;

use super::group::group_stage;
use super::{FairModelReport, Job, Outcome, Plan, Problem, ProblemKind, Progress};
use crate::error::Result;
use crate::model::Model;

/// The waves of the hierarchy: wave 0 holds the surfaces without links, a slave is one wave
/// after its latest master; within a wave, file order.
pub fn waves(model: &Model) -> Result<Vec<Vec<usize>>> {
    let order = model.hierarchy_order()?;
    let mut wave_of = vec![0usize; model.surfaces.len()];
    for &k in &order {
        let own = model
            .links_of_slave(k)
            .iter()
            .map(|&l| wave_of[model.links[l].master] + 1)
            .max()
            .unwrap_or(0);
        wave_of[k] = own.max(group_start(model, k, &wave_of));
    }
    let count = wave_of.iter().copied().max().map_or(0, |w| w + 1);
    let mut waves = vec![Vec::new(); count];
    for k in 0..model.surfaces.len() {
        waves[wave_of[k]].push(k);
    }
    Ok(waves)
}

/// `outcomes` with the problems of `why` that name their surfaces added.
fn noted(outcomes: Vec<(usize, Outcome)>, why: &[(usize, Problem)]) -> Vec<(usize, Outcome)> {
    outcomes
        .into_iter()
        .map(|(k, mut outcome)| {
            outcome
                .problems
                .extend(why.iter().filter(|p| p.0 == k).map(|p| p.1.clone()));
            (k, outcome)
        })
        .collect()
}

/// The earliest wave of the corner group of surface `k` (0 when it is in none): one after the
/// latest master outside the group of any of its patches, so the whole group can be faired as
/// one mesh before its first patch runs.
fn group_start(model: &Model, k: usize, wave_of: &[usize]) -> usize {
    model
        .corners
        .iter()
        .filter(|g| g.patches.contains(&k))
        .flat_map(|g| {
            g.patches.iter().flat_map(move |&p| {
                model
                    .links_of_slave(p)
                    .into_iter()
                    .map(|l| model.links[l].master)
                    .filter(move |m| !g.patches.contains(m))
            })
        })
        .map(|m| wave_of[m] + 1)
        .max()
        .unwrap_or(0)
}

/// What the report says of a part of a ring run again with its seams linked
/// ([`Plan::seams_linked`]).
const SEAM_LINKED: &str = "run again after the part it meets there, with its seams to it linked G2";

/// What the report says of a part of a ring run again with its seams kept.
const SEAM_KEPT: &str = "run again with the seam kept as it came, so its links follow the input's cross-section at the seam's ends";

impl Plan<'_> {
    /// Runs the waves one after another into `out`: each wave's corner groups first (\[SV\]
    /// §3.4), then its surfaces ([`Plan::wave`]), reporting each surface as it finishes.
    pub(super) fn run(
        &self,
        out: &mut Model,
        report: &mut FairModelReport,
        progress: &(dyn Fn(Progress<'_>) + Sync),
    ) -> Result<()> {
        let model = self.model;
        let total = model.surfaces.len();
        let mut done = 0;
        let mut group_done = vec![false; model.corners.len()];
        for wave in waves(model)? {
            // n-sided corner groups whose first patch runs in this wave: one mesh, refit
            for (g, group) in model.corners.iter().enumerate() {
                if group_done[g] || !group.patches.iter().any(|p| wave.contains(p)) {
                    continue;
                }
                group_done[g] = true;
                // the group moves all its patches together: the tightest of their tolerances
                let group_tolerance = group
                    .patches
                    .iter()
                    .map(|&k| self.tolerance_of(k))
                    .fold(f64::INFINITY, f64::min);
                group_stage(model, out, group, group_tolerance, self.params, report);
            }
            for (k, outcome) in self.wave(out, &wave) {
                let sectioned = outcome.report.stages.first().and_then(|s| s.section_ramp);
                if let (Some(_), Some(flag)) = (sectioned, self.sectioned.get(k)) {
                    flag.store(true, Ordering::Relaxed);
                }
                out.surfaces[k].surface = outcome.surface;
                report.surfaces.push(outcome.report);
                report.problems.extend(outcome.problems);
                done += 1;
                progress(Progress {
                    done,
                    total,
                    name: &model.surfaces[k].name,
                });
            }
        }
        Ok(())
    }

    /// The job of surface `k` of `model` (the plan's model, or one with more links), from its
    /// surface in `current`, against the masters there.
    pub(super) fn job<'a>(
        &'a self,
        model: &'a Model,
        current: &'a Model,
        k: usize,
        free_seams: bool,
    ) -> Job<'a> {
        Job {
            model,
            current,
            start: &current.surfaces[k].surface,
            surface: k,
            fairing: self.fairers.of(self.model.surfaces[k].role),
            tolerance: self.tolerance_of(k),
            connect: self.connect,
            params: self.params,
            cap: self.cap,
            before: self.before,
            edges: self.edges,
            ranges: self.ranges,
            free_seams,
            section_allowed: !self.no_section.get(k).copied().unwrap_or(false),
            spread: self.connect.set.spread_boundary_move
                && !model.links.iter().any(|l| l.master == k)
                && model.links_of_slave(k).into_iter().any(|l| {
                    let m = model.links[l].master;
                    self.sectioned
                        .get(m)
                        .is_some_and(|f| f.load(Ordering::Relaxed))
                }),
        }
    }

    /// Surface `k`'s deviation tolerance ([`Model::deviation_of`]).
    pub(super) fn tolerance_of(&self, k: usize) -> f64 {
        self.model
            .deviation_of(k, &self.params.role_tolerance, self.params.tolerance)
    }

    /// The surfaces of one wave run against `out` (the earlier waves' results), in parallel
    /// when asked. Seams are left to the continuity steps (with the linked boundaries' end
    /// tangents turned into their masters' planes there, [`Job::set_params`]); a seam they
    /// opened beyond its tolerance has its surfaces run again one after the other, each linked
    /// G2 to the parts it meets that ran before or keep their result ([`Plan::seams_linked`]),
    /// ring by ring, or, where that still leaves a seam of the ring open, the whole ring with
    /// the seams' frames kept ([`super::seams::ring_closure`]).
    fn wave(&self, out: &Model, wave: &[usize]) -> Vec<(usize, Outcome)> {
        let job = |&k: &usize, free_seams: bool| -> (usize, Outcome) {
            (k, self.job(self.model, out, k, free_seams).run())
        };
        let run = |ks: &[usize], free_seams: bool| -> Vec<(usize, Outcome)> {
            if self.params.parallel {
                ks.par_iter().map(|k| job(k, free_seams)).collect()
            } else {
                ks.iter().map(|k| job(k, free_seams)).collect()
            }
        };
        let mut results = run(wave, true);
        let now = |k: usize| {
            results
                .iter()
                .find(|r| r.0 == k)
                .map_or(&out.surfaces[k].surface, |r| &r.1.surface)
        };
        let opened = super::seams::on_opened_seams(
            self.model,
            &now,
            self.edges,
            self.edges_before,
            wave,
            wave,
        );
        if opened.is_empty() {
            return results;
        }
        // each ring on its own: linked where that closes its seams, else kept
        let mut replaced: Vec<(usize, Outcome)> = Vec::new();
        let mut kept: Vec<usize> = Vec::new();
        // the rings are independent of each other: in parallel, as the wave's surfaces
        let rings = super::seams::seam_rings(self.model, self.edges, &opened);
        let linked: Vec<_> = if self.params.parallel {
            rings
                .par_iter()
                .map(|ring| self.seams_linked(out, wave, ring, &results))
                .collect()
        } else {
            rings
                .iter()
                .map(|ring| self.seams_linked(out, wave, ring, &results))
                .collect()
        };
        for (ring, linked) in rings.into_iter().zip(linked) {
            match linked {
                Some(linked) => {
                    let why = self.opened_seam_notes(&now, &ring, SEAM_LINKED);
                    replaced.extend(noted(linked, &why));
                }
                None => kept.extend(ring),
            }
        }
        let again = super::seams::ring_closure(self.model, self.edges, wave, &kept);
        if !again.is_empty() {
            let (outcomes, why) = match self.linked_losing(out, wave, &results, &kept, &again) {
                Some((linked, parts)) => {
                    (linked, self.opened_seam_notes(&now, &parts, SEAM_LINKED))
                }
                None => (
                    run(&again, false),
                    self.opened_seam_notes(&now, &again, SEAM_KEPT),
                ),
            };
            replaced.extend(noted(outcomes, &why));
        }
        for (k, outcome) in replaced {
            if let Some(r) = results.iter_mut().find(|r| r.0 == k) {
                r.1 = outcome;
            }
        }
        results
    }

    /// Per surface of `again`, why it runs again: each of its seams as the free continuity
    /// steps left it (`now`), with the input's figures and the tolerances — the report then
    /// names what the kept seam costs (its links' G2 at the seam's ends follows the input's
    /// cross-section there).
    fn opened_seam_notes<'a>(
        &self,
        now: &dyn Fn(usize) -> &'a BSplineSurface,
        again: &[usize],
        then: &str,
    ) -> Vec<(usize, Problem)> {
        let t = &self.model.tolerances;
        self.edges
            .iter()
            .zip(self.edges_before)
            .filter(|(e, _)| again.contains(&e.surface) && crate::edges::is_seam(self.model, e))
            .filter_map(|(e, b)| {
                let m = crate::edges::measure_edge(e, now(e.surface), now(e.other));
                let opened = m.worse_than(b, t.g0, t.g1_deg);
                opened.then(|| {
                    (e.surface, Problem {
                        kind: ProblemKind::Limited,
                        surface: self.model.surfaces[e.surface].name.clone(),
                        link: None,
                        message: format!(
                            "its seam {} with {} was opened by the continuity steps to a gap of {:.3e} and an angle of {:.4}° (input {:.3e}, {:.4}°; tolerances {}, {}°): {then}",
                            e.side.name(),
                            self.model.surfaces[e.other].name,
                            m.gap,
                            m.angle_deg,
                            b.gap,
                            b.angle_deg,
                            t.g0,
                            t.g1_deg
                        ),
                        amount: Some(m.angle_deg / t.g1_deg),
                    })
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use nurbs_core::{Continuity, Point3, Side, Vector3, shapes::plane_patch};

    use super::{group_start, waves};
    use crate::model::{Link, Model};

    /// Four unit squares: 0 and 1 primaries, 2 a fillet on both, 3 a corner on the fillet and
    /// on primary 0.
    fn model() -> Model {
        let square = |x: f64| {
            plane_patch(
                Point3::new(x, 0.0, 0.0),
                Vector3::x(),
                Vector3::y(),
                (0.0, 1.0),
                (0.0, 1.0),
            )
            .unwrap()
        };
        let mut m = Model::from_primaries((0..4).map(|k| square(f64::from(k))).collect());
        m.surfaces[2].role = crate::model::Role::Connecting;
        m.surfaces[3].role = crate::model::Role::Corner;
        let link = |slave, side, master| Link {
            slave,
            side,
            master,
            continuity: Continuity::G2,
        };
        m.links = vec![
            link(2, Side::U0, 0),
            link(2, Side::U1, 1),
            link(3, Side::U0, 2),
            link(3, Side::V0, 0),
        ];
        m
    }

    #[test]
    fn masters_run_in_a_wave_before_their_slaves() {
        assert_eq!(waves(&model()).unwrap(), vec![vec![0, 1], vec![2], vec![3]]);
    }

    #[test]
    fn a_cycle_of_links_has_no_waves() {
        let mut m = model();
        m.links.push(Link {
            slave: 0,
            side: Side::U1,
            master: 3,
            continuity: Continuity::G1,
        });
        assert!(waves(&m).is_err());
    }

    #[test]
    fn a_corner_group_starts_after_the_masters_outside_it() {
        let mut m = model();
        m.corners.push(crate::model::CornerGroup {
            name: "g".into(),
            patches: vec![2, 3],
        });
        let wave_of = [0, 0, 1, 2];
        // the group's patches hang on the primaries 0 and 1 (wave 0) only: it can start in wave 1
        assert_eq!(group_start(&m, 3, &wave_of), 1);
        assert_eq!(group_start(&m, 0, &wave_of), 0);
    }
}
