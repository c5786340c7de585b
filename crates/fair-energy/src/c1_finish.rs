//! The finishing step of the Bézier-spline extension: the smallest move of the free control points
//! that makes every joint exactly C¹, inside the ε-balls.
//!
//! Every joint gives one linear constraint per line of the net ([`crate::joints`]):
//! J_k = c₋ P_{j−1,k} + c₀ P_{j,k} + c₊ P_{j+1,k} = 0, i.e. P_{j,k} = (h₊ P_{j−1,k} + h₋ P_{j+1,k}) /
//! (h₋ + h₊). Where a u-joint meets a v-joint the constraints share points (the 3 × 3 block around
//! the cross point carries six of them, one redundant: both sides' twist), so the constraints are
//! grouped into connected components through shared free points and each component is solved at
//! once: Δ = argmin |Δ| subject to A Δ = −J (the minimum-norm least-squares solution by SVD, which
//! handles the redundancy), coordinates x, y, z sharing A.
//!
//! The distance tolerance is kept by an active set: the step X ← X + t Δ takes the largest
//! t ∈ [0, 1] that keeps every point within ε of its ORIGINAL position; when t < 1 the points that
//! reached their ball are frozen and the rest of the jump is solved for again by the remaining
//! points. Each round freezes a point, so the loop ends; ‖J‖ never grows (Δ is a least-squares
//! direction). Jumps that remain are measured and reported by the caller.
//!
//! # Deviation from the paper
//! \[H\] only penalizes the jumps (λ-weighted) and leaves them small but non-zero; this step makes
//! them vanish. A frozen point stays on its ball although it could still slide
//! along it: the active set is greedy, so a joint may be reported as left open where a cleverer
//! solver could still close it.
//!
//! # Tolerance
//! Singular values below [`RANK_REL`] × the largest count as zero (the redundant twist
//! constraint); points are placed within ε · [`BALL_SHRINK`] so that rounding keeps them inside.

use nalgebra::DMatrix;
use nurbs_core::{Point3, Vector3};

use crate::error::{EnergyError, Result};
use crate::joints::SurfaceJoint;
use crate::local::BALL_SHRINK;

/// Singular values at or below this fraction of the largest are treated as zero in the
/// minimum-norm solve: the constraint rows are exact combinations of each other at cross points,
/// so their dependent directions have σ at rounding level (~1e-16 relative).
pub const RANK_REL: f64 = 1e-12;

/// One constraint: joint `joint`, line `line`.
#[derive(Debug, Clone, Copy)]
struct Constraint {
    joint: usize,
    line: usize,
}

fn find(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

/// Largest t ∈ [0, ∞) with |d + t δ| ≤ e (|d| ≤ e expected; 0 if already outside and leaving).
fn ball_step(d: &Vector3, delta: &Vector3, e: f64) -> f64 {
    let dd = delta.norm_squared();
    if !(dd > 0.0) {
        return f64::INFINITY;
    }
    let b = d.dot(delta);
    let disc = b * b + dd * (e * e - d.norm_squared());
    if !(disc >= 0.0) {
        return 0.0;
    }
    ((-b + disc.sqrt()) / dd).max(0.0)
}

/// Makes the joints C¹ by moving only points with `free[r]`, each within `tolerance` of
/// `origin[r]`; see the module docs.
pub(crate) fn project_to_c1(
    joints: &[SurfaceJoint],
    points: &mut [Point3],
    origin: &[Point3],
    free: &[bool],
    (nu, nv): (usize, usize),
    tolerance: f64,
) -> Result<()> {
    let e = tolerance * BALL_SHRINK;
    let mut local = vec![usize::MAX; nu * nv];
    for constraints in &constraint_groups(joints, free, (nu, nv)) {
        let group = Group::new(joints, constraints, free, nv, &mut local);
        group.project(points, origin, e, &local)?;
        for &r in &group.members {
            local[r] = usize::MAX;
        }
    }
    Ok(())
}

impl Constraint {
    /// The net indices of the constraint's three points.
    fn triple(&self, joints: &[SurfaceJoint], nv: usize) -> [usize; 3] {
        joints[self.joint].triple(self.line, nv)
    }
}

/// Every line of every joint as a constraint, grouped into connected components through shared
/// free points; constraints on three fixed points are left out (nothing can change them).
fn constraint_groups(
    joints: &[SurfaceJoint],
    free: &[bool],
    (nu, nv): (usize, usize),
) -> Vec<Vec<Constraint>> {
    let n = nu * nv;
    let constraints: Vec<Constraint> = joints
        .iter()
        .enumerate()
        .flat_map(|(joint, jt)| (0..jt.lines(nu, nv)).map(move |line| Constraint { joint, line }))
        .collect();
    // components through shared free points
    let mut parent: Vec<usize> = (0..n).collect();
    for c in &constraints {
        let t = c.triple(joints, nv);
        let frees: Vec<usize> = t.into_iter().filter(|&r| free[r]).collect();
        for w in frees.windows(2) {
            let (a, b) = (find(&mut parent, w[0]), find(&mut parent, w[1]));
            if a != b {
                parent[a] = b;
            }
        }
    }
    let mut groups: Vec<Vec<Constraint>> = Vec::new();
    let mut group_of = vec![usize::MAX; n];
    for c in &constraints {
        let Some(&r) = c.triple(joints, nv).iter().find(|&&r| free[r]) else {
            continue; // all three points fixed: nothing can change this jump
        };
        let root = find(&mut parent, r);
        if group_of[root] == usize::MAX {
            group_of[root] = groups.len();
            groups.push(Vec::new());
        }
        groups[group_of[root]].push(*c);
    }
    groups
}

/// One connected group of constraints and the free points they move.
struct Group<'a> {
    joints: &'a [SurfaceJoint],
    constraints: &'a [Constraint],
    free: &'a [bool],
    nv: usize,
    /// the group's free points, in first-seen order
    members: Vec<usize>,
}

