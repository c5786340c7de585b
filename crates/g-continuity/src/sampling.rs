//! Samples along a slave side and their master points (\[SV\] §4: "take K parameter points along
//! the border").
//!
//! For a side of the slave S (say `u0`, boundary parameter c = u_min) and a sample t_k of the
//! parameter running along it, the slave point is S(c, t_k) and the master point is its closest
//! point on the master M: masters may be trimmed, so their parameters are found by projection
//! (\[NB\] §6.1), never assumed to match the slave's. Consecutive samples are close, so each
//! projection starts from the previous foot point; a global (sampled) projection is used for the
//! first sample and whenever the warm start lands clearly farther away than its neighbour.
//!
//! [`SideBasis`] holds what the row equations of \[SV\] §4 need about the slave: the coefficient
//! a_r = N_r^{(r)}(c) of control row r in the r-th cross-boundary derivative at the side
//! (for a clamped knot vector a_1 = p/(t_{p+1} − t_1), a_2 = p(p−1)/((t_{p+1} − t_2)(t_{p+2} − t_2)),
//! with the signs of the u1/v1 sides included), and the along-side basis values M_j(t_k).
//!
//! # Tolerance
//! [`WARM_START_JUMP`]: a warm-started foot point farther than this factor times the previous
//! sample's distance (plus [`WARM_START_SLACK`] × master size) is re-done globally;
//! [`EXTRAPOLATION_RATIO`]: how far a warm start is extrapolated from the two feet before it.

use nurbs_core::basis::basis_derivatives;
use nurbs_core::{
    BSplineSurface, BasisEvaluator, Direction, KnotVector, Point3, ProjectionParams, Side,
    SurfaceProjection, SurfaceProjector,
};

use crate::error::{Error, Result};

/// Factor by which a warm-started projection may exceed the previous distance before the
/// projection is redone from global starts.
pub const WARM_START_JUMP: f64 = 4.0;

/// Largest ratio of sample spacings over which a warm start is extrapolated: a side's samples
/// are uniform or follow its knot spans, whose lengths change gradually, so a sample more than
/// twice as far on as the one before is a jump (to another part of the side) that the last
/// step does not predict; it starts from the previous foot moved by twice that step.
pub const EXTRAPOLATION_RATIO: f64 = 2.0;

/// Absolute slack of the warm-start test, relative to the master size: distances of 1e-6 of the
/// model size are "touching" anyway.
pub const WARM_START_SLACK: f64 = 1e-6;

/// Start samples per knot span of the global projection of a side's first sample (the kernel
/// default is 4; the side's later samples are warm-started, so the first one only needs the right
/// basin: 2 per span cut the start grid — the dominant cost of a measurement — by 4).
pub(crate) const GLOBAL_START_SAMPLES_PER_SPAN: usize = 2;

/// `count` parameters spread uniformly over the side's domain, both ends included.
pub fn uniform_side_params(slave: &BSplineSurface, side: Side, count: usize) -> Result<Vec<f64>> {
    if count < 2 {
        return Err(Error::TooFewSamples {
            samples: count,
            min: 2,
        });
    }
    let (a, b) = side.along_domain(slave);
    Ok((0..count)
        .map(|i| a + (b - a) * i as f64 / (count - 1) as f64)
        .collect())
}

/// The along-side parameter interval of `range` clipped to `side`'s domain (`None`: the whole
/// domain) — the part of the side a link over part of it holds on (`SideLink::range`).
pub fn side_part(slave: &BSplineSurface, side: Side, range: Option<(f64, f64)>) -> (f64, f64) {
    let (a, b) = side.along_domain(slave);
    match range {
        Some((x, y)) => (x.max(a).min(b), y.min(b).max(a)),
        None => (a, b),
    }
}

/// `count` parameters spread uniformly over `side_part(slave, side, range)`, both ends included.
pub fn uniform_part_params(
    slave: &BSplineSurface,
    side: Side,
    range: Option<(f64, f64)>,
    count: usize,
) -> Result<Vec<f64>> {
    let mut ts = uniform_side_params(slave, side, count)?;
    if range.is_some() {
        let (x, y) = side_part(slave, side, range);
        for (i, t) in ts.iter_mut().enumerate() {
            *t = x + (y - x) * i as f64 / (count - 1) as f64;
        }
    }
    Ok(ts)
}

