//! Normals and principal curvatures on a parameter grid, batched per grid row.
//!
//! The formulas are those of [`SurfaceDerivatives::curvature_values`] (second fundamental form
//! in the orthonormal frame e1 = S_u/√E, e2 = n × e1):
//! b11 = L/E, b12 = (M − rL)/|S_u × S_v|, b22 = (N − 2rM + r²L)·E/|S_u × S_v|², r = F/E, and
//! k1,2 = (b11 + b22)/2 ± √(((b11 − b22)/2)² + b12²).
//!
//! What differs is the order of work: the derivatives of a whole grid row are evaluated first
//! (tensor-product structure, see [`crate::grid`]), their dot products stored column-wise, and the
//! square roots and divisions then run over contiguous arrays, where the compiler issues packed
//! SIMD instructions (two or four points per `sqrtpd`/`divpd`) instead of one latency chain per
//! point. The arithmetic per point is the same sequence of IEEE operations as the pointwise
//! method, so the results are bit-identical to it (tested), singular points included (`None`).

use crate::diffgeom::{CurvatureValues, NORMAL_SIN_EPS, TANGENT_RATIO_EPS};
use crate::grid::{GridOrder, GridPlan};
use crate::surface::{BSplineSurface, SurfaceDerivatives};
use crate::{Point3, Vector3};

/// One sample of [`BSplineSurface::eval_grid_curvatures_into`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridCurvature {
    /// S(u, v)
    pub point: Point3,
    /// unit normal and principal curvatures, `None` where the surface is singular
    pub values: Option<CurvatureValues>,
}

/// Column-wise scratch of one grid row (structure of arrays).
#[derive(Default)]
struct RowScratch {
    point: Vec<Point3>,
    cross: Vec<Vector3>,
    regular: Vec<bool>,
    lu2: Vec<f64>,
    lc2: Vec<f64>,
    lc: Vec<f64>,
    mc: Vec<f64>,
    nc: Vec<f64>,
    f: Vec<f64>,
    inv_len: Vec<f64>,
    k1: Vec<f64>,
    k2: Vec<f64>,
}

impl RowScratch {
    fn clear(&mut self) {
        self.point.clear();
        self.cross.clear();
        self.regular.clear();
        for v in [
            &mut self.lu2,
            &mut self.lc2,
            &mut self.lc,
            &mut self.mc,
            &mut self.nc,
            &mut self.f,
        ] {
            v.clear();
        }
    }

    /// The dot products of one sample (the part of the formula before any square root).
    #[inline]
    fn push(&mut self, d: &SurfaceDerivatives) {
        let (lu2, lv2) = (d.du.norm_squared(), d.dv.norm_squared());
        let (lo2, hi2) = if lu2 < lv2 { (lu2, lv2) } else { (lv2, lu2) };
        let c = d.du.cross(&d.dv);
        let lc2 = c.norm_squared();
        let regular = lo2 > TANGENT_RATIO_EPS * TANGENT_RATIO_EPS * hi2
            && lc2 > NORMAL_SIN_EPS * NORMAL_SIN_EPS * lu2 * lv2;
        self.point.push(d.point);
        self.cross.push(c);
        self.regular.push(regular);
        self.lu2.push(lu2);
        self.lc2.push(lc2);
        self.lc.push(d.duu.dot(&c));
        self.mc.push(d.duv.dot(&c));
        self.nc.push(d.dvv.dot(&c));
        self.f.push(d.du.dot(&d.dv));
    }