impl<'a> Group<'a> {
    /// The group of `constraints`; writes each member's index among the members into `local`.
    fn new(
        joints: &'a [SurfaceJoint],
        constraints: &'a [Constraint],
        free: &'a [bool],
        nv: usize,
        local: &mut [usize],
    ) -> Self {
        let mut members: Vec<usize> = Vec::new();
        for c in constraints {
            for r in c.triple(joints, nv) {
                if free[r] && local[r] == usize::MAX {
                    local[r] = members.len();
                    members.push(r);
                }
            }
        }
        Self {
            joints,
            constraints,
            free,
            nv,
            members,
        }
    }

    /// The active-set loop of the module docs: steps the active members towards zero jumps as
    /// far as their balls of radius `e` around `origin` allow, freezing those that reach them.
    fn project(
        &self,
        points: &mut [Point3],
        origin: &[Point3],
        e: f64,
        local: &[usize],
    ) -> Result<()> {
        let members = &self.members;
        let mut active = vec![true; members.len()];
        for _round in 0..=members.len() {
            let cols: Vec<usize> = (0..members.len()).filter(|&q| active[q]).collect();
            if cols.is_empty() {
                break;
            }
            let step = self.minimum_norm_step(points, &cols, local)?;
            let limits: Vec<f64> = cols
                .iter()
                .zip(&step)
                .map(|(&q, s)| {
                    let r = members[q];
                    ball_step(&(points[r] - origin[r]), s, e)
                })
                .collect();
            let t = limits.iter().cloned().fold(1.0, f64::min);
            for (&q, s) in cols.iter().zip(&step) {
                let r = members[q];
                points[r] += s * t;
            }
            if t >= 1.0 {
                break;
            }
            for (&q, &limit) in cols.iter().zip(&limits) {
                if limit <= t {
                    active[q] = false;
                }
            }
        }
        Ok(())
    }

    /// Δ = argmin |Δ| subject to A Δ = −J over the members `cols` (indices into `members`),
    /// one 3-vector per column: the minimum-norm least-squares solution by SVD.
    fn minimum_norm_step(
        &self,
        points: &[Point3],
        cols: &[usize],
        local: &[usize],
    ) -> Result<Vec<Vector3>> {
        let mut col_of = vec![usize::MAX; self.members.len()];
        for (a, &q) in cols.iter().enumerate() {
            col_of[q] = a;
        }
        let m = self.constraints.len();
        let mut a = DMatrix::zeros(m, cols.len());
        let mut rhs = DMatrix::zeros(m, 3);
        for (row, c) in self.constraints.iter().enumerate() {
            let jt = &self.joints[c.joint];
            let jump = jt.jump(points, c.line, self.nv);
            for d in 0..3 {
                rhs[(row, d)] = -jump[d];
            }
            for (&r, &coef) in jt.triple(c.line, self.nv).iter().zip(&jt.joint.c) {
                if self.free[r] && col_of[local[r]] != usize::MAX {
                    a[(row, col_of[local[r]])] = coef;
                }
            }
        }
        let svd = a.svd(true, true);
        let sigma_max = svd.singular_values.iter().cloned().fold(0.0, f64::max);
        let delta =
            svd.solve(&rhs, RANK_REL * sigma_max)
                .map_err(|reason| EnergyError::SolveFailed {
                    solver: "nalgebra SVD",
                    reason: reason.to_string(),
                })?;
        Ok((0..cols.len())
            .map(|k| Vector3::new(delta[(k, 0)], delta[(k, 1)], delta[(k, 2)]))
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ball_step_reaches_the_sphere() {
        let d = Vector3::new(0.3, 0.0, 0.0);
        let s = Vector3::new(1.0, 1.0, 0.0);
        let t = ball_step(&d, &s, 1.0);
        assert!(((d + s * t).norm() - 1.0).abs() < 1e-14);
        assert_eq!(ball_step(&d, &Vector3::zeros(), 1.0), f64::INFINITY);
    }
}
