//! The joint polish of a surface's frames ([`g_continuity::joint`]): where the stages' result
//! misses a G2 link, every link's conditions are solved at once over the rows the links own,
//! and the result is kept only where it is better; where links are still missed, the
//! continuity setting is polished instead and then faired keeping G2
//! ([`Job::polished_stages`]). (Polishing the dry run's G2 step in every lead-in trial and the
//! stages' G2 set step as well met one more link of the six kernel models, at 2–4 s more on
//! the lofted block and the variable-radius box: docs/benchmarks.md.)

use g_continuity::{ConnectParams, LinkMeasure, SideLink};
use nurbs_core::energy::max_deviation;
use nurbs_core::{BSplineSurface, Continuity};

use super::stages::StagePlan;
use super::{Job, Problem, StageReport};
use crate::fairness::PEAK_FACTOR;

/// How the problem that names a polish refused for a curvature spike begins
/// ([`Job::joint_polish`]).
pub(super) const SPIKE_REFUSAL: &str = "the joint polish would meet";

/// Whether `p` names a polish refused for a curvature spike on its surface.
pub(super) fn is_spike_refusal(p: &Problem) -> bool {
    p.kind == super::ProblemKind::Limited && p.message.starts_with(SPIKE_REFUSAL)
}

impl Job<'_> {
    /// `surface` polished by [`g_continuity::polish_joint`] with the settings `params`, where it
    /// misses a G2 link of `links`: [`Polished::Kept`] only when the polish meets more links (by
    /// the tolerances of `params`), every link met before stays met, no link's gap or angle
    /// grows beyond its tolerance, the result deviates from the input at most `budget`, and its
    /// curvature spikes no higher than [`PEAK_FACTOR`] × the input's or the surface's own
    /// ([`crate::fairness::FairnessVerdict::spike`], within the relative G2 tolerance);
    /// [`Polished::Spiked`] where only that last condition fails.
    pub(super) fn polished(
        &self,
        surface: &BSplineSurface,
        links: &[SideLink<'_>],
        params: &ConnectParams,
        budget: f64,
    ) -> Polished {
        if !links.iter().any(|l| l.target >= Continuity::G2) {
            return Polished::Not;
        }
        let t = params.tolerances;
        let measure = |s: &BSplineSurface| -> Option<Vec<LinkMeasure>> {
            links
                .iter()
                .map(|l| l.measure(s, &params.measure).ok())
                .collect()
        };
        let meets = |l: &SideLink, m: &LinkMeasure| m.meets(l.target, t.g0, t.g1_deg, t.g2_rel);
        let met = |ms: &[LinkMeasure]| links.iter().zip(ms).filter(|(l, m)| meets(l, m)).count();
        let Some(before) = measure(surface) else {
            return Polished::Not;
        };
        if met(&before) == links.len() {
            return Polished::Not;
        }
        // no move bound: the result's own deviation is checked below. (A bound on the control
        // moves — the budget less the deviation so far, or the whole budget — rejects the
        // steps whose path takes a point beyond it, though the surface, whose moves are
        // averages of the points', may stay within: on a three-radii corner's blend that cost
        // G2 on two sides whose unbounded polish deviates within the budget.)
        let original = &self.model.surfaces[self.surface].surface;
        let grid = self.params.deviation_grid;
        let Ok((polished, _)) = g_continuity::polish_joint(surface, links, params, f64::INFINITY)
        else {
            return Polished::Not;
        };
        let Some(after) = measure(&polished) else {
            return Polished::Not;
        };
        let kept = links
            .iter()
            .zip(before.iter().zip(&after))
            .all(|(l, (b, a))| {
                let angle = |m: &LinkMeasure| m.g1_deg.unwrap_or(0.0);
                (!meets(l, b) || meets(l, a))
                    && a.g0 <= b.g0.max(t.g0)
                    && angle(a) <= angle(b).max(t.g1_deg)
            });
        if met(&after) <= met(&before) || !kept || max_deviation(original, &polished, grid) > budget
        {
            return Polished::Not;
        }
        // G2 is not bought with a curvature spike (\[SV\] §1.2: the constraints "may crease the
        // surface near the sides"): a polish that raises the peak beyond PEAK_FACTOR and beyond
        // what the surface had (by more than the relative G2 tolerance, the model's "same
        // curvature") is no candidate — on a three-radii corner by default it met four links
        // with a crease of 76 /mm beside a side against the input's 0.16
        let (now, then) = (
            self.verdict_of(surface).spike(),
            self.verdict_of(&polished).spike(),
        );
        if then > PEAK_FACTOR && then > now * (1.0 + t.g2_rel) {
            return Polished::Spiked {
                met: met(&after) - met(&before),
                spike: then,
            };
        }
        Polished::Kept(polished)
    }

    /// The stages' result `surface`, polished where [`Self::polished`] keeps it (the links
    /// judged by the model's tolerances, the deviation within what the fairing stages plan
    /// with, [`DeviationBudget::fairing`]: a master's half, so its slaves keep theirs).
    /// Never worse than the input either ([`Job::worse_link`], which judges every figure of
    /// each link against the input's, not only against the stages' result).
    pub(super) fn joint_polish(
        &self,
        surface: BSplineSurface,
        problems: &mut Vec<Problem>,
    ) -> BSplineSurface {
        let labelled = self.links();
        let links: Vec<SideLink> = labelled.iter().map(|(_, l)| *l).collect();
        let params = ConnectParams {
            tolerances: self.connect.tolerances,
            ..self.set_params()
        };
        let budget = self.params.budget.fairing(self.tolerance, self.is_master());
        match self.polished(&surface, &links, &params, budget) {
            Polished::Kept(p) if self.worse_link(&labelled, &p).is_none() => p,
            Polished::Spiked { met, spike } => {
                let note = format!(
                    "{SPIKE_REFUSAL} {met} more link(s) only with a curvature spike of {spike:.2}× its input's (at most {PEAK_FACTOR}): not taken, the links stay as the stages left them"
                );
                if !problems.iter().any(|p| {
                    p.message == note && p.surface == self.model.surfaces[self.surface].name
                }) {
                    self.limited(problems, note, Some(spike));
                }
                surface
            }
            _ => surface,
        }
    }

    /// The links of this surface that `surface` meets by the model's tolerances.
    pub(super) fn met_links(&self, links: &[SideLink<'_>], surface: &BSplineSurface) -> usize {
        let t = &self.connect.tolerances;
        links
            .iter()
            .filter(|l| {
                l.measure(surface, &self.connect.measure)
                    .is_ok_and(|m| m.meets(l.target, t.g0, t.g1_deg, t.g2_rel))
            })
            .count()
    }

    /// The stages' result `s` polished ([`Self::joint_polish`]); where it still misses a link
    /// and the plan reached G2, also the other order: the continuity setting polished first,
    /// then faired once keeping G2 ([`Job::faired_once`]; its rows at every G2 side are fixed, so
    /// the fairing keeps what the polish met). The stages' fairing moves the frames the polish
    /// starts from by up to the fairing budget, which on a vertex blend with a degenerate
    /// corner can leave a state the polish does not bring back, while the setting's frames,
    /// the ones the dry run measured, are within reach. The other order is taken only when it
    /// meets more links, is no worse than the input and stays within the tolerance.
    pub(super) fn polished_stages(
        &self,
        plan: &StagePlan<'_>,
        original: &BSplineSurface,
        s: BSplineSurface,
        stages: Vec<StageReport>,
        problems: &mut Vec<Problem>,
    ) -> (BSplineSurface, Vec<StageReport>) {
        // the polish sees only the rows the links own (with the knots and the boundary's feet):
        // a result that kept the setting's rows (the setting faired once keeping G2) would be
        // polished the same way again. The two differ inside only, where the polish's deviation
        // check could still judge them apart; it did on none of the 18 kernel models measured.
        let same_frames = same_frames(&s, &plan.connected, plan.links);
        let s = self.joint_polish(s, problems);
        let met = self.met_links(plan.links, &s);
        if plan.highest != Some(Continuity::G2) || met == plan.links.len() || same_frames {
            return (s, stages);
        }
        let polished = self.joint_polish(plan.connected.clone(), problems);
        if self.met_links(plan.links, &polished) <= met {
            return (s, stages);
        }
        let other = StagePlan {
            connected: polished,
            master_sides: plan.master_sides.clone(),
            prepared: plan.prepared.clone(),
            ..*plan
        };
        let Some(prepare) = stages.first() else {
            return (s, stages);
        };
        let Some((faired, once)) = self.faired_once(&other, original, prepare) else {
            return (s, stages);
        };
        if self.met_links(plan.links, &faired) <= met
            || self.worse_link(plan.labelled, &faired).is_some()
        {
            return (s, stages);
        }
        self.limited(
            problems,
            "the continuity setting was polished and then faired once keeping G2: the stages' result missed links the polish could not bring back".to_string(),
            None,
        );
        (faired, once)
    }
}

/// What [`Job::polished`] made of a surface.
pub(super) enum Polished {
    /// no polish, or one that is not better (or deviates too much)
    Not,
    /// a polish that meets more links within every bound
    Kept(BSplineSurface),
    /// a polish that would meet `met` more links with its curvature spiking `spike` × the
    /// input's ([`crate::fairness::FairnessVerdict::spike`])
    Spiked { met: usize, spike: f64 },
}

/// Whether `a` and `b` have the same knots and weights and the same control points in rows
/// 0..=r of every side of `links` (r: the row of the link's target, [`g_continuity::rows::row_of`]).
fn same_frames(a: &BSplineSurface, b: &BSplineSurface, links: &[SideLink<'_>]) -> bool {
    let (nu, nv) = (a.num_u(), a.num_v());
    a.knots_u() == b.knots_u()
        && a.knots_v() == b.knots_v()
        && a.weights() == b.weights()
        && links.iter().all(|l| {
            (0..=g_continuity::rows::row_of(l.target)).all(|k| {
                l.side
                    .row(k, nu, nv)
                    .into_iter()
                    .all(|(i, j)| a.control_points()[i * nv + j] == b.control_points()[i * nv + j])
            })
        })
}

#[cfg(test)]
mod tests {
    use g_continuity::SideLink;
    use nurbs_core::shapes::plane_patch;
    use nurbs_core::{BSplineSurface, Continuity, Point3, Side, Vector3};

    use super::same_frames;

    /// A 6 × 6 bicubic patch of the unit square (knots inserted into the bilinear plane).
    fn patch() -> BSplineSurface {
        let p = plane_patch(
            Point3::origin(),
            Vector3::x(),
            Vector3::y(),
            (0.0, 1.0),
            (0.0, 1.0),
        )
        .unwrap();
        let p = p.elevate_degree(nurbs_core::Direction::U, 2).unwrap();
        let p = p.elevate_degree(nurbs_core::Direction::V, 2).unwrap();
        let p = p.refine(nurbs_core::Direction::U, &[0.3, 0.6]).unwrap();
        p.refine(nurbs_core::Direction::V, &[0.3, 0.6]).unwrap()
    }

    /// Frames are the rows 0..=r a link owns: a move there tells two surfaces apart, a move
    /// inside does not, nor does a row beyond the link's target.
    #[test]
    fn same_frames_compares_the_rows_the_links_own() {
        let a = patch();
        let (nu, nv) = (a.num_u(), a.num_v());
        assert_eq!((nu, nv), (6, 6));
        let master = patch();
        let links = [
            SideLink {
                side: Side::U0,
                master: &master,
                target: Continuity::G2,
                range: None,
                g2_zones: [0.0; 2],
            },
            SideLink {
                side: Side::V1,
                master: &master,
                target: Continuity::G1,
                range: None,
                g2_zones: [0.0; 2],
            },
        ];
        let moved = |i: usize, j: usize| {
            let mut b = a.clone();
            b.control_points_mut()[i * nv + j].z += 1e-9;
            same_frames(&a, &b, &links)
        };
        assert!(same_frames(&a, &a.clone(), &links));
        // U0, G2: rows i = 0, 1, 2
        assert!(!moved(2, 3));
        assert!(moved(3, 2));
        // V1, G1: columns j = 5, 4 only
        assert!(!moved(3, 4));
        assert!(moved(4, 3));
        // other knots are other frames
        let refined = a.refine(nurbs_core::Direction::U, &[0.8]).unwrap();
        assert!(!same_frames(&a, &refined, &links));
    }
}
