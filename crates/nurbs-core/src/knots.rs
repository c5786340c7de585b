//! Knot vectors: validation, domain, multiplicities and span lookup.
//!
//! A knot vector t_0 ≤ … ≤ t_m of degree p carries n + 1 = m − p basis functions; the parameter
//! domain is [t_p, t_{n+1}] (\[NB\] §2.2). Span lookup returns the index k ∈ [p, n] with
//! t_k ≤ t < t_{k+1} (the last non-empty span at the end of the domain), \[NB\] A2.1.

use crate::error::{Error, Result};

/// Knots closer than this fraction of the domain are one knot. A parameter from a file is
/// written with 12–15 significant digits, and a span midpoint is rounded: a span of a 10⁻⁹th of
/// the domain carries no geometry of its own, but a knot of high multiplicity bounding it makes
/// the derivatives there those of a sliver (a CAD face bounded 2·10⁻¹³ from a knot of its
/// surface came out with a 10° wrong normal at its corner).
pub const KNOT_MERGE_RELATIVE: f64 = 1e-9;

/// A validated, non-decreasing knot vector together with its degree.
#[derive(Debug, Clone, PartialEq)]
pub struct KnotVector {
    degree: usize,
    knots: Vec<f64>,
    first_span: usize,
    last_span: usize,
}

impl KnotVector {
    /// Validates and builds a knot vector: degree ≥ 1, all knots finite and non-decreasing, at
    /// least 2(p + 1) knots, a non-empty domain, no knot inside the domain with multiplicity above
    /// p and none anywhere above p + 1.
    pub fn new(degree: usize, knots: Vec<f64>) -> Result<Self> {
        if degree == 0 {
            return Err(Error::InvalidDegree { degree });
        }
        let min = 2 * (degree + 1);
        if knots.len() < min {
            return Err(Error::TooFewKnots {
                len: knots.len(),
                degree,
                min,
            });
        }
        for (index, &value) in knots.iter().enumerate() {
            if !value.is_finite() {
                return Err(Error::NonFiniteKnot { index, value });
            }
            if index > 0 && value < knots[index - 1] {
                return Err(Error::DecreasingKnots {
                    index,
                    previous: knots[index - 1],
                    value,
                });
            }
        }
        let n = knots.len() - degree - 2;
        let (start, end) = (knots[degree], knots[n + 1]);
        if start >= end {
            return Err(Error::EmptyDomain { start, end });
        }
        let mut i = 0;
        while i < knots.len() {
            let value = knots[i];
            let mut j = i;
            while j < knots.len() && knots[j] == value {
                j += 1;
            }
            let multiplicity = j - i;
            let interior = value > start && value < end;
            let max = if interior { degree } else { degree + 1 };
            if multiplicity > max {
                return Err(Error::KnotMultiplicity {
                    value,
                    multiplicity,
                    max,
                    degree,
                });
            }
            i = j;
        }
        let mut first_span = degree;
        while knots[first_span + 1] <= knots[first_span] {
            first_span += 1;
        }
        let mut last_span = n;
        while knots[last_span] >= knots[last_span + 1] {
            last_span -= 1;
        }
        Ok(Self {
            degree,
            knots,
            first_span,
            last_span,
        })
    }

    /// The clamped uniform knot vector of `degree` for `count` control points on [0, 1].
    pub fn clamped_uniform(degree: usize, count: usize) -> Result<Self> {
        if count < degree + 1 {
            return Err(Error::TooFewKnots {
                len: count + degree + 1,
                degree,
                min: 2 * (degree + 1),
            });
        }
        let segments = count - degree;
        let mut knots = vec![0.0; degree + 1];
        knots.extend((1..segments).map(|i| i as f64 / segments as f64));
        knots.extend(std::iter::repeat_n(1.0, degree + 1));
        Self::new(degree, knots)
    }

    /// The Bézier knot vector `[0]*(p+1) + [1]*(p+1)`.
    pub fn bezier(degree: usize) -> Result<Self> {
        Self::clamped_uniform(degree, degree + 1)
    }

    /// Degree p.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The knots t_0 … t_m.
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// Number of knots m + 1.
    pub fn len(&self) -> usize {
        self.knots.len()
    }

    /// Always false: a valid knot vector has at least 2(p + 1) knots.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Number of basis functions (control points) n + 1 = m − p.
    pub fn num_basis(&self) -> usize {
        self.knots.len() - self.degree - 1
    }

