//! The local scheme of \[H\] (slides "The new control point", "Ranking number"): move one control
//! point at a time to its optimal position with all others fixed.
//!
//! With the functional E(d) = Σ_c x_cᵀ K x_c and g_r = Σ_s K_rs d_s, moving d_r by δ changes E by
//! 2 δ·g_r + K_rr |δ|², so the unconstrained optimum is d̃_r = d_r − g_r / K_rr
//! (= Σ_{s≠r} γ_s d_s with γ_s = −K_rs / K_rr, \[H\] "The new control point (2)") and the ranking
//! number is z_r = |g_r|² / K_rr = K_rr |d_r − d̃_r|² (\[H\] "Ranking number").
//!
//! The distance tolerance (\[H\] "Solution", case 2): the new point must stay within ε of the
//! ORIGINAL point o_r. Energy level sets around one point are spheres centred at d̃_r, so the
//! constrained optimum is the point of the ball nearest to d̃_r: o_r + ε (d̃_r − o_r)/|d̃_r − o_r|.
//! The ranking number is then the constrained decrease −(2 δ·g_r + K_rr |δ|²) ≥ 0.
//!
//! Bookkeeping: g is kept up to date (a move of d_s changes g only inside the stencil of s), ranks
//! live in a [`MaxTree`] over blocks of `RANK_BLOCK` points, and only the ranks inside the
//! stencil of the moved point are recomputed: one iteration costs O(stencil · log n), no full
//! rescan and no allocation.
//!
//! # Tolerance
//! New points are placed at distance ≤ ε·[`BALL_SHRINK`] so that rounding never puts them outside
//! the ball. A run stops when the best ranking number falls to `min_relative_decrease` times the
//! starting energy (a relative, unit-free threshold) or after `max_iterations` moves.

use nurbs_core::max_tree::{MaxTree, NEVER};
use nurbs_core::{Point3, Vector3};

/// What the local scheme needs of a stiffness matrix K: its net shape and stencil, g = K d, the
/// diagonal, and the couplings of one point row by row. Implemented by the separable K of
/// polynomial surfaces and curves ([`crate::SeparableStiffness`]) and the stencil-stored K of
/// rational surfaces ([`crate::RationalStiffness`]).
pub(crate) trait LocalStiffness {
    /// Scratch holding the stencil of one point.
    type Stencil;
    /// Control points (n_u, n_v); flat index i·n_v + j.
    fn shape(&self) -> (usize, usize);
    /// (w_u, w_v): K couples (i, j) and (k, l) only when |i − k| ≤ w_u and |j − l| ≤ w_v.
    fn half_widths(&self) -> (usize, usize);
    /// K_rr.
    fn diagonal(&self, r: usize) -> f64;
    /// K_{(i,j),(k,l)} (zero outside the stencil).
    fn entry(&self, r: (usize, usize), s: (usize, usize)) -> f64;
    /// g = K d.
    fn multiply(&self, d: &[Point3], g: &mut [Vector3]);
    /// Scratch for [`LocalStiffness::load`].
    fn new_stencil(&self) -> Self::Stencil;
    /// Loads the couplings of point (k, l).
    fn load(&self, k: usize, l: usize, st: &mut Self::Stencil);
    /// K_{(i0 + a, j),(k, l)} for j = j0, j0 + 1, … of the loaded point (k, l), where
    /// i0 = k − w_u and j0 = l − w_v clamped to the net; the caller takes the first j1 − j0 + 1.
    fn row(&self, st: &Self::Stencil, a: usize) -> impl Iterator<Item = f64>;
}

/// Factor (just below 1) applied to ε when a point is projected onto its tolerance sphere, so that
/// the stored point is within ε despite rounding (the kernel's value).
pub use nurbs_core::fairing::BALL_SHRINK;

/// Diagonal entries K_rr at or below this fraction of the largest one count as zero: such a point
/// does not influence the functional (e.g. a degree-1 curve) and is never moved.
pub(crate) const NULL_DIAGONAL_REL: f64 = 1e-14;

/// Why a local run stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// `max_iterations` moves were made
    IterationLimit,
    /// the best ranking number fell below the threshold
    Converged,
    /// the mask frees no point that influences the functional: nothing could move
    NothingFree,
}

/// What a local run achieved (energies are values of the functional being minimized).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalOutcome {
    /// moves made
    pub iterations: usize,
    /// functional before
    pub energy_before: f64,
    /// functional after
    pub energy_after: f64,
    /// largest distance of a control point from its original (model units)
    pub max_control_move: f64,
    /// why the run stopped
    pub stop: StopReason,
}

/// Settings of one local run.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LocalSettings {
    pub tolerance: f64,
    pub max_iterations: usize,
    pub min_relative_decrease: f64,
}

/// Leaves per block of [`Ranks`]: a block's maximum is refreshed by scanning it, which is cheaper
/// than one more tree level for the short row runs of a stencil.
const RANK_BLOCK: usize = 8;

