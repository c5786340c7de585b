//! Curvature targets from osculating quadrics: the "averaged Hessian" of \[SV\] §5.3 estimated by
//! a least-squares quadric through the reference surface's samples around each sample.
//!
//! In the local frame (e₁ = R_u/|R_u|, e₂ = n × e₁, n) at the sample R(u, v), with coordinates
//! scaled by the window's extent, we fit
//!
//! Q(x, y, z) = c + b₁x + b₂y + z + A₁₁x² + 2A₁₂xy + A₂₂y² + 2A₁₃xz + 2A₂₃yz + A₃₃z² = 0
//!
//! by linear least squares (the z coefficient fixed to 1: the surface is a graph over its own
//! tangent plane near the sample). The shape operator at the sample is that of the quadric at the
//! projection of R(u, v) onto it: with ∇Q = b + 2Ap and T_a the tangents R_u, R_v projected on the
//! quadric's tangent plane, II_ab = −T_aᵀ (2A) T_b / |∇Q| and X = g⁻¹ II in the basis (R_u, R_v),
//! so it compares entry by entry with the reference's own shape operator.
//!
//! Every quadric (plane, sphere, cylinder, cone, paraboloid, hyperbolic paraboloid) is fitted
//! exactly, so exact quadric patches keep their curvature to rounding while control-point noise
//! is averaged over the window. Surfaces that are no quadric within a window (a torus, free
//! forms) get the curvature of the best-fitting quadric: a bias that grows with the window.
//! Rank-deficient fits (a plane leaves A₁₃, A₂₃, A₃₃ free) take the minimum-norm solution, which
//! does not change the tangential Hessian that the curvature reads.
//!
//! # Tolerance
//! Eigenvalues of the 9 × 9 normal matrix below [`QUADRIC_RANK_REL`] × the largest count as zero
//! (unit-free: the coordinates are scaled to the window).

use nalgebra::{Matrix3, SMatrix, SVector, SymmetricEigen};
use nurbs_core::{Point3, Vector3};

use crate::hessian::shape_operator;

/// Relative eigenvalue of the normal matrix below which a direction of the quadric's
/// coefficients counts as undetermined (squared singular value ratio 1e-7).
pub const QUADRIC_RANK_REL: f64 = 1e-14;

/// Newton steps projecting the sample onto the fitted quadric.
const PROJECTION_STEPS: usize = 3;

/// The sample's frame: its point, its tangents R_u, R_v and unit normal.
#[derive(Debug, Clone, Copy)]
pub struct SampleFrame {
    /// R(u, v)
    pub point: Point3,
    /// R_u
    pub du: Vector3,
    /// R_v
    pub dv: Vector3,
    /// unit normal R_u × R_v / |R_u × R_v|
    pub normal: Vector3,
}

/// The shape operator g⁻¹ II (row-major, in the basis R_u, R_v, oriented by `frame.normal`) of
/// the quadric fitted to `points` around `frame`, `None` when the fit or the frame degenerates.
pub fn osculating_shape(frame: &SampleFrame, points: &[Point3]) -> Option<[f64; 4]> {
    let quadric = LocalQuadric::fit(frame, points)?;
    let (a, b) = (quadric.a, quadric.b);
    let p = quadric.foot_of_sample()?;
    let grad = b + 2.0 * a * p;
    let gn = grad.norm();
    // oriented like the reference: its normal is +z in the local frame
    let nq = if grad.z >= 0.0 { grad / gn } else { -grad / gn };
    let sign = if grad.z >= 0.0 { 1.0 } else { -1.0 };
    let project = |t: Vector3| {
        let t = quadric.rot * t;
        t - t.dot(&nq) * nq
    };
    let (ta, tb) = (project(frame.du), project(frame.dv));
    let f = -2.0 * sign / (gn * quadric.scale);
    let ii = [
        f * ta.dot(&(a * ta)),
        f * ta.dot(&(a * tb)),
        f * tb.dot(&(a * tb)),
    ];
    let (e, ff, g) = (ta.dot(&ta), ta.dot(&tb), tb.dot(&tb));
    let det = e * g - ff * ff;
    if !(det > 0.0) {
        return None;
    }
    let shape = shape_operator([g / det, -ff / det, e / det], ii);
    shape.iter().all(|v| v.is_finite()).then_some(shape)
}

