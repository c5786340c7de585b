//! Tensor-product B-spline and NURBS surfaces in 3D: storage and point evaluation.
//!
//! S(u, v) = Σ_i Σ_j N_i(u) M_j(v) w_ij P_ij / Σ_i Σ_j N_i(u) M_j(v) w_ij (\[NB\] eq. 4.15). The control
//! net is stored flat, `P[i * n_v + j]`, i over u (rows), j over v (columns). Derivatives of order
//! ≤ 2 come from the homogeneous derivatives A_kl, w_kl by the quotient rule (\[NB\] A4.4, eq. 4.20):
//! S_kl = (A_kl − Σ_{j≥1} C(l,j) w_0j S_{k,l−j} − Σ_{i≥1} C(k,i) w_i0 S_{k−i,l}
//!        − Σ_{i≥1} C(k,i) Σ_{j≥1} C(l,j) w_ij S_{k−i,l−j}) / w_00.

use crate::basis::BasisEvaluator;
use crate::error::{Error, Result};
use crate::knots::KnotVector;
use crate::{Point3, Vector3};

/// A (possibly rational) tensor-product B-spline surface in 3D.
#[derive(Debug, Clone, PartialEq)]
pub struct BSplineSurface {
    pub(crate) knots_u: KnotVector,
    pub(crate) knots_v: KnotVector,
    pub(crate) points: Vec<Point3>,
    pub(crate) weights: Option<Vec<f64>>,
}

/// Point and partial derivatives up to order 2 at one parameter pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceDerivatives {
    /// S(u, v)
    pub point: Point3,
    /// ∂S/∂u
    pub du: Vector3,
    /// ∂S/∂v
    pub dv: Vector3,
    /// ∂²S/∂u²
    pub duu: Vector3,
    /// ∂²S/∂u∂v
    pub duv: Vector3,
    /// ∂²S/∂v²
    pub dvv: Vector3,
}

impl Default for SurfaceDerivatives {
    fn default() -> Self {
        Self {
            point: Point3::origin(),
            du: Vector3::zeros(),
            dv: Vector3::zeros(),
            duu: Vector3::zeros(),
            duv: Vector3::zeros(),
            dvv: Vector3::zeros(),
        }
    }
}

impl BSplineSurface {
    /// Validates and builds a surface. `points` is the flat control net (i over u, j over v) of
    /// `knots_u.num_basis() × knots_v.num_basis()` points; `weights` (optional) has the same
    /// shape, finite and > 0.
    pub fn new(
        knots_u: KnotVector,
        knots_v: KnotVector,
        points: Vec<Point3>,
        weights: Option<Vec<f64>>,
    ) -> Result<Self> {
        let (nu, nv) = (knots_u.num_basis(), knots_v.num_basis());
        if points.len() != nu * nv {
            return Err(Error::ControlNetShape {
                detail: format!(
                    "{} control points, but the knot vectors need {nu}×{nv} = {}",
                    points.len(),
                    nu * nv
                ),
            });
        }
        for (k, p) in points.iter().enumerate() {
            if !p.coords.iter().all(|c| c.is_finite()) {
                return Err(Error::NonFiniteControlPoint {
                    i: k / nv,
                    j: k % nv,
                });
            }
        }
        if let Some(w) = &weights {
            if w.len() != nu * nv {
                return Err(Error::ControlNetShape {
                    detail: format!("{} weights for {nu}×{nv} control points", w.len()),
                });
            }
            for (k, &value) in w.iter().enumerate() {
                if !(value.is_finite() && value > 0.0) {
                    return Err(Error::InvalidWeight {
                        i: k / nv,
                        j: k % nv,
                        value,
                    });
                }
            }
        }
        Ok(Self {
            knots_u,
            knots_v,
            points,
            weights,
        })
    }

    /// Builds a surface from a homogeneous net (w·x, w·y, w·z, w), flat as the control net;
    /// polynomial when every weight is exactly 1.
    pub fn from_homogeneous(
        knots_u: KnotVector,
        knots_v: KnotVector,
        pw: &[[f64; 4]],
    ) -> Result<Self> {
        let (points, weights) = crate::homogeneous::split(pw);
        Self::new(knots_u, knots_v, points, weights)
    }

