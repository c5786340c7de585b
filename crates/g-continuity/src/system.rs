//! The row systems of the continuity steps (\[SV\] §4): per sample of a side, the C0 rows (the
//! gap to the master), the G1 row (n·e = 0, with two down-weighted rows keeping the tangential
//! part of the cross derivative) and the G2 row (the normal curvature across the side, with its
//! tangential rows), built on the rational basis of the moving row, and their solve.

use nalgebra::DMatrix;
use nurbs_core::{BSplineSurface, Continuity, Point3, Side, SurfaceDerivatives, Vector3};

use crate::ladder::solve_g2_ladder;
use crate::lsq::{SolveError, solve_least_squares};
use crate::measure::cross_derivative;
use crate::params::{G2Method, SetParams};
use crate::sampling::SideBasis;

/// The fixed directions of the G2 variant [`G2Method::FixedDirections`]: the slave normal at the
/// Greville abscissae of the `m` points of the row.
pub(crate) fn fixed_directions(
    slave: &BSplineSurface,
    side: Side,
    basis: &SideBasis,
    m: usize,
    eval: &mut nurbs_core::SurfaceEvaluator<'_>,
) -> Vec<Vector3> {
    (0..m)
        .map(|j| {
            let (u, v) = side.params(slave, basis.greville(j));
            eval.derivatives(u, v)
                .normal()
                .unwrap_or_else(Vector3::zeros)
        })
        .collect()
}

/// The displacement of each movable point (`indices`, of `row`) from the solution `x`: G0 one
/// row per point with the three coordinates, a 3D move three rows per point, a fixed-direction
/// move one scalar along its direction.
pub(crate) fn point_moves(
    x: &DMatrix<f64>,
    step: Continuity,
    unknowns: usize,
    row: &[(usize, usize)],
    indices: &[(usize, usize)],
    directions: &[Vector3],
) -> Vec<Vector3> {
    (0..indices.len())
        .map(|c| match (step, unknowns) {
            (Continuity::G0, _) => Vector3::new(x[(c, 0)], x[(c, 1)], x[(c, 2)]),
            (_, 3) => Vector3::new(x[(3 * c, 0)], x[(3 * c + 1, 0)], x[(3 * c + 2, 0)]),
            _ => {
                let j = row.iter().position(|&ij| ij == indices[c]).unwrap_or(0);
                directions[j] * x[(c, 0)]
            }
        })
        .collect()
}

/// The column block of each point of `row` in the system (`None`: it does not move) and the
/// movable points in order.
pub(crate) fn movable_columns(
    row: &[(usize, usize)],
    movable: &[bool],
) -> (Vec<Option<usize>>, Vec<(usize, usize)>) {
    let mut column = vec![None; row.len()];
    let mut indices = Vec::new();
    for (j, &ij) in row.iter().enumerate() {
        if movable.get(j).copied().unwrap_or(false) {
            column[j] = Some(indices.len());
            indices.push(ij);
        }
    }
    (column, indices)
}

/// What one row solve works on: the slave's side and its master, the step and its row `k`, the
/// column block of each row point (`None`: fixed), the fixed G2 directions, the settings.
#[derive(Clone, Copy)]
pub(crate) struct RowContext<'a> {
    pub(crate) master: &'a BSplineSurface,
    pub(crate) slave: &'a BSplineSurface,
    pub(crate) side: Side,
    pub(crate) step: Continuity,
    pub(crate) k: usize,
    pub(crate) column: &'a [Option<usize>],
    pub(crate) directions: &'a [Vector3],
    pub(crate) params: &'a SetParams,
}

/// The least-squares system of one row solve (\[SV\] §4): one row per sample for the condition of
/// the step (G0: the three coordinates of the gap; G1: n·e = 0; G2: the normal curvature), and
/// for G1 and G2 with free 3D moves two down-weighted rows per sample that keep the tangential
/// part of the change.
pub(crate) struct RowSystem {
    a: DMatrix<f64>,
    pub(crate) b: DMatrix<f64>,
    /// samples (the rows of the condition; the tangential rows follow them)
    rows: usize,
    /// unknowns per movable point: 3 (a 3D move), or 1 (G0 per coordinate, G2 along a fixed
    /// direction)
    pub(crate) unknowns: usize,
    /// whether the G2 system has the tangential rows (solved by the weight ladder)
    g2_tangential: bool,
    /// the coefficient a_k of the moving row in the k-th cross derivative
    a_k: f64,
    /// G1: the largest correction the condition asks for, max |n·e| / |a_k|
    pub(crate) needed: f64,
}

