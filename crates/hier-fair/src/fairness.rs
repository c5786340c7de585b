//! The fairness of a model's surfaces, measured in their place in the hierarchy, and the
//! verdict of a result against its input: what a surfacer rejects even where every link is
//! continuous (\[SV\] §1: "even curvature distribution with large, monotone curvature areas is
//! crucial"; §1.2: continuity constraints "may crease the surface near the sides").
//!
//! The figures are nurbs-core's [`nurbs_core::fairness()`]; the model decides which iso-lines are
//! cross-boundary (those across the sides a surface is linked by, as a slave) and the
//! hysteresis of their extrema (the model's relative G2 tolerance, with the link measure's
//! flatness cut-off as a floor).
//!
//! # The verdict ([`FairnessVerdict`])
//! A result is fair against its input when
//! - its peak curvature, and the peak of its comb along the cross-boundary iso-lines, are at
//!   most [`PEAK_FACTOR`] × the input's (a rolling-ball section set G2
//!   to flat masters must overshoot the arc's curvature to turn the same angle: a quintic
//!   lead-in keeps its peak within 1.1–1.6× of the arc's; beyond that the G2 was bought with a
//!   spike) — where the input's peak is smaller than the curvature the surface has to reach at
//!   its joins (its masters'), that joint curvature is the reference instead. The comb's peak
//!   is a maximum over the profiles, not a quantile: a crease beside a side, a strip too thin
//!   for the grid's quantile to see, shows in the comb (a three-radii corner polished to G2 by
//!   default peaked at 0.25 /mm on the grid's 99 % and at 76 /mm in its comb);
//! - its thin-plate energy is at most [`ENERGY_FACTOR`] × the input's;
//! - along a slave's cross-boundary iso-lines, its profile has at most [`ONE_HUMP_EXTREMA`]
//!   interior extremum more than the input's (the one hump of a lead-in that rises once and falls
//!   once);
//! - its net grows to at most max(2n, n + [`NET_GROWTH_ROWS`]) per direction of its input's n.

use g_continuity::MeasureParams;
use nurbs_core::fairness::{Fairness, FairnessParams, fairness};
use nurbs_core::{BSplineSurface, Direction};

use crate::model::{Model, ModelTolerances};

/// Largest peak curvature of a result relative to its input's (or to its masters' at the
/// joints where the input is flatter): 1.6, the top of the range of a quintic lead-in that
/// keeps a rolling-ball section's contact lines (1.1–1.6× the arc's curvature for ramps from
/// a tenth to a third of the section).
pub const PEAK_FACTOR: f64 = 1.6;

/// Largest thin-plate energy of a result relative to its input's: 3. A result whose curvature
/// stays within [`PEAK_FACTOR`] of its input's everywhere has at most PEAK_FACTOR² ≈ 2.56 times
/// its ∫κ²; the rest is room for the parametric part of the thin-plate energy (a lead-in's
/// denser knots change the speed of the parametrization, not the shape).
pub const ENERGY_FACTOR: f64 = 3.0;

/// Interior extrema a cross-boundary profile may gain over its input's: one, the hump of a
/// profile that rises once from each G2 side and falls once.
pub const ONE_HUMP_EXTREMA: usize = 1;

/// The rows a net may gain per direction beyond doubling a small one: 16 — what a sparse input
/// (a kernel's 3 × 3 sphere blend) needs in one direction for G2 on both its sides: degree
/// raised to 5 (+3), three lead-in knots at each of the two sides (+6), and seven rows for the
/// refinement of a side that the first setting misses.
pub const NET_GROWTH_ROWS: usize = 16;

/// The largest net per direction a result of an input with `n` rows may have.
pub fn net_limit(n: usize) -> usize {
    (2 * n).max(n + NET_GROWTH_ROWS)
}

