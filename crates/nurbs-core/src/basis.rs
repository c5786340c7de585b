//! B-spline basis functions and their derivatives — the one home of basis-function code.
//!
//! N_{i,0}(t) = 1 on [t_i, t_{i+1}), and
//! N_{i,p}(t) = (t − t_i)/(t_{i+p} − t_i) N_{i,p−1}(t) + (t_{i+p+1} − t)/(t_{i+p+1} − t_{i+1}) N_{i+1,p−1}(t)
//! (Cox–de Boor). The p + 1 functions N_{k−p..=k} that do not vanish on span k are computed by the
//! triangular scheme of \[NB\] A2.2; their derivatives up to any order by \[NB\] A2.3.
//!
//! [`BasisEvaluator`] holds the scratch arrays so that hot loops evaluate without allocating.

use crate::knots::KnotVector;

/// Scratch space for basis evaluation of one degree; reuse it across calls in hot loops.
#[derive(Debug, Clone)]
pub struct BasisEvaluator {
    degree: usize,
    left: Vec<f64>,
    right: Vec<f64>,
    ndu: Vec<f64>,
    a: Vec<f64>,
}

impl BasisEvaluator {
    /// Scratch for `degree`.
    pub fn new(degree: usize) -> Self {
        let p1 = degree + 1;
        Self {
            degree,
            left: vec![0.0; p1],
            right: vec![0.0; p1],
            ndu: vec![0.0; p1 * p1.max(3)],
            a: vec![0.0; 2 * p1],
        }
    }

    /// The degree this scratch serves.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// Values N_{span−p+r}(t), r = 0..=p, into `out[..=p]` (\[NB\] A2.2).
    #[inline]
    pub fn values(&mut self, knots: &[f64], span: usize, t: f64, out: &mut [f64]) {
        let p = self.degree;
        out[0] = 1.0;
        for j in 1..=p {
            self.left[j] = t - knots[span + 1 - j];
            self.right[j] = knots[span + j] - t;
            let mut saved = 0.0;
            for r in 0..j {
                let temp = out[r] / (self.right[r + 1] + self.left[j - r]);
                out[r] = saved + self.right[r + 1] * temp;
                saved = self.left[j - r] * temp;
            }
            out[j] = saved;
        }
    }

    /// Derivatives of order 0..=n of the p + 1 non-vanishing functions at `t` (\[NB\] A2.3).
    ///
    /// `out[k * (p + 1) + r]` = N^{(k)}_{span−p+r}(t); derivatives above the degree are zero.
    /// Orders up to 2 take a direct route (`derivatives_upto2`); higher orders use A2.3.
    pub fn derivatives(&mut self, knots: &[f64], span: usize, t: f64, n: usize, out: &mut [f64]) {
        if n <= 2 {
            self.derivatives_upto2(knots, span, t, n, out);
        } else {
            self.derivatives_general(knots, span, t, n, out);
        }
    }

    /// Orders 0..=n ≤ 2 from the lower-degree values: with
    /// N'_{i,p} = p (N_{i,p−1}/(t_{i+p} − t_i) − N_{i+1,p−1}/(t_{i+p+1} − t_{i+1})) (\[NB\] eq. 2.7)
    /// applied once to degree p − 1 values and twice to degree p − 2 values (0/0 terms are 0).
    fn derivatives_upto2(&mut self, knots: &[f64], span: usize, t: f64, n: usize, out: &mut [f64]) {
        let p = self.degree;
        let p1 = p + 1;
        // scratch rows: degree p values, degree p − 1 values, degree p − 2 values
        let (vals, rest) = self.ndu.split_at_mut(p1);
        let (lower1, rest) = rest.split_at_mut(p1);
        let lower2 = &mut rest[..p1];
        vals[0] = 1.0;
        for j in 1..=p {
            // at the start of step j, vals[..j] holds the degree j − 1 values
            if j == p {
                lower1[..j].copy_from_slice(&vals[..j]);
            }
            if j + 1 == p {
                lower2[..j].copy_from_slice(&vals[..j]);
            }
            self.left[j] = t - knots[span + 1 - j];
            self.right[j] = knots[span + j] - t;
            let mut saved = 0.0;
            for r in 0..j {
                let temp = vals[r] / (self.right[r + 1] + self.left[j - r]);
                vals[r] = saved + self.right[r + 1] * temp;
                saved = self.left[j - r] * temp;
            }
            vals[j] = saved;
        }
        out[..p1].copy_from_slice(&vals[..p1]);
        if n == 0 {
            return;
        }
        let first = span - p; // index of the first function of degree p
        // first derivatives of degree p from degree p − 1 (row lower1, functions span−p+1..=span)
        differentiate(knots, first, p, lower1, &mut out[p1..2 * p1]);
        if n == 1 {
            return;
        }
        if p < 2 {
            out[2 * p1..3 * p1].fill(0.0);
            return;
        }
        // first derivatives of degree p − 1 (functions span−p+1..=span) from degree p − 2, then
        // of degree p from those
        let d1 = &mut self.a[..p];
        differentiate(knots, first + 1, p - 1, lower2, d1);
        differentiate(knots, first, p, d1, &mut out[2 * p1..3 * p1]);
    }