impl RowSystem {
    pub(crate) fn new(
        step: Continuity,
        params: &SetParams,
        rows: usize,
        free: usize,
        a_k: f64,
    ) -> Self {
        let unknowns = match step {
            Continuity::G0 => 1,
            Continuity::G1 => 3,
            Continuity::G2 if params.g2_method == G2Method::FixedDirections => 1,
            Continuity::G2 => 3,
        };
        let rhs_cols = if step == Continuity::G0 { 3 } else { 1 };
        let g2_tangential = step == Continuity::G2 && unknowns == 3;
        let total_rows = if step == Continuity::G1 || g2_tangential {
            3 * rows
        } else {
            rows
        };
        Self {
            a: DMatrix::zeros(total_rows, free * unknowns),
            b: DMatrix::zeros(total_rows, rhs_cols),
            rows,
            unknowns,
            g2_tangential,
            a_k,
            needed: 0.0,
        }
    }

    /// One row (and its tangential rows) per sample `ts` of the side, from the slave and its
    /// master point there.
    pub(crate) fn fill(
        &mut self,
        ctx: &RowContext<'_>,
        ts: &[f64],
        basis: &mut SideBasis,
        slave_eval: &mut nurbs_core::SurfaceEvaluator<'_>,
    ) {
        let RowContext {
            master,
            slave,
            side,
            step,
            k,
            column,
            directions,
            params,
        } = *ctx;
        let a_k = self.a_k;
        let q = basis.along_degree();
        let mut mvals = vec![0.0; q + 1];
        let mut master_eval = master.evaluator();
        let order = if step == Continuity::G2 { 2 } else { 1 };
        let slave_points: Vec<SurfaceDerivatives> = ts
            .iter()
            .map(|&t| {
                let (u, v) = side.params(slave, t);
                slave_eval.evaluate(u, v, order)
            })
            .collect();
        let points: Vec<Point3> = slave_points.iter().map(|d| d.point).collect();
        let feet = crate::memo::project_side(master, params.projection, &points);
        // one buffer for every sample's coefficients
        let mut cols: Vec<(usize, usize, f64)> = Vec::with_capacity(q + 1);
        for (r, ((&t, ds), proj)) in ts.iter().zip(slave_points).zip(feet).enumerate() {
            let first = basis.row_basis(k, t, &mut mvals);
            // the sample's row coefficients, per movable point: (row position, column block,
            // a_k · M_j(t))
            cols.clear();
            cols.extend(
                mvals
                    .iter()
                    .enumerate()
                    .filter_map(|(l, &mv)| column[first + l].map(|c| (first + l, c, a_k * mv))),
            );
            match step {
                Continuity::G0 => self.g0_sample(r, &cols, proj.point - ds.point),
                Continuity::G1 => {
                    let dm = master_eval.evaluate(proj.u, proj.v, 1);
                    self.g1_sample(r, &cols, &ds, &dm, side, params.g1_tangential_weight);
                }
                Continuity::G2 => {
                    let dm = master_eval.derivatives(proj.u, proj.v);
                    let w = params.g2_tangential_weight;
                    self.g2_sample(r, &cols, &ds, &dm, side, directions, w);
                }
            }
        }
    }

    /// One more row of the G0 system: coefficients `cols` (column, value), right-hand side `rhs`.
    pub(crate) fn push_g0_row(&mut self, cols: &[(usize, f64)], rhs: Vector3) {
        let r = self.a.nrows();
        let a = std::mem::replace(&mut self.a, DMatrix::zeros(0, 0));
        self.a = a.insert_row(r, 0.0);
        let b = std::mem::replace(&mut self.b, DMatrix::zeros(0, 0));
        self.b = b.insert_row(r, 0.0);
        for &(c, value) in cols {
            self.a[(r, c)] = value;
        }
        for d in 0..3 {
            self.b[(r, d)] = rhs[d];
        }
        self.rows += 1;
    }