/// The fairness settings of a model: the hysteresis of the comb's extrema is its relative G2
/// tolerance, with the flatness cut-off of the link measure (a radius of a thousand surface
/// sizes, g-continuity's `FLAT_RADIUS_FACTOR`) as a floor.
pub fn fairness_params(tolerances: &ModelTolerances, surface: &BSplineSurface) -> FairnessParams {
    FairnessParams {
        wiggle_relative: tolerances.g2_rel,
        flat_curvature: 1.0
            / (g_continuity::measure::FLAT_RADIUS_FACTOR * surface.size().max(f64::MIN_POSITIVE)),
        ..FairnessParams::default()
    }
}

/// The directions across the sides surface `k` of `model` hangs on as a slave (each once).
pub fn cross_directions(model: &Model, k: usize) -> Vec<Direction> {
    let mut out = Vec::new();
    for l in model.links_of_slave(k) {
        let d = model.links[l].side.cross_direction();
        if !out.contains(&d) {
            out.push(d);
        }
    }
    out
}

/// The fairness figures of every surface of `model`, with the links the framework finds on its
/// shared edges ([`crate::edges::link_edges`]: a fillet side lying tangentially on a higher
/// surface) counted as links, as `fair` counts them.
pub fn model_fairness(model: &Model) -> Vec<Fairness> {
    let edges = crate::edges::shared_edges(model);
    let (work, _, _) = crate::edges::link_edges(model, &edges);
    (0..work.surfaces.len())
        .map(|k| surface_fairness(&work, k, &work.surfaces[k].surface))
        .collect()
}

/// The fairness figures of `surface` standing as surface `k` of `model`.
pub fn surface_fairness(model: &Model, k: usize, surface: &BSplineSurface) -> Fairness {
    let params = fairness_params(&model.tolerances, surface);
    fairness(surface, &cross_directions(model, k), &params)
}

/// The largest |normal curvature| across the joins of surface `k` that its masters have there
/// (1/model unit): the curvature a G2 result must reach at its sides, measured on the masters
/// of `model` as they stand, each link over its part of the side (`ranges`, per link of the
/// model, `None`: the whole side, [`crate::edges`]); `measure` gives the samples; 0 without G2
/// links.
pub fn joint_curvature(
    model: &Model,
    k: usize,
    surface: &BSplineSurface,
    ranges: &[Option<(f64, f64)>],
    measure: &MeasureParams,
) -> f64 {
    let mut out = 0.0_f64;
    for l in model.links_of_slave(k) {
        let link = &model.links[l];
        if link.continuity != nurbs_core::Continuity::G2 {
            continue;
        }
        let master = &model.surfaces[link.master].surface;
        let range = ranges.get(l).copied().flatten();
        if let Ok(m) =
            g_continuity::measure::measure_link_on(master, surface, link.side, range, measure)
        {
            for s in &m.detail {
                if let Some(km) = s.kappa_master {
                    out = out.max(km.abs());
                }
            }
        }
    }
    out
}

/// How a result's fairness compares with its input's (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct FairnessVerdict {
    /// peak curvature after / the reference (the input's peak, or the masters' joint curvature
    /// where that is larger); 0 when the reference is 0 and the result flat
    pub peak_ratio: f64,
    /// the comb's peak across the linked sides after ([`Fairness::cross_peak`]) / its
    /// reference (the input's comb peak, or the joint curvature where that is larger); 1 for a
    /// surface no side of which is linked as a slave
    pub comb_ratio: f64,
    /// thin-plate energy after / before (1 when both are 0)
    pub energy_ratio: f64,
    /// cross-boundary extrema gained over the input's (0 when there are none or fewer)
    pub extrema_gained: usize,
    /// whether the net stays within [`net_limit`] in both directions
    pub net_within: bool,
}

impl FairnessVerdict {
    /// The verdict of `after` against `before`, with `joint` the masters' curvature at the
    /// joins ([`joint_curvature`]).
    pub fn new(before: &Fairness, after: &Fairness, joint: f64) -> Self {
        let reference = before.peak_curvature.max(joint);
        let peak_ratio = ratio(after.peak_curvature, reference);
        let comb_ratio = match (before.cross_peak, after.cross_peak) {
            (Some(b), Some(a)) => ratio(a, b.max(joint)),
            _ => 1.0,
        };
        let energy_ratio = ratio(after.energy, before.energy);
        let extrema_gained = after
            .cross_extrema
            .unwrap_or(0)
            .saturating_sub(before.cross_extrema.unwrap_or(0));
        let net_within =
            after.net.0 <= net_limit(before.net.0) && after.net.1 <= net_limit(before.net.1);
        Self {
            peak_ratio,
            comb_ratio,
            energy_ratio,
            extrema_gained,
            net_within,
        }
    }