    /// Any order by \[NB\] A2.3.
    pub fn derivatives_general(
        &mut self,
        knots: &[f64],
        span: usize,
        t: f64,
        n: usize,
        out: &mut [f64],
    ) {
        let p = self.degree;
        let p1 = p + 1;
        let ndu = &mut self.ndu;
        ndu[0] = 1.0;
        for j in 1..=p {
            self.left[j] = t - knots[span + 1 - j];
            self.right[j] = knots[span + j] - t;
            let mut saved = 0.0;
            for r in 0..j {
                // lower triangle: knot differences
                ndu[j * p1 + r] = self.right[r + 1] + self.left[j - r];
                let temp = ndu[r * p1 + j - 1] / ndu[j * p1 + r];
                // upper triangle: basis values
                ndu[r * p1 + j] = saved + self.right[r + 1] * temp;
                saved = self.left[j - r] * temp;
            }
            ndu[j * p1 + j] = saved;
        }
        for j in 0..=p {
            out[j] = ndu[j * p1 + p];
        }
        let nmax = n.min(p);
        for k in (nmax + 1)..=n {
            out[k * p1..(k + 1) * p1].fill(0.0);
        }
        if nmax == 0 {
            return;
        }
        let a = &mut self.a;
        for r in 0..=p {
            let (mut s1, mut s2) = (0usize, 1usize);
            a[0] = 1.0;
            for k in 1..=nmax {
                let mut d = 0.0;
                let rk = r as isize - k as isize;
                let pk = p - k;
                if r >= k {
                    a[s2 * p1] = a[s1 * p1] / ndu[(pk + 1) * p1 + (r - k)];
                    d = a[s2 * p1] * ndu[(r - k) * p1 + pk];
                }
                let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
                let j2 = if (r as isize - 1) <= pk as isize {
                    k - 1
                } else {
                    p - r
                };
                for j in j1..=j2 {
                    let idx = (rk + j as isize) as usize;
                    a[s2 * p1 + j] =
                        (a[s1 * p1 + j] - a[s1 * p1 + j - 1]) / ndu[(pk + 1) * p1 + idx];
                    d += a[s2 * p1 + j] * ndu[idx * p1 + pk];
                }
                if r <= pk {
                    a[s2 * p1 + k] = -a[s1 * p1 + k - 1] / ndu[(pk + 1) * p1 + r];
                    d += a[s2 * p1 + k] * ndu[r * p1 + pk];
                }
                out[k * p1 + r] = d;
                std::mem::swap(&mut s1, &mut s2);
            }
        }
        let mut factor = p as f64;
        for k in 1..=nmax {
            for j in 0..=p {
                out[k * p1 + j] *= factor;
            }
            factor *= (p - k) as f64;
        }
    }
}

