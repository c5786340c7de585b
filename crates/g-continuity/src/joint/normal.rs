//! The polish's linear algebra: the block pattern of JᵀJ, the normal equations in 3 × 3 point
//! blocks, and the damped step solved by sparse Cholesky (\[NW\] §10.3).

use nalgebra::DMatrix;
use nurbs_core::sparse::{FillOrdering, SparseSpd, SpdSymbolic};
use nurbs_core::{BSplineSurface, SurfaceDerivatives, Vector3};

use super::{
    DAMPING_DOWN, DAMPING_MAX, DAMPING_MIN, DAMPING_START, DAMPING_UP, JOINT_GOAL, Problem, RES,
    cost,
};
use crate::error::Result;
use crate::params::ConnectParams;

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
    /// JᵀJ's compressed columns (both triangles): column pointers and rows
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// per slot, the position in the values of each entry [d][e] of its block and, for a pair
    /// of two points, of its mirror
    at: Vec<Positions>,
}

/// Where the entries [d][e] of one 3 × 3 block go in the compressed values: (the entry, its
/// mirror across the diagonal), the same position twice in a diagonal block.
type Positions = [[(usize, usize); 3]; 3];

/// The compressed columns of a symmetric matrix with the 3 × 3 blocks `keys` (pairs a ≥ b,
/// sorted): column pointers, rows, and per block where each entry and its mirror go.
fn csc_of(n: usize, keys: &[(usize, usize)]) -> (Vec<usize>, Vec<usize>, Vec<Positions>) {
    // the entries of both triangles, each (row, column, slot, d, e, mirror)
    let mut entries = Vec::with_capacity(18 * keys.len());
    for (k, &(a, b)) in keys.iter().enumerate() {
        for d in 0..3 {
            for e in 0..3 {
                let (i, j) = (3 * a + d, 3 * b + e);
                entries.push((j, i, k, d, e, false));
                // a diagonal block holds both triangles already
                if a != b {
                    entries.push((i, j, k, d, e, true));
                }
            }
        }
    }
    entries.sort_unstable_by_key(|&(col, row, ..)| (col, row));
    let mut col_ptr = vec![0; n + 1];
    let mut row_idx = Vec::with_capacity(entries.len());
    let mut at = vec![[[(0, 0); 3]; 3]; keys.len()];
    for (pos, &(col, row, k, d, e, mirror)) in entries.iter().enumerate() {
        col_ptr[col + 1] += 1;
        row_idx.push(row);
        if mirror {
            at[k][d][e].1 = pos;
        } else {
            at[k][d][e] = (pos, pos);
        }
    }
    for j in 0..n {
        col_ptr[j + 1] += col_ptr[j];
    }
    (col_ptr, row_idx, at)
}

fn dot(a: &[f64; RES], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// block[x][y] += Σ_q first[x][q] · second[y][q], each sum taken in the order of [`dot`] (the
/// first product, then the others added one by one) for all nine entries at once, so that the
/// compiler keeps them in registers side by side.
#[inline(always)]
fn add_products(block: &mut [[f64; 3]; 3], first: &[[f64; RES]; 3], second: &[[f64; RES]; 3]) {
    let mut acc = [[0.0; 3]; 3];
    for (ax, fx) in acc.iter_mut().zip(first) {
        for (a, sy) in ax.iter_mut().zip(second) {
            *a = fx[0] * sy[0];
        }
    }
    for q in 1..RES {
        for (ax, fx) in acc.iter_mut().zip(first) {
            for (a, sy) in ax.iter_mut().zip(second) {
                *a += fx[q] * sy[q];
            }
        }
    }
    for (bx, ax) in block.iter_mut().zip(&acc) {
        for (b, a) in bx.iter_mut().zip(ax) {
            *b += a;
        }
    }
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
        let (col_ptr, row_idx, at) = csc_of(3 * self.points.len(), &keys);
        Pattern {
            keys,
            slots,
            col_ptr,
            row_idx,
            at,
        }
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
                    add_products(block, first, second);
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
        let mut values = vec![0.0; pattern.row_idx.len()];
        for (at, m) in pattern.at.iter().zip(blocks) {
            for (ad, md) in at.iter().zip(m) {
                for (&(lower, upper), &v) in ad.iter().zip(md) {
                    values[lower] = v;
                    values[upper] = v;
                }
            }
        }
        let (col_ptr, row_idx) = (pattern.col_ptr.clone(), pattern.row_idx.clone());
        Ok((SparseSpd::from_csc(n, col_ptr, row_idx, values)?, big))
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

/// The state of the Levenberg–Marquardt iteration ([`Problem::least_squares`]): the pattern and
/// its symbolic factor (found once), the surface, its (weighted) residuals and derivatives, and
/// each moving point's displacement from the start.
pub(super) struct Lm {
    pub(super) pattern: Pattern,
    pub(super) symbolic: Option<SpdSymbolic>,
    pub(super) s: BSplineSurface,
    pub(super) r: Vec<f64>,
    pub(super) ds: Vec<SurfaceDerivatives>,
    pub(super) offset: Vec<f64>,
}

impl Problem<'_> {
    /// Damped Gauss–Newton steps from `lm` (\[NW\] §10.3) until every residual is within
    /// [`JOINT_GOAL`], every link meets its target by the measure of `params`, no step lowers
    /// the cost, or `limit` steps; no point moves more than `max_move` from the start. Returns
    /// the steps taken.
    pub(super) fn least_squares(
        &self,
        lm: &mut Lm,
        limit: usize,
        max_move: f64,
        params: &ConnectParams,
    ) -> Result<usize> {
        let mut lambda = DAMPING_START;
        let mut iterations = 0;
        let mut done = self.points.is_empty() || self.worst(&lm.r) <= JOINT_GOAL;
        while !done && iterations < limit {
            let (blocks, jtr) = self.normal_equations(&lm.ds, &lm.r, &lm.pattern);
            let (jtj, big) = self.matrix(&lm.pattern, &blocks)?;
            done = true;
            while lambda <= DAMPING_MAX {
                let dx = self.step((&jtj, big), &jtr, lambda, &mut lm.symbolic)?;
                let moved: Vec<f64> = lm.offset.iter().zip(&dx).map(|(o, d)| o + d).collect();
                let within = moved
                    .chunks(3)
                    .all(|m| Vector3::new(m[0], m[1], m[2]).norm() <= max_move);
                if within {
                    let trial = self.apply(&lm.s, &dx);
                    let (rt, dt) = self.residual(&trial);
                    if cost(&rt) < cost(&lm.r) {
                        (lm.s, lm.r, lm.ds, lm.offset) = (trial, rt, dt, moved);
                        lambda = (lambda / DAMPING_DOWN).max(DAMPING_MIN);
                        iterations += 1;
                        done = self.worst(&lm.r) <= JOINT_GOAL || self.all_met(&lm.s, params);
                        break;
                    }
                }
                lambda *= DAMPING_UP;
            }
        }
        Ok(iterations)
    }
}