    /// Builds a surface from a homogeneous net, rational or polynomial as told (see
    /// [`crate::homogeneous::split_as`]).
    pub fn from_homogeneous_as(
        knots_u: KnotVector,
        knots_v: KnotVector,
        pw: &[[f64; 4]],
        rational: bool,
    ) -> Result<Self> {
        let (points, weights) = crate::homogeneous::split_as(pw, rational);
        Self::new(knots_u, knots_v, points, weights)
    }

    /// The homogeneous control net, flat.
    pub fn homogeneous(&self) -> Vec<[f64; 4]> {
        crate::homogeneous::join(&self.points, self.weights.as_deref())
    }

    /// Knot vector in u.
    pub fn knots_u(&self) -> &KnotVector {
        &self.knots_u
    }
    /// Knot vector in v.
    pub fn knots_v(&self) -> &KnotVector {
        &self.knots_v
    }
    /// Degree in u.
    pub fn degree_u(&self) -> usize {
        self.knots_u.degree()
    }
    /// Degree in v.
    pub fn degree_v(&self) -> usize {
        self.knots_v.degree()
    }
    /// Number of control points in u (rows).
    pub fn num_u(&self) -> usize {
        self.knots_u.num_basis()
    }
    /// Number of control points in v (columns).
    pub fn num_v(&self) -> usize {
        self.knots_v.num_basis()
    }
    /// Flat index of control point (i, j).
    #[inline]
    pub fn index(&self, i: usize, j: usize) -> usize {
        i * self.num_v() + j
    }
    /// Control point (i, j).
    pub fn control_point(&self, i: usize, j: usize) -> Point3 {
        self.points[self.index(i, j)]
    }
    /// The flat control net.
    pub fn control_points(&self) -> &[Point3] {
        &self.points
    }
    /// Mutable flat control net (knots and weights stay; keep coordinates finite).
    pub fn control_points_mut(&mut self) -> &mut [Point3] {
        &mut self.points
    }
    /// Weights, `None` for a polynomial surface.
    pub fn weights(&self) -> Option<&[f64]> {
        self.weights.as_deref()
    }
    /// Weight of control point (i, j) (1 for polynomial surfaces).
    pub fn weight(&self, i: usize, j: usize) -> f64 {
        self.weights.as_ref().map_or(1.0, |w| w[self.index(i, j)])
    }
    /// True when weights are present.
    pub fn is_rational(&self) -> bool {
        self.weights.is_some()
    }
    /// Domain in u.
    pub fn domain_u(&self) -> (f64, f64) {
        self.knots_u.domain()
    }
    /// Domain in v.
    pub fn domain_v(&self) -> (f64, f64) {
        self.knots_v.domain()
    }
    /// Diagonal of the control net's bounding box: the size used to scale tolerances.
    pub fn size(&self) -> f64 {
        crate::homogeneous::bounding_diagonal(&self.points)
    }

    /// An evaluator with its own scratch space, for hot loops.
    pub fn evaluator(&self) -> SurfaceEvaluator<'_> {
        SurfaceEvaluator::new(self)
    }

    /// Point and derivatives up to order 2 at (u, v); parameters are clamped into the domain.
    pub fn derivatives(&self, u: f64, v: f64) -> SurfaceDerivatives {
        self.evaluator().derivatives(u, v)
    }

    /// The point S(u, v); parameters are clamped into the domain.
    pub fn point(&self, u: f64, v: f64) -> Point3 {
        self.evaluator().point(u, v)
    }
}

/// Evaluates one surface at many scattered parameters without allocating per call.
#[derive(Debug, Clone)]
pub struct SurfaceEvaluator<'a> {
    surface: &'a BSplineSurface,
    basis_u: BasisEvaluator,
    basis_v: BasisEvaluator,
    ders_u: Vec<f64>,
    ders_v: Vec<f64>,
}