/// Parameters for solving: `per_span` samples in every non-empty knot span of the along direction
/// (the span start included) plus the domain end, and never fewer than `min_total` — then
/// uniform, unless the uniform samples leave a basis function of the along direction without
/// a sample of its own (Schoenberg–Whitney: the row system is then rank-deficient, its solve
/// falls back to the minimum-norm solution and the condition holds only at the samples). A span
/// between knots of high multiplicity (a kernel's degree-11 fillet of C1-joined pieces) is
/// nearly a Bézier piece of q + 1 coefficients, most of them its own; such sides get
/// max(`per_span`, q + 1, ⌈(`min_total` − 1)/spans⌉) samples in every span.
pub fn solve_side_params(
    slave: &BSplineSurface,
    side: Side,
    per_span: usize,
    min_total: usize,
) -> Vec<f64> {
    let kv = along_knots(slave, side);
    let mut out = kv.span_samples(per_span);
    if out.len() < min_total {
        let (a, b) = kv.domain();
        let uniform: Vec<f64> = (0..min_total)
            .map(|i| a + (b - a) * i as f64 / (min_total - 1).max(1) as f64)
            .collect();
        out = if determines_every_basis(kv, &uniform) {
            uniform
        } else {
            let spans = kv.spans().count().max(1);
            let per = per_span
                .max(kv.degree() + 1)
                .max((min_total - 1).div_ceil(spans));
            kv.span_samples(per)
        };
    }
    out
}

/// Whether the sorted parameters `ts` can be matched, in order, to the basis functions of `kv`
/// with every parameter inside its function's support (the Schoenberg–Whitney condition: the
/// collocation matrix then has full column rank).
fn determines_every_basis(kv: &KnotVector, ts: &[f64]) -> bool {
    let (k, q) = (kv.knots(), kv.degree());
    let (a, b) = kv.domain();
    let mut j = 0;
    for i in 0..kv.num_basis() {
        let (lo, hi) = (k[i], k[i + q + 1]);
        while j < ts.len() && !(ts[j] > lo || (lo <= a && ts[j] >= lo)) {
            j += 1;
        }
        if j >= ts.len() || !(ts[j] < hi || (hi >= b && ts[j] <= hi)) {
            return false;
        }
        j += 1;
    }
    true
}

/// The knot vector running along `side`.
pub fn along_knots(surface: &BSplineSurface, side: Side) -> &KnotVector {
    match side.along_direction() {
        Direction::U => surface.knots_u(),
        Direction::V => surface.knots_v(),
    }
}

/// The knot vector across `side`.
pub fn cross_knots(surface: &BSplineSurface, side: Side) -> &KnotVector {
    match side.cross_direction() {
        Direction::U => surface.knots_u(),
        Direction::V => surface.knots_v(),
    }
}

/// Row coefficients and along-side basis of one side of a clamped slave, polynomial or rational.
///
/// For a rational slave with its weights held fixed, S = A/W with A = Σ N_i M_j w_ij P_ij; on a
/// clamped side the r-th cross derivative is S^(r) = (A^(r) − Σ_{i=1..r} C(r,i) W^(i) S^(r−i))/W,
/// and only A^(r) holds control row r. So row r enters S^(r)(c, t) linearly with the coefficient
/// a_r · w_rj M_j(t) / W(c, t), W(c, t) = Σ_j w_0j M_j(t): the row equations keep their form with
/// the along basis M_j replaced by the *rational row basis* of [`SideBasis::row_basis`] (\[SV\] §4
/// with fixed weights; \[NB\] §4.4). Nothing is re-approximated.
#[derive(Debug, Clone)]
pub struct SideBasis {
    /// the side
    pub side: Side,
    /// a_r = N^{(r)}_{row r}(c), r = 0, 1, 2: coefficient of control row r (counted inward) in the
    /// r-th cross-boundary derivative on the side (0 where r exceeds the degree)
    pub row_coefficient: [f64; 3],
    along: KnotVector,
    evaluator: BasisEvaluator,
    /// weights of rows 0, 1, 2 along the side (rational slaves only; rows beyond the net empty)
    row_weights: Option<[Vec<f64>; 3]>,
}

