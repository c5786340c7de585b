//! The fairness functional as a quadratic form in the control points, K = Σ_t α_t A_t ⊗ B_t.
//!
//! Thin plate (\[H\] slide "Fairness criterion", linearized with a = b = 1):
//! Π = ∬ |X_uu|² + 2|X_uv|² + |X_vv|² du dv = Σ_c x_cᵀ (U²²⊗V⁰⁰ + 2 U¹¹⊗V¹¹ + U⁰⁰⊗V²²) x_c,
//! with the Gram integrals U^{a,b}_{ik} = ∫ N_i^{(a)} N_k^{(b)} du of nurbs-core's [`gram_matrix`]
//! (banded, half-bandwidth p). Curves: ∫ |x''|² + β |x'''|² dt = Σ_c x_cᵀ (G²² + β G³³) x_c, stored
//! as a surface with one column (B = `[1]`).
//!
//! Bézier-spline extension (\[H\] slide "Fairness criterion: Thin-plate energy + continuity"):
//! Φ = (1 − λ) Π + λ Σ_{u_i: mult = p} ∫ |X_u(u_i⁻, v) − X_u(u_i⁺, v)|² dv + (same in v). The jump of
//! X_u across u_i is Σ_k c_k d_kj N_j(v) with c_k = N_k'(u_i⁻) − N_k'(u_i⁺), so the term is
//! (Σ_i c cᵀ) ⊗ V⁰⁰ — one more separable term per direction.
//!
//! # Deviation from the paper
//! \[H\] sums the squared jumps at the v-knots; we integrate them over v (the V⁰⁰ Gram matrix), which
//! does not depend on where knots happen to lie and keeps Φ separable.

use nurbs_core::{BandedMatrix, KnotVector, Point3, Vector3, gram_matrix};

use crate::error::{EnergyError, Result};
use crate::joints::knot_joints;
use crate::local::LocalStiffness;

/// A square band matrix stored row by row: entry (i, k) at `i·(2w + 1) + k + w − i`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Band {
    n: usize,
    w: usize,
    data: Vec<f64>,
}

impl Band {
    fn from_banded(m: &BandedMatrix) -> Self {
        let (n, w) = (m.dim(), m.half_bandwidth());
        let mut data = vec![0.0; n * (2 * w + 1)];
        for i in 0..n {
            for k in i.saturating_sub(w)..(i + w + 1).min(n) {
                data[i * (2 * w + 1) + k + w - i] = m.get(i, k);
            }
        }
        Self { n, w, data }
    }

    fn identity_1x1() -> Self {
        Self {
            n: 1,
            w: 0,
            data: vec![1.0],
        }
    }

    /// Entry (i, k), which must satisfy |i − k| ≤ w.
    #[inline(always)]
    fn at(&self, i: usize, k: usize) -> f64 {
        self.data[i * (2 * self.w + 1) + k + self.w - i]
    }