/// The derivatives N'_{i,d} = d (N_{i,d−1}/(t_{i+d} − t_i) − N_{i+1,d−1}/(t_{i+d+1} − t_{i+1}))
/// (\[NB\] eq. 2.7) of the d + 1 functions i = first..=first + d into `out[..=d]`, from the d
/// degree-(d − 1) values N_{first+1..=first+d, d−1} in `lower` (0/0 terms are 0).
#[inline(always)]
fn differentiate(knots: &[f64], first: usize, d: usize, lower: &[f64], out: &mut [f64]) {
    let div = |x: f64, den: f64| if den == 0.0 { 0.0 } else { x / den };
    for r in 0..=d {
        let i = first + r;
        let a = if r >= 1 {
            div(lower[r - 1], knots[i + d] - knots[i])
        } else {
            0.0
        };
        let b = if r < d {
            div(lower[r], knots[i + d + 1] - knots[i + 1])
        } else {
            0.0
        };
        out[r] = d as f64 * (a - b);
    }
}

/// Values, first and second derivatives of the P1 = p + 1 functions that do not vanish on
/// `span`, with the degree known at compile time (no scratch, no allocation): the hot path of
/// scattered evaluation. Same formulas as [`BasisEvaluator::derivatives`] for n = 2.
///
/// The quotients N_{k,d}/(t_{k+d+1} − t_k) that the last two steps of the triangular scheme
/// compute anyway are exactly the terms of the derivative formula, so the derivatives cost no
/// further division: with q1, q2 the quotients of the steps to degree p and p − 1,
/// N'_{i,p} = p (q1_{r−1} − q1_r), D_k = (p − 1)(q2_{r−1} − q2_r) (first derivatives of degree
/// p − 1) and N''_{i,p} = p (D_{r−1}/(t_{i+p} − t_i) − D_r/(t_{i+p+1} − t_{i+1})). Inside a
/// non-empty span every denominator is positive.
#[inline(always)]
pub fn derivatives2_fixed<const P1: usize>(knots: &[f64], span: usize, t: f64) -> [[f64; P1]; 3] {
    let p = P1 - 1;
    let mut left = [0.0; P1];
    let mut right = [0.0; P1];
    let mut vals = [0.0; P1];
    let mut q1 = [0.0; P1];
    let mut q2 = [0.0; P1];
    let mut inv_p = [0.0; P1];
    vals[0] = 1.0;
    for j in 1..=p {
        left[j] = t - knots[span + 1 - j];
        right[j] = knots[span + j] - t;
        let mut saved = 0.0;
        for r in 0..j {
            let inv = 1.0 / (right[r + 1] + left[j - r]);
            let temp = vals[r] * inv;
            if j == p {
                q1[r] = temp;
                inv_p[r] = inv;
            } else if j + 1 == p {
                q2[r] = temp;
            }
            vals[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        vals[j] = saved;
    }
    let pf = p as f64;
    let mut d1 = [0.0; P1];
    for r in 0..=p {
        let a = if r >= 1 { q1[r - 1] } else { 0.0 };
        let b = if r < p { q1[r] } else { 0.0 };
        d1[r] = pf * (a - b);
    }
    let mut d2 = [0.0; P1];
    if p >= 2 {
        let qf = (p - 1) as f64;
        let mut lower_d1 = [0.0; P1];
        for r in 0..p {
            let a = if r >= 1 { q2[r - 1] } else { 0.0 };
            let b = if r + 1 < p { q2[r] } else { 0.0 };
            lower_d1[r] = qf * (a - b);
        }
        for r in 0..=p {
            let a = if r >= 1 {
                lower_d1[r - 1] * inv_p[r - 1]
            } else {
                0.0
            };
            let b = if r < p { lower_d1[r] * inv_p[r] } else { 0.0 };
            d2[r] = pf * (a - b);
        }
    }
    [vals, d1, d2]
}

/// Convenience (allocating): the span of `t` and the derivatives of order 0..=n of the p + 1
/// non-vanishing basis functions, laid out as in [`BasisEvaluator::derivatives`].
pub fn basis_derivatives(knots: &KnotVector, t: f64, n: usize) -> (usize, Vec<f64>) {
    let p = knots.degree();
    let t = knots.clamp_param(t);
    let span = knots.span(t);
    let mut out = vec![0.0; (n + 1) * (p + 1)];
    BasisEvaluator::new(p).derivatives(knots.knots(), span, t, n, &mut out);
    (span, out)
}

/// Convenience (allocating): the values of all n + 1 basis functions at `t` (zeros outside the
/// span), e.g. to build a collocation matrix.
pub fn basis_row(knots: &KnotVector, t: f64) -> Vec<f64> {
    let (span, vals) = basis_derivatives(knots, t, 0);
    let p = knots.degree();
    let mut row = vec![0.0; knots.num_basis()];
    row[span - p..=span].copy_from_slice(&vals[..=p]);
    row
}

/// Derivative of order `order` of basis function `i` at `t` (allocating; for tests and setup).
pub fn basis_function_derivative(knots: &KnotVector, i: usize, t: f64, order: usize) -> f64 {
    let p = knots.degree();
    let (span, vals) = basis_derivatives(knots, t, order);
    if i + p < span || i > span {
        0.0
    } else {
        vals[order * (p + 1) + i + p - span]
    }
}

/// The integral of basis function `i` over [a, b] (zero outside its support [t_i, t_{i+p+1})):
/// Gauss–Legendre with ⌈(p + 1)/2⌉ nodes on each knot span of the support within [a, b], exact
/// for the span's polynomial of degree p (\[AS\] 25.4.29). Over the whole support the integral is
/// (t_{i+p+1} − t_i)/(p + 1), [`basis_function_mass`].
pub fn basis_function_integral(knots: &KnotVector, i: usize, a: f64, b: f64) -> f64 {
    let p = knots.degree();
    let t = knots.knots();
    if i + p + 1 >= t.len() || !(b > a) {
        return 0.0;
    }
    let rule = crate::quadrature::GaussLegendre::new((p + 2) / 2);
    let mut eval = BasisEvaluator::new(p);
    let mut vals = vec![0.0; p + 1];
    let mut sum = 0.0;
    for k in i..=i + p {
        let (x0, x1) = (t[k].max(a), t[k + 1].min(b));
        if !(x1 > x0) {
            continue;
        }
        for (x, w) in rule.on(x0, x1) {
            eval.values(t, k, x, &mut vals);
            sum += w * vals[i + p - k];
        }
    }
    sum
}

/// The integral of basis function `i` over its whole support, (t_{i+p+1} − t_i)/(p + 1) (a
/// standard identity of normalized B-splines, checked against [`basis_function_integral`] in
/// the tests).
pub fn basis_function_mass(knots: &KnotVector, i: usize) -> f64 {
    let p = knots.degree();
    let t = knots.knots();
    if i + p + 1 >= t.len() {
        return 0.0;
    }
    (t[i + p + 1] - t[i]) / (p + 1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Direct Cox–de Boor recursion, the textbook definition, as an independent reference.
    fn cox_de_boor(k: &[f64], i: usize, p: usize, t: f64) -> f64 {
        if p == 0 {
            return if k[i] <= t && t < k[i + 1] { 1.0 } else { 0.0 };
        }
        let mut v = 0.0;
        if k[i + p] > k[i] {
            v += (t - k[i]) / (k[i + p] - k[i]) * cox_de_boor(k, i, p - 1, t);
        }
        if k[i + p + 1] > k[i + 1] {
            v += (k[i + p + 1] - t) / (k[i + p + 1] - k[i + 1]) * cox_de_boor(k, i + 1, p - 1, t);
        }
        v
    }

    #[test]
    fn values_match_cox_de_boor() {
        let kv =
            KnotVector::new(3, vec![0., 0., 0., 0., 0.2, 0.5, 0.5, 0.9, 1., 1., 1., 1.]).unwrap();
        for s in 0..50 {
            let t = s as f64 / 50.0;
            let row = basis_row(&kv, t);
            for (i, &value) in row.iter().enumerate() {
                let reference = cox_de_boor(kv.knots(), i, 3, t);
                assert!((value - reference).abs() < 1e-14, "i={i} t={t}");
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let kv = KnotVector::new(
            4,
            vec![0., 0., 0., 0., 0., 0.3, 0.45, 0.8, 1., 1., 1., 1., 1.],
        )
        .unwrap();
        let h = 1e-6;
        for &t in &[0.1, 0.37, 0.6, 0.95] {
            for i in 0..kv.num_basis() {
                for order in 1..=3 {
                    let d = basis_function_derivative(&kv, i, t, order);
                    let fd = (basis_function_derivative(&kv, i, t + h, order - 1)
                        - basis_function_derivative(&kv, i, t - h, order - 1))
                        / (2.0 * h);
                    assert!(
                        (d - fd).abs() < 1e-5 * (1.0 + d.abs()),
                        "i={i} t={t} k={order}: {d} vs {fd}"
                    );
                }
            }
        }
    }

    #[test]
    fn direct_route_matches_a2_3() {
        for (p, knots) in [
            (1, vec![0., 0., 0.3, 0.45, 0.6, 1., 1.]),
            (2, vec![0., 0., 0., 0.2, 0.2, 0.5, 0.8, 1., 1., 1.]),
            (
                3,
                vec![0., 0., 0., 0., 0.1, 0.5, 0.5, 0.5, 0.9, 1., 1., 1., 1.],
            ),
            (
                5,
                vec![
                    0., 0., 0., 0., 0., 0., 0.3, 0.3, 0.7, 1., 1., 1., 1., 1., 1.,
                ],
            ),
        ] {
            let kv = KnotVector::new(p, knots).unwrap();
            let mut e = BasisEvaluator::new(p);
            for s in 0..=40 {
                let t = s as f64 / 40.0;
                let span = kv.span(t);
                let mut fast = vec![0.0; 3 * (p + 1)];
                let mut general = vec![0.0; 3 * (p + 1)];
                e.derivatives(kv.knots(), span, t, 2, &mut fast);
                e.derivatives_general(kv.knots(), span, t, 2, &mut general);
                for (a, b) in fast.iter().zip(&general) {
                    assert!(
                        (a - b).abs() < 1e-10 * (1.0 + b.abs()),
                        "p={p} t={t}: {fast:?} vs {general:?}"
                    );
                }
                let fixed: Vec<f64> = match p {
                    1 => derivatives2_fixed::<2>(kv.knots(), span, t).concat(),
                    2 => derivatives2_fixed::<3>(kv.knots(), span, t).concat(),
                    3 => derivatives2_fixed::<4>(kv.knots(), span, t).concat(),
                    _ => derivatives2_fixed::<6>(kv.knots(), span, t).concat(),
                };
                for (a, b) in fixed.iter().zip(&fast) {
                    assert!(
                        (a - b).abs() < 1e-12 * (1.0 + b.abs()),
                        "p={p} t={t}: {fixed:?} vs {fast:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn derivatives_above_degree_vanish() {
        let kv = KnotVector::clamped_uniform(2, 5).unwrap();
        let (_, d) = basis_derivatives(&kv, 0.4, 4);
        assert!(d[3 * 3..].iter().all(|&x| x == 0.0));
    }

    #[test]
    fn basis_integrals_match_closed_forms() {
        // Bernstein B_0 of degree 13 on [0, 1]: (1 − x)^13, whose integral over [0, x] is
        // (1 − (1 − x)^14)/14
        let bez = KnotVector::bezier(13).unwrap();
        for x in [0.01f64, 0.3, 0.397, 0.8, 1.0] {
            let want = (1.0 - (1.0 - x).powi(14)) / 14.0;
            let got = basis_function_integral(&bez, 0, 0.0, x);
            assert!((got - want).abs() < 1e-14, "x {x}: {got} vs {want}");
        }
        // a nonuniform cubic knot vector with a double knot: each function's whole integral is
        // (t_{i+p+1} − t_i)/(p + 1), and the functions sum to 1 over any interval
        let kv =
            KnotVector::new(3, vec![0., 0., 0., 0., 0.2, 0.5, 0.5, 0.9, 1., 1., 1., 1.]).unwrap();
        let mut sum = 0.0;
        for i in 0..kv.num_basis() {
            let whole = basis_function_integral(&kv, i, -1.0, 2.0);
            assert!(
                (whole - basis_function_mass(&kv, i)).abs() < 1e-15,
                "function {i}"
            );
            sum += basis_function_integral(&kv, i, 0.13, 0.71);
        }
        assert!((sum - 0.58).abs() < 1e-14, "partition of unity: {sum}");
        assert_eq!(basis_function_integral(&kv, 0, 0.5, 0.4), 0.0);
    }
}