impl SideBasis {
    /// Coefficients for `side` of `slave` (the cross knot vector must be clamped at that side).
    pub fn new(slave: &BSplineSurface, side: Side) -> Self {
        let cross = cross_knots(slave, side);
        let p = cross.degree();
        let c = side.boundary_param(slave);
        let (span, ders) = basis_derivatives(cross, c, 2);
        let n = cross.num_basis();
        let mut row_coefficient = [0.0; 3];
        for (r, coef) in row_coefficient.iter_mut().enumerate() {
            let index = if side.is_start() { r } else { n - 1 - r };
            if index + p >= span && index <= span && r <= p {
                *coef = ders[r * (p + 1) + index + p - span];
            }
        }
        let along = along_knots(slave, side).clone();
        let evaluator = BasisEvaluator::new(along.degree());
        let row_weights = slave.weights().map(|_| {
            let (nu, nv) = (slave.num_u(), slave.num_v());
            let rows_across = n;
            std::array::from_fn(|r| {
                if r < rows_across {
                    side.row(r, nu, nv)
                        .iter()
                        .map(|&(i, j)| slave.weight(i, j))
                        .collect()
                } else {
                    Vec::new()
                }
            })
        });
        Self {
            side,
            row_coefficient,
            along,
            evaluator,
            row_weights,
        }
    }

    /// Whether the slave is rational (the row basis then carries its weights).
    pub fn is_rational(&self) -> bool {
        self.row_weights.is_some()
    }

    /// The basis with which control row `r` enters the r-th cross derivative at `t` (divided by
    /// a_r): M_j(t) for a polynomial slave, w_rj M_j(t) / W(c, t) for a rational one (see the
    /// type's documentation). Returns the first along index; the q + 1 values go into `out`.
    pub fn row_basis(&mut self, r: usize, t: f64, out: &mut [f64]) -> usize {
        let first = self.along_basis(t, out);
        if let Some(w) = &self.row_weights {
            let q1 = self.along.degree() + 1;
            let w0: f64 = (0..q1).map(|l| w[0][first + l] * out[l]).sum();
            if let Some(wr) = w.get(r).filter(|x| !x.is_empty()) {
                for (l, o) in out.iter_mut().enumerate().take(q1) {
                    *o *= wr[first + l] / w0;
                }
            }
        }
        first
    }

    /// The second derivative along the side, at `t`, of the basis with which the boundary row
    /// (row 0) enters the boundary curve C(t) = S(c, t): M_j''(t) for a polynomial slave, the
    /// second derivative of w_0j M_j(t) / W(c, t) for a rational one. Returns the first along
    /// index; the q + 1 values go into `out`.
    pub fn boundary_second_derivative(&mut self, t: f64, out: &mut [f64]) -> usize {
        let q1 = self.along.degree() + 1;
        let (span, ders) = basis_derivatives(&self.along, t, 2);
        let first = span - self.along.degree();
        let (m0, m1, m2) = (&ders[..q1], &ders[q1..2 * q1], &ders[2 * q1..3 * q1]);
        match &self.row_weights {
            None => out[..q1].copy_from_slice(m2),
            Some(w) => {
                // R = w M / W: R' = (w M' − R W') / W, R'' = (w M'' − 2 R' W' − R W'') / W
                let w0 = &w[0][first..first + q1];
                let dot = |m: &[f64]| w0.iter().zip(m).map(|(a, b)| a * b).sum::<f64>();
                let (big_w, w1, w2) = (dot(m0), dot(m1), dot(m2));
                for l in 0..q1 {
                    let r = w0[l] * m0[l] / big_w;
                    let r1 = (w0[l] * m1[l] - r * w1) / big_w;
                    out[l] = (w0[l] * m2[l] - 2.0 * r1 * w1 - r * w2) / big_w;
                }
            }
        }
        first
    }

    /// Degree along the side.
    pub fn along_degree(&self) -> usize {
        self.along.degree()
    }

    /// The along-side basis at `t`: the first along index and the q + 1 values into `out`.
    pub fn along_basis(&mut self, t: f64, out: &mut [f64]) -> usize {
        let t = self.along.clamp_param(t);
        let span = self.along.span(t);
        self.evaluator.values(self.along.knots(), span, t, out);
        span - self.along.degree()
    }

    /// Greville abscissa of along index j: (t_{j+1} + … + t_{j+q}) / q.
    pub fn greville(&self, j: usize) -> f64 {
        let q = self.along.degree();
        let k = self.along.knots();
        k[j + 1..=j + q].iter().sum::<f64>() / q as f64
    }
}

