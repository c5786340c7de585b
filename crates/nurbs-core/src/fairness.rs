//! Fairness figures of a surface: what a surfacer reads off a curvature map and a curvature
//! comb, as numbers that can be compared before and after a fairing (\[SV\] §1: "even curvature
//! distribution with large, monotone curvature areas").
//!
//! On a grid of `samples × samples` parameters spread evenly over the domain (both ends
//! included), at every regular point (singular points — the row of a collapsed side, a
//! degenerate corner — have no curvature and drop out, their neighbourhood stays in):
//! - **peak curvature**: the `percentile` quantile of κ_max = max(|k1|, |k2|) over the points;
//!   the largest value itself is kept as `max_curvature`;
//! - **mean-curvature spread**: the standard deviation of H = (k1 + k2)/2, each point weighted by
//!   its area element |S_u × S_v| (a uniform curvature reads 0 whatever the parametrization);
//! - **thin-plate energy** ∬ |S_uu|² + 2|S_uv|² + |S_vv|² ([`crate::energy`]).
//!
//! Along the cross-boundary iso-lines — the lines of constant v that run across a u side, of
//! constant u across a v side — the **comb's wiggles**: the normal curvature in the iso-line's
//! own direction κ_n(S_u) (or κ_n(S_v)) sampled from side to side, and its number of interior
//! extrema counted with a hysteresis ([`count_extrema`]). A rolling-ball fillet set G2 to flat
//! masters rises once and falls once: one extremum; a wave beside a lead-in adds two.
//!
//! # Tolerance
//! [`FairnessParams::wiggle_relative`]: a rise or fall of the profile counts only when it exceeds
//! this fraction of the line's largest |κ_n|. The framework passes the model's relative G2
//! tolerance: a change in curvature smaller than what the model calls "the same curvature"
//! across a join is no wiggle either.

use crate::energy::thin_plate_energy;
use crate::ops::Direction;
use crate::surface::BSplineSurface;

/// Grid samples per direction (41: a sample every 2.5 % of the parameter range, so that the
/// row next to a collapsed side lies at 2.5 % of the domain from it, inside the neighbourhood
/// where a pole blend's curvature spike lives).
pub const DEFAULT_SAMPLES: usize = 41;

/// Quantile taken as the peak curvature (0.99: the top 1 % — 17 of 1681 points, less than half
/// a grid row — is left out, so one rounding outlier at a near-degenerate point does not set
/// the figure, while a spike along a whole row or around a pole still does).
pub const DEFAULT_PERCENTILE: f64 = 0.99;

/// Iso-lines across each measured direction, at the fractions (k + ½)/n of the other
/// parameter's range (5: the middle line and two on each side, none on a boundary).
pub const DEFAULT_CROSS_LINES: usize = 5;

/// Samples along one cross-boundary iso-line, both ends included (81: a lead-in of a twentieth
/// of the line is still sampled by four points).
pub const DEFAULT_PROFILE_SAMPLES: usize = 81;

/// Default relative hysteresis of [`count_extrema`]: the default relative G2 tolerance of a
/// model (0.5 %, model-format.md).
pub const DEFAULT_WIGGLE_RELATIVE: f64 = 5e-3;

/// Settings of [`fairness`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FairnessParams {
    /// grid samples per direction (default [`DEFAULT_SAMPLES`]; at least 2)
    pub samples: usize,
    /// quantile of κ_max reported as the peak (default [`DEFAULT_PERCENTILE`]; in [0, 1])
    pub percentile: f64,
    /// iso-lines per cross-boundary direction (default [`DEFAULT_CROSS_LINES`])
    pub cross_lines: usize,
    /// samples along an iso-line (default [`DEFAULT_PROFILE_SAMPLES`]; at least 3)
    pub profile_samples: usize,
    /// hysteresis of the extrema count, relative to the line's largest |κ_n| (default
    /// [`DEFAULT_WIGGLE_RELATIVE`])
    pub wiggle_relative: f64,
    /// absolute hysteresis floor (1/model unit): curvature changes below it never count (a line
    /// that is flat to this is straight); default 0
    pub flat_curvature: f64,
}

