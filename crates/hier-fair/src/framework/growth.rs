//! How much worse a link leaves than it came: growth factors of gap, angle and curvature
//! against the input ([`LinkGrowth`]: their order and report phrase), and the links a result
//! leaves worse or loses.

use g_continuity::{LinkMeasure, SideLink, Tolerances};
use nurbs_core::{BSplineSurface, Continuity};

use super::Job;
use super::report::{Problem, StageReport};

/// How much worse a link leaves than it came: the factors by which its gap, normal angle and
/// relative curvature difference exceed their input values (each against the larger of its
/// input value and its tolerance; 0 above the link's target), or the worst of several links
/// kind by kind ([`LinkGrowth::max`]). A factor up to 1 means "no worse".
///
/// Ordered by severity (`Ord`): the growth that leaves a gap grow less is the lesser, then the
/// angle, then the curvature — a join that opens is a defect, one that loses tangency is
/// visible in every reflection, a curvature step only in a zebra or curvature plot. A factor
/// up to 1 counts as 1 there, so two growths that are both no worse in a kind are equal in it
/// (equality is the same severity, not the same figures).
#[derive(Debug, Clone, Copy, Default)]
pub struct LinkGrowth {
    /// gap after / max(gap before, G0 tolerance)
    pub gap: f64,
    /// normal angle after / max(angle before, G1 tolerance)
    pub angle: f64,
    /// relative curvature difference after / max(before, G2 tolerance), where the absolute
    /// difference grew too (see [`LinkGrowth::of`])
    pub curvature: f64,
}

impl LinkGrowth {
    /// The growth of a link that could not be measured after: opened in every kind.
    pub const OPENED: Self = Self {
        gap: f64::INFINITY,
        angle: f64::INFINITY,
        curvature: f64::INFINITY,
    };

    /// The growth from `before` to `after` up to `target`. A relative curvature figure counts
    /// only where the absolute difference grew too: a relative figure that grows while the
    /// absolute difference shrinks means that both curvatures went down — a lead-in
    /// flattening a vertex blend next to a fillet that is straight across the join (a sphere
    /// corner: 1.000 → 1.002 while |Δκ| went 0.2 → 2e-4): the join got better, not worse.
    pub fn of(
        before: &LinkMeasure,
        after: &LinkMeasure,
        target: Continuity,
        t: &Tolerances,
    ) -> Self {
        let mut out = raw_growths(before, after, target, t);
        // an increase below a thousandth of its tolerance is none ([`NEGLIGIBLE_GROWTH`])
        let rises = [
            (after.g0 - before.g0, t.g0),
            (
                after.g1_deg.unwrap_or(0.0) - before.g1_deg.unwrap_or(0.0),
                t.g1_deg,
            ),
            (
                after.g2_rel.unwrap_or(0.0) - before.g2_rel.unwrap_or(0.0),
                t.g2_rel,
            ),
        ];
        for (g, (rise, tol)) in out.iter_mut().zip(rises) {
            if *g > 1.0 && rise <= NEGLIGIBLE_GROWTH * tol {
                *g = 1.0;
            }
        }
        Self::from(out)
    }

    /// The worse of `self` and `other` in each kind.
    #[must_use]
    pub fn max(self, other: Self) -> Self {
        Self {
            gap: self.gap.max(other.gap),
            angle: self.angle.max(other.angle),
            curvature: self.curvature.max(other.curvature),
        }
    }

    /// Whether no kind grew (every factor up to 1).
    pub fn no_worse(&self) -> bool {
        self.factors().iter().all(|&x| x <= 1.0)
    }

    /// Whether the gap and the angle did not grow (the curvature may have). The never-worse
    /// rule's alternatives are tried for gaps and angles; a curvature difference that grows (a
    /// vertex blend between masters that disagree) is reported, and does not make every
    /// variant run.
    pub fn joins_kept(&self) -> bool {
        self.gap <= 1.0 && self.angle <= 1.0
    }

    /// The largest factor of the three.
    pub fn largest(&self) -> f64 {
        self.factors().into_iter().fold(0.0, f64::max)
    }

    /// `[gap, angle, curvature]`.
    fn factors(&self) -> [f64; 3] {
        [self.gap, self.angle, self.curvature]
    }
}

impl From<[f64; 3]> for LinkGrowth {
    fn from([gap, angle, curvature]: [f64; 3]) -> Self {
        Self {
            gap,
            angle,
            curvature,
        }
    }
}