/// Finds master points for consecutive slave points, warm-starting each projection.
#[derive(Debug, Clone)]
pub struct MasterTracker<'m> {
    /// warm-started Newton projections (evaluator and surface size kept between calls)
    warm: SurfaceProjector<'m>,
    /// global projections from a coarse start grid (built once)
    global: SurfaceProjector<'m>,
    /// the last sample and its foot
    last: Option<(Point3, SurfaceProjection)>,
    /// the sample and foot before `last` (the start of the next projection is extrapolated
    /// from the two)
    before: Option<(Point3, SurfaceProjection)>,
    slack: f64,
}

impl<'m> MasterTracker<'m> {
    /// A tracker on `master`.
    pub fn new(master: &'m BSplineSurface, params: ProjectionParams) -> Self {
        let coarse = ProjectionParams {
            samples_per_span: params.samples_per_span.min(GLOBAL_START_SAMPLES_PER_SPAN),
            ..params
        };
        Self {
            warm: SurfaceProjector::new(master, params),
            global: SurfaceProjector::new(master, coarse),
            last: None,
            before: None,
            slack: WARM_START_SLACK * master.size(),
        }
    }

    fn global(&mut self, point: &Point3) -> SurfaceProjection {
        self.global.project(point)
    }

    /// Forgets the previous foot point (the next projection is global).
    pub fn reset(&mut self) {
        self.last = None;
        self.before = None;
    }

    /// Where the Newton iteration for `point` starts: the previous foot, moved on along the
    /// step from the foot before it in proportion to how far the samples moved (a start off
    /// by the square of the sample spacing instead of by the spacing: a Newton iteration
    /// fewer to the cosine tolerance).
    fn start(&self, point: &Point3, p1: &Point3, prev: &SurfaceProjection) -> (f64, f64) {
        let Some((p0, f0)) = &self.before else {
            return (prev.u, prev.v);
        };
        let (step, next) = ((p1 - p0).norm(), (point - p1).norm());
        if !(step > 0.0 && next.is_finite()) {
            return (prev.u, prev.v);
        }
        let ratio = (next / step).min(EXTRAPOLATION_RATIO);
        (
            prev.u + ratio * (prev.u - f0.u),
            prev.v + ratio * (prev.v - f0.v),
        )
    }

    /// The master point of `point`.
    pub fn project(&mut self, point: &Point3) -> SurfaceProjection {
        let result = match self.last {
            Some((p1, prev)) => {
                let start = self.start(point, &p1, &prev);
                let warm = self.warm.project_from(point, start);
                if warm.converged && warm.distance <= WARM_START_JUMP * prev.distance + self.slack {
                    warm
                } else {
                    let global = self.global(point);
                    if global.distance < warm.distance {
                        global
                    } else {
                        warm
                    }
                }
            }
            None => self.global(point),
        };
        self.before = self.last.replace((*point, result));
        result
    }
}

