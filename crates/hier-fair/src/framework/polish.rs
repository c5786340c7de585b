//! The joint polish of a surface's frames after its stages ([`g_continuity::joint`]): where
//! the staged steps leave a G2 link missed, every link's conditions are solved at once over
//! the rows the links own, and the result is kept only where it is better.

use super::*;

impl Job<'_> {
    /// `surface` (the stages' result) polished by [`g_continuity::polish_joint`] where it
    /// misses a G2 link. Kept only when it meets more links, every link it met stays met, no
    /// link's gap or angle grows beyond its tolerance, and it stays within the deviation the
    /// fairing stages plan with ([`DeviationBudget::fairing`]: a master's half, so its slaves
    /// keep theirs); otherwise `surface` unchanged.
    pub(super) fn joint_polish(
        &self,
        original: &BSplineSurface,
        surface: BSplineSurface,
    ) -> BSplineSurface {
        let links: Vec<SideLink> = self.links().into_iter().map(|(_, l)| l).collect();
        if !links.iter().any(|l| l.target >= Continuity::G2) {
            return surface;
        }
        let t = self.connect.tolerances;
        let measure = |s: &BSplineSurface| -> Option<Vec<LinkMeasure>> {
            links
                .iter()
                .map(|l| l.measure(s, &self.connect.measure).ok())
                .collect()
        };
        let meets = |l: &SideLink, m: &LinkMeasure| m.meets(l.target, t.g0, t.g1_deg, t.g2_rel);
        let met = |ms: &[LinkMeasure]| links.iter().zip(ms).filter(|(l, m)| meets(l, m)).count();
        let Some(before) = measure(&surface) else {
            return surface;
        };
        if met(&before) == links.len() {
            return surface;
        }
        let Ok((polished, _)) = g_continuity::polish_joint(&surface, &links, &self.set_params())
        else {
            return surface;
        };
        let Some(after) = measure(&polished) else {
            return surface;
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
        let budget = self.params.budget.fairing(self.tolerance, self.is_master());
        if met(&after) > met(&before)
            && kept
            && max_deviation(original, &polished, self.params.deviation_grid) <= budget
        {
            polished
        } else {
            surface
        }
    }
}
