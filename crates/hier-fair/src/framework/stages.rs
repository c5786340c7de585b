//! The stages of one surface (\[SV\] §3.2): the set and fairing stages from the dry run's plan,
//! each fairing stage checked ([`nurbs_core::FairingProblem`]), and the fallback that keeps a
//! surface never worse than the input.

use g_continuity::{SideLink, set_step};
use nurbs_core::energy::{max_deviation, thin_plate_energy};
use nurbs_core::{BSplineSurface, Continuity, Direction, Side};

use super::error::{StageError, StageResult};
use super::masks::{knots_between, missing_knots, smooth_join_points, stage_mask};
use super::report::{self, Problem, ProblemKind, Stage, StageReport};
use super::{DeviationBudget, DryRun, Job, MASTER_FRAME, Run, UNCHANGED_RELATIVE};
use crate::check::TOUCH_FACTOR;

/// What the stages of one surface work from, after the dry run.
pub(super) struct StagePlan<'a> {
    /// the surface's links with their model indices
    pub(super) labelled: &'a [(usize, SideLink<'a>)],
    /// the same links
    pub(super) links: &'a [SideLink<'a>],
    /// sides along which a slave hangs on this surface ([`MASTER_FRAME`] kept)
    pub(super) master_sides: Vec<Side>,
    /// the deviation the fairing stages may plan with ([`DEVIATION_SAFETY`], [`MASTER_SHARE`])
    pub(super) budget: f64,
    /// the highest level the tolerance allows (`None`: not even C0)
    pub(super) highest: Option<Continuity>,
    /// the highest target of the links (`None`: no links)
    pub(super) top: Option<Continuity>,
    /// the prepared surface, with the dry run's knots
    pub(super) prepared: BSplineSurface,
    /// the dry run's result at `highest`
    pub(super) connected: BSplineSurface,
    /// whether the dry run started from the one-hump section ([`super::section`])
    pub(super) section: bool,
}

impl StagePlan<'_> {
    /// The levels the alternation goes through: G0 up to the highest (G0 alone without one).
    fn levels(&self) -> Vec<Continuity> {
        match self.highest {
            None => vec![Continuity::G0],
            Some(h) => [Continuity::G0, Continuity::G1, Continuity::G2]
                .into_iter()
                .filter(|&c| c <= h)
                .collect(),
        }
    }
}