    /// Whether the result is fair by every criterion of the module docs.
    pub fn fair(&self) -> bool {
        self.spike() <= PEAK_FACTOR
            && self.energy_ratio <= ENERGY_FACTOR
            && self.extrema_gained <= ONE_HUMP_EXTREMA
            && self.net_within
    }

    /// Whether this verdict is strictly fairer than `other`'s: fewer faults; else, where both
    /// peak beyond [`PEAK_FACTOR`], the lower peak ([`Self::spike`]: the grid's or the comb's);
    /// else fewer curvature extrema gained; else a peak lower by more than `same` (relative; the
    /// framework passes the model's relative G2 tolerance: curvatures that close are "the same
    /// curvature" at a join, and so are two peaks). A spike is the worse fault: a surface that peaks at 9× its input's with
    /// two fewer wiggles in its comb is not the fairer one (a sphere corner's setting against
    /// its faired result, by default).
    pub fn fairer_than(&self, other: &Self, same: f64) -> bool {
        let (a, b) = (self.faults().len(), other.faults().len());
        if a != b {
            return a < b;
        }
        let lower = |x: f64, y: f64| x < y * (1.0 - same);
        if self.spike().min(other.spike()) > PEAK_FACTOR
            && (lower(self.spike(), other.spike()) || lower(other.spike(), self.spike()))
        {
            return lower(self.spike(), other.spike());
        }
        if self.extrema_gained != other.extrema_gained {
            return self.extrema_gained < other.extrema_gained;
        }
        self.spike() < other.spike() * (1.0 - same)
    }

    /// The larger of the peak and comb ratios: how far the result's highest curvature rises
    /// above its reference ([`PEAK_FACTOR`] bounds it).
    pub fn spike(&self) -> f64 {
        self.peak_ratio.max(self.comb_ratio)
    }

    /// What is wrong, in words (empty when [`Self::fair`]).
    pub fn faults(&self) -> Vec<String> {
        let mut out = Vec::new();
        if self.peak_ratio > PEAK_FACTOR {
            out.push(format!(
                "peak curvature {:.2}× its input's (at most {PEAK_FACTOR})",
                self.peak_ratio
            ));
        }
        if self.comb_ratio > PEAK_FACTOR {
            out.push(format!(
                "curvature comb across its boundary peaks {:.2}× its input's (at most {PEAK_FACTOR})",
                self.comb_ratio
            ));
        }
        if self.energy_ratio > ENERGY_FACTOR {
            out.push(format!(
                "thin-plate energy {:.2}× its input's (at most {ENERGY_FACTOR})",
                self.energy_ratio
            ));
        }
        if self.extrema_gained > ONE_HUMP_EXTREMA {
            out.push(format!(
                "{} more curvature extrema across its boundary (one hump allows {ONE_HUMP_EXTREMA})",
                self.extrema_gained
            ));
        }
        if !self.net_within {
            out.push(format!(
                "its net grew beyond max(2n, n + {NET_GROWTH_ROWS})"
            ));
        }
        out
    }
}

