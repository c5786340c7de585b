//! The basis functions of a surface with their first and second partial derivatives at one
//! parameter pair: the rows of systems that are linear in the control points.
//!
//! R_ij(u, v) = w_ij N_i(u) M_j(v) / W(u, v), W = Σ_ij w_ij N_i M_j (\[NB\] eq. 4.16), so that
//! S = Σ R_ij P_ij and, with the weights held fixed, every derivative S_kl = Σ R_ij,kl P_ij is
//! linear in the control points. For polynomial surfaces R_ij = N_i M_j. With A_ij = w_ij N_i M_j
//! the quotient rule gives (\[NB\] eq. 4.20 applied to one function)
//! R_u = (A_u − W_u R)/W, R_uu = (A_uu − 2 W_u R_u − W_uu R)/W,
//! R_uv = (A_uv − W_u R_v − W_v R_u − W_uv R)/W (v likewise).

use crate::basis::BasisEvaluator;
use crate::surface::BSplineSurface;

/// Values and derivatives of the (p + 1)(q + 1) basis functions that do not vanish at one
/// parameter pair. Entry `a * (q + 1) + b` belongs to control point
/// (`first_u + a`, `first_v + b`).
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceBasis {
    /// u index of the first non-vanishing function
    pub first_u: usize,
    /// v index of the first non-vanishing function
    pub first_v: usize,
    /// p + 1
    pub count_u: usize,
    /// q + 1
    pub count_v: usize,
    /// R_ij
    pub value: Vec<f64>,
    /// ∂R_ij/∂u
    pub du: Vec<f64>,
    /// ∂R_ij/∂v
    pub dv: Vec<f64>,
    /// ∂²R_ij/∂u²
    pub duu: Vec<f64>,
    /// ∂²R_ij/∂u∂v
    pub duv: Vec<f64>,
    /// ∂²R_ij/∂v²
    pub dvv: Vec<f64>,
}

impl SurfaceBasis {
    /// Storage for the basis of `surface` (zeros until evaluated).
    pub fn new(surface: &BSplineSurface) -> Self {
        let (cu, cv) = (surface.degree_u() + 1, surface.degree_v() + 1);
        let zeros = vec![0.0; cu * cv];
        Self {
            first_u: 0,
            first_v: 0,
            count_u: cu,
            count_v: cv,
            value: zeros.clone(),
            du: zeros.clone(),
            dv: zeros.clone(),
            duu: zeros.clone(),
            duv: zeros.clone(),
            dvv: zeros,
        }
    }

    /// Number of non-vanishing functions, (p + 1)(q + 1).
    pub fn len(&self) -> usize {
        self.value.len()
    }

    /// Always false: a surface has at least one basis function per point.
    pub fn is_empty(&self) -> bool {
        self.value.is_empty()
    }

    /// Control indices (i, j) of entry `k`.
    #[inline]
    pub fn control_index(&self, k: usize) -> (usize, usize) {
        (
            self.first_u + k / self.count_v,
            self.first_v + k % self.count_v,
        )
    }
}

/// Evaluates [`SurfaceBasis`] at many parameters without allocating per call.
#[derive(Debug, Clone)]
pub struct SurfaceBasisEvaluator<'a> {
    surface: &'a BSplineSurface,
    basis_u: BasisEvaluator,
    basis_v: BasisEvaluator,
    ders_u: Vec<f64>,
    ders_v: Vec<f64>,
}

impl<'a> SurfaceBasisEvaluator<'a> {
    /// Scratch for `surface`.
    pub fn new(surface: &'a BSplineSurface) -> Self {
        let (p, q) = (surface.degree_u(), surface.degree_v());
        Self {
            surface,
            basis_u: BasisEvaluator::new(p),
            basis_v: BasisEvaluator::new(q),
            ders_u: vec![0.0; 3 * (p + 1)],
            ders_v: vec![0.0; 3 * (q + 1)],
        }
    }

    /// The basis and its derivatives up to order 2 at (u, v), clamped into the domain, into
    /// `out` (which must come from [`SurfaceBasis::new`] for the same surface).
    pub fn eval(&mut self, u: f64, v: f64, out: &mut SurfaceBasis) {
        let s = self.surface;
        let (ku, kv) = (s.knots_u(), s.knots_v());
        let (u, v) = (ku.clamp_param(u), kv.clamp_param(v));
        let (su, sv) = (ku.span(u), kv.span(v));
        self.basis_u
            .derivatives(ku.knots(), su, u, 2, &mut self.ders_u);
        self.basis_v
            .derivatives(kv.knots(), sv, v, 2, &mut self.ders_v);
        self.eval_from((su, sv), &self.ders_u, &self.ders_v, out);
    }

