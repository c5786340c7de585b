//! KRR fairing of surfaces (\[SV\] §5.1, Hahmann): the single-point solve of [`crate::jump`]
//! along the u-column, the v-row, or the average of both through P_ij.
//!
//! Rank of a free point: the largest jump of the p-th (q-th) derivative at its central knot in the
//! chosen direction(s); the best-ranked point moves to its target, clamped to the ball of radius ε
//! around its original. Moving P_ij changes only the jumps of the points within p + 1 rows in its
//! column and q + 1 columns in its row, so only those ranks are recomputed (a [`MaxTree`] holds
//! them). Only points the [`ControlMask`] frees move: the frames of \[SV\] §3.1 stay bit-identical.

use nurbs_core::max_tree::{MaxTree, NEVER};
use nurbs_core::{BSplineSurface, ControlMask, Faired, FairingProblem, Point3, SurfaceFairing};

use crate::curve::{KrrReport, KrrStop, MIN_MOVE_REL, check_params, clamp_to_ball};
use crate::error::{KrrError, Result, check_tolerance};
use crate::jump::KnotJumps;

/// Which isocurve directions KRR works along (\[SV\] §5.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KrrDirection {
    /// along u (the column through P_ij)
    U,
    /// along v (the row through P_ij)
    V,
    /// the average of the u and v targets (one of them where only one exists)
    Average,
}

/// Settings of surface KRR.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KrrParams {
    /// Largest number of single-point moves. Default 10,000, the budget of the energy method's
    /// seed example (\[H\] "Examples (1)").
    pub max_iterations: usize,
    /// Direction(s). Default [`KrrDirection::Average`]: independent of the parametrization's
    /// orientation (\[SV\] §5.1 "average the two values").
    pub direction: KrrDirection,
    /// How many of the last moved points are skipped. Default 2.
    pub taboo: usize,
    /// Stop when the largest jump falls below this fraction of the largest jump at the start.
    /// Default 1e-6.
    pub min_relative_jump: f64,
}

impl Default for KrrParams {
    fn default() -> Self {
        Self {
            max_iterations: 10_000,
            direction: KrrDirection::Average,
            taboo: 2,
            min_relative_jump: 1e-6,
        }
    }
}

struct Ranker<'a> {
    ju: KnotJumps,
    jv: KnotJumps,
    nv: usize,
    direction: KrrDirection,
    origin: &'a [Point3],
    tolerance: f64,
}

impl Ranker<'_> {
    /// Jump size and clamped target of point r; `None` when it has no knot in the direction(s).
    #[inline]
    fn evaluate(&self, p: &[Point3], r: usize) -> Option<(f64, Point3)> {
        let (i, j, nv) = (r / self.nv, r % self.nv, self.nv);
        let along_u = || {
            Some((
                self.ju.jump(i, |a| p[a * nv + j])?.norm(),
                self.ju.target(i, |a| p[a * nv + j])?,
            ))
        };
        let along_v = || {
            Some((
                self.jv.jump(j, |b| p[i * nv + b])?.norm(),
                self.jv.target(j, |b| p[i * nv + b])?,
            ))
        };
        let (size, target) = match self.direction {
            KrrDirection::U => along_u()?,
            KrrDirection::V => along_v()?,
            KrrDirection::Average => match (along_u(), along_v()) {
                (Some((a, ta)), Some((b, tb))) => {
                    (a.max(b), Point3::from((ta.coords + tb.coords) * 0.5))
                }
                (Some(x), None) | (None, Some(x)) => x,
                (None, None) => return None,
            },
        };
        Some((size, clamp_to_ball(target, &self.origin[r], self.tolerance)))
    }

    /// Largest jump over the free points.
    fn max_jump(&self, p: &[Point3], free: &[bool]) -> f64 {
        (0..p.len())
            .filter(|&r| free[r])
            .filter_map(|r| self.evaluate(p, r))
            .map(|(s, _)| s)
            .fold(0.0, f64::max)
    }
}

/// Fairs `surface` by KRR, moving only points `mask` frees, each within `tolerance` (model units)
/// of its original. A mask that frees no fairable point returns the surface unchanged with
/// [`KrrStop::NothingFree`].
pub fn fair_surface(
    surface: &BSplineSurface,
    mask: &ControlMask,
    tolerance: f64,
    params: &KrrParams,
) -> Result<(BSplineSurface, KrrReport)> {
    check_tolerance(tolerance)?;
    check_params(params.min_relative_jump)?;
    mask.check_shape(surface)?;
    if surface.is_rational() {
        return Err(KrrError::Rational { what: "surface" });
    }
    let origin = surface.control_points();
    let ranker = Ranker {
        ju: KnotJumps::new(surface.knots_u()),
        jv: KnotJumps::new(surface.knots_v()),
        nv: surface.num_v(),
        direction: params.direction,
        origin,
        tolerance,
    };
    let free = mask.as_slice();
    let mut out = surface.clone();
    let before = ranker.max_jump(origin, free);
    let threshold = params.min_relative_jump * before;
    let mut run = SurfaceRun::new(ranker, surface, free, params.taboo);
    let fairable = run.rank_all(origin);
    let mut stop = if fairable == 0 {
        KrrStop::NothingFree
    } else {
        KrrStop::IterationLimit
    };
    let mut iterations = 0;
    while iterations < params.max_iterations && stop == KrrStop::IterationLimit {
        let best = run.tree.arg_max().filter(|&(_, s)| s > threshold);
        let Some((r, _)) = best else {
            stop = KrrStop::Converged;
            break;
        };
        let points = out.control_points_mut();
        points[r] = run.target[r];
        iterations += 1;
        let released = run.make_taboo(r);
        run.rerank_around(points, r, released);
    }
    let p = out.control_points();
    let report = KrrReport {
        iterations,
        max_jump_before: before,
        max_jump_after: run.ranker.max_jump(p, free),
        max_control_move: nurbs_core::fairing::max_displacement(origin, p),
        stop,
    };
    Ok((out, report))
}

