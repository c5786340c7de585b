//! Least-squares integration of target curvatures along lines of samples (\[SSV08\] step 3 as
//! one boundary-value problem): the displacements y of the samples that make the discrete
//! curvature vectors follow their targets, with a soft pull and a hard ball around the
//! originals. Shared by curves (one line) and surfaces (the u- and v-isocurves of the grid).
//!
//! At an inner vertex i of a line with chords ℓ_{i−1}, ℓ_i the second divided difference
//!
//! L_i y = 2/(ℓ_{i−1} + ℓ_i) · ((y_{i+1} − y_i)/ℓ_i − (y_i − y_{i−1})/ℓ_{i−1})
//!
//! is the change of the curvature vector that the displacement y causes, to first order in
//! the normal part (a tangential slide along the line leaves the geometric curvature alone and
//! is not asked for). With the wanted changes δ_i = k̃_i − k_i of the curvature vectors
//! ([`crate::polyline`]) the displacements solve
//!
//! min Σ_rows w_r |L_r y − δ_r|² + μ Σ_s |y_s|²,  |x_s + y_s − o_s| ≤ D,
//!
//! with the row weights w_r the sample's share of length (curves) or area (surfaces), so the
//! sum approximates ∫ |Δk|² ds or ∬ (|Δk_u|² + |Δk_v|²) dA, and μ = ρ × the mean diagonal of
//! Σ w LᵀL. The same scalar matrix serves the three coordinates; it goes to nurbs-core's sparse
//! Cholesky ([`nurbs_core::sparse`]). Samples flagged fixed keep y = 0. Where a sample leaves
//! the ball of radius D its pull grows by [`BALL_PULL_GROWTH`] and the system is solved again
//! (at most [`BALL_RESOLVES`] times); what still sticks out is projected onto the ball.
//!
//! Integrating from both ends at once (a two-point boundary-value problem) replaces the two
//! initial-value integrations and their blend of \[SSV08\]: nothing accumulates along the line,
//! so the result neither drifts nor needs a pull strong enough to bring the noise back.
//!
//! # Tolerance
//! ρ is unit-free (relative to the rows' own scale); D is in model units.

use nalgebra::DMatrix;
use nurbs_core::sparse::{SparseSpd, SpdSolver};
use nurbs_core::{Point3, Vector3};

use crate::error::{CurvatureError, Result};

/// Factor by which the pull of a sample outside the ball grows before the next solve.
pub(crate) const BALL_PULL_GROWTH: f64 = 100.0;

/// Solves after the first one that may be spent on samples outside the ball.
pub(crate) const BALL_RESOLVES: usize = 3;

/// A line of samples: indices start, start + stride, … (len of them) into the point set, with
/// the wanted change δ of the curvature vector at each of its vertices (ends unused).
pub(crate) struct Line {
    pub start: usize,
    pub stride: usize,
    pub len: usize,
    pub delta: Vec<Vector3>,
}

impl Line {
    pub(crate) fn index(&self, i: usize) -> usize {
        self.start + i * self.stride
    }
}

/// The integration problem over `points` (the linearization point x), see the module docs.
pub(crate) struct Integration<'a> {
    /// x: where the curvatures were measured
    pub points: &'a [Point3],
    /// o: the centres of the balls
    pub original: &'a [Point3],
    /// samples that keep y = 0
    pub fixed: &'a [bool],
    /// per-sample weight of its rows (its share of length or area)
    pub measure: &'a [f64],
    /// D (model units)
    pub radius: f64,
    /// ρ (unit-free)
    pub rho: f64,
}

