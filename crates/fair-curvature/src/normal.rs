//! Least squares over the free control points of a surface, shared by both methods.
//!
//! Rows are linear in the control points through the basis of nurbs-core
//! ([`nurbs_core::SurfaceBasis`]): row r reads Σ_k c_rk P_k ≈ t_r (one right-hand side per
//! coordinate). The unknowns are the displacements δ = P − O of the free points from the
//! original O (fixed points have δ = 0 and are never written, so they stay bit-identical), and a
//! Tikhonov term keeps them small:
//!
//! min Σ_r w_r |c_r·δ − (t_r − c_r·O)|² + λ Σ_free |δ_k|²,
//! (Aᵀ W A + λ I) δ_f = Aᵀ W (t − A O) restricted to the free points.
//!
//! Solving for δ rather than P keeps exact shapes exact: when the original already satisfies
//! every row, the right-hand side is rounding noise and so is δ.
//!
//! Aᵀ W A is accumulated straight into a banded layout (every control point couples only with
//! those within ±p, ±q) and handed to nurbs-core's sparse Cholesky ([`nurbs_core::sparse`]).
//!
//! # Tolerance
//! λ = ρ × the mean diagonal of (Aᵀ W A)_ff, so ρ is unit-free whatever the rows measure.

use nalgebra::DMatrix;
use nurbs_core::sparse::{SparseSpd, SpdSolver};
use nurbs_core::{BSplineSurface, Point3, SurfaceBasis, Vector3};

use crate::error::{CurvatureError, Result};

/// Normal equations of one least-squares problem over a control net.
pub(crate) struct NormalSystem<'a> {
    original: &'a [Point3],
    nv: usize,
    p: usize,
    q: usize,
    width_v: usize,
    stride: usize,
    ata: Vec<f64>,
    atb: Vec<Vector3>,
    /// Σ w |t − A O|²: the objective at δ = 0
    btb: f64,
    /// Σ w over rows
    weight_sum: f64,
}

/// The solution of [`NormalSystem::solve`].
pub(crate) struct Displacement {
    /// δ for every control point (zero on fixed ones)
    pub delta: Vec<Vector3>,
    /// the weighted mean square row residual Σ w |c·δ − r|² / Σ w after the solve
    pub mean_square_after: f64,
}

