//! Greiner's Hessian of the coordinate functions on a reference surface (\[SV\] §5.3, \[G96\]).
//!
//! On the reference R (the original surface) with metric g = (R_i·R_j) and Christoffel symbols
//! Γ^i_jl = Σ_m g^{im} ⟨R_jl, R_m⟩, the Hessian of a function h on the parameter domain is
//! Hess_R(h) = g⁻¹ M(h), M_jl = ∂_j∂_l h − Σ_i ∂_i h Γ^i_jl. For the coordinates of the faired surface
//! S = Σ R_k P_k this is linear in the control points: M(S_c) = Σ_k M(R_k) P_k,c with the basis
//! functions R_k of nurbs-core ([`nurbs_core::SurfaceBasis`]). For S = R, M(R_c) = II n_c
//! (R_jl minus its tangential part), so Hess_R(R_c) = g⁻¹ II n_c: the shape operator times n_c,
//! Σ_c tr² = (κ1 + κ2)², Σ_c det = κ1 κ2.
//!
//! In an orthonormal tangent frame (g = L Lᵀ, L lower triangular, Cholesky) the Hessian is the
//! symmetric Y = L⁻¹ M L⁻ᵀ = Lᵀ (g⁻¹ M) L⁻ᵀ; its Frobenius norm tr(Xᵀ g X g⁻¹) does not depend on the
//! parameterization, so least squares on the entries (Y11, √2 Y12, Y22) does not depend on the
//! parametric directions either. tr Y = tr g⁻¹M = (G M11 − 2F M12 + E M22)/(EG − F²).
//!
//! # First variation of the metric
//! Greiner's rows give the second fundamental form of S = R + δ to first order,
//! II_S = n_R · M_R(S) + O(δ²), but measure it with R's metric; the shape operator of S is
//! g_S⁻¹ II_S with g_S = g + δg, δg_ab = R_a·δ_b + R_b·δ_a + O(δ²), so
//! X_S = g⁻¹ n·M_R(S) − g⁻¹ δg X_R + O(δ²). Dropping the second term is an error of first order
//! in the displacement's derivative times the curvature: on a noisy surface it is as large as the
//! curvature change the fairing asks for. In the orthonormal frame the complete linearization
//! reads Y_S ≈ L⁻¹ n·M_R(S) L⁻ᵀ − sym(L⁻¹ G(S) L⁻ᵀ Y_R) + 2 Y_R with G_ab(S) = R_a·S_b + R_b·S_a,
//! linear in the control points ([`SampleGeometry::metric_variation`]); at S = R it gives Y_R.
//!
//! # Tolerance
//! A sample whose metric has EG − F² ≤ [`DEGENERATE_METRIC_REL`] · E·G (a pole or parallel
//! tangents) carries no equation.

use nurbs_core::{SurfaceDerivatives, Vector3};

/// Relative size of det g against E·G below which a sample counts as singular (tangents
/// parallel to within ~1e-6 rad, or one of them vanished).
pub const DEGENERATE_METRIC_REL: f64 = 1e-12;

/// The precomputed reference data of one sample.
#[derive(Debug, Clone, Copy)]
pub struct SampleGeometry {
    /// unit normal n = R_u × R_v / |R_u × R_v|
    pub normal: Vector3,
    /// √det g (the area element)
    pub area: f64,
    /// E, F, G
    pub metric: [f64; 3],
    /// Γ^u, Γ^v of the pairs uu, uv, vv
    pub christoffel: [[f64; 2]; 3],
    /// L⁻¹ = [[a, 0], [b, c]]
    pub inverse_cholesky: [f64; 3],
    /// the shape operator g⁻¹ II of R, row-major
    pub shape: [f64; 4],
    /// R_u, R_v
    pub tangents: [Vector3; 2],
    /// Y_R = Lᵀ (g⁻¹ II) L⁻ᵀ as (Y11, √2 Y12, Y22)
    pub orthonormal_shape: [f64; 3],
}