impl Ord for LinkGrowth {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.factors()
            .iter()
            .zip(&other.factors())
            .map(|(x, y)| x.max(1.0).total_cmp(&y.max(1.0)))
            .find(|o| o.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    }
}

impl PartialOrd for LinkGrowth {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for LinkGrowth {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other).is_eq()
    }
}

impl Eq for LinkGrowth {}

impl std::fmt::Display for LinkGrowth {
    /// As a report phrase: "gap 1.000 ×, angle 2.500 ×, curvature 1.000 ×".
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "gap {:.3} ×, angle {:.3} ×, curvature {:.3} ×",
            self.gap, self.angle, self.curvature
        )
    }
}

/// A gap, angle or relative curvature difference that grows by less than this share of its
/// tolerance has not grown: the tolerance is the resolution at which a join is judged, and a
/// thousandth of it is below what any checker reports (a G0 tolerance of 1e-3 mm: 1e-6 mm).
/// A slave kept as it was beside a master faired inside its kept frame sees its gap of
/// 0.012 mm grow by 2e-9 mm; counted, that rise outranked an angle grown 6.6 %.
pub const NEGLIGIBLE_GROWTH: f64 = 1e-3;

/// [`LinkGrowth::of`] before rounding.
fn raw_growths(
    before: &LinkMeasure,
    after: &LinkMeasure,
    target: Continuity,
    t: &Tolerances,
) -> [f64; 3] {
    let mut out = [after.g0 / before.g0.max(t.g0), 0.0, 0.0];
    if target >= Continuity::G1 {
        out[1] = after.g1_deg.unwrap_or(0.0) / before.g1_deg.unwrap_or(0.0).max(t.g1_deg);
    }
    let (abs_before, abs_after) = (before.g2_abs.unwrap_or(0.0), after.g2_abs.unwrap_or(0.0));
    let rel_after = after.g2_rel.unwrap_or(0.0);
    if target >= Continuity::G2 && abs_after > abs_before * (1.0 + t.g2_rel) && rel_after > t.g2_rel
    {
        // the relative figure is bounded by 2 (|κ_s − κ_m| ≤ 2 max |κ|), so a join that stays
        // missed shows its growth in the absolute difference: 0.19 → 41 /mm is a crease, though
        // the relative figure only goes 1.0 → 1.02
        out[2] = (rel_after / before.g2_rel.unwrap_or(0.0).max(t.g2_rel))
            .max(abs_after / abs_before.max(f64::MIN_POSITIVE));
    }
    out
}

/// How `after` is worse than `before` up to `target` (beyond the tolerance), or `None`: a
/// [`LinkGrowth`] factor above 1 (a rise beyond [`NEGLIGIBLE_GROWTH`] of its tolerance) — a
/// larger gap, a larger normal angle, or a larger relative curvature difference together with a
/// larger absolute one.
pub fn worse_than(
    before: &LinkMeasure,
    after: &LinkMeasure,
    target: Continuity,
    t: &Tolerances,
) -> Option<String> {
    let LinkGrowth {
        gap: g0,
        angle: g1,
        curvature: g2,
    } = LinkGrowth::of(before, after, target, t);
    if g0 > 1.0 {
        Some(format!(
            "with a gap of {:.3e} (input {:.3e})",
            after.g0, before.g0
        ))
    } else if g1 > 1.0 {
        Some(format!(
            "with a normal angle of {:.3e}° (input {:.3e}°)",
            after.g1_deg.unwrap_or(0.0),
            before.g1_deg.unwrap_or(0.0)
        ))
    } else if g2 > 1.0 {
        Some(format!(
            "with a relative curvature difference of {:.3e} (input {:.3e}), absolute {:.3e} (input {:.3e})",
            after.g2_rel.unwrap_or(0.0),
            before.g2_rel.unwrap_or(0.0),
            after.g2_abs.unwrap_or(0.0),
            before.g2_abs.unwrap_or(0.0)
        ))
    } else {
        None
    }
}

