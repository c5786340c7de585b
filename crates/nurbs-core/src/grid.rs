//! Grid evaluation with the tensor-product structure.
//!
//! For a grid u_a × v_b the basis functions are evaluated once per grid row and once per grid
//! column. Per grid row the control net is first contracted in u,
//! R^{(k)}_j(u_a) = Σ_i N_i^{(k)}(u_a) w_ij P_ij (homogeneous, k ≤ order, every column j), and every
//! point of the row then needs only the q + 1 column terms: A_kl(u_a, v_b) = Σ_j M_j^{(l)}(v_b) R^{(k)}_j.
//! Per point the cost is (q + 1) multiply-adds per derivative instead of (p + 1)(q + 1).
//! Rows are independent, so [`BSplineSurface::par_eval_grid_with`] splits them over rayon threads
//! with results identical to the single-threaded run.

use rayon::prelude::*;

use crate::Point3;
use crate::basis::BasisEvaluator;
use crate::knots::KnotVector;
use crate::surface::{BSplineSurface, SurfaceDerivatives, quotient_rule};

/// Which derivatives a grid evaluation computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GridOrder {
    /// Points only (derivative fields stay zero).
    Points,
    /// Points, first and second partial derivatives.
    Second,
}

impl GridOrder {
    fn order(self) -> usize {
        match self {
            GridOrder::Points => 0,
            GridOrder::Second => 2,
        }
    }
}

/// Basis values (and derivatives) of one direction at a list of parameters.
struct DirectionBasis {
    spans: Vec<usize>,
    ders: Vec<f64>,
    stride: usize,
}

impl DirectionBasis {
    fn new(knots: &KnotVector, params: &[f64], order: usize) -> Self {
        let p = knots.degree();
        let stride = (order + 1) * (p + 1);
        let mut eval = BasisEvaluator::new(p);
        let mut spans = Vec::with_capacity(params.len());
        let mut ders = vec![0.0; stride * params.len()];
        for (a, &t) in params.iter().enumerate() {
            let t = knots.clamp_param(t);
            let span = knots.span(t);
            spans.push(span);
            eval.derivatives(
                knots.knots(),
                span,
                t,
                order,
                &mut ders[a * stride..(a + 1) * stride],
            );
        }
        Self {
            spans,
            ders,
            stride,
        }
    }
}

/// Everything a grid row needs, shared by all rows.
pub(crate) struct GridPlan<'a> {
    surface: &'a BSplineSurface,
    homogeneous: Vec<[f64; 4]>,
    bu: DirectionBasis,
    bv: DirectionBasis,
    order: usize,
}

impl<'a> GridPlan<'a> {
    pub(crate) fn new(
        surface: &'a BSplineSurface,
        us: &[f64],
        vs: &[f64],
        order: GridOrder,
    ) -> Self {
        let order = order.order();
        Self {
            surface,
            homogeneous: surface.homogeneous(),
            bu: DirectionBasis::new(surface.knots_u(), us, order),
            bv: DirectionBasis::new(surface.knots_v(), vs, order),
            order,
        }
    }

    /// Contracts the net in u for grid row `a`: `rows[k * n_v + j]` = R^{(k)}_j.
    pub(crate) fn contract_row(&self, a: usize, rows: &mut [[f64; 4]]) {
        let s = self.surface;
        let (p, nv) = (s.degree_u(), s.num_v());
        let span = self.bu.spans[a];
        let ders = &self.bu.ders[a * self.bu.stride..(a + 1) * self.bu.stride];
        rows.fill([0.0; 4]);
        for r in 0..=p {
            let net_row = &self.homogeneous[(span - p + r) * nv..(span - p + r + 1) * nv];
            for k in 0..=self.order {
                let n = ders[k * (p + 1) + r];
                let out = &mut rows[k * nv..(k + 1) * nv];
                for (o, h) in out.iter_mut().zip(net_row) {
                    o[0] += n * h[0];
                    o[1] += n * h[1];
                    o[2] += n * h[2];
                    o[3] += n * h[3];
                }
            }
        }
    }

    /// Evaluates every column of a contracted row, the degree dispatched once per row.
    #[inline]
    pub(crate) fn for_row(&self, rows: &[[f64; 4]], mut g: impl FnMut(usize, &SurfaceDerivatives)) {
        let n = self.bv.spans.len();
        macro_rules! run {
            ($kernel:expr) => {
                for b in 0..n {
                    let d = $kernel(b);
                    g(b, &d);
                }
            };
        }
        match self.surface.degree_v() {
            1 => run!(|b| self.point_in_row_fixed::<2>(b, rows)),
            2 => run!(|b| self.point_in_row_fixed::<3>(b, rows)),
            3 => run!(|b| self.point_in_row_fixed::<4>(b, rows)),
            4 => run!(|b| self.point_in_row_fixed::<5>(b, rows)),
            5 => run!(|b| self.point_in_row_fixed::<6>(b, rows)),
            _ => run!(|b| self.point_in_row_any(b, rows)),
        }
    }