/// The shape operator g⁻¹ II (row-major) from the inverse metric (g¹¹, g¹², g²²) and
/// II = (L, M, N).
#[inline]
pub fn shape_operator(inverse_metric: [f64; 3], ii: [f64; 3]) -> [f64; 4] {
    let [a, b, c] = inverse_metric;
    [
        a * ii[0] + b * ii[1],
        a * ii[1] + b * ii[2],
        b * ii[0] + c * ii[1],
        b * ii[1] + c * ii[2],
    ]
}

impl SampleGeometry {
    /// The reference data at a point of R, `None` at a singular sample.
    pub fn new(d: &SurfaceDerivatives) -> Option<Self> {
        let (e, f, g) = (d.du.dot(&d.du), d.du.dot(&d.dv), d.dv.dot(&d.dv));
        let det = e * g - f * f;
        if !(det > DEGENERATE_METRIC_REL * e * g) {
            return None;
        }
        let inv = [g / det, -f / det, e / det];
        let gamma = |r: &Vector3| {
            let (x, y) = (r.dot(&d.du), r.dot(&d.dv));
            [inv[0] * x + inv[1] * y, inv[1] * x + inv[2] * y]
        };
        let normal = d.du.cross(&d.dv) / det.sqrt();
        let (l, m, n) = (d.duu.dot(&normal), d.duv.dot(&normal), d.dvv.dot(&normal));
        let l11 = e.sqrt();
        let l21 = f / l11;
        let l22 = (g - l21 * l21).sqrt();
        let mut out = Self {
            normal,
            area: det.sqrt(),
            metric: [e, f, g],
            christoffel: [gamma(&d.duu), gamma(&d.duv), gamma(&d.dvv)],
            inverse_cholesky: [1.0 / l11, -l21 / (l11 * l22), 1.0 / l22],
            shape: shape_operator(inv, [l, m, n]),
            tangents: [d.du, d.dv],
            orthonormal_shape: [0.0; 3],
        };
        out.orthonormal_shape = out.orthonormal_mixed(out.shape);
        Some(out)
    }

    /// The metric term of the linearized shape operator for one basis function with first
    /// derivatives (N_u, N_v): for each coordinate c, sym(L⁻¹ G L⁻ᵀ Y_R) as (·11, √2 ·12, ·22),
    /// where G_ab = R_a,c N_b + R_b,c N_a is the metric variation of a unit move of the control
    /// point along coordinate c (see the module docs).
    pub fn metric_variation(&self, first: [f64; 2]) -> [[f64; 3]; 3] {
        let y = self.orthonormal_shape;
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let yr = [[y[0], h * y[1]], [h * y[1], y[2]]];
        let [a, b, c] = self.inverse_cholesky;
        let [ru, rv] = self.tangents;
        let mut out = [[0.0; 3]; 3];
        for (k, o) in out.iter_mut().enumerate() {
            let e11 = 2.0 * ru[k] * first[0];
            let e12 = ru[k] * first[1] + rv[k] * first[0];
            let e22 = 2.0 * rv[k] * first[1];
            // Z = L⁻¹ E L⁻ᵀ with L⁻¹ = [[a, 0], [b, c]]
            let z11 = a * a * e11;
            let z12 = a * (b * e11 + c * e12);
            let z22 = b * b * e11 + 2.0 * b * c * e12 + c * c * e22;
            let w11 = z11 * yr[0][0] + z12 * yr[1][0];
            let w12 = z11 * yr[0][1] + z12 * yr[1][1];
            let w21 = z12 * yr[0][0] + z22 * yr[1][0];
            let w22 = z12 * yr[0][1] + z22 * yr[1][1];
            *o = [w11, std::f64::consts::SQRT_2 * (w12 + w21) / 2.0, w22];
        }
        out
    }

    /// The constant of the linearized rows, 2 Y_R as (·11, √2 ·12, ·22).
    pub fn metric_constant(&self) -> [f64; 3] {
        self.orthonormal_shape.map(|v| 2.0 * v)
    }

