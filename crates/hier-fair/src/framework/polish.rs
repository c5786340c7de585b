//! The joint polish of a surface's frames ([`g_continuity::joint`]): where the stages' result
//! misses a G2 link, every link's conditions are solved at once over the rows the links own,
//! and the result is kept only where it is better. (Polishing the dry run's G2 step and the
//! stages' G2 set step as well met one more link of the six kernel models, at 2–4 s more on
//! the lofted block and the variable-radius box: docs/benchmarks.md.)

use super::*;

impl Job<'_> {
    /// `surface` polished by [`g_continuity::polish_joint`] with the settings `params`, where it
    /// misses a G2 link of `links`: `Some` only when the polish meets more links (by the
    /// tolerances of `params`), every link met before stays met, no link's gap or angle grows
    /// beyond its tolerance, and the result deviates from the input at most `budget`.
    pub(super) fn polished(
        &self,
        surface: &BSplineSurface,
        links: &[SideLink<'_>],
        params: &ConnectParams,
        budget: f64,
    ) -> Option<BSplineSurface> {
        if !links.iter().any(|l| l.target >= Continuity::G2) {
            return None;
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
        let before = measure(surface)?;
        if met(&before) == links.len() {
            return None;
        }
        // no move bound: the result's own deviation is checked below. (A bound on the control
        // moves — the budget less the deviation so far, or the whole budget — rejects the
        // steps whose path takes a point beyond it, though the surface, whose moves are
        // averages of the points', may stay within: on a three-radii corner's blend that cost
        // G2 on two sides whose unbounded polish deviates within the budget.)
        let original = &self.model.surfaces[self.surface].surface;
        let grid = self.params.deviation_grid;
        let (polished, _) =
            g_continuity::polish_joint(surface, links, params, f64::INFINITY).ok()?;
        let after = measure(&polished)?;
        let kept = links
            .iter()
            .zip(before.iter().zip(&after))
            .all(|(l, (b, a))| {
                let angle = |m: &LinkMeasure| m.g1_deg.unwrap_or(0.0);
                (!meets(l, b) || meets(l, a))
                    && a.g0 <= b.g0.max(t.g0)
                    && angle(a) <= angle(b).max(t.g1_deg)
            });
        (met(&after) > met(&before) && kept && max_deviation(original, &polished, grid) <= budget)
            .then_some(polished)
    }

    /// The stages' result `surface`, polished where [`Self::polished`] keeps it (the links
    /// judged by the model's tolerances, the deviation within what the fairing stages plan
    /// with, [`DeviationBudget::fairing`]: a master's half, so its slaves keep theirs).
    /// Never worse than the input either ([`Job::worse_link`], which judges every figure of
    /// each link against the input's, not only against the stages' result).
    pub(super) fn joint_polish(&self, surface: BSplineSurface) -> BSplineSurface {
        let labelled = self.links();
        let links: Vec<SideLink> = labelled.iter().map(|(_, l)| *l).collect();
        let params = ConnectParams {
            tolerances: self.connect.tolerances,
            ..self.set_params()
        };
        let budget = self.params.budget.fairing(self.tolerance, self.is_master());
        match self.polished(&surface, &links, &params, budget) {
            Some(p) if self.worse_link(&labelled, &p).is_none() => p,
            _ => surface,
        }
    }
}
