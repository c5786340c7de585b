//! One surface's run (\[SV\] §3.2): the per-surface state and what the run reports — the result
//! of its stages, its energy, creases and the problems it met — and what a surface knows of its
//! place in the model: its set-step settings, the sides its slaves hang on, its links.

use std::time::Instant;

use g_continuity::{ConnectParams, SideLink};
use nurbs_core::energy::{max_deviation, thin_plate_energy};
use nurbs_core::{BSplineSurface, Continuity, Side};

use super::{
    GROUP_CHAIN_SHARE, Job, Outcome, Problem, ProblemKind, Run, Stage, StageReport, SurfaceFair,
    net_bound, report,
};
use crate::check::TOUCH_FACTOR;
use crate::topology::{JOIN_SAMPLES, lies_on_side};

/// A result that lies within this fraction of the surface's size of its input everywhere is
/// the input (knot insertion is exact up to round-off, about 1e-15 of the size; a fairing move
/// the reports show starts at 1e-9).
pub const UNCHANGED_RELATIVE: f64 = 1e-12;

impl Run<'_> {
    pub(super) fn record(&mut self, stage: Stage, before: &BSplineSurface, after: &BSplineSurface) {
        self.record_known(stage, before, after, None);
    }
    /// [`Run::record`] with the energy of `after` when the caller has it already.
    pub(super) fn record_known(
        &mut self,
        stage: Stage,
        before: &BSplineSurface,
        after: &BSplineSurface,
        energy: Option<f64>,
    ) {
        let max_move = if before.control_points().len() == after.control_points().len() {
            nurbs_core::max_displacement(before.control_points(), after.control_points())
        } else {
            f64::NAN
        };
        let now = std::time::Instant::now();
        let seconds = now.duration_since(self.last).as_secs_f64();
        self.last = now;
        self.stages.push(StageReport {
            stage,
            seconds,
            max_move,
            deviation: max_deviation(self.original, after, self.grid),
            energy: energy.unwrap_or_else(|| thin_plate_energy(after)),
            iterations: 0,
            knots_inserted: 0,
            epsilon: 0.0,
            section_ramp: None,
        });
    }
    pub(super) fn deviation(&self) -> f64 {
        self.stages.last().map_or(0.0, |s| s.deviation)
    }
}

