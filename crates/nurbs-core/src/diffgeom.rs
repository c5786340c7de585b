//! Differential geometry of a surface point from its derivatives (\[DC\] §3-2, §3-3).
//!
//! Unit normal n = S_u × S_v / |S_u × S_v|. First fundamental form E = S_u·S_u, F = S_u·S_v,
//! G = S_v·S_v; second L = S_uu·n, M = S_uv·n, N = S_vv·n. Normal curvature in the tangent direction
//! a S_u + b S_v: κ_n = (L a² + 2M ab + N b²)/(E a² + 2F ab + G b²). Mean curvature
//! H = (k1 + k2)/2 and Gaussian K = k1·k2 from the principal curvatures k1 ≥ k2, the eigenvalues
//! of the shape operator. All curvatures are signed with respect to n: a sphere with the
//! outward normal has negative curvatures.
//!
//! # Tolerance
//! A point is singular (normal and curvatures `None`) when a tangent vanishes against the other
//! ([`TANGENT_RATIO_EPS`]) or the tangents are parallel ([`NORMAL_SIN_EPS`]); both are relative,
//! so the test does not depend on the model's units. Collapsed sides (poles) fall under the first.

use crate::Vector3;
use crate::surface::SurfaceDerivatives;

/// |S_u| / |S_v| (or its inverse) below which a tangent counts as vanished: a collapsed side
/// evaluates to a tangent of rounding size, ~1e-16 of the other.
pub const TANGENT_RATIO_EPS: f64 = 1e-10;

/// sin of the angle between S_u and S_v below which the tangents count as parallel.
pub const NORMAL_SIN_EPS: f64 = 1e-10;

/// Relative size of the tangential part of a 3D direction below which it counts as normal to
/// the surface (no normal curvature in that direction).
pub(crate) const DIRECTION_TANGENTIAL_EPS: f64 = 1e-9;

/// First and second fundamental forms at a regular point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FundamentalForms {
    /// E = S_u·S_u
    pub e: f64,
    /// F = S_u·S_v
    pub f: f64,
    /// G = S_v·S_v
    pub g: f64,
    /// L = S_uu·n
    pub l: f64,
    /// M = S_uv·n
    pub m: f64,
    /// N = S_vv·n
    pub n: f64,
    /// the unit normal used for the signs
    pub normal: Vector3,
}

/// The second fundamental form in an orthonormal tangent frame (see `shape_parts`).
#[derive(Debug, Clone, Copy)]
struct ShapeParts {
    normal: Vector3,
    b11: f64,
    b12: f64,
    b22: f64,
    /// F / E
    r: f64,
    /// E = |S_u|²
    lu2: f64,
    /// EG − F² = |S_u × S_v|²
    lc2: f64,
}

/// Normal and principal curvatures at a regular point, without directions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvatureValues {
    /// unit normal the signs refer to
    pub normal: Vector3,
    /// larger principal curvature
    pub k1: f64,
    /// smaller principal curvature
    pub k2: f64,
    /// mean curvature (k1 + k2)/2 (the JSON's `mean`)
    pub mean: f64,
    /// Gaussian curvature k1·k2 (the JSON's `gauss`)
    pub gauss: f64,
}

impl CurvatureValues {
    /// The values of principal curvatures `k1` ≥ `k2` signed against `normal`, with their
    /// mean and Gaussian curvature.
    pub fn new(normal: Vector3, k1: f64, k2: f64) -> Self {
        Self {
            normal,
            k1,
            k2,
            mean: 0.5 * (k1 + k2),
            gauss: k1 * k2,
        }
    }

    /// Mean curvature (k1 + k2)/2: the field [`Self::mean`].
    #[deprecated(note = "read the field `mean` (as the JSON names it)")]
    pub fn mean(&self) -> f64 {
        self.mean
    }

    /// Gaussian curvature k1·k2: the field [`Self::gauss`].
    #[deprecated(note = "read the field `gauss` (as the JSON names it)")]
    pub fn gauss(&self) -> f64 {
        self.gauss
    }
}

/// Principal curvatures and directions at a regular point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrincipalCurvatures {
    /// larger principal curvature
    pub k1: f64,
    /// smaller principal curvature
    pub k2: f64,
    /// unit 3D direction of k1
    pub dir1: Vector3,
    /// unit 3D direction of k2 (n × dir1)
    pub dir2: Vector3,
    /// unit normal the signs refer to
    pub normal: Vector3,
    /// mean curvature (k1 + k2)/2 (the JSON's `mean`)
    pub mean: f64,
    /// Gaussian curvature k1·k2 (the JSON's `gauss`)
    pub gauss: f64,
}