/// The state of one surface run: the ranks in a [`MaxTree`], each point's clamped target and
/// the taboo list.
struct SurfaceRun<'a> {
    ranker: Ranker<'a>,
    free: &'a [bool],
    /// net shape (n_u, n_v)
    shape: (usize, usize),
    /// degrees (p, q)
    degrees: (usize, usize),
    /// moves shorter than this count as none (model units)
    min_move: f64,
    /// each ranked point's clamped target
    target: Vec<Point3>,
    tree: MaxTree,
    /// the last moved points, oldest first
    taboo: Vec<usize>,
    /// at most this many of them
    taboo_len: usize,
    in_taboo: Vec<bool>,
}

impl<'a> SurfaceRun<'a> {
    /// An unranked run over `surface`'s net.
    fn new(ranker: Ranker<'a>, surface: &BSplineSurface, free: &'a [bool], taboo: usize) -> Self {
        let n = surface.num_u() * surface.num_v();
        Self {
            min_move: MIN_MOVE_REL * ranker.tolerance,
            target: ranker.origin.to_vec(),
            ranker,
            free,
            shape: (surface.num_u(), surface.num_v()),
            degrees: (surface.degree_u(), surface.degree_v()),
            tree: MaxTree::new(n),
            taboo: Vec::with_capacity(taboo + 1),
            taboo_len: taboo,
            in_taboo: vec![false; n],
        }
    }

    /// Rank of point r at `p`: its jump when its clamped target (stored) moves it, [`NEVER`]
    /// otherwise.
    fn rank(&mut self, p: &[Point3], r: usize) -> f64 {
        match self.ranker.evaluate(p, r) {
            Some((size, t)) if (t - p[r]).norm() > self.min_move => {
                self.target[r] = t;
                size
            }
            _ => NEVER,
        }
    }

    /// [`Self::rank`], or [`NEVER`] for a taboo point.
    fn rank_unless_taboo(&mut self, p: &[Point3], r: usize) -> f64 {
        if self.in_taboo[r] {
            NEVER
        } else {
            self.rank(p, r)
        }
    }

    /// Ranks every free point at `origin` and builds the tree; returns how many free points
    /// have a knot to fair.
    fn rank_all(&mut self, origin: &[Point3]) -> usize {
        let mut fairable = 0;
        for r in (0..origin.len()).filter(|&r| self.free[r]) {
            if self.ranker.evaluate(origin, r).is_some() {
                fairable += 1;
            }
            let z = self.rank(origin, r);
            self.tree.set_leaf(r, z);
        }
        self.tree.rebuild();
        fairable
    }

    /// Puts the moved point r on the taboo list; returns the point that leaves it.
    fn make_taboo(&mut self, r: usize) -> Option<usize> {
        self.taboo.push(r);
        self.in_taboo[r] = true;
        let released = if self.taboo.len() > self.taboo_len {
            Some(self.taboo.remove(0))
        } else {
            None
        };
        if let Some(q) = released {
            self.in_taboo[q] = false;
        }
        released
    }

    /// Re-ranks the free points whose jumps the move of point r changed (p + 1 rows along its
    /// column, q + 1 columns along its row) and the point `released` from the taboo list.
    fn rerank_around(&mut self, points: &[Point3], r: usize, released: Option<usize>) {
        let ((nu, nv), (p_deg, q_deg)) = (self.shape, self.degrees);
        let (i, j) = (r / nv, r % nv);
        let (a0, a1) = (i.saturating_sub(p_deg + 1), (i + p_deg + 1).min(nu - 1));
        let (b0, b1) = (j.saturating_sub(q_deg + 1), (j + q_deg + 1).min(nv - 1));
        for a in a0..=a1 {
            let s = a * nv + j;
            if self.free[s] {
                let v = self.rank_unless_taboo(points, s);
                self.tree.update(s, v);
            }
        }
        for b in b0..=b1 {
            let s = i * nv + b;
            if self.free[s] {
                let v = self.rank_unless_taboo(points, s);
                self.tree.set_leaf(s, v);
            }
        }
        self.tree.refresh(i * nv + b0, i * nv + b1);
        if let Some(q) = released.filter(|&q| self.free[q]) {
            let v = self.rank(points, q);
            self.tree.update(q, v);
        }
    }
}

/// The KRR method (`krr`) for the framework.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct KrrFairing {
    /// its settings
    pub params: KrrParams,
}

/// Name of the method.
pub const KRR_METHOD: &str = "krr";

impl SurfaceFairing for KrrFairing {
    fn name(&self) -> &str {
        KRR_METHOD
    }

    /// `max_iterations` limits the removal–reinsertion steps.
    fn fair(&self, problem: &FairingProblem<'_>) -> nurbs_core::Result<Faired> {
        let mut params = self.params;
        if let Some(n) = problem.max_iterations {
            params.max_iterations = n;
        }
        let (out, r) = fair_surface(problem.surface, problem.mask, problem.tolerance, &params)
            .map_err(|e| e.into_core(KRR_METHOD))?;
        Ok(Faired::new(out, r.iterations))
    }
}