impl Integration<'_> {
    /// The faired samples x + y.
    pub(crate) fn solve(&self, lines: &[Line]) -> Result<Vec<Point3>> {
        let n = self.points.len();
        let mut col = vec![usize::MAX; n];
        let mut nf = 0;
        for s in 0..n {
            if !self.fixed[s] {
                col[s] = nf;
                nf += 1;
            }
        }
        let mut out = self.points.to_vec();
        if nf == 0 {
            return Ok(out);
        }
        let mut normal = CurvatureNormal::new(nf);
        for line in lines {
            for i in 1..line.len.saturating_sub(1) {
                if let Some((idx, c, w)) = self.second_difference(line, i) {
                    normal.add_row(&col, idx, c, w, line.delta[i]);
                }
            }
        }
        let mean = normal.diag.iter().sum::<f64>() / nf as f64;
        if !(mean > 0.0) || !mean.is_finite() {
            return Err(singular(format!(
                "no curvature rows reach the free samples (mean diagonal {mean})"
            )));
        }
        self.solve_in_balls(normal, &col, self.rho * mean, &mut out)?;
        for (p, o) in out.iter_mut().zip(self.original) {
            let off = *p - o;
            let dist = off.norm();
            if dist > self.radius {
                *p = o + off * (self.radius / dist);
            }
        }
        Ok(out)
    }

    /// The row L_i at vertex i of `line`: its three samples, their coefficients and the row's
    /// weight; `None` where the weight vanishes or a chord collapses.
    fn second_difference(&self, line: &Line, i: usize) -> Option<([usize; 3], [f64; 3], f64)> {
        let idx = [line.index(i - 1), line.index(i), line.index(i + 1)];
        let (l0, l1) = (
            (self.points[idx[1]] - self.points[idx[0]]).norm(),
            (self.points[idx[2]] - self.points[idx[1]]).norm(),
        );
        let f = 2.0 / (l0 + l1);
        let c = [f / l0, -f / l0 - f / l1, f / l1];
        let w = self.measure[idx[1]];
        if !(w > 0.0) || !c.iter().all(|c| c.is_finite()) {
            return None;
        }
        Some((idx, c, w))
    }

    /// Solves `normal` with the pull `pull` on every free sample (`col`: column of each sample,
    /// `usize::MAX` when fixed), writing x + y into `out`; while a sample leaves its ball its
    /// pull grows by [`BALL_PULL_GROWTH`] and the system is solved again (at most
    /// [`BALL_RESOLVES`] times).
    fn solve_in_balls(
        &self,
        normal: CurvatureNormal,
        col: &[usize],
        pull: f64,
        out: &mut [Point3],
    ) -> Result<()> {
        let CurvatureNormal {
            mut triplets, rhs, ..
        } = normal;
        let nf = rhs.nrows();
        let mut pull = vec![pull; nf];
        let rows = triplets.len();
        for resolve in 0..=BALL_RESOLVES {
            triplets.truncate(rows);
            triplets.extend((0..nf).map(|c| (c, c, pull[c])));
            let matrix =
                SparseSpd::from_triplets(nf, &triplets).map_err(|e| singular(e.to_string()))?;
            let y = matrix
                .solve(&rhs, SpdSolver::DEFAULT)
                .map_err(|e| singular(e.to_string()))?;
            if let Some(k) = y.iter().position(|v| !v.is_finite()) {
                return Err(singular(format!("solution entry {k} is not finite")));
            }
            let mut outside = false;
            for (s, &c) in col.iter().enumerate() {
                if c == usize::MAX {
                    continue;
                }
                let p = self.points[s] + Vector3::new(y[(c, 0)], y[(c, 1)], y[(c, 2)]);
                if (p - self.original[s]).norm() > self.radius {
                    outside = true;
                    pull[c] *= BALL_PULL_GROWTH;
                }
                out[s] = p;
            }
            if !outside || resolve == BALL_RESOLVES {
                break;
            }
        }
        Ok(())
    }
}

/// The normal equations Σ w LᵀL y = Σ w Lᵀδ of the curvature rows over the free samples, before
/// the pull is added.
struct CurvatureNormal {
    /// entries of Σ w LᵀL as (row, column, value), repeated entries summed by the solver
    triplets: Vec<(usize, usize, f64)>,
    /// Σ w Lᵀδ, one column per coordinate
    rhs: DMatrix<f64>,
    /// the diagonal of Σ w LᵀL
    diag: Vec<f64>,
}

impl CurvatureNormal {
    /// Empty equations over `nf` free samples.
    fn new(nf: usize) -> Self {
        Self {
            triplets: Vec::new(),
            rhs: DMatrix::<f64>::zeros(nf, 3),
            diag: vec![0.0; nf],
        }
    }

    /// Adds the row Σ_a c[a] y_{idx[a]} ≈ `target` with weight `w`; fixed samples (`col`
    /// `usize::MAX`) drop out.
    fn add_row(&mut self, col: &[usize], idx: [usize; 3], c: [f64; 3], w: f64, target: Vector3) {
        for a in 0..3 {
            let ca = col[idx[a]];
            if ca == usize::MAX {
                continue;
            }
            for k in 0..3 {
                self.rhs[(ca, k)] += w * c[a] * target[k];
            }
            for b in 0..3 {
                let cb = col[idx[b]];
                if cb != usize::MAX {
                    self.triplets.push((ca, cb, w * c[a] * c[b]));
                    if ca == cb {
                        self.diag[ca] += w * c[a] * c[b];
                    }
                }
            }
        }
    }
}

/// The error of a singular or failed integration solve.
fn singular(reason: String) -> CurvatureError {
    CurvatureError::SingularSystem {
        stage: "curvature integration",
        reason,
    }
}