impl<'a> SurfaceEvaluator<'a> {
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

    /// The surface evaluated.
    pub fn surface(&self) -> &'a BSplineSurface {
        self.surface
    }

    /// Point and derivatives up to order 2 at (u, v), clamped into the domain.
    ///
    /// Degrees 1–5 in both directions take a path specialized at compile time.
    #[inline]
    pub fn derivatives(&mut self, u: f64, v: f64) -> SurfaceDerivatives {
        let s = self.surface;
        macro_rules! dispatch {
            ($($p:literal => [$($q:literal),*]),*) => {
                match (s.degree_u() + 1, s.degree_v() + 1) {
                    $($( ($p, $q) => derivatives_fixed::<$p, $q>(s, u, v), )*)*
                    _ => self.evaluate(u, v, 2),
                }
            };
        }
        dispatch!(2 => [2, 3, 4, 5, 6], 3 => [2, 3, 4, 5, 6], 4 => [2, 3, 4, 5, 6], 5 => [2, 3, 4, 5, 6], 6 => [2, 3, 4, 5, 6])
    }

    /// The point S(u, v), clamped into the domain.
    pub fn point(&mut self, u: f64, v: f64) -> Point3 {
        self.evaluate(u, v, 0).point
    }

    /// Point and derivatives up to `order` ≤ 2 (higher entries zero).
    pub fn evaluate(&mut self, u: f64, v: f64, order: usize) -> SurfaceDerivatives {
        let s = self.surface;
        let (p, q) = (s.degree_u(), s.degree_v());
        let u = s.knots_u.clamp_param(u);
        let v = s.knots_v.clamp_param(v);
        let su = s.knots_u.span(u);
        let sv = s.knots_v.span(v);
        let nu_ders = &mut self.ders_u[..(order + 1) * (p + 1)];
        let nv_ders = &mut self.ders_v[..(order + 1) * (q + 1)];
        if order == 0 {
            self.basis_u.values(s.knots_u.knots(), su, u, nu_ders);
            self.basis_v.values(s.knots_v.knots(), sv, v, nv_ders);
        } else {
            self.basis_u
                .derivatives(s.knots_u.knots(), su, u, order, nu_ders);
            self.basis_v
                .derivatives(s.knots_v.knots(), sv, v, order, nv_ders);
        }
        let nv = s.num_v();
        let mut a = [[0.0f64; 4]; 6];
        // a index: 0 = 00, 1 = 10, 2 = 01, 3 = 20, 4 = 11, 5 = 02
        for r in 0..=p {
            let row = (su - p + r) * nv + sv - q;
            let mut t = [[0.0f64; 4]; 3];
            match &s.weights {
                None => {
                    for (c, pt) in s.points[row..=row + q].iter().enumerate() {
                        for l in 0..=order {
                            let b = nv_ders[l * (q + 1) + c];
                            t[l][0] += b * pt.x;
                            t[l][1] += b * pt.y;
                            t[l][2] += b * pt.z;
                        }
                    }
                }
                Some(weights) => {
                    for c in 0..=q {
                        let (pt, w) = (&s.points[row + c], weights[row + c]);
                        let h = [pt.x * w, pt.y * w, pt.z * w, w];
                        for l in 0..=order {
                            let b = nv_ders[l * (q + 1) + c];
                            for d in 0..4 {
                                t[l][d] += b * h[d];
                            }
                        }
                    }
                }
            }
            let n0 = nu_ders[r];
            for d in 0..4 {
                a[0][d] += n0 * t[0][d];
            }
            if order >= 1 {
                let n1 = nu_ders[(p + 1) + r];
                for d in 0..4 {
                    a[1][d] += n1 * t[0][d];
                    a[2][d] += n0 * t[1][d];
                }
            }
            if order >= 2 {
                let n1 = nu_ders[(p + 1) + r];
                let n2 = nu_ders[2 * (p + 1) + r];
                for d in 0..4 {
                    a[3][d] += n2 * t[0][d];
                    a[4][d] += n1 * t[1][d];
                    a[5][d] += n0 * t[2][d];
                }
            }
        }
        quotient_rule(&a, s.is_rational())
    }
}