impl PrincipalCurvatures {
    /// Mean curvature (k1 + k2)/2: the field [`Self::mean`].
    #[deprecated(note = "read the field `mean` (as the JSON names it)")]
    pub fn mean(&self) -> f64 {
        self.mean
    }

    /// Gaussian curvature k1·k2: the field [`Self::gauss`].
    #[deprecated(note = "read the field `gauss` (as the JSON names it)")]
    pub fn gauss(&self) -> f64 {
        self.gauss
    }
}

impl SurfaceDerivatives {
    /// The unit normal S_u × S_v / |S_u × S_v|, `None` at singular points.
    #[inline]
    pub fn normal(&self) -> Option<Vector3> {
        let (lu2, lv2) = (self.du.norm_squared(), self.dv.norm_squared());
        let (lo2, hi2) = if lu2 < lv2 { (lu2, lv2) } else { (lv2, lu2) };
        if !(lo2 > TANGENT_RATIO_EPS * TANGENT_RATIO_EPS * hi2) {
            return None;
        }
        let c = self.du.cross(&self.dv);
        let lc2 = c.norm_squared();
        if !(lc2 > NORMAL_SIN_EPS * NORMAL_SIN_EPS * lu2 * lv2) {
            return None;
        }
        Some(c / lc2.sqrt())
    }

    /// First and second fundamental forms, `None` at singular points.
    pub fn fundamental_forms(&self) -> Option<FundamentalForms> {
        let normal = self.normal()?;
        Some(FundamentalForms {
            e: self.du.dot(&self.du),
            f: self.du.dot(&self.dv),
            g: self.dv.dot(&self.dv),
            l: self.duu.dot(&normal),
            m: self.duv.dot(&normal),
            n: self.dvv.dot(&normal),
            normal,
        })
    }

    /// Normal curvature in the 3D `direction` (its tangential part is used), `None` at singular
    /// points or when the direction is normal to the surface.
    pub fn normal_curvature(&self, direction: &Vector3) -> Option<f64> {
        self.normal_curvature_with(&self.fundamental_forms()?, direction)
    }

    /// [`Self::normal_curvature`] with this point's fundamental forms `ff` given (found once
    /// for many directions at the same point; the same value bit for bit).
    pub fn normal_curvature_with(&self, ff: &FundamentalForms, direction: &Vector3) -> Option<f64> {
        let det = ff.e * ff.g - ff.f * ff.f;
        let (du_d, dv_d) = (direction.dot(&self.du), direction.dot(&self.dv));
        let a = (ff.g * du_d - ff.f * dv_d) / det;
        let b = (ff.e * dv_d - ff.f * du_d) / det;
        let tangential = self.du * a + self.dv * b;
        if !(tangential.norm() > DIRECTION_TANGENTIAL_EPS * direction.norm()) {
            return None;
        }
        let first = ff.e * a * a + 2.0 * ff.f * a * b + ff.g * b * b;
        let second = ff.l * a * a + 2.0 * ff.m * a * b + ff.n * b * b;
        Some(second / first)
    }

    /// The second fundamental form in the orthonormal tangent frame e1 = S_u/√E,
    /// e2 = (S_v − (F/E) S_u)/√((EG − F²)/E) (= n × e1), as the symmetric matrix
    /// B = [[b11, b12], [b12, b22]]; with |S_u × S_v|² = EG − F² every entry needs only the
    /// square root already taken for the normal.
    #[inline]
    fn shape_parts(&self) -> Option<ShapeParts> {
        let (lu2, lv2) = (self.du.norm_squared(), self.dv.norm_squared());
        let (lo2, hi2) = if lu2 < lv2 { (lu2, lv2) } else { (lv2, lu2) };
        if !(lo2 > TANGENT_RATIO_EPS * TANGENT_RATIO_EPS * hi2) {
            return None;
        }
        let c = self.du.cross(&self.dv);
        let lc2 = c.norm_squared();
        if !(lc2 > NORMAL_SIN_EPS * NORMAL_SIN_EPS * lu2 * lv2) {
            return None;
        }
        // dot products with the unnormalized normal do not wait for the square root
        let (lc, mc, nc) = (self.duu.dot(&c), self.duv.dot(&c), self.dvv.dot(&c));
        let f = self.du.dot(&self.dv);
        let inv_len = 1.0 / lc2.sqrt();
        let inv_lu2 = 1.0 / lu2;
        let normal = c * inv_len;
        let (l, m, n) = (lc * inv_len, mc * inv_len, nc * inv_len);
        let r = f * inv_lu2;
        Some(ShapeParts {
            normal,
            b11: l * inv_lu2,
            b12: (m - r * l) * inv_len,
            b22: (n - 2.0 * r * m + r * r * l) * lu2 * inv_len * inv_len,
            r,
            lu2,
            lc2,
        })
    }