    /// Parameter domain [t_p, t_{n+1}].
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.num_basis()])
    }

    /// True when both ends have multiplicity p + 1 (the curve interpolates its end points).
    pub fn is_clamped(&self) -> bool {
        let p = self.degree;
        let k = &self.knots;
        let m = k.len() - 1;
        k[..=p].iter().all(|&t| t == k[0]) && k[m - p..].iter().all(|&t| t == k[m])
    }

    /// Number of knots equal to `t` (exact comparison).
    pub fn multiplicity(&self, t: f64) -> usize {
        self.knots.iter().filter(|&&k| k == t).count()
    }

    /// Distinct knot values strictly inside the domain with their multiplicities, ascending.
    pub fn interior_knots(&self) -> Vec<(f64, usize)> {
        let (a, b) = self.domain();
        let mut out: Vec<(f64, usize)> = Vec::new();
        for &t in self.knots.iter().filter(|&&t| t > a && t < b) {
            match out.last_mut() {
                Some((v, m)) if *v == t => *m += 1,
                _ => out.push((t, 1)),
            }
        }
        out
    }

    /// Indices k of the non-empty spans [t_k, t_{k+1}) inside the domain.
    pub fn spans(&self) -> impl Iterator<Item = usize> + '_ {
        (self.first_span..=self.last_span).filter(|&k| self.knots[k] < self.knots[k + 1])
    }

    /// The span index k ∈ [p, n] with t_k ≤ t < t_{k+1}; parameters outside the domain are
    /// clamped to it (the end of the domain belongs to the last non-empty span). \[NB\] A2.1.
    #[inline]
    pub fn span(&self, t: f64) -> usize {
        let k = &self.knots;
        if !(t > k[self.first_span]) {
            return self.first_span;
        }
        if t >= k[self.last_span + 1] {
            return self.last_span;
        }
        let (mut lo, mut hi) = (self.first_span, self.last_span + 1);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if t < k[mid] {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        lo
    }

    /// Clamps `t` into the domain (NaN maps to the domain start).
    #[inline]
    pub fn clamp_param(&self, t: f64) -> f64 {
        let (a, b) = self.domain();
        if t.is_nan() { a } else { t.clamp(a, b) }
    }

    /// `t` snapped onto the nearest knot (an end of the domain included) when it lies within
    /// [`KNOT_MERGE_RELATIVE`] of the domain length from it, `t` otherwise.
    pub fn snap(&self, t: f64) -> f64 {
        let (a, b) = self.domain();
        let close = KNOT_MERGE_RELATIVE * (b - a);
        let k = &self.knots[self.degree..self.knots.len() - self.degree];
        let i = k.partition_point(|&x| x < t);
        [i.checked_sub(1), Some(i)]
            .into_iter()
            .flatten()
            .filter_map(|j| k.get(j).copied())
            .filter(|x| (x - t).abs() <= close)
            .min_by(|x, y| (x - t).abs().total_cmp(&(y - t).abs()))
            .unwrap_or(t)
    }

    /// Checks that `t` is finite and inside the domain.
    pub fn check_param(&self, t: f64) -> Result<()> {
        let (start, end) = self.domain();
        if t.is_finite() && t >= start && t <= end {
            Ok(())
        } else {
            Err(Error::ParameterOutOfDomain {
                value: t,
                start,
                end,
            })
        }
    }

    /// `count` parameters spread uniformly over the domain, both ends included.
    pub fn uniform_params(&self, count: usize) -> Vec<f64> {
        let (a, b) = self.domain();
        match count {
            0 => Vec::new(),
            1 => vec![0.5 * (a + b)],
            _ => (0..count)
                .map(|i| a + (b - a) * i as f64 / (count - 1) as f64)
                .collect(),
        }
    }

    /// `per_span` parameters evenly spaced in every non-empty span (its start included) plus the
    /// domain end: samples that see every span, for start grids and least-squares rows.
    pub fn span_samples(&self, per_span: usize) -> Vec<f64> {
        let per = per_span.max(1);
        let k = &self.knots;
        let mut out = Vec::new();
        for s in self.spans() {
            out.extend((0..per).map(|i| k[s] + (k[s + 1] - k[s]) * i as f64 / per as f64));
        }
        out.push(self.domain().1);
        out
    }

    /// Greville abscissae, one per basis function: (t_{i+1} + … + t_{i+p}) / p, the parameter
    /// a control point sits over (the knot averages; the degree is at least 1). They rise with
    /// i and run from the domain's start to its end on a clamped vector.
    pub fn greville(&self) -> Vec<f64> {
        let p = self.degree;
        let t = &self.knots;
        (0..self.num_basis())
            .map(|i| t[i + 1..=i + p].iter().sum::<f64>() / p as f64)
            .collect()
    }

    /// [`KnotVector::greville`] as fractions of the domain (0 at its start, 1 at its end).
    pub fn greville_fractions(&self) -> Vec<f64> {
        let (a, b) = self.domain();
        self.greville().iter().map(|g| (g - a) / (b - a)).collect()
    }

    /// Length of the domain t_{n+1} − t_p.
    pub fn domain_length(&self) -> f64 {
        let (a, b) = self.domain();
        b - a
    }

    /// Checks that the vector fits `count` control points.
    pub(crate) fn check_count(&self, direction: &'static str, count: usize) -> Result<()> {
        let expected = count + self.degree + 1;
        if self.knots.len() != expected {
            return Err(Error::KnotCountMismatch {
                direction,
                len: self.knots.len(),
                degree: self.degree,
                count,
                expected,
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn greville_abscissae_are_the_knot_averages() {
        let g = KnotVector::bezier(3).unwrap().greville();
        assert_eq!(g.len(), 4);
        for (a, b) in g.iter().zip([0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0]) {
            assert!((a - b).abs() < 1e-15, "{g:?}");
        }
        let kv = KnotVector::new(3, vec![2.0, 2.0, 2.0, 2.0, 3.0, 4.0, 4.0, 4.0, 4.0]).unwrap();
        let f = kv.greville_fractions();
        for (a, b) in f.iter().zip([0.0, 1.0 / 6.0, 0.5, 5.0 / 6.0, 1.0]) {
            assert!((a - b).abs() < 1e-15, "{f:?}");
        }
    }

    #[test]
    fn rejects_bad_vectors() {
        assert!(matches!(
            KnotVector::new(0, vec![0.0, 1.0]),
            Err(Error::InvalidDegree { .. })
        ));
        assert!(matches!(
            KnotVector::new(2, vec![0.0, 0.0, 1.0, 1.0]),
            Err(Error::TooFewKnots { min: 6, .. })
        ));
        assert!(matches!(
            KnotVector::new(1, vec![0.0, 0.0, f64::NAN, 1.0]),
            Err(Error::NonFiniteKnot { index: 2, .. })
        ));
        assert!(matches!(
            KnotVector::new(1, vec![0.0, 0.5, 0.2, 1.0]),
            Err(Error::DecreasingKnots { index: 2, .. })
        ));
        assert!(matches!(
            KnotVector::new(1, vec![0.0, 0.0, 0.0, 0.0]),
            Err(Error::EmptyDomain { .. })
        ));
        assert!(matches!(
            KnotVector::new(2, vec![0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0]),
            Err(Error::KnotMultiplicity {
                multiplicity: 3,
                max: 2,
                ..
            })
        ));
    }

    #[test]
    fn span_lookup_matches_definition() {
        let kv = KnotVector::new(2, vec![0.0, 0.0, 0.0, 0.3, 0.3, 0.7, 1.0, 1.0, 1.0]).unwrap();
        assert_eq!(kv.num_basis(), 6);
        assert_eq!(kv.span(0.0), 2);
        assert_eq!(kv.span(0.29), 2);
        assert_eq!(kv.span(0.3), 4);
        assert_eq!(kv.span(0.69), 4);
        assert_eq!(kv.span(0.7), 5);
        assert_eq!(kv.span(1.0), 5);
        assert_eq!(kv.span(7.0), 5);
        assert_eq!(kv.span(-1.0), 2);
        assert_eq!(kv.spans().collect::<Vec<_>>(), vec![2, 4, 5]);
        assert_eq!(kv.interior_knots(), vec![(0.3, 2), (0.7, 1)]);
        assert!(kv.is_clamped());
        for t in [0.0, 0.1, 0.3, 0.5, 0.7, 0.99, 1.0] {
            let k = kv.span(t);
            assert!(kv.knots()[k] <= t && (t < kv.knots()[k + 1] || t == 1.0));
        }
    }

    #[test]
    fn unclamped_domain() {
        let kv = KnotVector::new(2, (0..8).map(f64::from).collect()).unwrap();
        assert_eq!(kv.domain(), (2.0, 5.0));
        assert!(!kv.is_clamped());
        assert_eq!(kv.span(5.0), 4);
    }
}
