//! The stages of one surface ([SV] §3.2): the set and fairing stages from the dry run's plan,
//! each fairing stage checked ([`nurbs_core::FairingProblem`]), and the fallback that keeps a
//! surface never worse than the input.

use super::*;

impl Job<'_> {
    pub(super) fn stages(
        &self,
        original: &BSplineSurface,
        problems: &mut Vec<Problem>,
        missed: &mut Vec<(usize, Problem)>,
    ) -> std::result::Result<(BSplineSurface, Vec<StageReport>), String> {
        let name = &self.model.surfaces[self.surface].name;
        let labelled = self.links();
        // links that do not touch their masters: bad input, the surface is left alone
        let limit = TOUCH_FACTOR * self.connect.tolerances.g0;
        for (k, l) in &labelled {
            let m = l
                .measure(self.start, &self.connect.measure)
                .map_err(|e| format!("link {}: {e}", self.model.link_label(*k)))?;
            if m.g0 > limit {
                return Err(format!(
                    "link {} does not touch its master: gap {:.3e} > {:.3e} ({} × the g0 tolerance)",
                    self.model.link_label(*k),
                    m.g0,
                    limit,
                    TOUCH_FACTOR
                ));
            }
        }
        let links: Vec<SideLink> = labelled.iter().map(|(_, l)| *l).collect();
        let mut run = Run {
            original,
            grid: self.params.deviation_grid,
            stages: Vec::new(),
        };
        // 0. prepare, with the curvature lead-in the continuity steps alone can afford
        let (dry, needed) = self.prepare_and_dry_run(&links)?;
        let prepared = dry.prepared.clone();
        run.record(Stage::Prepare, self.start, &prepared);
        run.stages[0].knots_inserted = knots_between(self.start, &prepared);
        let top = links.iter().map(|l| l.target).max();
        // the highest step whose deviation stays within the tolerance; a step beyond it is a
        // conflict naming its links, with the least deviation a trial needed to meet them
        let mut highest = dry
            .steps
            .iter()
            .take_while(|(_, _, d)| *d <= self.tolerance)
            .map(|(c, _, _)| *c)
            .last();
        // a step that misses its level and leaves a link worse than the input is not taken where
        // the step below met its own: G2 attempted and missed must not cost the G1 that was there
        if let Some(k) = highest.and_then(|h| dry.steps.iter().position(|(c, _, _)| *c == h))
            && k > 0
            && !dry.met_steps[k]
            && dry.met_steps[k - 1]
            && let Some(worse) = self.worse_link(&labelled, &dry.steps[k].1)
        {
            let (step, below) = (dry.steps[k].0, dry.steps[k - 1].0);
            problems.push(Problem {
                        kind: ProblemKind::Limited,
                        surface: name.clone(),
                        link: None,
                        message: format!(
                            "setting {step:?} misses its links within the deviations tried (up to {:.4}) and {worse}; the surface is kept at {below:?}",
                            dry.steps[k].2
                        ),
                        amount: Some(dry.steps[k].2),
                    });
            highest = Some(below);
        }
        if let Some((step, _, d)) = dry.steps.iter().find(|(_, _, d)| *d > self.tolerance) {
            let kept = highest.map_or("its input continuity".to_string(), |c| format!("{c:?}"));
            let amount = needed.filter(|&n| n > self.tolerance).unwrap_or(*d);
            for (k, l) in &labelled {
                if l.target >= *step {
                    problems.push(Problem {
                        kind: ProblemKind::Conflict,
                        surface: name.clone(),
                        link: Some(self.model.link_label(*k)),
                        message: format!(
                            "setting {step:?} needs a deviation of {amount:.4} from the original, above the tolerance {:.4}; the surface is kept at {kept}",
                            self.tolerance
                        ),
                        amount: Some(amount),
                    });
                }
            }
        }
        // a link the steps miss although every step stayed within the tolerance is no deviation
        // conflict: it is named with the deviation the kept trial took
        if !dry.met
            && dry.steps.iter().all(|(_, _, d)| *d <= self.tolerance)
            && let Some((step, last, d)) = dry.steps.last()
        {
            let t = &self.set_params().tolerances;
            for (k, l) in &labelled {
                let target = l.target.min(*step);
                let Ok(m) = l.measure(last, &self.connect.measure) else {
                    continue;
                };
                if m.meets(target, t.g0, t.g1_deg, t.g2_rel) {
                    continue;
                }
                let vertex = if target == Continuity::G2 {
                    self.vertex_conflict(&labelled, *l, last, &m)
                } else {
                    None
                };
                missed.push((*k, Problem {
                        kind: ProblemKind::Limited,
                        surface: name.clone(),
                        link: Some(self.model.link_label(*k)),
                        message: format!(
                            "the continuity steps miss {target:?} here in every curvature lead-in tried, deviating {d:.4} (tolerance {:.4}): not a deviation conflict{}",
                            self.tolerance,
                            vertex.unwrap_or_default()
                        ),
                        amount: Some(*d),
                    }));
            }
        }
        let connected = highest
            .and_then(|h| dry.steps.iter().find(|(c, _, _)| *c == h))
            .map_or_else(|| prepared.clone(), |(_, s, _)| s.clone());
        if top.is_some() && highest.is_none() {
            // not even C0 fits within the tolerance: keep the input
            return Ok((self.start.clone(), run.stages));
        }
        let levels: Vec<Continuity> = match highest {
            None => vec![Continuity::G0],
            Some(h) => [Continuity::G0, Continuity::G1, Continuity::G2]
                .into_iter()
                .filter(|&c| c <= h)
                .collect(),
        };
        // the knots the dry run's refinement found are inserted up front (shape unchanged): the
        // set steps below then start with the freedom they need instead of finding it again
        // round by round
        let prepared = if highest.is_some() {
            let (more_u, more_v) = (
                missing_knots(prepared.knots_u().knots(), connected.knots_u().knots()),
                missing_knots(prepared.knots_v().knots(), connected.knots_v().knots()),
            );
            let refined = prepared
                .refine(Direction::U, &more_u)
                .and_then(|p| p.refine(Direction::V, &more_v))
                .map_err(|e| format!("inserting knots into {name}: {e}"))?;
            if let Some(r) = run.stages.first_mut() {
                r.knots_inserted += more_u.len() + more_v.len();
            }
            refined
        } else {
            prepared
        };
        let master_sides = self.master_sides();
        let mut set_params = self.set_params();
        set_params.set.tangent_corners = dry.tangent_corners;
        let prepared_for_once = prepared.clone();
        let budget = if self.is_master() {
            MASTER_SHARE * self.tolerance
        } else {
            DEVIATION_SAFETY * self.tolerance
        };
        let mut s = prepared;
        let mut fair_left = levels.len();
        for level in levels {
            if highest.is_some() {
                let (next, step) = set_step(&s, &links, level, &set_params)
                    .map_err(|e| format!("setting {level:?} on {name}: {e}"))?;
                run.record(Stage::set(level), &s, &next);
                if let Some(r) = run.stages.last_mut() {
                    r.knots_inserted = step.knots_inserted;
                    r.max_move = step.max_move;
                }
                s = next;
                // at the top target every link's rows are fixed in the fairing stage, so its
                // gap, angle and curvature stay as this set step leaves them: a link it leaves
                // worse than the input or loses is final, and the stage's fairing is not run
                // (the fallback below decides from the same measures)
                if top.is_some_and(|t| level >= t)
                    && (self.worse_link(&labelled, &s).is_some()
                        || self.lost_link(&labelled, &connected, &s).is_some())
                {
                    run.record(Stage::fair(level), &s, &s);
                    break;
                }
            }
            // fairing keeping `level`
            let stage = Stage::fair(level);
            let eps = ((budget - run.deviation()) / fair_left as f64).max(0.0);
            fair_left -= 1;
            let known = run.stages.last().map(|r| r.energy);
            match self.fair_stage(&s, &links, level, &master_sides, eps, known) {
                Ok(Some((next, iterations, energy))) => {
                    run.record_known(stage, &s, &next, Some(energy));
                    if let Some(r) = run.stages.last_mut() {
                        r.iterations = iterations;
                        r.epsilon = eps;
                    }
                    s = next;
                }
                Ok(None) => run.record(stage, &s, &s),
                Err(e) => {
                    problems.push(Problem {
                        kind: ProblemKind::Limited,
                        surface: name.clone(),
                        link: None,
                        message: format!(
                            "{} fairing ({}) was not used: {e}",
                            self.fairing.name(),
                            stage.name()
                        ),
                        amount: None,
                    });
                    run.record(stage, &s, &s);
                }
            }
        }
        // never worse than the input: the faired result, else continuity alone, else the input
        let mut fallback = |why: String, amount: Option<f64>| {
            problems.push(Problem {
                kind: ProblemKind::Limited,
                surface: name.clone(),
                link: None,
                message: why,
                amount,
            });
        };
        if run.deviation() > self.tolerance {
            fallback(
                format!(
                    "the faired surface deviates {:.4} (tolerance {:.4}); fairing dropped, continuity setting kept",
                    run.deviation(),
                    self.tolerance
                ),
                Some(run.deviation()),
            );
        } else if let Some(worse) = self.worse_link(&labelled, &s) {
            fallback(
                format!("fairing dropped, continuity setting kept: {worse}"),
                None,
            );
        } else if let Some(lost) = self.lost_link(&labelled, &connected, &s) {
            // fairing keeps the continuity it is given ([SV] §3.2 steps 4 and 6): a stage that
            // loses a link the continuity setting met is not used
            fallback(
                format!("fairing dropped, continuity setting kept: {lost}"),
                None,
            );
        } else {
            return Ok((s, run.stages));
        }
        // the alternating stages failed: the continuity setting, faired once keeping its level
        // (its rows fixed, so it keeps every join the setting made), when that is no worse
        let mut once_result = None;
        if let Some(h) = highest {
            let dc = max_deviation(original, &connected, self.params.deviation_grid);
            let mut once = Run {
                original,
                grid: self.params.deviation_grid,
                stages: vec![run.stages[0].clone()],
            };
            once.record(Stage::set(h), &prepared_for_once, &connected);
            let known = once.stages.last().map(|r| r.energy);
            if let Ok(Some((faired, iterations, energy))) =
                self.fair_stage(&connected, &links, h, &master_sides, budget - dc, known)
            {
                once.record_known(Stage::fair(h), &connected, &faired, Some(energy));
                if let Some(r) = once.stages.last_mut() {
                    r.iterations = iterations;
                    r.epsilon = budget - dc;
                }
                if once.deviation() <= self.tolerance
                    && self.lost_link(&labelled, &connected, &faired).is_none()
                {
                    if self.worse_link(&labelled, &faired).is_none() {
                        fallback(
                            format!(
                                "the continuity setting was faired once keeping {h:?} instead of stage by stage"
                            ),
                            None,
                        );
                        return Ok((faired, once.stages));
                    }
                    once_result = Some((faired, once.stages));
                }
            }
        }
        let mut c = run.stages[0].clone();
        c.deviation = max_deviation(original, &connected, self.params.deviation_grid);
        c.energy = thin_plate_energy(&connected);
        let Some(worse) = self.worse_link(&labelled, &connected) else {
            return Ok((connected, vec![c]));
        };
        // continuity alone is worse somewhere too: of the candidates, the one whose links grow
        // the least against the input — a gap before an angle before a curvature
        // ([`growth_order`]); on a tie the fairer one. The start may no longer fit masters
        // that were faired before it.
        let mut candidates: Vec<(&str, BSplineSurface, Vec<StageReport>)> = Vec::new();
        if let Some((f, stages)) = once_result {
            candidates.push(("the continuity setting faired once", f, stages));
        }
        if run.deviation() <= self.tolerance {
            candidates.push(("the faired result", s, run.stages.clone()));
        }
        candidates.push(("the continuity setting", connected, vec![c]));
        candidates.push((
            "the surface as it was",
            self.start.clone(),
            vec![run.stages[0].clone()],
        ));
        let growth: Vec<[f64; 3]> = candidates
            .iter()
            .map(|(_, f, _)| self.worst_growth(&labelled, f))
            .collect();
        let mut pick = 0;
        for k in 1..candidates.len() {
            if growth_order(growth[k], growth[pick]).is_lt() {
                pick = k;
            }
        }
        let figures: Vec<String> = candidates
            .iter()
            .zip(&growth)
            .map(|((what, _, _), g)| format!("{what}: {}", growth_text(*g)))
            .collect();
        fallback(
            format!(
                "continuity alone: {worse}; kept {}, whose links grow the least against the input — {}",
                candidates[pick].0,
                figures.join("; ")
            ),
            Some(growth[pick].into_iter().fold(0.0, f64::max)),
        );
        let (_, kept, stages) = candidates.swap_remove(pick);
        Ok((kept, stages))
    }

    /// Where a missed G2 link is worst at an end of its side and the neighbouring side is G2
    /// too, whether the two masters disagree there: their normal curvatures in the slave's
    /// cross direction at the corner point differ by more than the G2 tolerance, so that no
    /// surface can be G2 to both at that point (two fillets of different radii meeting at a
    /// vertex blend's corner). Returns the phrase for the report.
    pub(super) fn vertex_conflict(
        &self,
        labelled: &[(usize, SideLink<'_>)],
        link: SideLink<'_>,
        slave: &BSplineSurface,
        m: &LinkMeasure,
    ) -> Option<String> {
        // the sample of the largest absolute difference (the relative figure peaks where both
        // curvatures are near the flatness cut-off)
        let (t, worst) = m
            .detail
            .iter()
            .filter_map(|x| Some((x.t, (x.kappa_slave? - x.kappa_master?).abs())))
            .max_by(|x, y| x.1.total_cmp(&y.1))?;
        let (a, b) = link.side.along_domain(slave);
        let near = 1e-9 * (b - a).abs();
        let (start, end) = link.side.neighbours();
        let neighbour = if (t - a).abs() <= near {
            start
        } else if (t - b).abs() <= near {
            end
        } else {
            return None;
        };
        let (k, other) = labelled
            .iter()
            .find(|(_, l)| l.side == neighbour && l.target >= Continuity::G2)?;
        let (u, v) = link.side.params(slave, t);
        let d = slave.derivatives(u, v);
        let dir = match link.side.cross_direction() {
            Direction::U => d.du,
            Direction::V => d.dv,
        };
        let params = nurbs_core::ProjectionParams::default();
        let curvature = |master: &BSplineSurface| {
            let f = nurbs_core::project_to_surface(master, &d.point, &params);
            let dm = master.derivatives(f.u, f.v);
            let n = dm.normal()?;
            let k = dm.normal_curvature(&dir)?;
            Some((k, n))
        };
        let ((k1, n1), (k2, n2)) = (curvature(link.master)?, curvature(other.master)?);
        let k2 = if n1.dot(&n2) < 0.0 { -k2 } else { k2 };
        let diff = (k1 - k2).abs();
        // the masters' disagreement is the reason when it accounts for at least half of the
        // slave's miss there and is above the flatness cut-off of the measure
        let flat = 1.0 / (g_continuity::measure::FLAT_RADIUS_FACTOR * slave.size());
        (diff >= 0.5 * worst && diff > flat).then(|| {
            format!(
                "; at its corner with {} ({}), the two masters differ in normal curvature across this side by {diff:.3e} (1/length unit, {k1:.3e} against {k2:.3e}): no surface is G2 to both at that point",
                neighbour.name(),
                self.model.link_label(*k)
            )
        })
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
    ) -> std::result::Result<Option<(BSplineSurface, usize, f64)>, String> {
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
            .map_err(|e| e.to_string())?;
        // a fairing stage ends fairer than it started, or is not used
        let after = thin_plate_energy(&out.surface);
        if after > before {
            return Err(format!(
                "it raised the thin-plate energy from {before:.4e} to {after:.4e}"
            ));
        }
        Ok(Some((out.surface, out.iterations, after)))
    }

    /// The largest [`growths`] factors of `result` over this surface's links against the input,
    /// per kind (gap, angle, curvature; ≤ 1: no link worse).
    pub(super) fn worst_growth(
        &self,
        labelled: &[(usize, SideLink<'_>)],
        result: &BSplineSurface,
    ) -> [f64; 3] {
        let t = &self.connect.tolerances;
        let mut worst = [0.0f64; 3];
        for (k, l) in labelled {
            let Some(before) = self.before.get(*k).and_then(Option::as_ref) else {
                continue;
            };
            let Ok(after) = l.measure(result, &self.connect.measure) else {
                return [f64::INFINITY; 3];
            };
            for (w, g) in worst.iter_mut().zip(growths(before, &after, l.target, t)) {
                *w = w.max(g);
            }
        }
        worst
    }

    /// The first link of this surface that `connected` meets and `faired` misses, described.
    pub(super) fn lost_link(
        &self,
        labelled: &[(usize, SideLink<'_>)],
        connected: &BSplineSurface,
        faired: &BSplineSurface,
    ) -> Option<String> {
        let t = &self.connect.tolerances;
        for (k, l) in labelled {
            let meets = |s: &BSplineSurface| {
                l.measure(s, &self.connect.measure)
                    .is_ok_and(|m| m.meets(l.target, t.g0, t.g1_deg, t.g2_rel))
            };
            if meets(connected) && !meets(faired) {
                return Some(format!(
                    "it would leave link {} unmet, which the continuity setting alone meets",
                    self.model.link_label(*k)
                ));
            }
        }
        None
    }

    /// The first link of this surface that `result` leaves worse than the input (a larger gap,
    /// angle or curvature difference, up to its target, beyond both the input's value and the
    /// tolerance), described; `None` when every link is at least as good.
    pub(super) fn worse_link(
        &self,
        labelled: &[(usize, SideLink<'_>)],
        result: &BSplineSurface,
    ) -> Option<String> {
        let t = &self.connect.tolerances;
        for (k, l) in labelled {
            let Some(before) = self.before.get(*k).and_then(Option::as_ref) else {
                continue;
            };
            let Ok(after) = l.measure(result, &self.connect.measure) else {
                return Some(format!(
                    "link {} could not be measured",
                    self.model.link_label(*k)
                ));
            };
            if let Some(what) = worse_than(before, &after, l.target, t) {
                return Some(format!(
                    "it would leave link {} {what}",
                    self.model.link_label(*k)
                ));
            }
        }
        None
    }
}
