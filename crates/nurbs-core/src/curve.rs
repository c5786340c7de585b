//! B-spline and NURBS curves in 3D: evaluation and derivatives up to order 3, curvature.
//!
//! C(t) = Σ N_i(t) w_i P_i / Σ N_i(t) w_i. Derivatives of the homogeneous curve A(t) = Σ N_i w_i P_i,
//! w(t) = Σ N_i w_i give the rational derivatives by the quotient rule
//! C^{(k)} = (A^{(k)} − Σ_{i=1..k} C(k,i) w^{(i)} C^{(k−i)}) / w (\[NB\] A4.2, eq. 4.8).
//! Curvature κ = |C' × C''| / |C'|³.

use crate::basis::BasisEvaluator;
use crate::error::{Error, Result};
use crate::knots::KnotVector;
use crate::{Point3, Vector3};

/// Highest curve derivative order the evaluators return.
pub(crate) const MAX_CURVE_DERIVATIVE: usize = 3;

/// Relative size of |C'| (against the control polygon's extent per unit parameter) below which a
/// curve point counts as singular and its curvature as undefined.
pub(crate) const CURVE_SINGULAR_SPEED: f64 = 1e-12;

/// A (possibly rational) B-spline curve in 3D.
#[derive(Debug, Clone, PartialEq)]
pub struct BSplineCurve {
    knots: KnotVector,
    points: Vec<Point3>,
    weights: Option<Vec<f64>>,
}

/// Point and derivatives of a curve at one parameter: `d[0]` is the point (as a vector), `d[k]` the
/// k-th derivative.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveDerivatives {
    /// C, C', C'', C'''
    pub d: [Vector3; MAX_CURVE_DERIVATIVE + 1],
}

impl CurveDerivatives {
    /// Curvature |C' × C''| / |C'|³, or `None` at a singular point (C' = 0).
    pub fn curvature(&self, scale: f64) -> Option<f64> {
        let speed = self.d[1].norm();
        if !(speed > CURVE_SINGULAR_SPEED * scale) {
            return None;
        }
        Some(self.d[1].cross(&self.d[2]).norm() / (speed * speed * speed))
    }
}

impl BSplineCurve {
    /// Validates and builds a curve: the knot count must be points + degree + 1, points finite,
    /// weights (when given) one per point, finite and > 0.
    pub fn new(knots: KnotVector, points: Vec<Point3>, weights: Option<Vec<f64>>) -> Result<Self> {
        knots.check_count("curve", points.len())?;
        for (i, p) in points.iter().enumerate() {
            if !p.coords.iter().all(|c| c.is_finite()) {
                return Err(Error::NonFiniteControlPoint { i, j: 0 });
            }
        }
        if let Some(w) = &weights {
            if w.len() != points.len() {
                return Err(Error::LengthMismatch {
                    what: "curve weights vs control points",
                    left: w.len(),
                    right: points.len(),
                });
            }
            for (i, &value) in w.iter().enumerate() {
                if !(value.is_finite() && value > 0.0) {
                    return Err(Error::InvalidWeight { i, j: 0, value });
                }
            }
        }
        Ok(Self {
            knots,
            points,
            weights,
        })
    }

    /// Builds a curve from homogeneous control points (w·x, w·y, w·z, w); polynomial when every
    /// weight is exactly 1.
    pub fn from_homogeneous(knots: KnotVector, pw: &[[f64; 4]]) -> Result<Self> {
        let (points, weights) = crate::homogeneous::split(pw);
        Self::new(knots, points, weights)
    }

    /// Builds a curve from homogeneous points, rational or polynomial as told (see
    /// [`crate::homogeneous::split_as`]).
    pub fn from_homogeneous_as(knots: KnotVector, pw: &[[f64; 4]], rational: bool) -> Result<Self> {
        let (points, weights) = crate::homogeneous::split_as(pw, rational);
        Self::new(knots, points, weights)
    }

    /// Homogeneous control points (w·x, w·y, w·z, w).
    pub fn homogeneous(&self) -> Vec<[f64; 4]> {
        crate::homogeneous::join(&self.points, self.weights.as_deref())
    }

    /// Degree p.
    pub fn degree(&self) -> usize {
        self.knots.degree()
    }
    /// The knot vector.
    pub fn knots(&self) -> &KnotVector {
        &self.knots
    }
    /// Control points.
    pub fn control_points(&self) -> &[Point3] {
        &self.points
    }
    /// Mutable control points (geometry changes, knots and weights stay).
    pub fn control_points_mut(&mut self) -> &mut [Point3] {
        &mut self.points
    }
    /// Weights, `None` for a polynomial curve.
    pub fn weights(&self) -> Option<&[f64]> {
        self.weights.as_deref()
    }
    /// True when weights are present.
    pub fn is_rational(&self) -> bool {
        self.weights.is_some()
    }
    /// Parameter domain.
    pub fn domain(&self) -> (f64, f64) {
        self.knots.domain()
    }

    /// Extent of the control polygon per unit parameter: the scale of |C'| used by the
    /// singularity tests.
    pub fn speed_scale(&self) -> f64 {
        crate::homogeneous::bounding_diagonal(&self.points) / self.knots.domain_length()
    }

    /// Point and derivatives up to order `n` ≤ 3 at `t` (clamped into the domain); higher entries
    /// are zero.
    pub fn derivatives(&self, t: f64, n: usize) -> CurveDerivatives {
        let n = n.min(MAX_CURVE_DERIVATIVE);
        let p = self.degree();
        let t = self.knots.clamp_param(t);
        let span = self.knots.span(t);
        let mut basis = [0.0; 64];
        let mut scratch;
        let ders: &mut [f64] = if (n + 1) * (p + 1) <= 64 {
            &mut basis[..(n + 1) * (p + 1)]
        } else {
            scratch = vec![0.0; (n + 1) * (p + 1)];
            &mut scratch
        };
        BasisEvaluator::new(p).derivatives(self.knots.knots(), span, t, n, ders);
        let mut a = [[0.0f64; 4]; MAX_CURVE_DERIVATIVE + 1];
        for r in 0..=p {
            let i = span - p + r;
            let w = self.weights.as_ref().map_or(1.0, |w| w[i]);
            let pt = &self.points[i];
            for k in 0..=n {
                let b = ders[k * (p + 1) + r] * w;
                a[k][0] += b * pt.x;
                a[k][1] += b * pt.y;
                a[k][2] += b * pt.z;
                a[k][3] += b;
            }
        }
        let mut d = [Vector3::zeros(); MAX_CURVE_DERIVATIVE + 1];
        for k in 0..=n {
            let mut v = Vector3::new(a[k][0], a[k][1], a[k][2]);
            for i in 1..=k {
                v -= binomial(k, i) * a[i][3] * d[k - i];
            }
            d[k] = v / a[0][3];
        }
        CurveDerivatives { d }
    }

    /// The point C(t).
    pub fn point(&self, t: f64) -> Point3 {
        Point3::from(self.derivatives(t, 0).d[0])
    }

    /// Curvature at `t`, `None` where C' vanishes.
    pub fn curvature(&self, t: f64) -> Option<f64> {
        self.derivatives(t, 2).curvature(self.speed_scale())
    }
}

/// Binomial coefficient C(n, k) for the small orders used in derivative formulas.
pub(crate) fn binomial(n: usize, k: usize) -> f64 {
    let mut r = 1.0;
    for i in 0..k {
        r = r * (n - i) as f64 / (i + 1) as f64;
    }
    r
}