impl Job<'_> {
    /// Continuity alone is worse somewhere too (`worse`): of the candidates, the one whose
    /// links grow the least against the input — a gap before an angle before a curvature
    /// ([`LinkGrowth`]'s order); on a tie the fairer one (listed first). The start may no longer fit
    /// masters that were faired before it.
    pub(super) fn least_grown(
        &self,
        labelled: &[(usize, SideLink<'_>)],
        mut candidates: Vec<(&str, BSplineSurface, Vec<StageReport>)>,
        worse: &str,
        problems: &mut Vec<Problem>,
    ) -> (BSplineSurface, Vec<StageReport>) {
        let growth: Vec<LinkGrowth> = candidates
            .iter()
            .map(|(_, f, _)| self.worst_growth(labelled, f))
            .collect();
        let mut pick = 0;
        for k in 1..candidates.len() {
            if growth[k] < growth[pick] {
                pick = k;
            }
        }
        let figures: Vec<String> = candidates
            .iter()
            .zip(&growth)
            .map(|((what, _, _), g)| format!("{what}: {g}"))
            .collect();
        self.limited(
            problems,
            format!(
                "continuity alone: {worse}; kept {}, whose links grow the least against the input — {}",
                candidates[pick].0,
                figures.join("; ")
            ),
            Some(growth[pick].largest()),
        );
        let (_, kept, stages) = candidates.swap_remove(pick);
        (kept, stages)
    }

    /// The worst [`LinkGrowth`] of `result` over this surface's links against the input, kind
    /// by kind (every factor ≤ 1: no link worse).
    pub(super) fn worst_growth(
        &self,
        labelled: &[(usize, SideLink<'_>)],
        result: &BSplineSurface,
    ) -> LinkGrowth {
        let t = &self.connect.tolerances;
        let mut worst = LinkGrowth::default();
        for (k, l) in labelled {
            let Some(before) = self.before.get(*k).and_then(Option::as_ref) else {
                continue;
            };
            let Ok(after) = l.measure(result, &self.connect.measure) else {
                return LinkGrowth::OPENED;
            };
            worst = worst.max(LinkGrowth::of(before, &after, l.target, t));
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

#[cfg(test)]
mod tests {
    use super::LinkGrowth;

    fn g(gap: f64, angle: f64, curvature: f64) -> LinkGrowth {
        LinkGrowth::from([gap, angle, curvature])
    }

    /// Severity orders by gap, then angle, then curvature; a factor up to 1 is "no worse" and
    /// counts as 1, so growths that differ only below 1 are equally severe.
    #[test]
    fn growths_order_by_gap_then_angle_then_curvature() {
        assert!(g(1.2, 1.0, 1.0) > g(1.0, 50.0, 50.0));
        assert!(g(1.0, 1.3, 1.0) > g(1.0, 1.0, 40.0));
        assert!(g(1.0, 1.0, 2.0) > g(1.0, 1.0, 1.5));
        assert_eq!(g(0.2, 0.9, 0.0), g(1.0, 0.5, 1.0));
        assert!(g(0.2, 0.9, 0.0) < g(1.0, 1.0, 1.0001));
        assert!(LinkGrowth::OPENED > g(1e300, 1e300, 1e300));
        let mut v = vec![g(1.0, 2.0, 1.0), g(3.0, 1.0, 1.0), g(1.0, 1.0, 5.0)];
        v.sort();
        assert_eq!(
            v,
            vec![g(1.0, 1.0, 5.0), g(1.0, 2.0, 1.0), g(3.0, 1.0, 1.0)]
        );
    }

    /// The worst of several links is taken kind by kind, and the verdicts read the factors.
    #[test]
    fn the_worst_of_several_links_is_taken_kind_by_kind() {
        let w = g(0.5, 3.0, 1.0).max(g(2.0, 1.0, 0.0));
        assert_eq!(
            (w.gap, w.angle, w.curvature),
            (2.0, 3.0, 1.0),
            "kind by kind"
        );
        assert!(!w.no_worse() && !w.joins_kept());
        assert_eq!(w.largest(), 3.0);
        assert!(g(1.0, 1.0, 1.0).no_worse());
        assert!(g(0.9, 1.0, 7.0).joins_kept() && !g(0.9, 1.0, 7.0).no_worse());
        assert!(LinkGrowth::default().no_worse());
    }

    /// The report phrase names each kind with three decimals.
    #[test]
    fn a_growth_reads_as_a_report_phrase() {
        assert_eq!(
            g(1.0, 2.5, 1.23456).to_string(),
            "gap 1.000 ×, angle 2.500 ×, curvature 1.235 ×"
        );
    }
}