/// Point and derivatives up to order 2 for compile-time orders P1 = p + 1, Q1 = q + 1.
#[inline(always)]
fn derivatives_fixed<const P1: usize, const Q1: usize>(
    s: &BSplineSurface,
    u: f64,
    v: f64,
) -> SurfaceDerivatives {
    use crate::basis::derivatives2_fixed;
    let u = s.knots_u.clamp_param(u);
    let v = s.knots_v.clamp_param(v);
    let su = s.knots_u.span(u);
    let sv = s.knots_v.span(v);
    let nu = derivatives2_fixed::<P1>(s.knots_u.knots(), su, u);
    let nv_ = derivatives2_fixed::<Q1>(s.knots_v.knots(), sv, v);
    let nv = s.num_v();
    let mut a = [[0.0f64; 4]; 6];
    for r in 0..P1 {
        let row = (su + 1 - P1 + r) * nv + sv + 1 - Q1;
        let mut t = [[0.0f64; 4]; 3];
        match &s.weights {
            None => {
                let pts: &[Point3; Q1] = s.points[row..row + Q1]
                    .try_into()
                    .expect("span inside the net");
                for c in 0..Q1 {
                    let h = [pts[c].x, pts[c].y, pts[c].z, 1.0];
                    for l in 0..3 {
                        for d in 0..4 {
                            t[l][d] += nv_[l][c] * h[d];
                        }
                    }
                }
            }
            Some(w) => {
                let pts: &[Point3; Q1] = s.points[row..row + Q1]
                    .try_into()
                    .expect("span inside the net");
                let ws: &[f64; Q1] = w[row..row + Q1].try_into().expect("span inside the net");
                for c in 0..Q1 {
                    let h = [pts[c].x * ws[c], pts[c].y * ws[c], pts[c].z * ws[c], ws[c]];
                    for l in 0..3 {
                        for d in 0..4 {
                            t[l][d] += nv_[l][c] * h[d];
                        }
                    }
                }
            }
        }
        let (n0, n1, n2) = (nu[0][r], nu[1][r], nu[2][r]);
        for d in 0..4 {
            a[0][d] += n0 * t[0][d];
            a[1][d] += n1 * t[0][d];
            a[2][d] += n0 * t[1][d];
            a[3][d] += n2 * t[0][d];
            a[4][d] += n1 * t[1][d];
            a[5][d] += n0 * t[2][d];
        }
    }
    quotient_rule(&a, s.is_rational())
}

/// Turns homogeneous derivatives (order 00, 10, 01, 20, 11, 02) into Euclidean ones
/// (\[NB\] eq. 4.20); for polynomial surfaces the w-components are ignored (Σ N = 1).
#[inline]
pub(crate) fn quotient_rule(a: &[[f64; 4]; 6], rational: bool) -> SurfaceDerivatives {
    let v = |k: usize| Vector3::new(a[k][0], a[k][1], a[k][2]);
    if !rational {
        return SurfaceDerivatives {
            point: Point3::from(v(0)),
            du: v(1),
            dv: v(2),
            duu: v(3),
            duv: v(4),
            dvv: v(5),
        };
    }
    let w = a[0][3];
    let (wu, wv, wuu, wuv, wvv) = (a[1][3], a[2][3], a[3][3], a[4][3], a[5][3]);
    let s = v(0) / w;
    let su = (v(1) - wu * s) / w;
    let sv = (v(2) - wv * s) / w;
    let suu = (v(3) - 2.0 * wu * su - wuu * s) / w;
    let suv = (v(4) - wu * sv - wv * su - wuv * s) / w;
    let svv = (v(5) - 2.0 * wv * sv - wvv * s) / w;
    SurfaceDerivatives {
        point: Point3::from(s),
        du: su,
        dv: sv,
        duu: suu,
        duv: suv,
        dvv: svv,
    }
}
