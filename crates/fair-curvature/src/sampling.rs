//! The parameter grid both surface methods sample, and its quadrature weights.
//!
//! [`Sampling::PerSpan`] puts n samples into every non-empty knot span (its start included) plus
//! the domain end, so every span is seen whatever the knot spacing; [`Sampling::Uniform`] spreads
//! a fixed count uniformly over each domain. The two directions are treated alike, so swapping
//! the u and v roles of a surface swaps the grid.
//!
//! Weights are the trapezoid rule of each direction, w_a = (t_{a+1} − t_{a−1})/2 (halved at the
//! ends): Σ_ab w_a w_b f(u_a, v_b) ≈ ∬ f du dv.

use nurbs_core::KnotVector;

use crate::error::{CurvatureError, Result};

/// How many samples per direction a surface method takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sampling {
    /// this many per non-empty knot span (≥ 1), plus the domain end
    PerSpan(usize),
    /// this many in u and in v (each ≥ 3), uniform in parameter
    Uniform(usize, usize),
}

impl Default for Sampling {
    /// Three per span: enough to resolve the curvature variation of a cubic span, and the
    /// u- and v-isocurves of a bicubic then have ≥ 3 samples per control point.
    fn default() -> Self {
        Sampling::PerSpan(3)
    }
}

/// Fewest samples per direction a method accepts (smoothing needs an interior).
pub(crate) const MIN_SAMPLES: usize = 3;

impl Sampling {
    pub(crate) fn check(&self) -> Result<()> {
        let bad = |value: usize, expected| CurvatureError::InvalidParameter {
            name: "sampling",
            value: value as f64,
            expected,
        };
        match *self {
            Sampling::PerSpan(0) => Err(bad(0, "at least 1 sample per span")),
            Sampling::Uniform(u, v) if u.min(v) < MIN_SAMPLES => {
                Err(bad(u.min(v), "at least 3 samples per direction"))
            }
            _ => Ok(()),
        }
    }

    /// The sample parameters of one direction.
    pub fn params(&self, knots: &KnotVector, first: bool) -> Vec<f64> {
        let mut t = match *self {
            Sampling::PerSpan(n) => knots.span_samples(n),
            Sampling::Uniform(u, v) => knots.uniform_params(if first { u } else { v }),
        };
        if t.len() < MIN_SAMPLES {
            t = knots.uniform_params(MIN_SAMPLES);
        }
        t
    }
}

/// Trapezoid weights of the sample parameters `t` (ascending).
pub fn trapezoid_weights(t: &[f64]) -> Vec<f64> {
    let n = t.len();
    (0..n)
        .map(|a| {
            let lo = t[a.saturating_sub(1)];
            let hi = t[(a + 1).min(n - 1)];
            (hi - lo) / 2.0
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_integrate_the_domain() {
        let kv = KnotVector::new(3, vec![0., 0., 0., 0., 0.2, 0.7, 1., 1., 1., 1.]).unwrap();
        let t = Sampling::PerSpan(3).params(&kv, true);
        assert_eq!(t.len(), 3 * 3 + 1);
        let w = trapezoid_weights(&t);
        let total: f64 = w.iter().sum();
        assert!((total - 1.0).abs() < 1e-15);
        assert!(Sampling::PerSpan(0).check().is_err());
        assert!(Sampling::Uniform(2, 9).check().is_err());
    }
}
