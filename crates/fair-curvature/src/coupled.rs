//! Least squares over the free control points with scalar rows along a direction:
//! row r reads n_r · Σ_k c_rk P_k ≈ t_r, which couples the three coordinates of a control point.
//!
//! The unknowns are the displacements δ = P − O (fixed points keep δ = 0 and are never
//! written), with the Tikhonov term of [`crate::normal`]:
//!
//! min Σ_r w_r (n_r · Σ_k c_rk δ_k − (t_r − n_r · Σ_k c_rk O_k))² + λ Σ_free |δ_k|²,
//!
//! λ = ρ × the mean diagonal entry of the normal matrix over the free coordinates. The normal
//! matrix is accumulated in 3 × 3 blocks on the band of the control net (every control point
//! couples with those within ±p, ±q) and solved with nurbs-core's sparse Cholesky.

use nalgebra::{DMatrix, Matrix3};
use nurbs_core::sparse::{SparseSpd, SpdSolver};
use nurbs_core::{BSplineSurface, Point3, SurfaceBasis, Vector3};

use crate::error::{CurvatureError, Result};
use crate::normal::{Displacement, band_neighbours, band_objective, free_columns};

/// Normal equations of rows along directions, over a control net.
pub(crate) struct CoupledSystem<'a> {
    original: &'a [Point3],
    nv: usize,
    p: usize,
    q: usize,
    width_v: usize,
    stride: usize,
    ata: Vec<Matrix3<f64>>,
    atb: Vec<Vector3>,
    btb: f64,
    weight_sum: f64,
}

impl<'a> CoupledSystem<'a> {
    pub(crate) fn new(surface: &'a BSplineSurface) -> Self {
        let (p, q) = (surface.degree_u(), surface.degree_v());
        let n = surface.num_u() * surface.num_v();
        let width_v = 2 * q + 1;
        let stride = (2 * p + 1) * width_v;
        Self {
            original: surface.control_points(),
            nv: surface.num_v(),
            p,
            q,
            width_v,
            stride,
            ata: vec![Matrix3::zeros(); n * stride],
            atb: vec![Vector3::zeros(); n],
            btb: 0.0,
            weight_sum: 0.0,
        }
    }

    /// Adds the row Σ_k coeffs[k] · P_k ≈ target with weight `weight` ≥ 0 (one 3-vector per
    /// control point); `coeffs` is laid out like the entries of `basis`.
    pub(crate) fn add_row(
        &mut self,
        basis: &SurfaceBasis,
        coeffs: &[Vector3],
        weight: f64,
        target: f64,
    ) {
        let cv = basis.count_v;
        let index = |k: usize| (basis.first_u + k / cv) * self.nv + basis.first_v + k % cv;
        let mut residual = target;
        for (k, c) in coeffs.iter().enumerate() {
            residual -= c.dot(&self.original[index(k)].coords);
        }
        self.btb += weight * residual * residual;
        self.weight_sum += weight;
        for (a, ca) in coeffs.iter().enumerate() {
            if *ca == Vector3::zeros() {
                continue;
            }
            let ga = index(a);
            let wa = weight * ca;
            self.atb[ga] += residual * wa;
            let (ai, aj) = (a / cv, a % cv);
            let row = &mut self.ata[ga * self.stride..(ga + 1) * self.stride];
            for (b, cb) in coeffs.iter().enumerate() {
                if *cb == Vector3::zeros() {
                    continue;
                }
                let (bi, bj) = (b / cv, b % cv);
                let slot = (bi + self.p - ai) * self.width_v + (bj + self.q - aj);
                row[slot] += wa * cb.transpose();
            }
        }
    }

    fn neighbours(&self, a: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        band_neighbours(self.atb.len(), self.nv, self.p, self.q, a)
    }

    /// Solves for the displacements of the points with `free[k]`, λ = ρ × mean diagonal.
    pub(crate) fn solve(
        &self,
        free: &[bool],
        rho: f64,
        stage: &'static str,
    ) -> Result<Displacement> {
        self.solve_offset(free, rho, stage, None)
    }

    pub(crate) fn solve_offset(
        &self,
        free: &[bool],
        rho: f64,
        stage: &'static str,
        offset: Option<&[Vector3]>,
    ) -> Result<Displacement> {
        let n = self.atb.len();
        let (col, nf) = free_columns(free);
        let mut delta = vec![Vector3::zeros(); n];
        if nf == 0 {
            return Ok(Displacement {
                delta,
                mean_square_after: self.btb / self.weight_sum.max(f64::MIN_POSITIVE),
            });
        }
        let centre = self.p * self.width_v + self.q;
        let diag_sum: f64 = (0..n)
            .filter(|&k| free[k])
            .map(|k| self.ata[k * self.stride + centre].trace())
            .sum();
        let lambda = rho * diag_sum / (3 * nf) as f64;
        let singular = |reason: String| CurvatureError::SingularSystem { stage, reason };
        if !(diag_sum > 0.0) || !lambda.is_finite() {
            return Err(singular(format!(
                "the rows do not reach the free control points (diagonal sum {diag_sum})"
            )));
        }
        let mut triplets = Vec::with_capacity(9 * nf * self.stride);
        let mut rhs = DMatrix::<f64>::zeros(3 * nf, 1);
        for a in 0..n {
            let ca = col[a];
            if ca == usize::MAX {
                continue;
            }
            for d in 0..3 {
                rhs[(3 * ca + d, 0)] = self.atb[a][d] - offset.map_or(0.0, |o| lambda * o[a][d]);
            }
            for (b, slot) in self.neighbours(a) {
                let cb = col[b];
                if cb == usize::MAX {
                    continue;
                }
                let block = &self.ata[a * self.stride + slot];
                for d in 0..3 {
                    for e in 0..3 {
                        let mut value = block[(d, e)];
                        if a == b && d == e {
                            value += lambda;
                        }
                        if value != 0.0 {
                            triplets.push((3 * ca + d, 3 * cb + e, value));
                        }
                    }
                }
            }
        }
        let matrix =
            SparseSpd::from_triplets(3 * nf, &triplets).map_err(|e| singular(e.to_string()))?;
        let x = matrix
            .solve(&rhs, SpdSolver::DEFAULT)
            .map_err(|e| singular(e.to_string()))?;
        if let Some(k) = x.iter().position(|v| !v.is_finite()) {
            return Err(singular(format!("solution entry {k} is not finite")));
        }
        for a in 0..n {
            if col[a] != usize::MAX {
                let c = 3 * col[a];
                delta[a] = Vector3::new(x[(c, 0)], x[(c + 1, 0)], x[(c + 2, 0)]);
            }
        }
        let mean_square_after = self.objective(&delta) / self.weight_sum.max(f64::MIN_POSITIVE);
        Ok(Displacement {
            delta,
            mean_square_after,
        })
    }

    /// Σ w (n·c·δ − r)² = bᵀb − 2 δ·Aᵀb + δᵀ AᵀA δ.
    fn objective(&self, delta: &[Vector3]) -> f64 {
        band_objective(
            self.btb,
            &self.atb,
            delta,
            |a, b, slot| self.ata[a * self.stride + slot] * delta[b],
            |a| self.neighbours(a),
        )
    }

    /// The weighted mean square residual at δ = 0.
    pub(crate) fn mean_square_before(&self) -> f64 {
        self.btb / self.weight_sum.max(f64::MIN_POSITIVE)
    }
}