/// a / b, 1 when both vanish, infinite when only b does.
fn ratio(a: f64, b: f64) -> f64 {
    if b > 0.0 {
        a / b
    } else if a > 0.0 {
        f64::INFINITY
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figures(peak: f64, energy: f64, extrema: Option<usize>, net: (usize, usize)) -> Fairness {
        Fairness {
            energy,
            peak_curvature: peak,
            max_curvature: peak,
            mean_curvature_spread: 0.0,
            cross_extrema: extrema,
            cross_peak: None,
            net,
            degree: (3, 3),
            regular_samples: 1,
        }
    }

    #[test]
    fn net_limits() {
        assert_eq!(net_limit(3), 19);
        assert_eq!(net_limit(16), 32);
        assert_eq!(net_limit(40), 80);
    }

    #[test]
    fn verdicts() {
        let before = figures(0.2, 10.0, Some(0), (4, 4));
        let fair = FairnessVerdict::new(&before, &figures(0.3, 25.0, Some(1), (20, 9)), 0.0);
        assert!(fair.fair(), "{fair:?}");
        assert!(fair.faults().is_empty());
        let spike = FairnessVerdict::new(&before, &figures(0.5, 25.0, Some(1), (20, 9)), 0.0);
        assert!(!spike.fair());
        assert_eq!(spike.faults().len(), 1);
        // the masters' curvature at the joints is the reference where the input is flatter
        let flat = figures(0.0, 0.0, Some(0), (2, 2));
        let joined = FairnessVerdict::new(&flat, &figures(0.3, 0.0, Some(0), (2, 2)), 0.25);
        assert!((joined.peak_ratio - 1.2).abs() < 1e-12);
        let wave = FairnessVerdict::new(&before, &figures(0.3, 25.0, Some(3), (4, 4)), 0.0);
        assert_eq!(wave.extrema_gained, 3);
        assert!(!wave.fair());
        assert!(fair.fairer_than(&spike, 0.005));
        assert!(!spike.fairer_than(&fair, 0.005));
        assert!(!fair.fairer_than(&fair, 0.005));
        // both beyond the peak bound: the lower spike is fairer, whatever the extrema
        let high = FairnessVerdict::new(&before, &figures(1.8, 25.0, Some(9), (4, 4)), 0.0);
        let low = FairnessVerdict::new(&before, &figures(1.2, 25.0, Some(11), (4, 4)), 0.0);
        assert_eq!(high.faults().len(), low.faults().len());
        assert!(low.fairer_than(&high, 0.005));
        assert!(!high.fairer_than(&low, 0.005));
        // peaks within the bound: the extrema decide
        let calm = FairnessVerdict::new(&before, &figures(0.3, 25.0, Some(3), (4, 4)), 0.0);
        let rough = FairnessVerdict::new(&before, &figures(0.25, 25.0, Some(6), (4, 4)), 0.0);
        assert!(calm.fairer_than(&rough, 0.005));
        let grown = FairnessVerdict::new(&before, &figures(0.2, 10.0, Some(0), (57, 61)), 0.0);
        assert!(!grown.net_within);
        assert_eq!(grown.faults().len(), 1);
    }

    /// A crease beside a side: the grid's quantile within the bound, the comb's maximum far
    /// beyond it (the three-radii corner polished by default: 0.25 against 76 /mm).
    #[test]
    fn a_crease_shows_in_the_comb() {
        let combed = |peak: f64, comb: f64| Fairness {
            cross_peak: Some(comb),
            ..figures(peak, 10.0, Some(1), (4, 4))
        };
        let before = combed(0.18, 0.164);
        let crease = FairnessVerdict::new(&before, &combed(0.22, 76.6), 0.2);
        // the comb's reference is the larger of the input's comb and the joint curvature
        assert!((crease.comb_ratio - 76.6 / 0.2).abs() < 1e-9, "{crease:?}");
        assert!(crease.peak_ratio <= PEAK_FACTOR);
        assert_eq!(crease.spike(), crease.comb_ratio);
        assert!(!crease.fair());
        assert_eq!(crease.faults().len(), 1);
        assert!(crease.faults()[0].starts_with("curvature comb across its boundary peaks"));
        let smooth = FairnessVerdict::new(&before, &combed(0.22, 0.25), 0.2);
        assert!(smooth.fair(), "{smooth:?}");
        assert!(smooth.fairer_than(&crease, 0.005));
        assert!(!crease.fairer_than(&smooth, 0.005));
        // no linked side (no comb): the comb does not judge
        let unlinked = FairnessVerdict::new(
            &figures(0.18, 10.0, None, (4, 4)),
            &figures(0.2, 10.0, None, (4, 4)),
            0.0,
        );
        assert_eq!(unlinked.comb_ratio, 1.0);
        assert!(unlinked.fair());
    }
}