/// Whether `t` lies within `zones[0]` of `a` or `zones[1]` of `b` (strictly inside a zone of
/// positive length; a zone of length 0 holds no parameter).
pub fn in_zones(t: f64, (a, b): (f64, f64), zones: [f64; 2]) -> bool {
    (zones[0] > 0.0 && t < a + zones[0]) || (zones[1] > 0.0 && t > b - zones[1])
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs_core::{Point3, Vector3};

    /// A plane patch, linear in u, with the knot vector `kv` in v.
    fn along_v(kv: KnotVector) -> BSplineSurface {
        let n = kv.num_basis();
        let pts = (0..2)
            .flat_map(|i| (0..n).map(move |j| Point3::new(i as f64, j as f64, 0.0)))
            .collect();
        BSplineSurface::new(KnotVector::bezier(1).unwrap(), kv, pts, None).unwrap()
    }

    #[test]
    fn solve_samples_give_every_basis_function_of_a_side_its_own() {
        // degree 11, two interior knots of multiplicity 10 (C1-joined pieces of 12 coefficients
        // each) and a short middle span: 101 uniform samples put only 5 into it
        let mut knots = vec![0.0; 12];
        knots.extend([0.45; 10]);
        knots.extend([0.5; 10]);
        knots.extend([1.0; 12]);
        let kv = KnotVector::new(11, knots).unwrap();
        let s = along_v(kv.clone());
        let uniform: Vec<f64> = (0..101).map(|i| f64::from(i) / 100.0).collect();
        assert!(!determines_every_basis(&kv, &uniform));
        let ts = solve_side_params(&s, Side::U0, 10, 101);
        assert!(determines_every_basis(&kv, &ts));
        for (x, y) in [(0.0, 0.45), (0.45, 0.5), (0.5, 1.0)] {
            let inside = ts.iter().filter(|&&t| t >= x && t < y).count();
            assert!(inside >= 12, "[{x}, {y}): {inside} samples");
        }
        assert!(ts.len() >= 101);
        // a cubic with simple knots keeps its uniform samples
        let cubic =
            KnotVector::new(3, vec![0.0, 0.0, 0.0, 0.0, 0.1, 0.12, 1.0, 1.0, 1.0, 1.0]).unwrap();
        assert_eq!(
            solve_side_params(&along_v(cubic), Side::U0, 10, 101),
            uniform
        );
    }

    #[test]
    fn boundary_second_derivative_gives_the_curvature_of_a_cylinders_boundaries() {
        // a rational quarter cylinder of radius 2: two boundaries are quarter circles (curvature
        // 1/2), two are straight segments (curvature 0); from the basis alone, C'' = Σ R_j'' P_j
        let r = 2.0;
        let s = nurbs_core::shapes::cylinder(r, 3.0)
            .unwrap()
            .elevate_degree(nurbs_core::Direction::U, 2)
            .unwrap();
        for side in Side::ALL {
            let mut basis = SideBasis::new(&s, side);
            let q = basis.along_degree();
            let row = side.row(0, s.num_u(), s.num_v());
            let (t0, t1) = side.along_domain(&s);
            for k in 0..=4 {
                let t = t0 + (t1 - t0) * f64::from(k) / 4.0;
                let mut values = vec![0.0; q + 1];
                let first = basis.boundary_second_derivative(t, &mut values);
                let second = values
                    .iter()
                    .enumerate()
                    .fold(Vector3::zeros(), |acc, (l, m)| {
                        let (i, j) = row[first + l];
                        acc + (s.control_point(i, j) - Point3::origin()) * *m
                    });
                let (u, v) = side.params(&s, t);
                let d = s.derivatives(u, v);
                let first_derivative = match side.along_direction() {
                    nurbs_core::Direction::U => d.du,
                    nurbs_core::Direction::V => d.dv,
                };
                let curvature =
                    first_derivative.cross(&second).norm() / first_derivative.norm().powi(3);
                let circle = first_derivative.z.abs() < 1e-12;
                let expected = if circle { 1.0 / r } else { 0.0 };
                assert!(
                    (curvature - expected).abs() < 1e-12,
                    "{side:?} t = {t}: {curvature} against {expected}"
                );
            }
        }
    }

    #[test]
    fn row_coefficients_match_the_end_derivative_formulas() {
        // cubic in u with non-uniform knots; the v direction is irrelevant here
        let ku = KnotVector::new(
            3,
            vec![0.0, 0.0, 0.0, 0.0, 0.2, 0.5, 0.7, 1.0, 1.0, 1.0, 1.0],
        )
        .unwrap();
        let kv = KnotVector::bezier(1).unwrap();
        let pts = (0..7)
            .flat_map(|i| (0..2).map(move |j| Point3::new(i as f64, j as f64, 0.0)))
            .collect();
        let s = BSplineSurface::new(ku.clone(), kv, pts, None).unwrap();
        let t = ku.knots();
        let p = 3.0;
        let start = SideBasis::new(&s, Side::U0).row_coefficient;
        assert!((start[0] - 1.0).abs() < 1e-14);
        assert!((start[1] - p / (t[4] - t[1])).abs() < 1e-12, "{start:?}");
        assert!(
            (start[2] - p * (p - 1.0) / ((t[4] - t[2]) * (t[5] - t[2]))).abs() < 1e-12,
            "{start:?}"
        );
        // at u_max the row-1 coefficient of S_u is −p/(t_{n+p} − t_n) (n = 6, last index)
        let end = SideBasis::new(&s, Side::U1).row_coefficient;
        assert!((end[0] - 1.0).abs() < 1e-14);
        assert!((end[1] + p / (t[9] - t[6])).abs() < 1e-12, "{end:?}");
        assert!(
            (end[2] - p * (p - 1.0) / ((t[9] - t[6]) * (t[9] - t[5]))).abs() < 1e-12,
            "{end:?}"
        );
    }
}