/// Ranking numbers with a max-tree over blocks of [`RANK_BLOCK`] consecutive points.
struct Ranks {
    z: Vec<f64>,
    blocks: MaxTree,
}

impl Ranks {
    fn new(n: usize) -> Self {
        Self {
            z: vec![NEVER; n.div_ceil(RANK_BLOCK) * RANK_BLOCK],
            blocks: MaxTree::new(n.div_ceil(RANK_BLOCK)),
        }
    }
    #[inline(always)]
    fn set(&mut self, idx: usize, z: f64) {
        self.z[idx] = z;
    }
    /// Refreshes the blocks holding points lo..=hi (their block leaves only).
    #[inline]
    fn refresh_blocks(&mut self, lo: usize, hi: usize) {
        for b in lo / RANK_BLOCK..=hi / RANK_BLOCK {
            let m = self.z[b * RANK_BLOCK..(b + 1) * RANK_BLOCK]
                .iter()
                .fold(NEVER, |m, &v| if v > m { v } else { m });
            self.blocks.set_leaf(b, m);
        }
    }
    fn rebuild(&mut self) {
        for b in 0..self.blocks.len() {
            self.refresh_blocks(b * RANK_BLOCK, b * RANK_BLOCK);
        }
        self.blocks.rebuild();
    }
    fn arg_max(&self) -> Option<(usize, f64)> {
        let (b, m) = self.blocks.arg_max()?;
        let k = self.z[b * RANK_BLOCK..(b + 1) * RANK_BLOCK]
            .iter()
            .position(|&v| v == m)?;
        Some((b * RANK_BLOCK + k, m))
    }
}

/// The constrained optimum of one point and its energy decrease (`inv_kr` = 1 / K_rr).
#[inline(always)]
fn candidate(d: &Point3, g: &Vector3, kr: f64, inv_kr: f64, o: &Point3, eps: f64) -> (Point3, f64) {
    let opt = d - g * inv_kr;
    let w = opt - o;
    let dist2 = w.norm_squared();
    let new = if dist2 <= eps * eps {
        opt
    } else {
        o + w * (eps * BALL_SHRINK / dist2.sqrt())
    };
    let delta = new - d;
    (new, -(2.0 * delta.dot(g) + kr * delta.norm_squared()))
}

/// E(d) = Σ_c d_cᵀ (K d)_c.
pub(crate) fn energy_of<K: LocalStiffness>(k: &K, d: &[Point3]) -> f64 {
    let mut g = vec![Vector3::zeros(); d.len()];
    k.multiply(d, &mut g);
    d.iter().zip(&g).map(|(p, v)| p.coords.dot(v)).sum()
}

/// Runs the local scheme on `current` (inside the ε-balls around `origin`), moving only points
/// with `free[r]`.
pub(crate) fn run_local<K: LocalStiffness>(
    k: &K,
    origin: &[Point3],
    current: &mut [Point3],
    free: &[bool],
    s: LocalSettings,
) -> LocalOutcome {
    let mut run = LocalRun::new(k, origin, current, free, s.tolerance);
    let energy_before = run.energy_before;
    let threshold = s.min_relative_decrease * energy_before.max(0.0);
    let mut stop = if run.movable.iter().any(|&m| m) {
        StopReason::IterationLimit
    } else {
        StopReason::NothingFree
    };
    let mut iterations = 0;
    let mut energy = energy_before;
    while iterations < s.max_iterations && stop == StopReason::IterationLimit {
        let Some((r, z)) = run.tree.arg_max() else {
            stop = StopReason::Converged;
            break;
        };
        if z <= threshold || z == NEVER {
            stop = StopReason::Converged;
            break;
        }
        run.move_point(r);
        iterations += 1;
        energy -= z;
    }
    // tracked as E₀ − Σ z (exact in exact arithmetic; rounding stays far below 1e-9 E₀)
    let energy_after = energy.max(0.0);
    let max_control_move = nurbs_core::fairing::max_displacement(origin, run.current);
    LocalOutcome {
        iterations,
        energy_before,
        energy_after,
        max_control_move,
        stop,
    }
}

/// The state of one local run: the points, g = K d, the diagonal, the ranks and the scratch of
/// one stencil update.
struct LocalRun<'a, K: LocalStiffness> {
    k: &'a K,
    origin: &'a [Point3],
    current: &'a mut [Point3],
    /// ε (model units)
    tolerance: f64,
    /// net shape (n_u, n_v)
    shape: (usize, usize),
    /// g = K d
    g: Vec<Vector3>,
    /// K_rr
    diag: Vec<f64>,
    /// 1 / K_rr, 0 where K_rr counts as zero
    inv_diag: Vec<f64>,
    /// free points that influence the functional
    movable: Vec<bool>,
    /// E before the run
    energy_before: f64,
    tree: Ranks,
    stencil: K::Stencil,
    /// block ranges of one stencil update
    block_ranges: Vec<(usize, usize)>,
}