    /// Sample `r` of the G0 step: the row moves onto the master point, `gap` = master − slave.
    fn g0_sample(&mut self, r: usize, cols: &[(usize, usize, f64)], gap: Vector3) {
        for &(_, c, coef) in cols {
            self.a[(r, c)] = coef;
        }
        for d in 0..3 {
            self.b[(r, d)] = gap[d];
        }
    }

    /// A 3D move of column block `c` with coefficient `f` on the condition row `r` along `n`
    /// and on its two tangential rows along `t1`, `t2` with weight `w`.
    #[allow(clippy::too_many_arguments)]
    fn three_rows(
        &mut self,
        r: usize,
        c: usize,
        f: f64,
        n: Vector3,
        t1: Vector3,
        t2: Vector3,
        w: f64,
    ) {
        let rows = self.rows;
        for d in 0..3 {
            self.a[(r, 3 * c + d)] = f * n[d];
            self.a[(rows + 2 * r, 3 * c + d)] = w * f * t1[d];
            self.a[(rows + 2 * r + 1, 3 * c + d)] = w * f * t2[d];
        }
    }

    /// Sample `r` of the G1 step: the cross derivative e of the slave (`ds`) into the master's
    /// tangent plane (`dm`), n·e = 0, its tangential part kept with weight `w`.
    fn g1_sample(
        &mut self,
        r: usize,
        cols: &[(usize, usize, f64)],
        ds: &SurfaceDerivatives,
        dm: &SurfaceDerivatives,
        side: Side,
        w: f64,
    ) {
        let (Some(n), e) = (dm.normal(), cross_derivative(ds, side)) else {
            return;
        };
        let len = e.norm();
        if !(len > 0.0) {
            return;
        }
        let t1 = (dm.du - n * n.dot(&dm.du)).normalize();
        let t2 = n.cross(&t1);
        for &(_, c, coef) in cols {
            self.three_rows(r, c, coef / len, n, t1, t2, w);
        }
        self.b[(r, 0)] = -n.dot(&e) / len;
        self.needed = self.needed.max(n.dot(&e).abs() / self.a_k.abs());
    }

    /// Sample `r` of the G2 step: the slave's normal curvature across the side made the
    /// master's (signed to the slave's normal), moving the curvature row along the slave normal
    /// (its tangential part kept with weight `w`) or along the fixed `directions`.
    #[allow(clippy::too_many_arguments)]
    fn g2_sample(
        &mut self,
        r: usize,
        cols: &[(usize, usize, f64)],
        ds: &SurfaceDerivatives,
        dm: &SurfaceDerivatives,
        side: Side,
        directions: &[Vector3],
        w: f64,
    ) {
        let e = cross_derivative(ds, side);
        let (Some(ns), Some(nm)) = (ds.normal(), dm.normal()) else {
            return;
        };
        let Some(km) = dm.normal_curvature(&e) else {
            return;
        };
        let km = if nm.dot(&ns) < 0.0 { -km } else { km };
        let big_e = e.norm_squared();
        let second = match side.cross_direction() {
            nurbs_core::Direction::U => ds.duu,
            nurbs_core::Direction::V => ds.dvv,
        };
        let ks = second.dot(&ns) / big_e;
        // unit tangents of the slave at the sample: the cross direction and the along-side
        // direction (perpendicular to it)
        let (t1, t2) = match (e - ns * ns.dot(&e)).try_normalize(f64::EPSILON) {
            Some(t1) => (t1, ns.cross(&t1)),
            None => (Vector3::zeros(), Vector3::zeros()),
        };
        for &(j, c, coef) in cols {
            let coef = coef / big_e;
            if self.unknowns == 1 {
                self.a[(r, c)] = coef * ns.dot(&directions[j]);
            } else {
                self.three_rows(r, c, coef, ns, t1, t2, w);
            }
        }
        self.b[(r, 0)] = km - ks;
    }

    /// The solution (one column block per movable point) and the G2 slack
    /// ([`RowMove::g2_slack`]; ∞ without the weight ladder).
    pub(crate) fn solve(
        self,
        g2_move_factor: f64,
    ) -> std::result::Result<(DMatrix<f64>, f64), SolveError> {
        if self.g2_tangential {
            solve_g2_ladder(self.a, &self.b, self.rows, g2_move_factor)
        } else {
            solve_least_squares(self.a, &self.b).map(|x| (x, f64::INFINITY))
        }
    }
}