impl Default for FairnessParams {
    fn default() -> Self {
        Self {
            samples: DEFAULT_SAMPLES,
            percentile: DEFAULT_PERCENTILE,
            cross_lines: DEFAULT_CROSS_LINES,
            profile_samples: DEFAULT_PROFILE_SAMPLES,
            wiggle_relative: DEFAULT_WIGGLE_RELATIVE,
            flat_curvature: 0.0,
        }
    }
}

/// The fairness figures of one surface (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Fairness {
    /// thin-plate energy
    pub energy: f64,
    /// the `percentile` quantile of max(|k1|, |k2|) over the regular grid points (1/unit)
    pub peak_curvature: f64,
    /// the largest max(|k1|, |k2|) of the grid (1/unit)
    pub max_curvature: f64,
    /// area-weighted standard deviation of the mean curvature (1/unit)
    pub mean_curvature_spread: f64,
    /// the most interior extrema of κ_n along one cross-boundary iso-line; `None` when no
    /// direction was asked for
    pub cross_extrema: Option<usize>,
    /// the cross-boundary profiles' largest |κ_n| (1/unit); `None` as `cross_extrema`
    pub cross_peak: Option<f64>,
    /// control net (u, v)
    pub net: (usize, usize),
    /// degree (u, v)
    pub degree: (usize, usize),
    /// regular grid points measured (the others are singular)
    pub regular_samples: usize,
}

/// `n` parameters spread evenly over `(a, b)`, both ends included.
fn spread(a: f64, b: f64, n: usize) -> Vec<f64> {
    let n = n.max(2);
    (0..n)
        .map(|k| a + (b - a) * k as f64 / (n - 1) as f64)
        .collect()
}

/// The fairness figures of `surface`; the comb's wiggles are counted along the iso-lines that
/// run in each direction of `cross` (`Direction::U`: lines of constant v, across the u sides).
pub fn fairness(
    surface: &BSplineSurface,
    cross: &[Direction],
    params: &FairnessParams,
) -> Fairness {
    let (u0, u1) = surface.domain_u();
    let (v0, v1) = surface.domain_v();
    let us = spread(u0, u1, params.samples);
    let vs = spread(v0, v1, params.samples);
    let derivatives = surface.eval_grid_derivatives(&us, &vs);
    let mut kmax = Vec::with_capacity(derivatives.len());
    let (mut w_sum, mut h_sum, mut h2_sum) = (0.0, 0.0, 0.0);
    for d in &derivatives {
        let Some(c) = d.curvature_values() else {
            continue;
        };
        kmax.push(c.k1.abs().max(c.k2.abs()));
        let w = d.du.cross(&d.dv).norm();
        let h = c.mean;
        w_sum += w;
        h_sum += w * h;
        h2_sum += w * h * h;
    }
    let mean_curvature_spread = if w_sum > 0.0 {
        let m = h_sum / w_sum;
        (h2_sum / w_sum - m * m).max(0.0).sqrt()
    } else {
        0.0
    };
    let regular_samples = kmax.len();
    kmax.sort_by(f64::total_cmp);
    let peak_curvature = quantile(&kmax, params.percentile);
    let max_curvature = kmax.last().copied().unwrap_or(0.0);
    let mut cross_extrema = None;
    let mut cross_peak = None;
    for &dir in cross {
        for k in 0..params.cross_lines.max(1) {
            let at = (k as f64 + 0.5) / params.cross_lines.max(1) as f64;
            let profile = cross_profile(surface, dir, at, params.profile_samples);
            let line: Vec<f64> = profile.into_iter().flatten().collect();
            let peak = line.iter().fold(0.0_f64, |a, k| a.max(k.abs()));
            let h = (params.wiggle_relative * peak).max(params.flat_curvature);
            let n = count_extrema(&line, h);
            cross_extrema = Some(cross_extrema.map_or(n, |m: usize| m.max(n)));
            cross_peak = Some(cross_peak.map_or(peak, |m: f64| m.max(peak)));
        }
    }
    Fairness {
        energy: thin_plate_energy(surface),
        peak_curvature,
        max_curvature,
        mean_curvature_spread,
        cross_extrema,
        cross_peak,
        net: (surface.num_u(), surface.num_v()),
        degree: (surface.degree_u(), surface.degree_v()),
        regular_samples,
    }
}

