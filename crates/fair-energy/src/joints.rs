//! Joints of a Bézier-spline surface: interior knots of full multiplicity (= degree), where the
//! surface is only C⁰ (\[H\] part ②, slide "B-spline surfaces with multiple inner knots").
//!
//! At a u-knot ū of multiplicity p the only functions with a non-zero derivative on either side
//! are N_{j−1}, N_j, N_{j+1} (N_j(ū) = 1: row j of the net lies on the surface), so the jump of the
//! cross derivative along column k of the net is
//! X_u(ū⁻, ·) − X_u(ū⁺, ·) ↦ J_k = c₋ P_{j−1,k} + c₀ P_{j,k} + c₊ P_{j+1,k},
//! c = N'(ū⁻) − N'(ū⁺) = (−p/h₋, p/h₋ + p/h₊, −p/h₊), h₋, h₊ the adjacent knot spans; the jump
//! function is Σ_k J_k N_k(v), so max_k |J_k| bounds it and the surface is C¹ across ū exactly
//! when every J_k = 0, i.e. P_{j,k} = (h₊ P_{j−1,k} + h₋ P_{j+1,k}) / (h₋ + h₊) (\[NB\] §5.4, the
//! condition under which the knot is removable once). The same holds for v-knots along rows.
//!
//! The coefficients c come from nurbs-core's [`BasisEvaluator`] (left and right spans), so the
//! same numbers build the jump term of [`crate::stiffness`].
//!
//! # Tolerance
//! A joint counts as C¹ when max_k |J_k| ≤ [`C1_JUMP_REL`] × its derivative scale (the largest
//! one-sided cross-derivative coefficient |c₋| |P_{j,k} − P_{j−1,k}|, |c₊| |P_{j+1,k} − P_{j,k}|):
//! a unit-free, round-off-level threshold.

use nurbs_core::{BSplineSurface, BasisEvaluator, Direction, KnotVector, Point3, Vector3};

/// Relative jump (against the joint's derivative scale) at or below which a joint counts as C¹:
/// 1e-9 is far above the rounding of the projection (~1e-15) and far below any visible crease.
pub const C1_JUMP_REL: f64 = 1e-9;

/// One interior knot of full multiplicity in one direction of a knot vector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct KnotJoint {
    /// the knot value ū
    pub knot: f64,
    /// j: the index of the control row on the joint (N_j(ū) = 1)
    pub index: usize,
    /// (c₋, c₀, c₊) = N'_{j−1..=j+1}(ū⁻) − N'_{j−1..=j+1}(ū⁺)
    pub c: [f64; 3],
}

/// The interior knots of full multiplicity of `knots`, ascending.
pub(crate) fn knot_joints(knots: &KnotVector) -> Vec<KnotJoint> {
    let p = knots.degree();
    let t = knots.knots();
    let mut eval = BasisEvaluator::new(p);
    let mut left = vec![0.0; 2 * (p + 1)];
    let mut right = vec![0.0; 2 * (p + 1)];
    let mut out = Vec::new();
    for (x, m) in knots.interior_knots() {
        if m != p {
            continue;
        }
        // a: first index with t_a = x; the joint function is N_{a−1}
        let Some(a) = t.iter().position(|&k| k == x) else {
            continue;
        };
        let (span_l, span_r) = (a - 1, a + p - 1);
        eval.derivatives(t, span_l, x, 1, &mut left);
        eval.derivatives(t, span_r, x, 1, &mut right);
        // left span: functions a − 1 − p + r; right span: functions a − 1 + r
        let j = a - 1;
        let c = [
            left[p + 1 + p - 1],
            left[p + 1 + p] - right[p + 1],
            -right[p + 1 + 1],
        ];
        out.push(KnotJoint {
            knot: x,
            index: j,
            c,
        });
    }
    out
}

/// A joint of a surface: a full-multiplicity knot of one direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SurfaceJoint {
    pub direction: Direction,
    pub joint: KnotJoint,
}

/// Every joint of `surface`, u-joints first.
pub(crate) fn surface_joints(surface: &BSplineSurface) -> Vec<SurfaceJoint> {
    let u = knot_joints(surface.knots_u())
        .into_iter()
        .map(|joint| SurfaceJoint {
            direction: Direction::U,
            joint,
        });
    let v = knot_joints(surface.knots_v())
        .into_iter()
        .map(|joint| SurfaceJoint {
            direction: Direction::V,
            joint,
        });
    u.chain(v).collect()
}

impl SurfaceJoint {
    /// Number of jump constraints (columns k for a u-joint, rows for a v-joint).
    pub fn lines(&self, nu: usize, nv: usize) -> usize {
        match self.direction {
            Direction::U => nv,
            Direction::V => nu,
        }
    }

    /// Flat indices of the three points (j − 1, j, j + 1) across the joint on line `k`.
    #[inline]
    pub fn triple(&self, k: usize, nv: usize) -> [usize; 3] {
        let j = self.joint.index;
        match self.direction {
            Direction::U => [(j - 1) * nv + k, j * nv + k, (j + 1) * nv + k],
            Direction::V => [k * nv + j - 1, k * nv + j, k * nv + j + 1],
        }
    }

    /// J_k = Σ c_a P_a on line `k`.
    #[inline]
    pub fn jump(&self, points: &[Point3], k: usize, nv: usize) -> Vector3 {
        let idx = self.triple(k, nv);
        let c = self.joint.c;
        c[0] * points[idx[0]].coords + c[1] * points[idx[1]].coords + c[2] * points[idx[2]].coords
    }

    /// (max_k |J_k|, derivative scale) of the joint.
    pub fn measure(&self, points: &[Point3], nu: usize, nv: usize) -> (f64, f64) {
        let c = self.joint.c;
        let mut jump: f64 = 0.0;
        let mut scale: f64 = 0.0;
        for k in 0..self.lines(nu, nv) {
            let idx = self.triple(k, nv);
            jump = jump.max(self.jump(points, k, nv).norm());
            scale = scale
                .max(c[0].abs() * (points[idx[1]] - points[idx[0]]).norm())
                .max(c[2].abs() * (points[idx[2]] - points[idx[1]]).norm());
        }
        (jump, scale)
    }

    /// Whether the joint is C¹ within [`C1_JUMP_REL`].
    pub fn is_c1(&self, points: &[Point3], nu: usize, nv: usize) -> bool {
        let (jump, scale) = self.measure(points, nu, nv);
        jump <= C1_JUMP_REL * scale
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coefficients_are_the_span_differences() {
        // cubic, knots 0 0 0 0 | 0.25 ×3 | 0.75 ×3 | 1 1 1 1: h₋ = 0.25, h₊ = 0.5 at 0.25
        let mut k = vec![0.0; 4];
        k.extend([0.25; 3]);
        k.extend([0.75; 3]);
        k.extend([1.0; 4]);
        let kv = KnotVector::new(3, k).expect("knots");
        let joints = knot_joints(&kv);
        assert_eq!(joints.len(), 2);
        let j = joints[0];
        assert_eq!((j.knot, j.index), (0.25, 3));
        let want = [-3.0 / 0.25, 3.0 / 0.25 + 3.0 / 0.5, -3.0 / 0.5];
        for (a, b) in j.c.iter().zip(want) {
            assert!((a - b).abs() <= 1e-12 * b.abs(), "{a} vs {b}");
        }
        assert_eq!(joints[1].index, 6);
    }
}
