//! How much worse a link leaves than it came: growth factors of gap, angle and curvature
//! against the input, their order, and the report phrases.

use super::*;

/// The factors by which `after` exceeds `before` in gap, normal angle and relative curvature
/// difference (each against the larger of its input value and its tolerance; 0 above the
/// target). A relative curvature figure counts only where the absolute difference grew too: a
/// relative figure that grows while the absolute difference shrinks means that both curvatures
/// went down — a lead-in flattening a vertex blend next to a fillet that is straight across the
/// join (box12_r5: 1.000 → 1.002 while |Δκ| went 0.2 → 2e-4): the join got better, not worse.
pub(crate) fn growths(
    before: &LinkMeasure,
    after: &LinkMeasure,
    target: Continuity,
    t: &Tolerances,
) -> [f64; 3] {
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
    out
}

/// A gap, angle or relative curvature difference that grows by less than this share of its
/// tolerance has not grown: the tolerance is the resolution at which a join is judged, and a
/// thousandth of it is below what any checker reports (a G0 tolerance of 1e-3 mm: 1e-6 mm).
/// A slave kept as it was beside a master faired inside its kept frame sees its gap of
/// 0.012 mm grow by 2e-9 mm; counted, that rise outranked an angle grown 6.6 %.
pub const NEGLIGIBLE_GROWTH: f64 = 1e-3;

/// [`growths`] before rounding.
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
/// `growths` factor above 1 (a rise beyond [`NEGLIGIBLE_GROWTH`] of its tolerance) — a larger gap, a larger normal angle, or a larger relative
/// curvature difference together with a larger absolute one.
pub fn worse_than(
    before: &LinkMeasure,
    after: &LinkMeasure,
    target: Continuity,
    t: &Tolerances,
) -> Option<String> {
    let [g0, g1, g2] = growths(before, after, target, t);
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

/// Orders two [`Job::worst_growth`] results: the one that leaves a gap grow less is better,
/// then the angle, then the curvature — a join that opens is a defect, one that loses
/// tangency is visible in every reflection, a curvature step only in a zebra or curvature
/// plot. A factor up to 1 (no link worse) counts as 1.
pub(crate) fn growth_order(a: [f64; 3], b: [f64; 3]) -> std::cmp::Ordering {
    a.iter()
        .zip(&b)
        .map(|(x, y)| x.max(1.0).total_cmp(&y.max(1.0)))
        .find(|o| o.is_ne())
        .unwrap_or(std::cmp::Ordering::Equal)
}

/// `[gap, angle, curvature]` growth factors, as a report phrase.
pub(crate) fn growth_text(g: [f64; 3]) -> String {
    format!(
        "gap {:.3} ×, angle {:.3} ×, curvature {:.3} ×",
        g[0], g[1], g[2]
    )
}

impl Job<'_> {
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