    /// Normal and principal curvatures k1 ≥ k2 without the directions (the cheaper part of
    /// [`Self::principal_curvatures`]), `None` at singular points.
    #[inline]
    pub fn curvature_values(&self) -> Option<CurvatureValues> {
        let s = self.shape_parts()?;
        let mid = 0.5 * (s.b11 + s.b22);
        let half = 0.5 * (s.b11 - s.b22);
        let radius = (half * half + s.b12 * s.b12).sqrt();
        Some(CurvatureValues::new(s.normal, mid + radius, mid - radius))
    }

    /// Principal curvatures (k1 ≥ k2) and directions, `None` at singular points.
    ///
    /// The eigenvalues of B are m ± √(h² + b12²), m = (b11 + b22)/2, h = (b11 − b22)/2: no
    /// cancellation of H ± √(H² − K) near umbilics. The eigenvector of k1 is (h + r, b12) or
    /// (b12, r − h), whichever is better conditioned.
    #[inline]
    pub fn principal_curvatures(&self) -> Option<PrincipalCurvatures> {
        let s = self.shape_parts()?;
        let mid = 0.5 * (s.b11 + s.b22);
        let half = 0.5 * (s.b11 - s.b22);
        let radius = (half * half + s.b12 * s.b12).sqrt();
        let (x, y) = if half >= 0.0 {
            (half + radius, s.b12)
        } else {
            (s.b12, radius - half)
        };
        let len = (x * x + y * y).sqrt();
        let (x, y) = if len > 0.0 {
            (x / len, y / len)
        } else {
            (1.0, 0.0)
        };
        let e1 = self.du / s.lu2.sqrt();
        let e2 = (self.dv - self.du * s.r) / (s.lc2 / s.lu2).sqrt();
        let dir1 = e1 * x + e2 * y;
        let dir2 = s.normal.cross(&dir1);
        let (k1, k2) = (mid + radius, mid - radius);
        Some(PrincipalCurvatures {
            k1,
            k2,
            dir1,
            dir2,
            normal: s.normal,
            mean: 0.5 * (k1 + k2),
            gauss: k1 * k2,
        })
    }

    /// Mean curvature (k1 + k2)/2, `None` at singular points.
    pub fn mean_curvature(&self) -> Option<f64> {
        self.curvature_values().map(|c| c.mean)
    }

    /// Gaussian curvature k1·k2, `None` at singular points.
    pub fn gaussian_curvature(&self) -> Option<f64> {
        self.curvature_values().map(|c| c.gauss)
    }
}

#[cfg(test)]
mod tests {
    use crate::shapes::torus;

    /// mean and gauss are filled at construction from k1 and k2, on both paths, and the
    /// deprecated accessors of the same names return them
    #[test]
    #[allow(deprecated)]
    fn mean_and_gauss_fields_are_the_halved_sum_and_the_product() {
        let s = torus(3.0, 1.0).unwrap();
        for (u, v) in [(0.1, 0.2), (0.45, 0.8), (0.7, 0.05)] {
            let d = s.derivatives(u, v);
            let c = d.curvature_values().unwrap();
            assert!(c.k1 > c.k2, "a torus has no umbilic points");
            assert_eq!(c.mean, 0.5 * (c.k1 + c.k2));
            assert_eq!(c.gauss, c.k1 * c.k2);
            assert_eq!((c.mean(), c.gauss()), (c.mean, c.gauss));
            let p = d.principal_curvatures().unwrap();
            assert_eq!(p.mean, 0.5 * (p.k1 + p.k2));
            assert_eq!(p.gauss, p.k1 * p.k2);
            assert_eq!((p.mean(), p.gauss()), (p.mean, p.gauss));
            assert_eq!(d.mean_curvature(), Some(c.mean));
            assert_eq!(d.gaussian_curvature(), Some(c.gauss));
        }
        let built = super::CurvatureValues::new(crate::Vector3::z(), 2.0, -0.5);
        assert_eq!((built.mean, built.gauss), (0.75, -1.0));
    }
}