/// The quadric Q(p) = c + b·p + pᵀAp of the module docs in a sample's local frame, p the
/// local coordinates rot (x − R) / scale.
struct LocalQuadric {
    /// rows e₁, e₂, n: model directions to local ones
    rot: Matrix3<f64>,
    /// the window's extent (model units)
    scale: f64,
    /// c
    c: f64,
    /// b = (b₁, b₂, 1)
    b: Vector3,
    /// A (symmetric)
    a: Matrix3<f64>,
}

impl LocalQuadric {
    /// Fits the quadric to `points` around `frame` by least squares; `None` when the frame or
    /// the window degenerates.
    fn fit(frame: &SampleFrame, points: &[Point3]) -> Option<Self> {
        let e1 = frame.du.try_normalize(f64::MIN_POSITIVE)?;
        let n = frame.normal;
        let e2 = n.cross(&e1);
        let scale = points
            .iter()
            .map(|p| (p - frame.point).norm())
            .fold(0.0, f64::max);
        if !(scale > 0.0) || !scale.is_finite() {
            return None;
        }
        let rot = Matrix3::from_rows(&[e1.transpose(), e2.transpose(), n.transpose()]);
        let mut ata = SMatrix::<f64, 9, 9>::zeros();
        let mut atb = SVector::<f64, 9>::zeros();
        for p in points {
            let l = rot * ((p - frame.point) / scale);
            let (x, y, z) = (l.x, l.y, l.z);
            let row = SVector::<f64, 9>::from_column_slice(&[
                1.0,
                x,
                y,
                x * x,
                2.0 * x * y,
                y * y,
                2.0 * x * z,
                2.0 * y * z,
                z * z,
            ]);
            ata.syger(1.0, &row, &row, 1.0);
            atb -= z * row;
        }
        let sol = minimum_norm_solution(ata, &atb)?;
        Some(Self {
            rot,
            scale,
            c: sol[0],
            b: Vector3::new(sol[1], sol[2], 1.0),
            a: Matrix3::new(
                sol[3], sol[4], sol[6], sol[4], sol[5], sol[7], sol[6], sol[7], sol[8],
            ),
        })
    }

    /// The sample (the local origin) projected onto the quadric by [`PROJECTION_STEPS`]
    /// Newton steps along the gradient; `None` where the gradient vanishes.
    fn foot_of_sample(&self) -> Option<Vector3> {
        let (a, b) = (self.a, self.b);
        let q = |p: &Vector3| self.c + b.dot(p) + p.dot(&(a * p));
        let mut p = Vector3::zeros();
        for _ in 0..PROJECTION_STEPS {
            let grad = b + 2.0 * a * p;
            let g2 = grad.norm_squared();
            if !(g2 > 0.0) {
                return None;
            }
            p -= q(&p) / g2 * grad;
        }
        Some(p)
    }
}