    /// [`Self::eval`] at a point of spans (`su`, `sv`) from the derivatives of orders 0..=2 of
    /// the p + 1 (q + 1) univariate functions there, laid out as [`BasisEvaluator::derivatives`]
    /// writes them: for tensor grids of points (quadrature), whose univariate derivatives depend
    /// on one coordinate each and are computed once per node instead of once per point. The
    /// same values as [`Self::eval`] at that point, bit for bit.
    pub fn eval_from(
        &self,
        (su, sv): (usize, usize),
        ders_u: &[f64],
        ders_v: &[f64],
        out: &mut SurfaceBasis,
    ) {
        let s = self.surface;
        let (p, q) = (s.degree_u(), s.degree_v());
        let (cu, cv) = (p + 1, q + 1);
        out.first_u = su - p;
        out.first_v = sv - q;
        out.count_u = cu;
        out.count_v = cv;
        let (nu, nv) = (ders_u, ders_v);
        for a in 0..cu {
            for b in 0..cv {
                let k = a * cv + b;
                out.value[k] = nu[a] * nv[b];
                out.du[k] = nu[cu + a] * nv[b];
                out.dv[k] = nu[a] * nv[cv + b];
                out.duu[k] = nu[2 * cu + a] * nv[b];
                out.duv[k] = nu[cu + a] * nv[cv + b];
                out.dvv[k] = nu[a] * nv[2 * cv + b];
            }
        }
        let Some(weights) = s.weights() else {
            return;
        };
        let n_v = s.num_v();
        // A_ij = w_ij N_i M_j and the derivatives of W = Σ A_ij
        let mut w = [0.0f64; 6];
        for k in 0..cu * cv {
            let wk = weights[(out.first_u + k / cv) * n_v + out.first_v + k % cv];
            out.value[k] *= wk;
            out.du[k] *= wk;
            out.dv[k] *= wk;
            out.duu[k] *= wk;
            out.duv[k] *= wk;
            out.dvv[k] *= wk;
            w[0] += out.value[k];
            w[1] += out.du[k];
            w[2] += out.dv[k];
            w[3] += out.duu[k];
            w[4] += out.duv[k];
            w[5] += out.dvv[k];
        }
        for k in 0..cu * cv {
            let r = out.value[k] / w[0];
            let ru = (out.du[k] - w[1] * r) / w[0];
            let rv = (out.dv[k] - w[2] * r) / w[0];
            out.duu[k] = (out.duu[k] - 2.0 * w[1] * ru - w[3] * r) / w[0];
            out.duv[k] = (out.duv[k] - w[1] * rv - w[2] * ru - w[4] * r) / w[0];
            out.dvv[k] = (out.dvv[k] - 2.0 * w[2] * rv - w[5] * r) / w[0];
            out.value[k] = r;
            out.du[k] = ru;
            out.dv[k] = rv;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Vector3;
    use crate::testing::random_surface;

    fn combine(basis: &SurfaceBasis, s: &BSplineSurface, field: &[f64]) -> Vector3 {
        (0..basis.len())
            .map(|k| {
                let (i, j) = basis.control_index(k);
                field[k] * s.control_point(i, j).coords
            })
            .sum()
    }

    #[test]
    fn rows_reproduce_the_evaluator_for_random_surfaces() {
        for seed in 0..12 {
            let s = random_surface(seed, 1..=5, 9, seed % 2 == 0);
            let mut basis = SurfaceBasis::new(&s);
            let mut be = SurfaceBasisEvaluator::new(&s);
            let mut ev = s.evaluator();
            let scale = s.size().max(1.0);
            for a in 0..7 {
                for b in 0..7 {
                    let (u, v) = (a as f64 / 6.0, b as f64 / 6.0);
                    be.eval(u, v, &mut basis);
                    let d = ev.derivatives(u, v);
                    let sum: f64 = basis.value.iter().sum();
                    assert!((sum - 1.0).abs() < 1e-12, "partition of unity {sum}");
                    for (field, want, what) in [
                        (&basis.value, d.point.coords, "S"),
                        (&basis.du, d.du, "S_u"),
                        (&basis.dv, d.dv, "S_v"),
                        (&basis.duu, d.duu, "S_uu"),
                        (&basis.duv, d.duv, "S_uv"),
                        (&basis.dvv, d.dvv, "S_vv"),
                    ] {
                        let got = combine(&basis, &s, field);
                        let tol = 1e-9 * scale * (1.0 + want.norm());
                        assert!(
                            (got - want).norm() <= tol,
                            "seed {seed} {what} at ({u}, {v}): {got:?} vs {want:?}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn entries_name_their_control_points() {
        let s = random_surface(3, 3..=3, 8, false);
        let mut basis = SurfaceBasis::new(&s);
        SurfaceBasisEvaluator::new(&s).eval(0.5, 0.5, &mut basis);
        let p = basis.control_index(0);
        assert_eq!(p, (basis.first_u, basis.first_v));
        let last = basis.control_index(basis.len() - 1);
        assert_eq!(last, (basis.first_u + 3, basis.first_v + 3));
    }
}