impl<'a, K: LocalStiffness> LocalRun<'a, K> {
    /// Measures g, E and the diagonal at `current` and ranks every movable point.
    fn new(
        k: &'a K,
        origin: &'a [Point3],
        current: &'a mut [Point3],
        free: &[bool],
        tolerance: f64,
    ) -> Self {
        let (nu, nv) = k.shape();
        let n = nu * nv;
        let mut g = vec![Vector3::zeros(); n];
        k.multiply(current, &mut g);
        let energy_before: f64 = current.iter().zip(&g).map(|(p, v)| p.coords.dot(v)).sum();
        let diag: Vec<f64> = (0..n).map(|r| k.diagonal(r)).collect();
        let diag_cut = NULL_DIAGONAL_REL * diag.iter().cloned().fold(0.0, f64::max);
        let movable: Vec<bool> = (0..n).map(|r| free[r] && diag[r] > diag_cut).collect();
        let inv_diag: Vec<f64> = diag
            .iter()
            .map(|&d| if d > diag_cut { 1.0 / d } else { 0.0 })
            .collect();
        let (wu, _) = k.half_widths();
        let mut run = Self {
            k,
            origin,
            current,
            tolerance,
            shape: (nu, nv),
            g,
            diag,
            inv_diag,
            movable,
            energy_before,
            tree: Ranks::new(n),
            stencil: k.new_stencil(),
            block_ranges: Vec::with_capacity(2 * wu + 1),
        };
        for r in (0..n).filter(|&r| run.movable[r]) {
            let (_, z) = run.candidate(r);
            run.tree.set(r, z);
        }
        run.tree.rebuild();
        run
    }

    /// The constrained optimum of point r and its energy decrease.
    fn candidate(&self, r: usize) -> (Point3, f64) {
        candidate(
            &self.current[r],
            &self.g[r],
            self.diag[r],
            self.inv_diag[r],
            &self.origin[r],
            self.tolerance,
        )
    }

    /// Moves point r to its constrained optimum and updates g and the ranks inside its stencil.
    fn move_point(&mut self, r: usize) {
        let (new, _) = self.candidate(r);
        let delta = new - self.current[r];
        self.current[r] = new;
        let (nu, nv) = self.shape;
        let (wu, wv) = self.k.half_widths();
        let (kr, lr) = (r / nv, r % nv);
        self.k.load(kr, lr, &mut self.stencil);
        let (i0, i1) = (kr.saturating_sub(wu), (kr + wu).min(nu - 1));
        let (j0, j1) = (lr.saturating_sub(wv), (lr + wv).min(nv - 1));
        // one pass over the stencil: update g, then each point's candidate and rank
        for (di, i) in (i0..=i1).enumerate() {
            self.update_row(di, i * nv + j0, i * nv + j1 + 1, delta);
        }
        self.refresh_block_tree((i0, i1), (j0, j1));
    }

    /// Adds K's couplings in stencil row `di` (points lo..hi) times `delta` to g and re-ranks
    /// those points.
    #[inline]
    fn update_row(&mut self, di: usize, lo: usize, hi: usize, delta: Vector3) {
        let rows = self.g[lo..hi]
            .iter_mut()
            .zip(&self.current[lo..hi])
            .zip(&self.origin[lo..hi]);
        let data = self.diag[lo..hi]
            .iter()
            .zip(&self.inv_diag[lo..hi])
            .zip(&self.movable[lo..hi])
            .zip(self.k.row(&self.stencil, di));
        for (idx, (((gj, dj), oj), ((kj, ikj), mj), kij)) in
            (lo..hi).zip(rows.zip(data).map(|(a, (b, c))| (a, b, c)))
        {
            *gj += kij * delta;
            if *mj {
                let z = candidate(dj, gj, *kj, *ikj, oj, self.tolerance).1;
                self.tree.set(idx, z);
            }
        }
        self.tree.refresh_blocks(lo, hi - 1);
    }

    /// Refreshes the block tree over the stencil rows i0..=i1, columns j0..=j1: their block
    /// ranges merged where they touch, then one level-by-level refresh.
    fn refresh_block_tree(&mut self, (i0, i1): (usize, usize), (j0, j1): (usize, usize)) {
        let nv = self.shape.1;
        self.block_ranges.clear();
        for i in i0..=i1 {
            let (lo, hi) = ((i * nv + j0) / RANK_BLOCK, (i * nv + j1) / RANK_BLOCK);
            match self.block_ranges.last_mut() {
                Some(last) if lo <= last.1 + 1 => last.1 = last.1.max(hi),
                _ => self.block_ranges.push((lo, hi)),
            }
        }
        self.tree.blocks.refresh_ranges(&mut self.block_ranges);
    }
}