/// The minimum-norm solution of the normal equations `ata` x = `atb`, eigenvalues below
/// [`QUADRIC_RANK_REL`] × the largest taken as zero; `None` for a zero matrix.
fn minimum_norm_solution(
    ata: SMatrix<f64, 9, 9>,
    atb: &SVector<f64, 9>,
) -> Option<SVector<f64, 9>> {
    let eig = SymmetricEigen::new(ata);
    let largest = eig.eigenvalues.amax();
    if !(largest > 0.0) {
        return None;
    }
    let mut sol = SVector::<f64, 9>::zeros();
    for (k, &lambda) in eig.eigenvalues.iter().enumerate() {
        if lambda > QUADRIC_RANK_REL * largest {
            let v = eig.eigenvectors.column(k);
            sol += v * (v.dot(atb) / lambda);
        }
    }
    Some(sol)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples of z = a x² + b y² (+ a tilt) around (x0, y0) and the frame there.
    fn quadric_patch(
        a: f64,
        b: f64,
        x0: f64,
        y0: f64,
        h: f64,
    ) -> (SampleFrame, Vec<Point3>, [f64; 4]) {
        let f = |x: f64, y: f64| Point3::new(x, y, a * x * x + b * y * y);
        let mut pts = Vec::new();
        for i in -4..=4 {
            for j in -4..=4 {
                pts.push(f(x0 + i as f64 * h, y0 + j as f64 * h));
            }
        }
        let du = Vector3::new(1.0, 0.0, 2.0 * a * x0);
        let dv = Vector3::new(0.0, 1.0, 2.0 * b * y0);
        let normal = du.cross(&dv).normalize();
        let (e, ff, g) = (du.dot(&du), du.dot(&dv), dv.dot(&dv));
        let ii = [2.0 * a * normal.z, 0.0, 2.0 * b * normal.z];
        let det = e * g - ff * ff;
        let shape = shape_operator([g / det, -ff / det, e / det], ii);
        let frame = SampleFrame {
            point: f(x0, y0),
            du,
            dv,
            normal,
        };
        (frame, pts, shape)
    }

    #[test]
    fn paraboloids_and_saddles_are_fitted_exactly() {
        for (a, b, x0, y0) in [
            (1.0, 1.0, 0.0, 0.0),
            (1.0, -1.0, 0.3, -0.4),
            (0.5, 2.0, -0.7, 0.2),
        ] {
            let (frame, pts, want) = quadric_patch(a, b, x0, y0, 0.05);
            let got = osculating_shape(&frame, &pts).unwrap();
            for k in 0..4 {
                assert!((got[k] - want[k]).abs() < 1e-9, "{got:?} vs {want:?}");
            }
        }
    }

    #[test]
    fn spheres_are_fitted_exactly_and_planes_give_zero() {
        let r = 2.0;
        let sph =
            |t: f64, p: f64| Point3::new(r * t.cos() * p.cos(), r * t.sin() * p.cos(), r * p.sin());
        let mut pts = Vec::new();
        for i in -3..=3 {
            for j in -3..=3 {
                pts.push(sph(0.4 + 0.05 * i as f64, 0.3 + 0.05 * j as f64));
            }
        }
        let (t, p) = (0.4f64, 0.3f64);
        let du = Vector3::new(-r * t.sin() * p.cos(), r * t.cos() * p.cos(), 0.0);
        let dv = Vector3::new(-r * t.cos() * p.sin(), -r * t.sin() * p.sin(), r * p.cos());
        let normal = du.cross(&dv).normalize();
        let frame = SampleFrame {
            point: sph(t, p),
            du,
            dv,
            normal,
        };
        let x = osculating_shape(&frame, &pts).unwrap();
        // outward normal: II = −g / r, X = −I / r (and +I / r for the inward one)
        let outward = normal.dot(&frame.point.coords).signum();
        let want = [-outward / r, 0.0, 0.0, -outward / r];
        for k in 0..4 {
            assert!((x[k] - want[k]).abs() < 1e-9, "{x:?}");
        }
        let plane: Vec<Point3> = (0..25)
            .map(|k| Point3::new((k / 5) as f64, (k % 5) as f64, 0.0))
            .collect();
        let frame = SampleFrame {
            point: Point3::new(2.0, 2.0, 0.0),
            du: Vector3::x(),
            dv: Vector3::y(),
            normal: Vector3::z(),
        };
        let x = osculating_shape(&frame, &plane).unwrap();
        assert!(x.iter().all(|v| v.abs() < 1e-12), "{x:?}");
    }

    #[test]
    fn degenerate_input_gives_none() {
        let frame = SampleFrame {
            point: Point3::origin(),
            du: Vector3::zeros(),
            dv: Vector3::y(),
            normal: Vector3::z(),
        };
        assert!(osculating_shape(&frame, &[Point3::origin()]).is_none());
        let frame = SampleFrame {
            du: Vector3::x(),
            ..frame
        };
        assert!(osculating_shape(&frame, &[Point3::origin()]).is_none());
    }
}
