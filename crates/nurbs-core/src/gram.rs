//! Gram integrals of B-spline basis derivatives, as banded matrices.
//!
//! G^{a,b}_{ij} = ∫_{t_p}^{t_{n+1}} N_i^{(a)}(t) N_j^{(b)}(t) dt, a, b ≤ 3 (\[H\] slide "energy"; the
//! U^{a,b} and V^{a,b} of the local energy fairing seed). The integrand is a polynomial of degree
//! ≤ 2p − a − b on each knot span, so p + 1 Gauss–Legendre points per span make the integral exact
//! up to rounding. N_i and N_j overlap only when |i − j| ≤ p: the matrix is banded with
//! half-bandwidth p.
//!
//! The thin-plate energy of a polynomial surface with coordinate nets X (n_u × n_v, one per
//! coordinate) is Σ_c x_cᵀ (U²²⊗V⁰⁰ + 2 U¹¹⊗V¹¹ + U⁰⁰⊗V²²) x_c (\[SV\] §5, \[H\]).

use crate::basis::BasisEvaluator;
use crate::error::{Error, Result};
use crate::knots::KnotVector;
use crate::quadrature::GaussLegendre;

/// Highest derivative order of a Gram integral.
pub(crate) const MAX_GRAM_ORDER: usize = 3;

/// A square matrix stored by diagonals: entry (i, j) with |i − j| ≤ `half_bandwidth`.
#[derive(Debug, Clone, PartialEq)]
pub struct BandedMatrix {
    n: usize,
    half_bandwidth: usize,
    data: Vec<f64>,
}

impl BandedMatrix {
    /// A zero n × n matrix with half-bandwidth `w`.
    pub fn zeros(n: usize, w: usize) -> Self {
        Self {
            n,
            half_bandwidth: w,
            data: vec![0.0; n * (2 * w + 1)],
        }
    }
    /// Dimension n.
    pub fn dim(&self) -> usize {
        self.n
    }
    /// Half-bandwidth w.
    pub fn half_bandwidth(&self) -> usize {
        self.half_bandwidth
    }
    #[inline]
    fn slot(&self, i: usize, j: usize) -> Option<usize> {
        let w = self.half_bandwidth;
        (i < self.n && j < self.n && i + w >= j && j + w >= i)
            .then(|| i * (2 * w + 1) + (j + w - i))
    }
    /// Entry (i, j); zero outside the band.
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.slot(i, j).map_or(0.0, |k| self.data[k])
    }
    /// Adds `x` to entry (i, j) (must lie in the band).
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, x: f64) {
        let k = self.slot(i, j).expect("entry outside the band");
        self.data[k] += x;
    }
    /// Dense copy.
    pub fn to_dense(&self) -> nalgebra::DMatrix<f64> {
        nalgebra::DMatrix::from_fn(self.n, self.n, |i, j| self.get(i, j))
    }
}

/// G^{a,b} of `knots` over its domain (a, b ≤ 3).
pub fn gram_matrix(knots: &KnotVector, a: usize, b: usize) -> Result<BandedMatrix> {
    if a > MAX_GRAM_ORDER || b > MAX_GRAM_ORDER {
        return Err(Error::InvalidDegree { degree: a.max(b) });
    }
    let p = knots.degree();
    let n = knots.num_basis();
    let order = a.max(b);
    let rule = GaussLegendre::new(p + 1);
    let mut eval = BasisEvaluator::new(p);
    let mut ders = vec![0.0; (order + 1) * (p + 1)];
    let mut g = BandedMatrix::zeros(n, p);
    let k = knots.knots();
    for span in knots.spans() {
        for (t, w) in rule.on(k[span], k[span + 1]) {
            eval.derivatives(k, span, t, order, &mut ders);
            for r in 0..=p {
                let da = ders[a * (p + 1) + r];
                if da == 0.0 {
                    continue;
                }
                for c in 0..=p {
                    g.add(span - p + r, span - p + c, w * da * ders[b * (p + 1) + c]);
                }
            }
        }
    }
    Ok(g)
}

/// The Gram matrices a surface's thin-plate energy needs: U^{aa} and V^{aa} for a = 0, 1, 2.
#[derive(Debug, Clone, PartialEq)]
pub struct ThinPlateGram {
    /// U^{00}, U^{11}, U^{22}
    pub u: [BandedMatrix; 3],
    /// V^{00}, V^{11}, V^{22}
    pub v: [BandedMatrix; 3],
}

impl ThinPlateGram {
    /// Gram matrices of the two knot vectors.
    pub fn new(knots_u: &KnotVector, knots_v: &KnotVector) -> Result<Self> {
        Ok(Self {
            u: [
                gram_matrix(knots_u, 0, 0)?,
                gram_matrix(knots_u, 1, 1)?,
                gram_matrix(knots_u, 2, 2)?,
            ],
            v: [
                gram_matrix(knots_v, 0, 0)?,
                gram_matrix(knots_v, 1, 1)?,
                gram_matrix(knots_v, 2, 2)?,
            ],
        })
    }

    /// Entry of the thin-plate stiffness K = U²²⊗V⁰⁰ + 2 U¹¹⊗V¹¹ + U⁰⁰⊗V²² between control points
    /// (i, j) and (k, l).
    #[inline]
    pub fn stiffness(&self, (i, j): (usize, usize), (k, l): (usize, usize)) -> f64 {
        self.u[2].get(i, k) * self.v[0].get(j, l)
            + 2.0 * self.u[1].get(i, k) * self.v[1].get(j, l)
            + self.u[0].get(i, k) * self.v[2].get(j, l)
    }
}