    /// Only the point of grid column `b` (no derivatives).
    #[inline]
    fn point_only(&self, b: usize, rows: &[[f64; 4]]) -> Point3 {
        match self.surface.degree_v() {
            1 => self.point_only_fixed::<2>(b, rows),
            2 => self.point_only_fixed::<3>(b, rows),
            3 => self.point_only_fixed::<4>(b, rows),
            4 => self.point_only_fixed::<5>(b, rows),
            5 => self.point_only_fixed::<6>(b, rows),
            _ => self.point_in_row_any(b, rows).point,
        }
    }

    #[inline(always)]
    fn point_only_fixed<const Q1: usize>(&self, b: usize, rows: &[[f64; 4]]) -> Point3 {
        let span = self.bv.spans[b];
        let first = span + 1 - Q1;
        let r0: &[[f64; 4]; Q1] = rows[first..first + Q1]
            .try_into()
            .expect("span inside the net");
        let m0: &[f64; Q1] = self.bv.ders[b * self.bv.stride..b * self.bv.stride + Q1]
            .try_into()
            .expect("stride ≥ Q1");
        let mut a = [0.0f64; 4];
        for c in 0..Q1 {
            for d in 0..4 {
                a[d] += m0[c] * r0[c][d];
            }
        }
        if self.surface.is_rational() {
            Point3::new(a[0] / a[3], a[1] / a[3], a[2] / a[3])
        } else {
            Point3::new(a[0], a[1], a[2])
        }
    }

    /// Point and derivatives of grid column `b` from a contracted row, for a compile-time v
    /// order Q1 = q + 1.
    #[inline(always)]
    fn point_in_row_fixed<const Q1: usize>(
        &self,
        b: usize,
        rows: &[[f64; 4]],
    ) -> SurfaceDerivatives {
        let nv = self.surface.num_v();
        let span = self.bv.spans[b];
        let ders = &self.bv.ders[b * self.bv.stride..(b + 1) * self.bv.stride];
        let first = span + 1 - Q1;
        let mut a = [[0.0f64; 4]; 6];
        let r0: &[[f64; 4]; Q1] = rows[first..first + Q1]
            .try_into()
            .expect("span inside the net");
        let m0: &[f64; Q1] = ders[..Q1].try_into().expect("stride ≥ Q1");
        if self.order == 0 {
            for c in 0..Q1 {
                for d in 0..4 {
                    a[0][d] += m0[c] * r0[c][d];
                }
            }
        } else {
            let r1: &[[f64; 4]; Q1] = rows[nv + first..nv + first + Q1]
                .try_into()
                .expect("span inside the net");
            let r2: &[[f64; 4]; Q1] = rows[2 * nv + first..2 * nv + first + Q1]
                .try_into()
                .expect("span inside the net");
            let m1: &[f64; Q1] = ders[Q1..2 * Q1].try_into().expect("stride ≥ 3 Q1");
            let m2: &[f64; Q1] = ders[2 * Q1..3 * Q1].try_into().expect("stride ≥ 3 Q1");
            for c in 0..Q1 {
                for d in 0..4 {
                    a[0][d] += m0[c] * r0[c][d];
                    a[1][d] += m0[c] * r1[c][d];
                    a[2][d] += m1[c] * r0[c][d];
                    a[3][d] += m0[c] * r2[c][d];
                    a[4][d] += m1[c] * r1[c][d];
                    a[5][d] += m2[c] * r0[c][d];
                }
            }
        }
        quotient_rule(&a, self.surface.is_rational())
    }

    /// [`Self::point_in_row_fixed`] for any degree.
    fn point_in_row_any(&self, b: usize, rows: &[[f64; 4]]) -> SurfaceDerivatives {
        let s = self.surface;
        let (q, nv) = (s.degree_v(), s.num_v());
        let span = self.bv.spans[b];
        let ders = &self.bv.ders[b * self.bv.stride..(b + 1) * self.bv.stride];
        let first = span - q;
        let mut a = [[0.0f64; 4]; 6];
        let q1 = q + 1;
        for c in 0..=q {
            let h0 = &rows[first + c];
            if self.order == 0 {
                for d in 0..4 {
                    a[0][d] += ders[c] * h0[d];
                }
                continue;
            }
            let (m0, m1, m2) = (ders[c], ders[q1 + c], ders[2 * q1 + c]);
            let h1 = &rows[nv + first + c];
            let h2 = &rows[2 * nv + first + c];
            for d in 0..4 {
                a[0][d] += m0 * h0[d];
                a[1][d] += m0 * h1[d];
                a[2][d] += m1 * h0[d];
                a[3][d] += m0 * h2[d];
                a[4][d] += m1 * h1[d];
                a[5][d] += m2 * h0[d];
            }
        }
        quotient_rule(&a, s.is_rational())
    }