impl Job<'_> {
    /// [`Job::stages`] with the spread allowed or not ([`super::spread`]).
    pub(super) fn stages_with(
        &self,
        original: &BSplineSurface,
        problems: &mut Vec<Problem>,
        missed: &mut Vec<(usize, Problem)>,
        spread: bool,
    ) -> StageResult<(BSplineSurface, Vec<StageReport>)> {
        let labelled = self.links();
        self.check_touch(&labelled)?;
        let links: Vec<SideLink> = labelled.iter().map(|(_, l)| *l).collect();
        let mut run = Run {
            original,
            grid: self.params.deviation_grid,
            stages: Vec::new(),
            last: std::time::Instant::now(),
        };
        // 0. prepare, with the curvature lead-in the continuity steps alone can afford
        let (dry, needed) = self.prepare_and_dry_run(&links, spread)?;
        let prepared = dry.prepared.clone();
        run.record(Stage::Prepare, self.start, &prepared);
        run.stages[0].knots_inserted = knots_between(self.start, &prepared);
        run.stages[0].section_ramp = dry.section_ramp;
        let top = links.iter().map(|l| l.target).max();
        let highest = self.highest_level(&labelled, &dry, problems);
        self.report_conflicts(&labelled, &dry, highest, needed, problems);
        self.report_missed(&labelled, &dry, missed);
        let connected = highest
            .and_then(|h| dry.steps.iter().find(|(c, _, _)| *c == h))
            .map_or_else(|| prepared.clone(), |(_, s, _)| s.clone());
        if top.is_some() && highest.is_none() {
            // not even C0 fits within the tolerance: keep the input (polished where that is
            // better, [`Job::joint_polish`])
            return Ok((self.joint_polish(self.start.clone(), problems), run.stages));
        }
        let prepared = self.with_dry_run_knots(prepared, &connected, highest, &mut run)?;
        let plan = StagePlan {
            labelled: &labelled,
            links: &links,
            master_sides: self.master_sides(),
            budget: self.params.budget.fairing(self.tolerance, self.is_master()),
            highest,
            top,
            prepared: prepared.clone(),
            connected,
            section: dry.section_ramp.is_some(),
        };
        let s = if dry.section_ramp.is_some() && highest == top {
            self.section_stages(&plan, &mut run)
        } else {
            self.run_levels(
                &plan,
                prepared,
                (dry.tangent_corners, dry.spread),
                &mut run,
                problems,
            )?
        };
        let original = run.original;
        let (s, stages) = self.never_worse(&plan, s, run, problems);
        Ok(self.polished_stages(&plan, original, s, stages, problems))
    }

    /// Links that do not touch their masters are bad input: the surface is left alone. Measured
    /// against the masters as they came in — a master the framework moved (a fillet's one-hump
    /// section, [`super::section`]) has moved within its own tolerance, and the continuity
    /// steps fit this surface's rows to it.
    fn check_touch(&self, labelled: &[(usize, SideLink<'_>)]) -> StageResult<()> {
        let limit = TOUCH_FACTOR * self.connect.tolerances.g0;
        for (k, l) in labelled {
            let input = SideLink {
                master: &self.model.surfaces[self.model.links[*k].master].surface,
                ..*l
            };
            let m = input
                .measure(self.start, &self.connect.measure)
                .map_err(|source| StageError::Measure {
                    link: self.model.link_label(*k),
                    source,
                })?;
            if m.g0 > limit {
                return Err(StageError::NotTouching {
                    link: self.model.link_label(*k),
                    gap: m.g0,
                    limit,
                    factor: TOUCH_FACTOR,
                });
            }
        }
        Ok(())
    }

    /// The highest step of the dry run whose deviation stays within the tolerance. A step that
    /// misses its level and leaves a link worse than the input is not taken where the step below
    /// met its own: G2 attempted and missed must not cost the G1 that was there (reported).
    fn highest_level(
        &self,
        labelled: &[(usize, SideLink<'_>)],
        dry: &DryRun,
        problems: &mut Vec<Problem>,
    ) -> Option<Continuity> {
        let highest = dry
            .steps
            .iter()
            .take_while(|(_, _, d)| *d <= self.tolerance)
            .map(|(c, _, _)| *c)
            .last();
        if let Some(k) = highest.and_then(|h| dry.steps.iter().position(|(c, _, _)| *c == h))
            && k > 0
            && !dry.met_steps[k]
            && dry.met_steps[k - 1]
            && let Some(worse) = self.worse_link(labelled, &dry.steps[k].1)
        {
            let (step, below) = (dry.steps[k].0, dry.steps[k - 1].0);
            // named on every link of that level: each is left at the level below for it
            for (j, _) in labelled.iter().filter(|(_, l)| l.target >= step) {
                problems.push(Problem {
                    kind: ProblemKind::Limited,
                    surface: self.model.surfaces[self.surface].name.clone(),
                    link: Some(self.model.link_label(*j)),
                    message: format!(
                        "setting {step:?} misses its links within the deviations tried (up to {}) and {worse}; the surface is kept at {below:?}",
                        report::length(dry.steps[k].2)
                    ),
                    amount: Some(dry.steps[k].2),
                });
            }
            return Some(below);
        }
        highest
    }

    /// A dry-run step beyond the tolerance is a conflict naming its links, with the least
    /// deviation a trial needed to meet them (`needed`), or the step's own.
    fn report_conflicts(
        &self,
        labelled: &[(usize, SideLink<'_>)],
        dry: &DryRun,
        highest: Option<Continuity>,
        needed: Option<f64>,
        problems: &mut Vec<Problem>,
    ) {
        let Some((step, _, d)) = dry.steps.iter().find(|(_, _, d)| *d > self.tolerance) else {
            return;
        };
        let kept = highest.map_or("its input continuity".to_string(), |c| format!("{c:?}"));
        let amount = needed.filter(|&n| n > self.tolerance).unwrap_or(*d);
        for (k, l) in labelled {
            if l.target >= *step {
                problems.push(Problem {
                    kind: ProblemKind::Conflict,
                    surface: self.model.surfaces[self.surface].name.clone(),
                    link: Some(self.model.link_label(*k)),
                    message: format!(
                        "setting {step:?} needs a deviation of {} from the original, above the tolerance {}; the surface is kept at {kept}",
                        report::length(amount),
                        report::length(self.tolerance)
                    ),
                    amount: Some(amount),
                });
            }
        }
    }

    /// A link the dry run misses although every step stayed within the tolerance is no conflict
    /// of the dry run's: it is named with the deviation the kept trial took (and a vertex
    /// conflict of its masters where that is the reason); `run` reports it if the result still
    /// misses it, and the model's verification run names what deviation meets it
    /// ([`super::verify`]).
    fn report_missed(
        &self,
        labelled: &[(usize, SideLink<'_>)],
        dry: &DryRun,
        missed: &mut Vec<(usize, Problem)>,
    ) {
        if dry.met || dry.steps.iter().any(|(_, _, d)| *d > self.tolerance) {
            return;
        }
        let Some((step, last, d)) = dry.steps.last() else {
            return;
        };
        let t = &self.set_params().tolerances;
        for (k, l) in labelled {
            let target = l.target.min(*step);
            let Ok(m) = l.measure(last, &self.connect.measure) else {
                continue;
            };
            if m.meets(target, t.g0, t.g1_deg, t.g2_rel) {
                continue;
            }
            missed.push((*k, Problem {
                kind: ProblemKind::Limited,
                surface: self.model.surfaces[self.surface].name.clone(),
                link: Some(self.model.link_label(*k)),
                message: format!(
                    "the continuity steps miss {target:?} here in every curvature lead-in tried, deviating only {} (tolerance {})",
                    report::length(*d),
                    report::length(self.tolerance),
                ),
                amount: Some(*d),
            }));
        }
    }

    /// `prepared` with the knots the dry run's refinement found (shape unchanged): the set
    /// steps then start with the freedom they need instead of finding it again round by round.
    fn with_dry_run_knots(
        &self,
        prepared: BSplineSurface,
        connected: &BSplineSurface,
        highest: Option<Continuity>,
        run: &mut Run<'_>,
    ) -> StageResult<BSplineSurface> {
        if highest.is_none() {
            return Ok(prepared);
        }
        let name = &self.model.surfaces[self.surface].name;
        let (more_u, more_v) = (
            missing_knots(prepared.knots_u().knots(), connected.knots_u().knots()),
            missing_knots(prepared.knots_v().knots(), connected.knots_v().knots()),
        );
        let refined = prepared
            .refine(Direction::U, &more_u)
            .and_then(|p| p.refine(Direction::V, &more_v))
            .map_err(|source| StageError::Knots {
                surface: name.clone(),
                source,
            })?;
        if let Some(r) = run.stages.first_mut() {
            r.knots_inserted += more_u.len() + more_v.len();
        }
        Ok(refined)
    }

    /// The alternation up to the plan's highest level (\[SV\] §3.2): set a level, fair keeping it,
    /// each fairing stage with its share of the deviation budget left. Returns the result.
    fn run_levels(
        &self,
        plan: &StagePlan<'_>,
        prepared: BSplineSurface,
        (tangent_corners, spread): (bool, bool),
        run: &mut Run<'_>,
        problems: &mut Vec<Problem>,
    ) -> StageResult<BSplineSurface> {
        let name = &self.model.surfaces[self.surface].name;
        let mut set_params = self.set_params();
        set_params.set.tangent_corners = tangent_corners;
        set_params.set.spread_boundary_move = spread;
        let levels = plan.levels();
        let mut s = prepared;
        let mut fair_left = levels.len();
        for level in levels {
            if plan.highest.is_some() {
                let (next, step) =
                    set_step(&s, plan.links, level, &set_params).map_err(|source| {
                        StageError::Set {
                            level,
                            surface: name.clone(),
                            source,
                        }
                    })?;
                run.record(Stage::set(level), &s, &next);
                if let Some(r) = run.stages.last_mut() {
                    r.knots_inserted = step.knots_inserted;
                    r.max_move = step.max_move;
                }
                s = next;
                // at the top target every link's rows are fixed in the fairing stage, so its
                // gap, angle and curvature stay as this set step leaves them: a link it leaves
                // worse than the input or loses is final, and the stage's fairing is not run
                // (the fallback decides from the same measures)
                if plan.top.is_some_and(|t| level >= t)
                    && (self.worse_link(plan.labelled, &s).is_some()
                        || self.lost_link(plan.labelled, &plan.connected, &s).is_some())
                {
                    run.record(Stage::fair(level), &s, &s);
                    break;
                }
            }
            // fairing keeping `level`
            let eps = DeviationBudget::stage_epsilon(plan.budget, run.deviation(), fair_left);
            fair_left -= 1;
            s = self.fair_level(plan, s, level, eps, run, problems);
        }
        Ok(s)
    }

    /// The fairing stage keeping `level` within `eps`, recorded in `run`; a method that fails or
    /// breaks its contract leaves `s` as it was (reported).
    fn fair_level(
        &self,
        plan: &StagePlan<'_>,
        s: BSplineSurface,
        level: Continuity,
        eps: f64,
        run: &mut Run<'_>,
        problems: &mut Vec<Problem>,
    ) -> BSplineSurface {
        let stage = Stage::fair(level);
        let known = run.stages.last().map(|r| r.energy);
        match self.fair_stage(&s, plan.links, level, &plan.master_sides, eps, known) {
            Ok(Some((next, iterations, energy))) => {
                run.record_known(stage, &s, &next, Some(energy));
                if let Some(r) = run.stages.last_mut() {
                    r.iterations = iterations;
                    r.epsilon = eps;
                }
                next
            }
            Ok(None) => {
                run.record(stage, &s, &s);
                s
            }
            Err(e) => {
                problems.push(Problem {
                    kind: ProblemKind::Limited,
                    surface: self.model.surfaces[self.surface].name.clone(),
                    link: None,
                    message: format!(
                        "{} fairing ({}) was not used: {e}",
                        self.fairing.name(),
                        stage.name()
                    ),
                    amount: None,
                });
                run.record(stage, &s, &s);
                s
            }
        }
    }

    /// Never worse than the input: the faired result `s`, else the continuity setting faired
    /// once keeping its level, else continuity alone, else the least grown of the candidates
    /// ([`Job::least_grown`]); every step down is reported.
    fn never_worse(
        &self,
        plan: &StagePlan<'_>,
        s: BSplineSurface,
        run: Run<'_>,
        problems: &mut Vec<Problem>,
    ) -> (BSplineSurface, Vec<StageReport>) {
        let why = if run.deviation() > self.tolerance {
            (
                format!(
                    "the faired surface deviates {} (tolerance {}); fairing dropped, continuity setting kept",
                    report::length(run.deviation()),
                    report::length(self.tolerance)
                ),
                Some(run.deviation()),
            )
        } else if let Some(worse) = self.worse_link(plan.labelled, &s) {
            (
                format!("fairing dropped, continuity setting kept: {worse}"),
                None,
            )
        } else if let Some(lost) = self.lost_link(plan.labelled, &plan.connected, &s) {
            // fairing keeps the continuity it is given ([SV] §3.2 steps 4 and 6): a stage that
            // loses a link the continuity setting met is not used
            (
                format!("fairing dropped, continuity setting kept: {lost}"),
                None,
            )
        } else {
            return self.fairer_of(plan, s, run, problems);
        };
        self.limited(problems, why.0, why.1);
        // the alternating stages failed: the continuity setting, faired once keeping its level
        // (its rows fixed, so it keeps every join the setting made), when that is no worse
        let mut once_result = None;
        if let Some((faired, stages)) = self.faired_once(plan, run.original, &run.stages[0]) {
            if self.worse_link(plan.labelled, &faired).is_none() {
                // the setting faired once is judged as the stages' result is
                if let Some(why) = self.setting_is_fairer(plan, &faired, run.original) {
                    self.limited(problems, why, None);
                    return (
                        plan.connected.clone(),
                        vec![self.connected_record(plan, &run)],
                    );
                }
                let h = plan.highest.unwrap_or(Continuity::G0);
                self.limited(
                    problems,
                    format!(
                        "the continuity setting was faired once keeping {h:?} instead of stage by stage"
                    ),
                    None,
                );
                return (faired, stages);
            }
            once_result = Some((faired, stages));
        }
        let c = self.connected_record(plan, &run);
        let Some(worse) = self.worse_link(plan.labelled, &plan.connected) else {
            return (plan.connected.clone(), vec![c]);
        };
        let mut candidates: Vec<(&str, BSplineSurface, Vec<StageReport>)> = Vec::new();
        if let Some((f, stages)) = once_result {
            candidates.push(("the continuity setting faired once", f, stages));
        }
        if run.deviation() <= self.tolerance {
            candidates.push(("the faired result", s, run.stages.clone()));
        }
        candidates.push(("the continuity setting", plan.connected.clone(), vec![c]));
        candidates.push((
            "the surface as it was",
            self.start.clone(),
            vec![run.stages[0].clone()],
        ));
        self.least_grown(plan.labelled, candidates, &worse, problems)
    }

    /// The faired result `s` (no link worse, none lost, within the tolerance), or the
    /// continuity setting alone where [`Job::setting_is_fairer`] says so (reported with both
    /// figures).
    fn fairer_of(
        &self,
        plan: &StagePlan<'_>,
        s: BSplineSurface,
        run: Run<'_>,
        problems: &mut Vec<Problem>,
    ) -> (BSplineSurface, Vec<StageReport>) {
        match self.setting_is_fairer(plan, &s, run.original) {
            Some(why) => {
                self.limited(problems, why, None);
                (
                    plan.connected.clone(),
                    vec![self.connected_record(plan, &run)],
                )
            }
            None => (s, run.stages),
        }
    }

    /// Why the continuity setting alone (`plan.connected`) replaces the faired result `s`, or
    /// `None` to keep `s`. It replaces it only with [`FairParams::prefer_fairer`], where the
    /// faired result's peak curvature is beyond [`crate::fairness::PEAK_FACTOR`] of its
    /// input's (a one-hump section's result: where it is not fair by any figure of
    /// [`crate::fairness`]), the setting meets as many links as `s` and is fairer
    /// ([`crate::fairness::FairnessVerdict::fairer_than`]): a fairing stage minimizes its
    /// method's functional, which on a strongly curved connecting surface need not lower its
    /// curvature peaks (with 0.5 mm of deviation the thin-plate energy of a boss's
    /// torus fillet drops 4 % while its peak curvature grows 2.6×; a box's sphere corners
    /// per role drop 7 % in energy and go from 1.18× to 1.81× in peak), nor keep the one hump
    /// of a fillet's section ([`super::section`]).
    fn setting_is_fairer(
        &self,
        plan: &StagePlan<'_>,
        s: &BSplineSurface,
        original: &BSplineSurface,
    ) -> Option<String> {
        // a master's result is what its slaves are set against; they are set after it, against the
        // setting where that is kept. Measured on the 36 runs of the six kernel models and their
        // twelve variants (per role and by default), masters included: every link met as before,
        // 336 fair surfaces against 330, the lofted blocks' fillets per role from 2.7–4.0× to
        // 1.3–1.4× their input's peak (their thin-plate fairing lowered the energy by a tenth and
        // tripled the peak), a three-radii corner per role 14.0 → 3.9 s. (An earlier state of the
        // framework, before the slaves' C0 move was spread, made a vertex blend between four lofted
        // fillets kept at their settings miss G2 on all four sides.) The setting replaces the
        // faired result only where it meets as many links (a polish follows either,
        // [`Job::polished_stages`]). It was every link before: then a box's sphere corners by
        // default, whose settings and faired results alike fall short of every link by the
        // job's own measure (the model's check, with its vertex zones, counts them all met),
        // kept faired results peaking at 2.4–3.1× their input's instead of settings at
        // 1.02–1.38×, and eleven small fillets of a metre part,
        // which meet two of their four links either way, kept faired results wrinkled to
        // 3–37× (docs/benchmarks.md)
        if !self.params.prefer_fairer
            || plan.highest.is_none()
            || self.worse_link(plan.labelled, &plan.connected).is_some()
            || self.met_links(plan.links, &plan.connected) < self.met_links(plan.links, s)
        {
            return None;
        }
        let before = crate::fairness::surface_fairness(self.model, self.surface, original);
        let verdict = |x: &BSplineSurface| {
            let after = crate::fairness::surface_fairness(self.model, self.surface, x);
            crate::fairness::FairnessVerdict::new(&before, &after, self.joint_curvature(x))
        };
        let faired = verdict(s);
        // the one-hump section is judged by every figure (its fairing must keep the hump); any
        // other result by its peak: below that bound the method's own functional decides
        // ([SV] §3.2) — on near-flat fillets (the X-node's, a few 1e-3 /mm) the comb's extrema
        // counted at the G2 tolerance's hysteresis trade against a lower energy
        let judged_fair = if plan.section {
            faired.fair()
        } else {
            faired.spike() <= crate::fairness::PEAK_FACTOR
        };
        if judged_fair {
            return None;
        }
        let setting = verdict(&plan.connected);
        setting
            .fairer_than(&faired, self.connect.tolerances.g2_rel)
            .then(|| {
                format!(
                    "fairing dropped, continuity setting kept: it is fairer (peak curvature {:.2}× the input's, {} curvature extrema gained across the boundary; the faired result {:.2}×, {})",
                    setting.spike(),
                    setting.extrema_gained,
                    faired.spike(),
                    faired.extrema_gained
                )
            })
    }

    /// The stage record of the continuity setting alone (`plan.connected`): the prepare
    /// record with the setting's deviation from the original and its energy.
    fn connected_record(&self, plan: &StagePlan<'_>, run: &Run<'_>) -> StageReport {
        let mut c = run.stages[0].clone();
        c.deviation = max_deviation(run.original, &plan.connected, self.params.deviation_grid);
        c.energy = thin_plate_energy(&plan.connected);
        c
    }

    /// A `limited` problem of this surface.
    pub(super) fn limited(
        &self,
        problems: &mut Vec<Problem>,
        message: String,
        amount: Option<f64>,
    ) {
        problems.push(Problem {
            kind: ProblemKind::Limited,
            surface: self.model.surfaces[self.surface].name.clone(),
            link: None,
            message,
            amount,
        });
    }

    /// The plan's continuity setting faired once keeping its level, with its stage records
    /// (`prepare` the prepare stage's record), when that stays within the tolerance and loses
    /// no link the setting met.
    pub(super) fn faired_once(
        &self,
        plan: &StagePlan<'_>,
        original: &BSplineSurface,
        prepare: &StageReport,
    ) -> Option<(BSplineSurface, Vec<StageReport>)> {
        let h = plan.highest?;
        let dc = max_deviation(original, &plan.connected, self.params.deviation_grid);
        let mut once = Run {
            original,
            grid: self.params.deviation_grid,
            stages: vec![prepare.clone()],
            last: std::time::Instant::now(),
        };
        once.record(Stage::set(h), &plan.prepared, &plan.connected);
        let known = once.stages.last().map(|r| r.energy);
        let eps = plan.budget - dc;
        let Ok(Some((faired, iterations, energy))) = self.fair_stage(
            &plan.connected,
            plan.links,
            h,
            &plan.master_sides,
            eps,
            known,
        ) else {
            return None;
        };
        once.record_known(Stage::fair(h), &plan.connected, &faired, Some(energy));
        if let Some(r) = once.stages.last_mut() {
            r.iterations = iterations;
            r.epsilon = eps;
        }
        (once.deviation() <= self.tolerance
            && self
                .lost_link(plan.labelled, &plan.connected, &faired)
                .is_none())
        .then_some((faired, once.stages))
    }

    /// Whether this surface came in as a plane (thin-plate energy exactly 0: a kernel's
    /// bilinear patch) and `s` is still that surface: rows added to it (a degree raised, knots
    /// inserted) give an energy of rounding size (1e-28), which no method can lower.
    pub(super) fn still_a_plane(&self, s: &BSplineSurface) -> bool {
        thin_plate_energy(self.start) == 0.0
            && max_deviation(self.start, s, self.params.deviation_grid)
                <= UNCHANGED_RELATIVE * self.start.size()
    }

    /// One fairing stage keeping `level` on `s` within `eps`: the stage mask, this surface's
    /// master frames and interior join points fixed. `None` when nothing is free, `eps` is 0, or
    /// the thin-plate energy of `s` is 0 (a plane: S_uu = S_uv = S_vv = 0 everywhere, no surface
    /// is fairer, and a method could only add round-off to it).
    pub(super) fn fair_stage(
        &self,
        s: &BSplineSurface,
        links: &[SideLink<'_>],
        level: Continuity,
        master_sides: &[Side],
        eps: f64,
        energy_of_s: Option<f64>,
    ) -> StageResult<Option<(BSplineSurface, usize, f64)>> {
        let mut mask = stage_mask(s, links, level);
        for &side in master_sides {
            mask.fix_frame(side, MASTER_FRAME);
        }
        for &(i, j) in &self.interior_join_points(s) {
            mask.set_free(i, j, false);
        }
        // shared edges no link covers keep their tangential frame on both surfaces
        for e in self.edges.iter().filter(|e| e.surface == self.surface) {
            mask.fix_frame(e.side, nurbs_core::Frame::Tangential);
        }
        for (i, j) in crate::edges::carrying_points(self.edges, self.surface, s, self.model) {
            mask.set_free(i, j, false);
        }
        for (i, j) in smooth_join_points(self.start, s, self.connect.tolerances.g1_deg) {
            mask.set_free(i, j, false);
        }
        if mask.free_count() == 0 || eps <= 0.0 {
            return Ok(None);
        }
        // (the energy of `s` as the caller's stage record has it, when it has)
        let before = energy_of_s.unwrap_or_else(|| thin_plate_energy(s));
        if before <= 0.0 || self.still_a_plane(s) {
            return Ok(None);
        }
        // checked: a method that moves a fixed point or leaves ε is not used; the stage measures
        // what it needs itself (the energy here, the deviation from the original in its record)
        let out = nurbs_core::FairingProblem::new(s, &mask, eps)
            .keeping(level)
            .run(self.fairing)
            .map_err(StageError::Method)?;
        // a fairing stage ends fairer than it started, or is not used
        let after = thin_plate_energy(&out.surface);
        if after > before {
            return Err(StageError::RaisedEnergy { before, after });
        }
        Ok(Some((out.surface, out.iterations, after)))
    }
}