    /// Entry (i, k), zero outside the band.
    #[inline]
    fn get(&self, i: usize, k: usize) -> f64 {
        if i.abs_diff(k) <= self.w && i < self.n && k < self.n {
            self.at(i, k)
        } else {
            0.0
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
struct Term {
    alpha: f64,
    a: Band,
    b: Band,
}

/// Largest number of separable terms (thin plate 3 + two joint terms).
pub(crate) const MAX_TERMS: usize = 5;

/// Σ_t a[t] b[t]: one entry of K from its u- and v-factors.
#[inline(always)]
pub(crate) fn kron(a: &[f64; MAX_TERMS], b: &[f64; MAX_TERMS]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] + a[4] * b[4]
}

/// K = Σ_t α_t A_t ⊗ B_t over an n_u × n_v control net (flat index i·n_v + j).
#[derive(Debug, Clone, PartialEq)]
pub struct SeparableStiffness {
    nu: usize,
    nv: usize,
    wu: usize,
    wv: usize,
    terms: Vec<Term>,
}

/// The jump matrix Σ_i c cᵀ over the interior knots of full multiplicity (= degree), with
/// c_k = N_k'(u_i⁻) − N_k'(u_i⁺) non-zero for k = j − 1, j, j + 1 only ([`crate::joints`]);
/// `None` when there is no such knot.
fn joint_jumps(knots: &KnotVector) -> Option<Band> {
    let joints = knot_joints(knots);
    if joints.is_empty() {
        return None;
    }
    let n = knots.num_basis();
    let w = 2;
    let mut band = Band {
        n,
        w,
        data: vec![0.0; n * (2 * w + 1)],
    };
    for joint in &joints {
        let lo = joint.index - 1;
        for (a, &ca) in joint.c.iter().enumerate() {
            for (b, &cb) in joint.c.iter().enumerate() {
                let (i, k) = (lo + a, lo + b);
                if i < n && k < n {
                    band.data[i * (2 * w + 1) + k + w - i] += ca * cb;
                }
            }
        }
    }
    Some(band)
}

impl SeparableStiffness {
    /// The thin-plate functional Π of a surface with these knot vectors.
    pub fn thin_plate(knots_u: &KnotVector, knots_v: &KnotVector) -> Result<Self> {
        let u: Vec<Band> = (0..3)
            .map(|a| gram_matrix(knots_u, a, a).map(|m| Band::from_banded(&m)))
            .collect::<Result<_, _>>()?;
        let v: Vec<Band> = (0..3)
            .map(|a| gram_matrix(knots_v, a, a).map(|m| Band::from_banded(&m)))
            .collect::<Result<_, _>>()?;
        let terms = vec![
            Term {
                alpha: 1.0,
                a: u[2].clone(),
                b: v[0].clone(),
            },
            Term {
                alpha: 2.0,
                a: u[1].clone(),
                b: v[1].clone(),
            },
            Term {
                alpha: 1.0,
                a: u[0].clone(),
                b: v[2].clone(),
            },
        ];
        Ok(Self::from_terms(
            knots_u.num_basis(),
            knots_v.num_basis(),
            terms,
        ))
    }

    /// The Bézier-spline functional Φ = (1 − λ) Π + λ (cross-derivative jumps at interior knots of
    /// full multiplicity), 0 ≤ λ < 1. Without such knots Φ = (1 − λ) Π.
    pub fn with_joints(knots_u: &KnotVector, knots_v: &KnotVector, lambda: f64) -> Result<Self> {
        if !(0.0..1.0).contains(&lambda) {
            return Err(EnergyError::InvalidParameter {
                name: "joint_weight",
                value: lambda,
                expected: "in [0, 1)",
            });
        }
        let mut k = Self::thin_plate(knots_u, knots_v)?;
        if lambda == 0.0 {
            return Ok(k);
        }
        for t in &mut k.terms {
            t.alpha *= 1.0 - lambda;
        }
        if let Some(ju) = joint_jumps(knots_u) {
            let v00 = Band::from_banded(&gram_matrix(knots_v, 0, 0)?);
            k.terms.push(Term {
                alpha: lambda,
                a: ju,
                b: v00,
            });
        }
        if let Some(jv) = joint_jumps(knots_v) {
            let u00 = Band::from_banded(&gram_matrix(knots_u, 0, 0)?);
            k.terms.push(Term {
                alpha: lambda,
                a: u00,
                b: jv,
            });
        }
        Ok(Self::from_terms(k.nu, k.nv, k.terms))
    }

    /// The curve functional ∫ |x''|² + β |x'''|² (β ≥ 0) as an n × 1 net.
    pub fn curve(knots: &KnotVector, third_weight: f64) -> Result<Self> {
        if !(third_weight.is_finite() && third_weight >= 0.0) {
            return Err(EnergyError::InvalidParameter {
                name: "third_derivative_weight",
                value: third_weight,
                expected: "finite and ≥ 0",
            });
        }
        let mut terms = vec![Term {
            alpha: 1.0,
            a: Band::from_banded(&gram_matrix(knots, 2, 2)?),
            b: Band::identity_1x1(),
        }];
        if third_weight > 0.0 {
            terms.push(Term {
                alpha: third_weight,
                a: Band::from_banded(&gram_matrix(knots, 3, 3)?),
                b: Band::identity_1x1(),
            });
        }
        Ok(Self::from_terms(knots.num_basis(), 1, terms))
    }

    fn from_terms(nu: usize, nv: usize, terms: Vec<Term>) -> Self {
        let wu = terms.iter().map(|t| t.a.w).max().unwrap_or(0);
        let wv = terms.iter().map(|t| t.b.w).max().unwrap_or(0);
        Self {
            nu,
            nv,
            wu,
            wv,
            terms,
        }
    }

    /// Control points in u.
    pub fn num_u(&self) -> usize {
        self.nu
    }
    /// Control points in v.
    pub fn num_v(&self) -> usize {
        self.nv
    }
    /// Stencil half-widths (w_u, w_v): K couples (i, j) and (k, l) only when |i − k| ≤ w_u and
    /// |j − l| ≤ w_v.
    pub fn stencil(&self) -> (usize, usize) {
        (self.wu, self.wv)
    }

    /// Entry K_{(i,j),(k,l)}.
    pub fn entry(&self, (i, j): (usize, usize), (k, l): (usize, usize)) -> f64 {
        self.terms
            .iter()
            .map(|t| t.alpha * t.a.get(i, k) * t.b.get(j, l))
            .sum()
    }

    /// Rows i (or columns j) within the stencil of k.
    #[inline]
    pub(crate) fn range_u(&self, k: usize) -> (usize, usize) {
        (k.saturating_sub(self.wu), (k + self.wu).min(self.nu - 1))
    }
    #[inline]
    pub(crate) fn range_v(&self, l: usize) -> (usize, usize) {
        (l.saturating_sub(self.wv), (l + self.wv).min(self.nv - 1))
    }

    /// Fills `fa[i − i0][t] = α_t A_t(i, k)` for i in the u-stencil of k (zero for t ≥ terms), so
    /// that K_{(i,j),(k,l)} = Σ_t fa[i − i0][t] · fb[j − j0][t].
    #[inline]
    pub(crate) fn factors_u(&self, k: usize, fa: &mut [[f64; MAX_TERMS]]) {
        let (i0, i1) = self.range_u(k);
        for (i, f) in (i0..=i1).zip(fa.iter_mut()) {
            *f = [0.0; MAX_TERMS];
            for (t, term) in self.terms.iter().enumerate() {
                f[t] = term.alpha * term.a.get(i, k);
            }
        }
    }
    /// Fills `fb[j − j0][t] = B_t(j, l)` for j in the v-stencil of l (zero for t ≥ terms).
    #[inline]
    pub(crate) fn factors_v(&self, l: usize, fb: &mut [[f64; MAX_TERMS]]) {
        let (j0, j1) = self.range_v(l);
        for (j, f) in (j0..=j1).zip(fb.iter_mut()) {
            *f = [0.0; MAX_TERMS];
            for (t, term) in self.terms.iter().enumerate() {
                f[t] = term.b.get(j, l);
            }
        }
    }

    /// g = K d (one vector per control point).
    pub fn multiply(&self, d: &[Point3], g: &mut [Vector3]) {
        let mut fa = vec![[0.0; MAX_TERMS]; 2 * self.wu + 1];
        let mut fb = vec![[0.0; MAX_TERMS]; 2 * self.wv + 1];
        for k in 0..self.nu {
            self.factors_u(k, &mut fa);
            let (i0, i1) = self.range_u(k);
            for l in 0..self.nv {
                self.factors_v(l, &mut fb);
                let (j0, j1) = self.range_v(l);
                let mut acc = Vector3::zeros();
                for (i, fi) in (i0..=i1).zip(&fa) {
                    let row = &d[i * self.nv + j0..=i * self.nv + j1];
                    for (p, fj) in row.iter().zip(&fb) {
                        acc += kron(fi, fj) * p.coords;
                    }
                }
                g[k * self.nv + l] = acc;
            }
        }
    }

    /// The functional's value Σ_c x_cᵀ K x_c.
    pub fn energy(&self, d: &[Point3]) -> f64 {
        let mut g = vec![Vector3::zeros(); d.len()];
        self.multiply(d, &mut g);
        d.iter().zip(&g).map(|(p, v)| p.coords.dot(v)).sum()
    }
}

/// The u- and v-factors of one point's stencil ([`SeparableStiffness::factors_u`],
/// [`SeparableStiffness::factors_v`]).
pub(crate) struct Factors {
    fa: Vec<[f64; MAX_TERMS]>,
    fb: Vec<[f64; MAX_TERMS]>,
}

impl LocalStiffness for SeparableStiffness {
    type Stencil = Factors;

    #[inline]
    fn shape(&self) -> (usize, usize) {
        (self.nu, self.nv)
    }
    #[inline]
    fn half_widths(&self) -> (usize, usize) {
        (self.wu, self.wv)
    }
    fn diagonal(&self, r: usize) -> f64 {
        let (i, j) = (r / self.nv, r % self.nv);
        self.entry((i, j), (i, j))
    }
    fn multiply(&self, d: &[Point3], g: &mut [Vector3]) {
        SeparableStiffness::multiply(self, d, g);
    }
    fn entry(&self, r: (usize, usize), s: (usize, usize)) -> f64 {
        SeparableStiffness::entry(self, r, s)
    }
    fn new_stencil(&self) -> Factors {
        Factors {
            fa: vec![[0.0; MAX_TERMS]; 2 * self.wu + 1],
            fb: vec![[0.0; MAX_TERMS]; 2 * self.wv + 1],
        }
    }
    #[inline]
    fn load(&self, k: usize, l: usize, st: &mut Factors) {
        self.factors_u(k, &mut st.fa);
        self.factors_v(l, &mut st.fb);
    }
    #[inline(always)]
    fn row(&self, st: &Factors, a: usize) -> impl Iterator<Item = f64> {
        let fi = &st.fa[a];
        st.fb.iter().map(move |fj| kron(fi, fj))
    }
}