/// The `q` quantile of the sorted `values` (nearest rank below; 0 when empty).
fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return 0.0;
    }
    let q = q.clamp(0.0, 1.0);
    let k = (q * (sorted.len() - 1) as f64).floor() as usize;
    sorted[k]
}

/// The normal curvature κ_n in the iso-line's own direction along the iso-line that runs in
/// `along` (`Direction::U`: v fixed at the fraction `at` of its range, u from its start to its
/// end), at `samples` parameters both ends included; `None` at singular points. Signed with
/// respect to the normal S_u × S_v.
pub fn cross_profile(
    surface: &BSplineSurface,
    along: Direction,
    at: f64,
    samples: usize,
) -> Vec<Option<f64>> {
    let (u0, u1) = surface.domain_u();
    let (v0, v1) = surface.domain_v();
    let (us, vs) = match along {
        Direction::U => (spread(u0, u1, samples), vec![v0 + at * (v1 - v0)]),
        Direction::V => (vec![u0 + at * (u1 - u0)], spread(v0, v1, samples)),
    };
    surface
        .eval_grid_derivatives(&us, &vs)
        .iter()
        .map(|d| {
            let dir = match along {
                Direction::U => d.du,
                Direction::V => d.dv,
            };
            d.normal_curvature(&dir)
        })
        .collect()
}

