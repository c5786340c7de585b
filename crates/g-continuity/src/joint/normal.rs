//! The polish's linear algebra: the block pattern of JᵀJ, the normal equations in 3 × 3 point
//! blocks, and the damped step solved by sparse Cholesky ([NW] §10.3).

use nalgebra::DMatrix;
use nurbs_core::SurfaceDerivatives;
use nurbs_core::sparse::{FillOrdering, SparseSpd, SpdSymbolic};

use super::{Problem, RES};
use crate::error::Result;

/// Added to every diagonal entry of the normal equations, relative to the largest: keeps the
/// factorization positive definite where a direction of a point reaches no residual (rounding
/// against the largest entry, no pull on the solution).
const NUGGET: f64 = 1e-14;

/// The block pattern of JᵀJ ([`Problem::pattern`]).
pub(super) struct Pattern {
    /// the point pairs (a ≥ b), sorted
    pub(super) keys: Vec<(usize, usize)>,
    /// per sample, the slot in `keys` of each pair it couples, in visiting order
    pub(super) slots: Vec<Vec<usize>>,
}

fn dot(a: &[f64; RES], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Problem<'_> {
    /// The block pattern of JᵀJ: the point pairs (a ≥ b) some sample couples, sorted, and per
    /// sample the slot of each of its pairs in the order [`Self::normal_equations`] visits them.
    /// The pattern depends on the knots only, so it is found once.
    pub(super) fn pattern(&self) -> Pattern {
        let points: Vec<Vec<usize>> = self
            .basis
            .iter()
            .map(|b| b.iter().map(|&(c, _)| c).collect())
            .collect();
        let mut keys: Vec<(usize, usize)> = points
            .iter()
            .flat_map(|p| {
                p.iter().enumerate().flat_map(move |(a, &ca)| {
                    p[..=a].iter().map(move |&cb| (ca.max(cb), ca.min(cb)))
                })
            })
            .collect();
        keys.sort_unstable();
        keys.dedup();
        let slots = points
            .iter()
            .map(|p| {
                p.iter()
                    .enumerate()
                    .flat_map(|(a, &ca)| {
                        let keys = &keys;
                        p[..=a].iter().map(move |&cb| {
                            keys.binary_search(&(ca.max(cb), ca.min(cb))).unwrap_or(0)
                        })
                    })
                    .collect()
            })
            .collect();
        Pattern { keys, slots }
    }

    /// The normal equations at the state whose per-sample derivatives are `ds` and residuals
    /// `r` ([`Problem::residual`]): JᵀJ in the 3 × 3 blocks of `pattern` (entry [d][e] couples
    /// coordinate d of the pair's first point with coordinate e of its second), and Jᵀr.
    pub(super) fn normal_equations(
        &self,
        ds: &[SurfaceDerivatives],
        r: &[f64],
        pattern: &Pattern,
    ) -> (Vec<[[f64; 3]; 3]>, Vec<f64>) {
        let mut jac = Vec::new();
        let mut blocks = vec![[[0.0; 3]; 3]; pattern.keys.len()];
        let mut jtr = vec![0.0; 3 * self.points.len()];
        for (k, (dk, slots)) in ds.iter().zip(&pattern.slots).enumerate() {
            self.jacobian(k, dk, &mut jac);
            let rk = &r[RES * k..RES * (k + 1)];
            let mut slot = slots.iter();
            for (a, (ca, ja)) in jac.iter().enumerate() {
                for d in 0..3 {
                    jtr[3 * ca + d] += dot(&ja[d], rk);
                }
                for (cb, jb) in &jac[..=a] {
                    let (first, second) = if ca >= cb { (ja, jb) } else { (jb, ja) };
                    let block = &mut blocks[*slot.next().unwrap_or(&0)];
                    for (x, row) in block.iter_mut().zip(first) {
                        for (y, col) in x.iter_mut().zip(second) {
                            *y += dot(row, col);
                        }
                    }
                }
            }
        }
        (blocks, jtr)
    }

    /// JᵀJ of the normal equations' `blocks` on `pattern` as one sparse matrix (both
    /// triangles), with the largest diagonal entry: built once per iteration, and damped per
    /// trial by [`Self::step`].
    pub(super) fn matrix(
        &self,
        pattern: &Pattern,
        blocks: &[[[f64; 3]; 3]],
    ) -> Result<(SparseSpd, f64)> {
        let n = 3 * self.points.len();
        let big = pattern
            .keys
            .iter()
            .zip(blocks)
            .filter(|((a, b), _)| a == b)
            .flat_map(|(_, m)| (0..3).map(move |d| m[d][d]))
            .fold(0.0f64, f64::max);
        let mut triplets = Vec::with_capacity(18 * blocks.len());
        for (&(a, b), m) in pattern.keys.iter().zip(blocks) {
            for (da, row) in m.iter().enumerate() {
                for (db, &v) in row.iter().enumerate() {
                    let (i, j) = (3 * a + da, 3 * b + db);
                    triplets.push((i, j, v));
                    // a diagonal block holds both triangles already
                    if a != b {
                        triplets.push((j, i, v));
                    }
                }
            }
        }
        Ok((SparseSpd::from_triplets(n, &triplets)?, big))
    }

    /// The damped Gauss–Newton step (JᵀJ + λ diag(JᵀJ)) dx = −Jᵀr from [`Self::matrix`]'s
    /// `(jtj, big)`, with [`NUGGET`] · `big` on the diagonal; `cache` keeps the symbolic
    /// factorization of the problem's pattern between calls.
    pub(super) fn step(
        &self,
        (jtj, big): (&SparseSpd, f64),
        jtr: &[f64],
        lambda: f64,
        cache: &mut Option<SpdSymbolic>,
    ) -> Result<Vec<f64>> {
        let spd = jtj.map_diagonal(|v| v * (1.0 + lambda) + NUGGET * big);
        let rhs = DMatrix::from_iterator(jtr.len(), 1, jtr.iter().map(|x| -x));
        // the pattern is the problem's: its ordering and symbolic factor are found once
        let symbolic = match cache.take() {
            Some(f) if f.fits(&spd) => f,
            _ => SpdSymbolic::new(&spd, FillOrdering::Amd)?,
        };
        let x = symbolic.solve(&spd, &rhs);
        *cache = Some(symbolic);
        Ok(x?.column(0).iter().copied().collect())
    }
}