impl<'a> NormalSystem<'a> {
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
            ata: vec![0.0; n * stride],
            atb: vec![Vector3::zeros(); n],
            btb: 0.0,
            weight_sum: 0.0,
        }
    }

    /// Adds the row Σ_k coeffs[k] P_k ≈ target with weight `weight` ≥ 0; `coeffs` is laid out
    /// like the entries of `basis`.
    pub(crate) fn add_row(
        &mut self,
        basis: &SurfaceBasis,
        coeffs: &[f64],
        weight: f64,
        target: Vector3,
    ) {
        let cv = basis.count_v;
        let index = |k: usize| (basis.first_u + k / cv) * self.nv + basis.first_v + k % cv;
        let mut residual = target;
        for (k, &c) in coeffs.iter().enumerate() {
            residual -= c * self.original[index(k)].coords;
        }
        self.btb += weight * residual.norm_squared();
        self.weight_sum += weight;
        for (a, &ca) in coeffs.iter().enumerate() {
            if ca == 0.0 {
                continue;
            }
            let ga = index(a);
            let wa = weight * ca;
            self.atb[ga] += wa * residual;
            let (ai, aj) = (a / cv, a % cv);
            let row = &mut self.ata[ga * self.stride..(ga + 1) * self.stride];
            for (b, &cb) in coeffs.iter().enumerate() {
                let (bi, bj) = (b / cv, b % cv);
                let slot = (bi + self.p - ai) * self.width_v + (bj + self.q - aj);
                row[slot] += wa * cb;
            }
        }
    }

    fn neighbours(&self, a: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        band_neighbours(self.atb.len(), self.nv, self.p, self.q, a)
    }

    /// Solves for the displacements of the points with `free[k]`, with λ = ρ × mean diagonal.
    pub(crate) fn solve(
        &self,
        free: &[bool],
        rho: f64,
        stage: &'static str,
    ) -> Result<Displacement> {
        let n = self.atb.len();
        let (col, nf) = free_columns(free);
        let mut delta = vec![Vector3::zeros(); n];
        let mean_before = self.btb / self.weight_sum.max(f64::MIN_POSITIVE);
        if nf == 0 {
            return Ok(Displacement {
                delta,
                mean_square_after: mean_before,
            });
        }
        let centre = self.p * self.width_v + self.q;
        let diag_sum: f64 = (0..n)
            .filter(|&k| free[k])
            .map(|k| self.ata[k * self.stride + centre])
            .sum();
        let lambda = rho * diag_sum / nf as f64;
        let singular = |reason: String| CurvatureError::SingularSystem { stage, reason };
        if !(diag_sum > 0.0) || !lambda.is_finite() {
            return Err(singular(format!(
                "the rows do not reach the free control points (diagonal sum {diag_sum})"
            )));
        }
        let mut triplets = Vec::with_capacity(nf * self.stride);
        let mut rhs = DMatrix::<f64>::zeros(nf, 3);
        for a in 0..n {
            let ca = col[a];
            if ca == usize::MAX {
                continue;
            }
            for c in 0..3 {
                rhs[(ca, c)] = self.atb[a][c];
            }
            for (b, slot) in self.neighbours(a) {
                let cb = col[b];
                if cb == usize::MAX {
                    continue;
                }
                let mut value = self.ata[a * self.stride + slot];
                if a == b {
                    value += lambda;
                }
                if value != 0.0 {
                    triplets.push((ca, cb, value));
                }
            }
        }
        let matrix =
            SparseSpd::from_triplets(nf, &triplets).map_err(|e| singular(e.to_string()))?;
        let x = matrix
            .solve(&rhs, SpdSolver::DEFAULT)
            .map_err(|e| singular(e.to_string()))?;
        if let Some(k) = x.iter().position(|v| !v.is_finite()) {
            return Err(singular(format!("solution entry {k} is not finite")));
        }
        for a in 0..n {
            if col[a] != usize::MAX {
                delta[a] = Vector3::new(x[(col[a], 0)], x[(col[a], 1)], x[(col[a], 2)]);
            }
        }
        let mean_square_after = self.objective(&delta) / self.weight_sum.max(f64::MIN_POSITIVE);
        Ok(Displacement {
            delta,
            mean_square_after,
        })
    }

    /// Σ w |c·δ − r|² = bᵀb − 2 δ·Aᵀb + δᵀ AᵀA δ.
    pub(crate) fn objective(&self, delta: &[Vector3]) -> f64 {
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

/// Flat index and band slot of every neighbour (di, dj), |di| ≤ p, |dj| ≤ q, of control point
/// `a` of an `n`-point net with `nv` points per row (slots laid out row by row over the
/// (2p + 1) × (2q + 1) window).
pub(crate) fn band_neighbours(
    n: usize,
    nv: usize,
    p: usize,
    q: usize,
    a: usize,
) -> impl Iterator<Item = (usize, usize)> {
    let (ai, aj) = ((a / nv) as isize, (a % nv) as isize);
    let (p, q) = (p as isize, q as isize);
    let nu = (n / nv) as isize;
    let nv = nv as isize;
    (-p..=p).flat_map(move |di| {
        (-q..=q).filter_map(move |dj| {
            let (bi, bj) = (ai + di, aj + dj);
            (bi >= 0 && bi < nu && bj >= 0 && bj < nv).then(|| {
                (
                    (bi * nv + bj) as usize,
                    ((di + p) * (2 * q + 1) + dj + q) as usize,
                )
            })
        })
    })
}

/// Column of each free control point among the free ones (`usize::MAX` for fixed points) and
/// the number of free points.
pub(crate) fn free_columns(free: &[bool]) -> (Vec<usize>, usize) {
    let mut col = vec![usize::MAX; free.len()];
    let mut nf = 0;
    for (k, &f) in free.iter().enumerate() {
        if f {
            col[k] = nf;
            nf += 1;
        }
    }
    (col, nf)
}

/// bᵀb − 2 δ·Aᵀb + δᵀ AᵀA δ for a banded normal matrix: `block(a, b, slot)` is the (a, b) block
/// of AᵀA applied to δ_b, `neighbours(a)` the band of a.
pub(crate) fn band_objective<I: Iterator<Item = (usize, usize)>>(
    btb: f64,
    atb: &[Vector3],
    delta: &[Vector3],
    block: impl Fn(usize, usize, usize) -> Vector3,
    neighbours: impl Fn(usize) -> I,
) -> f64 {
    let mut total = btb;
    for a in 0..delta.len() {
        if delta[a] == Vector3::zeros() {
            continue;
        }
        total -= 2.0 * delta[a].dot(&atb[a]);
        let mut ad = Vector3::zeros();
        for (b, slot) in neighbours(a) {
            ad += block(a, b, slot);
        }
        total += delta[a].dot(&ad);
    }
    total.max(0.0)
}

/// Largest |δ_k|.
pub(crate) fn max_norm(delta: &[Vector3]) -> f64 {
    delta.iter().map(|d| d.norm()).fold(0.0, f64::max)
}

/// Relative margin by which a displacement scaled back to the tolerance stays inside it
/// (rounding of the scaled coordinates must not push it over).
pub const SCALE_MARGIN: f64 = 1e-9;

/// Scales `delta` so that max |δ_k| ≤ `tolerance`; returns the factor (1 when nothing changed).
pub(crate) fn limit_to_tolerance(delta: &mut [Vector3], tolerance: f64) -> f64 {
    let m = max_norm(delta);
    if m <= tolerance {
        return 1.0;
    }
    let s = tolerance / m * (1.0 - SCALE_MARGIN);
    for d in delta.iter_mut() {
        *d *= s;
    }
    s
}

/// The surface with the free points displaced (fixed points copied untouched).
pub(crate) fn apply(surface: &BSplineSurface, free: &[bool], delta: &[Vector3]) -> BSplineSurface {
    let mut out = surface.clone();
    for (k, p) in out.control_points_mut().iter_mut().enumerate() {
        if free[k] {
            *p += delta[k];
        }
    }
    out
}