    /// M(h) = (M11, M12, M22) of a function with first derivatives (h_u, h_v) and second
    /// (h_uu, h_uv, h_vv).
    #[inline]
    pub fn covariant(&self, first: [f64; 2], second: [f64; 3]) -> [f64; 3] {
        let c = &self.christoffel;
        let mut out = [0.0; 3];
        for k in 0..3 {
            out[k] = second[k] - first[0] * c[k][0] - first[1] * c[k][1];
        }
        out
    }

    /// tr g⁻¹ M.
    #[inline]
    pub fn trace(&self, m: [f64; 3]) -> f64 {
        let [e, f, g] = self.metric;
        (g * m[0] - 2.0 * f * m[1] + e * m[2]) / (e * g - f * f)
    }

    /// (Y11, √2 Y12, Y22) of Y = L⁻¹ M L⁻ᵀ.
    #[inline]
    pub fn orthonormal(&self, m: [f64; 3]) -> [f64; 3] {
        let [a, b, c] = self.inverse_cholesky;
        [
            a * a * m[0],
            std::f64::consts::SQRT_2 * a * (b * m[0] + c * m[1]),
            b * b * m[0] + 2.0 * b * c * m[1] + c * c * m[2],
        ]
    }

    /// The symmetric part of Lᵀ X L⁻ᵀ for a mixed tensor X (row-major), as (Y11, √2 Y12, Y22):
    /// the orthonormal form of a target shape operator.
    pub fn orthonormal_mixed(&self, x: [f64; 4]) -> [f64; 3] {
        let [a, b, c] = self.inverse_cholesky;
        // L = inverse of [[a, 0], [b, c]] = [[1/a, 0], [−b/(a c), 1/c]]
        let (l11, l21, l22) = (1.0 / a, -b / (a * c), 1.0 / c);
        // Lᵀ = [[l11, l21], [0, l22]], L⁻ᵀ = [[a, b], [0, c]]
        let t = [
            l11 * x[0] + l21 * x[2],
            l11 * x[1] + l21 * x[3],
            l22 * x[2],
            l22 * x[3],
        ];
        let y11 = t[0] * a;
        let y12 = t[0] * b + t[1] * c;
        let y21 = t[2] * a;
        let y22 = t[2] * b + t[3] * c;
        [y11, std::f64::consts::SQRT_2 * (y12 + y21) / 2.0, y22]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs_core::Point3;

    fn sample(duu: Vector3, duv: Vector3, dvv: Vector3) -> SurfaceDerivatives {
        SurfaceDerivatives {
            point: Point3::origin(),
            du: Vector3::new(2.0, 0.3, 0.1),
            dv: Vector3::new(-0.4, 1.5, 0.2),
            duu,
            duv,
            dvv,
        }
    }

    #[test]
    fn the_coordinates_give_the_shape_operator_times_the_normal() {
        let d = sample(
            Vector3::new(0.3, -0.2, 1.1),
            Vector3::new(0.1, 0.4, -0.5),
            Vector3::new(-0.7, 0.2, 0.9),
        );
        let s = SampleGeometry::new(&d).unwrap();
        for c in 0..3 {
            let m = s.covariant([d.du[c], d.dv[c]], [d.duu[c], d.duv[c], d.dvv[c]]);
            let y = s.orthonormal(m);
            let want = s.orthonormal_mixed(s.shape);
            for k in 0..3 {
                assert!(
                    (y[k] - want[k] * s.normal[c]).abs() < 1e-12,
                    "{y:?} {want:?}"
                );
            }
            let tr = s.trace(m);
            assert!((tr - (s.shape[0] + s.shape[3]) * s.normal[c]).abs() < 1e-12);
            assert!((tr - (y[0] + y[2])).abs() < 1e-12);
        }
    }

    #[test]
    fn parallel_tangents_are_singular() {
        let mut d = sample(Vector3::zeros(), Vector3::zeros(), Vector3::zeros());
        d.dv = 2.0 * d.du;
        assert!(SampleGeometry::new(&d).is_none());
    }
}