    /// Square roots and divisions over the whole row (vectorizable: no branches, equal-length
    /// slices). Singular columns produce non-finite values here that [`Self::emit`] discards.
    fn solve(&mut self) {
        let n = self.lu2.len();
        self.inv_len.resize(n, 0.0);
        self.k1.resize(n, 0.0);
        self.k2.resize(n, 0.0);
        let (lu2, lc2, lc, mc, nc, f) = (
            &self.lu2[..n],
            &self.lc2[..n],
            &self.lc[..n],
            &self.mc[..n],
            &self.nc[..n],
            &self.f[..n],
        );
        let (inv_len_out, k1_out, k2_out) =
            (&mut self.inv_len[..n], &mut self.k1[..n], &mut self.k2[..n]);
        for i in 0..n {
            let inv_len = 1.0 / lc2[i].sqrt();
            let inv_lu2 = 1.0 / lu2[i];
            let (l, m, nn) = (lc[i] * inv_len, mc[i] * inv_len, nc[i] * inv_len);
            let r = f[i] * inv_lu2;
            let b11 = l * inv_lu2;
            let b12 = (m - r * l) * inv_len;
            let b22 = (nn - 2.0 * r * m + r * r * l) * lu2[i] * inv_len * inv_len;
            let mid = 0.5 * (b11 + b22);
            let half = 0.5 * (b11 - b22);
            let radius = (half * half + b12 * b12).sqrt();
            inv_len_out[i] = inv_len;
            k1_out[i] = mid + radius;
            k2_out[i] = mid - radius;
        }
    }

    fn emit(&self, out: &mut Vec<GridCurvature>) {
        out.extend((0..self.point.len()).map(|i| GridCurvature {
            point: self.point[i],
            values: self.regular[i].then(|| {
                CurvatureValues::new(self.cross[i] * self.inv_len[i], self.k1[i], self.k2[i])
            }),
        }));
    }
}

impl BSplineSurface {
    /// Point, unit normal and principal curvatures on the grid `us × vs` (u slowest) into `out`
    /// (cleared first). Equal, bit for bit, to mapping
    /// [`SurfaceDerivatives::curvature_values`] over [`Self::eval_grid_into`], and faster: the
    /// square roots and divisions of a grid row are batched (see the module docs).
    pub fn eval_grid_curvatures_into(&self, us: &[f64], vs: &[f64], out: &mut Vec<GridCurvature>) {
        let plan = GridPlan::new(self, us, vs, GridOrder::Second);
        let mut rows = plan.row_scratch();
        let mut scratch = RowScratch::default();
        out.clear();
        out.reserve(us.len() * vs.len());
        for a in 0..us.len() {
            plan.contract_row(a, &mut rows);
            scratch.clear();
            plan.for_row(&rows, |_, d| scratch.push(d));
            scratch.solve();
            scratch.emit(out);
        }
    }

    /// [`Self::eval_grid_curvatures_into`] into a new vector.
    pub fn eval_grid_curvatures(&self, us: &[f64], vs: &[f64]) -> Vec<GridCurvature> {
        let mut out = Vec::new();
        self.eval_grid_curvatures_into(us, vs, &mut out);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::random_surface;

    /// Bit-identical to the pointwise method on random polynomial and rational surfaces of
    /// degrees 1–5, including the parameters on knots.
    #[test]
    fn batched_equals_pointwise() {
        for seed in 0..12 {
            let s = random_surface(seed, 1..=5, 9, seed % 3 == 0);
            let us = s.knots_u().uniform_params(37);
            let vs = s.knots_v().uniform_params(23);
            let batched = s.eval_grid_curvatures(&us, &vs);
            let pointwise = s.eval_grid_with(&us, &vs, GridOrder::Second, |d| GridCurvature {
                point: d.point,
                values: d.curvature_values(),
            });
            assert_eq!(batched.len(), us.len() * vs.len());
            for (b, p) in batched.iter().zip(&pointwise) {
                assert_eq!(b.point, p.point, "seed {seed}");
                assert_eq!(b.values, p.values, "seed {seed}");
            }
        }
    }

    /// A collapsed side (all control points of row u = 0 equal) is singular there: `None`, not NaN.
    #[test]
    fn collapsed_side_gives_none() {
        let mut s = random_surface(3, 3..=3, 6, false);
        let (apex, nv) = (s.control_point(0, 0), s.num_v());
        s.control_points_mut()[..nv].fill(apex);
        let vs = s.knots_v().uniform_params(11);
        let u0 = s.knots_u().domain().0;
        let samples = s.eval_grid_curvatures(&[u0], &vs);
        assert!(samples.iter().all(|g| g.values.is_none()));
        let inner = s.eval_grid_curvatures(&[u0 + 0.3 * (s.knots_u().domain().1 - u0)], &vs);
        assert!(
            inner
                .iter()
                .all(|g| g.values.is_some_and(|c| c.k1.is_finite()))
        );
    }
}