    pub(crate) fn row_scratch(&self) -> Vec<[f64; 4]> {
        vec![[0.0; 4]; (self.order + 1) * self.surface.num_v()]
    }
}

impl BSplineSurface {
    /// Evaluates the grid `us × vs` (u slowest) and maps every sample through `f`.
    pub fn eval_grid_with<T, F>(&self, us: &[f64], vs: &[f64], order: GridOrder, f: F) -> Vec<T>
    where
        F: Fn(&SurfaceDerivatives) -> T,
    {
        let mut out = Vec::new();
        self.eval_grid_into(us, vs, order, &mut out, f);
        out
    }

    /// Like [`eval_grid_with`](Self::eval_grid_with) but writes into `out` (cleared first), so
    /// that repeated evaluations reuse one allocation.
    pub fn eval_grid_into<T, F>(
        &self,
        us: &[f64],
        vs: &[f64],
        order: GridOrder,
        out: &mut Vec<T>,
        f: F,
    ) where
        F: Fn(&SurfaceDerivatives) -> T,
    {
        let plan = GridPlan::new(self, us, vs, order);
        let mut rows = plan.row_scratch();
        out.clear();
        out.reserve(us.len() * vs.len());
        for a in 0..us.len() {
            plan.contract_row(a, &mut rows);
            plan.for_row(&rows, |_, d| out.push(f(d)));
        }
    }

    /// Points of the grid `us × vs` (u slowest) into `out` (cleared first).
    pub fn eval_grid_points_into(&self, us: &[f64], vs: &[f64], out: &mut Vec<Point3>) {
        let plan = GridPlan::new(self, us, vs, GridOrder::Points);
        let mut rows = plan.row_scratch();
        out.clear();
        out.reserve(us.len() * vs.len());
        for a in 0..us.len() {
            plan.contract_row(a, &mut rows);
            out.extend((0..vs.len()).map(|b| plan.point_only(b, &rows)));
        }
    }

    /// Points of the grid `us × vs` (u slowest).
    pub fn eval_grid_points(&self, us: &[f64], vs: &[f64]) -> Vec<Point3> {
        let mut out = Vec::new();
        self.eval_grid_points_into(us, vs, &mut out);
        out
    }

    /// Points and derivatives up to order 2 on the grid `us × vs` (u slowest).
    pub fn eval_grid_derivatives(&self, us: &[f64], vs: &[f64]) -> Vec<SurfaceDerivatives> {
        self.eval_grid_with(us, vs, GridOrder::Second, |d| *d)
    }

    /// Parallel [`eval_grid_with`](Self::eval_grid_with): grid rows are split over rayon's
    /// threads; the result is identical to the sequential one.
    pub fn par_eval_grid_with<T, F>(&self, us: &[f64], vs: &[f64], order: GridOrder, f: F) -> Vec<T>
    where
        T: Send + Clone + Default,
        F: Fn(&SurfaceDerivatives) -> T + Sync,
    {
        let mut out = Vec::new();
        self.par_eval_grid_into(us, vs, order, &mut out, f);
        out
    }

    /// Parallel [`eval_grid_into`](Self::eval_grid_into).
    pub fn par_eval_grid_into<T, F>(
        &self,
        us: &[f64],
        vs: &[f64],
        order: GridOrder,
        out: &mut Vec<T>,
        f: F,
    ) where
        T: Send + Clone + Default,
        F: Fn(&SurfaceDerivatives) -> T + Sync,
    {
        let plan = GridPlan::new(self, us, vs, order);
        let nvs = vs.len();
        out.resize(us.len() * nvs, T::default());
        if nvs == 0 {
            return;
        }
        let rows_per_chunk = us.len().div_ceil(4 * rayon::current_num_threads()).max(1);
        out.par_chunks_mut(rows_per_chunk * nvs)
            .enumerate()
            .for_each(|(chunk, block)| {
                let mut rows = plan.row_scratch();
                for (local, row_out) in block.chunks_mut(nvs).enumerate() {
                    let a = chunk * rows_per_chunk + local;
                    plan.contract_row(a, &mut rows);
                    plan.for_row(&rows, |b, d| row_out[b] = f(d));
                }
            });
    }
}