/// The number of interior extrema of the sampled `profile`: reversals of its direction by more
/// than `hysteresis` (a rise followed by a fall of more than `hysteresis` is one maximum). The
/// ends are not extrema; a monotone profile has none, a single hump one, a wave three.
pub fn count_extrema(profile: &[f64], hysteresis: f64) -> usize {
    let Some(&first) = profile.first() else {
        return 0;
    };
    let h = hysteresis.max(0.0);
    // direction: 0 undecided, 1 rising, -1 falling; hi/lo the extreme since the last reversal
    let (mut direction, mut hi, mut lo, mut count) = (0i8, first, first, 0usize);
    for &x in &profile[1..] {
        match direction {
            1 => {
                if x > hi {
                    hi = x;
                } else if x < hi - h {
                    count += 1;
                    direction = -1;
                    lo = x;
                }
            }
            -1 => {
                if x < lo {
                    lo = x;
                } else if x > lo + h {
                    count += 1;
                    direction = 1;
                    hi = x;
                }
            }
            _ => {
                if x > lo + h {
                    direction = 1;
                    hi = x;
                } else if x < hi - h {
                    direction = -1;
                    lo = x;
                } else {
                    hi = hi.max(x);
                    lo = lo.min(x);
                }
            }
        }
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::{cylinder, sphere_octant, sphere_patch, torus};
    use proptest::prelude::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * b.abs().max(1.0)
    }

    #[test]
    fn a_cylinder_reads_its_radius_and_no_wiggle() {
        let r = 5.0;
        let s = cylinder(r, 20.0).unwrap();
        let f = fairness(
            &s,
            &[Direction::U, Direction::V],
            &FairnessParams::default(),
        );
        assert!(close(f.peak_curvature, 1.0 / r, 1e-9), "{f:?}");
        assert!(close(f.max_curvature, 1.0 / r, 1e-9), "{f:?}");
        assert!(f.mean_curvature_spread < 1e-9, "{f:?}");
        assert_eq!(f.cross_extrema, Some(0));
        // across the rulings (v) the profile is the circle's 1/r, along them (u) 0
        assert!(close(f.cross_peak.unwrap(), 1.0 / r, 1e-9), "{f:?}");
        assert_eq!(f.regular_samples, 41 * 41);
    }

    #[test]
    fn a_sphere_octant_with_its_pole_reads_one_over_r() {
        // the pole row (u = 0) is singular and drops out; its neighbours read 1/r exactly
        let r = 5.0;
        let s = sphere_octant(r).unwrap();
        let f = fairness(&s, &[Direction::U], &FairnessParams::default());
        assert_eq!(f.regular_samples, 40 * 41);
        assert!(close(f.peak_curvature, 1.0 / r, 1e-9), "{f:?}");
        assert!(close(f.max_curvature, 1.0 / r, 1e-9), "{f:?}");
        // next to the pole |S_u × S_v| → 0 and the curvature's rounding grows: 1e-6 of 1/r
        assert!(f.mean_curvature_spread < 1e-6 / r, "{f:?}");
        assert_eq!(f.cross_extrema, Some(0));
        let g = fairness(&sphere_patch(r).unwrap(), &[], &FairnessParams::default());
        assert!(close(g.peak_curvature, 1.0 / r, 1e-9), "{g:?}");
        assert_eq!(g.cross_extrema, None);
    }

    #[test]
    fn a_torus_reads_its_tube_curvature_and_its_mean_spread() {
        // κ across the tube is 1/r everywhere; around the axis cos θ/(R + r cos θ): the peak is
        // the tube's, the mean curvature varies with θ
        let (big, r) = (15.0, 3.0);
        let s = torus(big, r).unwrap();
        let f = fairness(&s, &[Direction::U], &FairnessParams::default());
        assert!(close(f.peak_curvature, 1.0 / r, 1e-9), "{f:?}");
        assert!(f.mean_curvature_spread > 1e-3, "{f:?}");
        // along the tube circle κ_n = 1/r: constant, no extremum
        assert_eq!(f.cross_extrema, Some(0));
    }

    #[test]
    fn extrema_of_model_profiles() {
        let hump: Vec<f64> = (0..=20)
            .map(|k| (std::f64::consts::PI * k as f64 / 20.0).sin())
            .collect();
        assert_eq!(count_extrema(&hump, 0.01), 1);
        let monotone: Vec<f64> = (0..=20).map(|k| k as f64).collect();
        assert_eq!(count_extrema(&monotone, 0.01), 0);
        // the wave of a lead-in with a bump and a dip on each side: 0 .76 .14 .32 .28 .63 0
        let wave = [
            0.067, 0.758, 0.656, 0.333, 0.170, 0.141, 0.180, 0.236, 0.319, 0.278, 0.631, 0.0,
        ];
        assert_eq!(count_extrema(&wave, 0.005 * 0.758), 5);
        // wiggles below the hysteresis do not count
        let flat = [1.0, 1.004, 0.998, 1.003, 1.0];
        assert_eq!(count_extrema(&flat, 0.01), 0);
        assert_eq!(count_extrema(&flat, 0.001), 3);
        assert_eq!(count_extrema(&[], 0.1), 0);
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

        /// Scaling a profile and its hysteresis, shifting it, or reversing it changes nothing;
        /// a sampled sum of k sine half-waves has k extrema.
        #[test]
        fn extrema_are_invariant(k in 1usize..6, scale in 0.01f64..100.0, shift in -10.0f64..10.0) {
            let n = 40 * k;
            let p: Vec<f64> = (0..=n)
                .map(|i| (std::f64::consts::PI * k as f64 * i as f64 / n as f64).sin().abs())
                .collect();
            let h = 0.01;
            let base = count_extrema(&p, h);
            // |sin| of k half-waves: k maxima and k − 1 minima between them
            prop_assert_eq!(base, 2 * k - 1);
            let q: Vec<f64> = p.iter().map(|x| scale * x + shift).collect();
            prop_assert_eq!(count_extrema(&q, h * scale), base);
            let r: Vec<f64> = p.iter().rev().copied().collect();
            prop_assert_eq!(count_extrema(&r, h), base);
        }
    }
}