impl Job<'_> {
    /// Runs this surface's stages and reports them: the result (the input where the stages
    /// failed, named in the problems), its energy, creases and the problems it leaves.
    pub(super) fn run(&self) -> Outcome {
        let t0 = Instant::now();
        let entry = &self.model.surfaces[self.surface];
        let original = &entry.surface;
        let mut problems = Vec::new();
        let mut missed = Vec::new();
        let (surface, stages, processed) = match self.stages(original, &mut problems, &mut missed) {
            Ok((s, stages)) => (s, stages, true),
            Err(e) => {
                problems.push(Problem {
                    kind: ProblemKind::Failed,
                    surface: entry.name.clone(),
                    link: None,
                    message: e.to_string(),
                    amount: None,
                });
                (original.clone(), Vec::new(), false)
            }
        };
        let energy_before = thin_plate_energy(original);
        let (surface, stages) = if processed {
            self.unchanged_is_input(original, surface, stages, energy_before)
        } else {
            (surface, stages)
        };
        self.still_missed(&surface, missed, &mut problems);
        let energy_after = thin_plate_energy(&surface);
        if energy_after > energy_before {
            // fairing stages never raise it (`fair_stage`): the rise is what the joins cost
            problems.push(Problem {
                kind: ProblemKind::Limited,
                surface: entry.name.clone(),
                link: None,
                message: format!(
                    "its thin-plate energy rose from {energy_before:.4e} to {energy_after:.4e}: {}",
                    report::ENERGY_RISE_WHY
                ),
                amount: Some(energy_after / energy_before),
            });
        }
        let crease_deg = self.creases(original, &surface, &mut problems);
        let (fairness, joint_curvature) = self.fairness(original, &surface);
        let report = SurfaceFair {
            crease_deg,
            fairness,
            joint_curvature,
            surface: self.surface,
            name: entry.name.clone(),
            role: entry.role,
            method: self.fairing.name().to_string(),
            energy_before,
            energy_after,
            tolerance: self.tolerance,
            degree: (surface.degree_u(), surface.degree_v()),
            net: (
                (original.num_u(), original.num_v()),
                (surface.num_u(), surface.num_v()),
            ),
            max_deviation: if processed {
                max_deviation(original, &surface, self.params.deviation_grid)
            } else {
                0.0
            },
            iterations: stages.iter().map(|s| s.iterations).sum(),
            knots_inserted: stages.iter().map(|s| s.knots_inserted).sum(),
            seconds: t0.elapsed().as_secs_f64(),
            stages,
            processed,
        };
        Outcome {
            surface,
            report,
            problems,
        }
    }

    /// The fairness figures of `original` and `result` in this surface's place, and the
    /// masters' curvature across its G2 joins ([`crate::fairness`]).
    fn fairness(
        &self,
        original: &BSplineSurface,
        result: &BSplineSurface,
    ) -> ((nurbs_core::Fairness, nurbs_core::Fairness), f64) {
        let figures = (
            crate::fairness::surface_fairness(self.model, self.surface, original),
            crate::fairness::surface_fairness(self.model, self.surface, result),
        );
        (figures, self.joint_curvature(result))
    }

    /// The masters' largest curvature across this surface's G2 joins, with `result` in its
    /// place ([`crate::fairness::joint_curvature`], each link over its part of the side).
    pub(super) fn joint_curvature(&self, result: &BSplineSurface) -> f64 {
        crate::fairness::joint_curvature(
            self.current,
            self.surface,
            result,
            self.ranges,
            &self.connect.measure,
        )
    }

    /// A result of the input's shape (knots inserted, nothing moved) is the input itself: the
    /// inserted knots add nothing, and the energy integrated on the finer spans differs from the
    /// input's by the quadrature error of a rational surface (up to 4e-7 relative), which would
    /// read as a rise.
    fn unchanged_is_input(
        &self,
        original: &BSplineSurface,
        surface: BSplineSurface,
        stages: Vec<StageReport>,
        energy_before: f64,
    ) -> (BSplineSurface, Vec<StageReport>) {
        if max_deviation(original, &surface, self.params.deviation_grid)
            > UNCHANGED_RELATIVE * original.size()
        {
            return (surface, stages);
        }
        let stages = stages
            .into_iter()
            .map(|mut st| {
                st.knots_inserted = 0;
                st.energy = energy_before;
                st.deviation = 0.0;
                st
            })
            .collect();
        (original.clone(), stages)
    }

    /// The dry run's misses, reported for the links `surface` still misses; a missed G2 link
    /// whose corner joins masters that disagree there is named with their difference at the
    /// corner of `surface`, the result (the figure depends on the slave's cross direction at
    /// the corner, which the stages after the dry run may turn a little).
    fn still_missed(
        &self,
        surface: &BSplineSurface,
        missed: Vec<(usize, Problem)>,
        problems: &mut Vec<Problem>,
    ) {
        let t = &self.connect.tolerances;
        let labelled = self.links();
        for (k, mut p) in missed {
            let Some((_, link)) = labelled.iter().find(|(j, _)| *j == k) else {
                continue;
            };
            let Ok(m) = link.measure(surface, &self.connect.measure) else {
                continue;
            };
            if m.meets(link.target, t.g0, t.g1_deg, t.g2_rel) {
                continue;
            }
            if link.target == Continuity::G2 {
                p.message += &self
                    .vertex_conflict(&labelled, *link, surface, &m)
                    .unwrap_or_default();
            }
            problems.push(p);
        }
    }

    /// The largest crease of the input and of `surface`. The surface's own joins — C⁰ knot
    /// lines (rational arcs joined by double knots) — stay as smooth as they came
    /// ([`smooth_join_points`]); a result whose joins turn more than the input's and the G1
    /// tolerance is a defect the report names.
    fn creases(
        &self,
        original: &BSplineSurface,
        surface: &BSplineSurface,
        problems: &mut Vec<Problem>,
    ) -> (f64, f64) {
        let t = &self.connect.tolerances;
        let crease_deg = (
            nurbs_core::creases::largest_crease_deg(original),
            nurbs_core::creases::largest_crease_deg(surface),
        );
        if crease_deg.1 > crease_deg.0.max(t.g1_deg) {
            problems.push(Problem {
                kind: ProblemKind::Limited,
                surface: self.model.surfaces[self.surface].name.clone(),
                link: None,
                message: format!(
                    "a C0 knot line inside it turns the normal by {:.3e}° (input {:.3e}°, G1 tolerance {:.3e}°)",
                    crease_deg.1, crease_deg.0, t.g1_deg
                ),
                amount: Some(crease_deg.1),
            });
        }
        crease_deg
    }

    /// The continuity settings of this surface's set steps: a patch of a corner group aims at
    /// [`GROUP_CHAIN_SHARE`] × the G1/G2 tolerances.
    pub(super) fn set_params(&self) -> ConnectParams {
        let in_group = self
            .model
            .corners
            .iter()
            .any(|g| g.patches.contains(&self.surface));
        let mut tolerances = self.connect.tolerances;
        if in_group {
            tolerances.g1_deg *= GROUP_CHAIN_SHARE;
            tolerances.g2_rel *= GROUP_CHAIN_SHARE;
        }
        // the sides it shares with a surface no link covers keep their frame in the set steps
        // too ([`crate::edges`]); a free seam instead has the linked boundaries that end on it
        // turned into their masters' tangent planes there (`SetParams::seam_end_tangents`)
        let mut set = self.connect.set;
        // (a seam linked for a rerun, [`super::seams`], is a link, not an edge)
        let linked = |e: &crate::edges::SharedEdge| {
            self.model
                .links
                .iter()
                .any(|l| l.slave == self.surface && l.side == e.side && l.master == e.other)
        };
        for e in self
            .edges
            .iter()
            .filter(|e| e.surface == self.surface && !linked(e))
        {
            let k = e.side.index();
            if self.free_seams && crate::edges::is_seam(self.model, e) {
                set.seam_end_tangents[k] = true;
                continue;
            }
            set.kept_sides[k] = true;
        }
        set.contact_lines = self.contact_lines();
        let me = &self.model.surfaces[self.surface].surface;
        ConnectParams {
            tolerances,
            set,
            max_control_points: net_bound(self.connect.max_control_points, me),
            ..*self.connect
        }
    }

    pub(super) fn is_master(&self) -> bool {
        self.model.links.iter().any(|l| l.master == self.surface)
    }

    /// Sides of this surface along which a slave is linked G1 or higher (its linked side lies
    /// on this side's boundary curve, see [`lies_on_side`]); their tangential frame is kept in
    /// every fairing stage of this surface ([`MASTER_FRAME`]).
    pub(super) fn master_sides(&self) -> Vec<Side> {
        let me = self.start;
        let tol = TOUCH_FACTOR * self.connect.tolerances.g0;
        let mut sides = Vec::new();
        for l in self.model.links.iter().filter(|l| l.master == self.surface) {
            if (self.cap)(l.continuity) < Continuity::G1 {
                continue;
            }
            let slave = &self.current.surfaces[l.slave].surface;
            for side in Side::ALL {
                if !sides.contains(&side) && lies_on_side(slave, l.side, me, side, tol) {
                    sides.push(side);
                }
            }
        }
        sides
    }

    /// Control points of `me` (this surface as the stages have it) that carry the join of a
    /// slave whose linked side lies *inside* this surface rather than on one of its boundary
    /// sides (a trimmed master, model-format.md): every control point whose basis function is
    /// non-zero at a foot point of the slave side. Fixing them keeps the master exactly as it
    /// was on every knot span the join crosses — position, tangent plane and curvature — so the
    /// slave, set against the input, stays continuous whatever the fairing does elsewhere.
    pub(super) fn interior_join_points(&self, me: &BSplineSurface) -> Vec<(usize, usize)> {
        let tol = TOUCH_FACTOR * self.connect.tolerances.g0;
        let mut out: Vec<(usize, usize)> = Vec::new();
        let (p, q) = (me.degree_u(), me.degree_v());
        for (k, l) in self.model.links.iter().enumerate() {
            if l.master != self.surface {
                continue;
            }
            let slave = &self.current.surfaces[l.slave].surface;
            if Side::ALL
                .iter()
                .any(|&side| lies_on_side(slave, l.side, me, side, tol))
            {
                continue;
            }
            // (a link over part of the side, [`crate::edges`], holds there only)
            let (a, b) = self.ranges[k].unwrap_or_else(|| l.side.along_domain(slave));
            let mut projector =
                nurbs_core::SurfaceProjector::new(me, nurbs_core::ProjectionParams::default());
            for k in 0..=JOIN_SAMPLES {
                let t = a + (b - a) * k as f64 / JOIN_SAMPLES as f64;
                let (u, v) = l.side.params(slave, t);
                let foot = projector.project(&slave.point(u, v));
                let (su, sv) = (me.knots_u().span(foot.u), me.knots_v().span(foot.v));
                for i in su - p..=su {
                    for j in sv - q..=sv {
                        if !out.contains(&(i, j)) {
                            out.push((i, j));
                        }
                    }
                }
            }
        }
        out
    }

    pub(super) fn links(&self) -> Vec<(usize, SideLink<'_>)> {
        let ks = self.model.links_of_slave(self.surface);
        let links: Vec<SideLink<'_>> = ks
            .iter()
            .map(|&k| {
                let l = &self.model.links[k];
                SideLink {
                    side: l.side,
                    master: &self.current.surfaces[l.master].surface,
                    target: (self.cap)(l.continuity),
                    range: self.ranges.get(k).copied().flatten(),
                    g2_zones: [0.0; 2],
                }
            })
            .collect();
        let links = crate::zones::with_vertex_zones(links, self.start, &self.connect.tolerances);
        ks.into_iter().zip(links).collect()
    }
}
