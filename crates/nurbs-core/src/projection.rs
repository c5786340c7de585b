//! Closest-point projection (point inversion) onto curves and surfaces (\[NB\] §6.1).
//!
//! Minimizes f = ½|S(u, v) − P|². Start: the best of a sample grid (several samples per knot span),
//! then safeguarded Newton on ∇f = (r·S_u, r·S_v), r = S − P, with the Hessian
//! H = [[S_u·S_u + r·S_uu, S_u·S_v + r·S_uv], [·, S_v·S_v + r·S_vv]]; where H is not positive
//! definite the Gauss–Newton matrix (H without the r terms) is used instead. Each step is clamped
//! to the domain and halved until f decreases. Converged when the distance is below the point
//! tolerance, when r is orthogonal to both tangents within the cosine tolerance (zero-cosine test
//! of \[NB\] eq. 6.4), or when a clamped step no longer moves the point (for a Newton step at a
//! minimum of its quadratic model, judged from the step's second-order Taylor terms before it is
//! evaluated).
//!
//! # Tolerance
//! [`ProjectionParams::point_tolerance`] is relative to the size (bounding-box diagonal) of the
//! control net; [`ProjectionParams::cosine_tolerance`] is dimensionless.

use crate::curve::BSplineCurve;
use crate::surface::{BSplineSurface, SurfaceDerivatives};
use crate::{Point3, Vector3};

/// Settings of the projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProjectionParams {
    /// Distances below `point_tolerance × size` count as coincident (default 1e-12: about 1e4
    /// rounding units of the coordinates).
    pub point_tolerance: f64,
    /// |cos| of the angle between r and a tangent below which r is orthogonal (default 1e-10).
    pub cosine_tolerance: f64,
    /// Newton iterations from one start (default 50; quadratic convergence needs < 10).
    pub max_iterations: usize,
    /// Start samples per knot span and direction (default 4).
    pub samples_per_span: usize,
    /// How many of the best samples Newton starts from (default 3).
    pub starts: usize,
    /// Cap on start samples per direction (default [`MAX_START_SAMPLES`]), so that surfaces with
    /// many spans do not make every projection cost a dense grid; above it the samples are
    /// uniform in parameter.
    pub max_samples_per_direction: usize,
}

/// Default cap on the start samples per direction: 256, four per span up to 64 spans. The nearest
/// start must lie in the basin of the true foot, so the samples must be closer together than the
/// surface comes back near itself: a swept spring of seven turns over 96 spans (an Inventor export)
/// with 64 uniform samples had them 12 mm apart along a wire whose turns are 10.5 mm apart, and its
/// trim points projected onto the neighbouring turn, 3–6 mm off; with 256 every one lies on it. A
/// global projection scans the grid once (a surface of 256 × 37 starts: about 10⁴ distances), a
/// warm start none.
pub const MAX_START_SAMPLES: usize = 256;

impl Default for ProjectionParams {
    fn default() -> Self {
        Self {
            point_tolerance: 1e-12,
            cosine_tolerance: 1e-10,
            max_iterations: 50,
            samples_per_span: 4,
            starts: 3,
            max_samples_per_direction: MAX_START_SAMPLES,
        }
    }
}

/// Result of projecting a point onto a surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceProjection {
    /// parameter u of the closest point
    pub u: f64,
    /// parameter v of the closest point
    pub v: f64,
    /// the closest point S(u, v)
    pub point: Point3,
    /// |S(u, v) − P|
    pub distance: f64,
    /// whether a convergence test was met
    pub converged: bool,
    /// Newton iterations of the winning start
    pub iterations: usize,
}

/// Result of projecting a point onto a curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveProjection {
    /// parameter of the closest point
    pub t: f64,
    /// the closest point C(t)
    pub point: Point3,
    /// |C(t) − P|
    pub distance: f64,
    /// whether a convergence test was met
    pub converged: bool,
    /// Newton iterations of the winning start
    pub iterations: usize,
}

/// Sample parameters: `per_span` per non-empty span plus the domain end, at most `max` (then
/// uniform in parameter).
fn span_samples(knots: &crate::KnotVector, per_span: usize, max: usize) -> Vec<f64> {
    if knots.spans().count() * per_span.max(1) + 1 > max.max(2) {
        return knots.uniform_params(max.max(2));
    }
    knots.span_samples(per_span)
}

/// Projects many points onto one surface, keeping the evaluator and the surface's size between
/// calls (the free functions below build one per call).
#[derive(Debug, Clone)]
pub struct SurfaceProjector<'a> {
    surface: &'a BSplineSurface,
    eval: crate::surface::SurfaceEvaluator<'a>,
    params: ProjectionParams,
    eps: f64,
    stationary_tolerance: f64,
    /// start samples (u values, v values, points), built on the first global projection
    starts: Option<(Vec<f64>, Vec<f64>, Vec<Point3>)>,
}

/// Relative distance (against the surface size) under which a Newton iterate that cannot
/// decrease the distance any more still counts as converged.
const STATIONARY_REL: f64 = 1e-9;

impl<'a> SurfaceProjector<'a> {
    /// A projector onto `surface`.
    pub fn new(surface: &'a BSplineSurface, params: ProjectionParams) -> Self {
        let size = surface.size().max(f64::MIN_POSITIVE);
        Self {
            surface,
            eval: surface.evaluator(),
            params,
            eps: params.point_tolerance * size,
            stationary_tolerance: STATIONARY_REL * size,
            starts: None,
        }
    }

    /// Projects `point` from sampled starts.
    pub fn project(&mut self, point: &Point3) -> SurfaceProjection {
        let surface = self.surface;
        let params = self.params;
        let (us, vs, grid) = self.starts.get_or_insert_with(|| {
            let us = span_samples(
                surface.knots_u(),
                params.samples_per_span,
                params.max_samples_per_direction,
            );
            let vs = span_samples(
                surface.knots_v(),
                params.samples_per_span,
                params.max_samples_per_direction,
            );
            let grid = surface.eval_grid_points(&us, &vs);
            (us, vs, grid)
        });
        let nvs = vs.len();
        let mut order: Vec<(f64, usize)> = grid
            .iter()
            .enumerate()
            .map(|(k, q)| ((q - point).norm_squared(), k))
            .collect();
        let starts = params.starts.max(1).min(order.len());
        order.select_nth_unstable_by(starts - 1, |a, b| a.0.total_cmp(&b.0));
        order[..starts].sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        // the starts are distinct points: the samples of a collapsed row are one point (a
        // pole), where the tangent along the row vanishes and Newton cannot leave it, so that
        // three starts there found the pole 0.19 mm from a point on the sphere beside it
        let same = |a: usize, b: usize| (grid[a] - grid[b]).norm() <= self.eps;
        let repeated = (1..starts).any(|i| (0..i).any(|j| same(order[i].1, order[j].1)));
        let chosen: Vec<usize> = if repeated {
            order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let mut chosen: Vec<usize> = Vec::with_capacity(starts);
            for &(_, k) in order.iter() {
                if chosen.len() == starts {
                    break;
                }
                if !chosen.iter().any(|&c| same(c, k)) {
                    chosen.push(k);
                }
            }
            chosen
        } else {
            order[..starts].iter().map(|&(_, k)| k).collect()
        };
        let picks: Vec<(f64, f64)> = chosen.iter().map(|&k| (us[k / nvs], vs[k % nvs])).collect();
        let mut best: Option<SurfaceProjection> = None;
        for start in picks {
            let candidate = self.project_from(point, start);
            let better = match &best {
                None => true,
                Some(b) => {
                    candidate.distance < b.distance
                        || (candidate.converged && !b.converged && candidate.distance <= b.distance)
                }
            };
            if better {
                best = Some(candidate);
            }
        }
        best.expect("at least one start")
    }

    /// Projects `point` by safeguarded Newton from the parameters `start`.
    pub fn project_from(&mut self, point: &Point3, start: (f64, f64)) -> SurfaceProjection {
        let (ua, ub) = self.surface.domain_u();
        let (va, vb) = self.surface.domain_v();
        let eps = self.eps;
        let (u, v) = (start.0.clamp(ua, ub), start.1.clamp(va, vb));
        let d = self.eval.derivatives(u, v);
        let r = d.point - point;
        let mut it = Iterate {
            u,
            v,
            d,
            r,
            dist: r.norm(),
        };
        let mut converged = false;
        let mut iterations = 0;
        while iterations < self.params.max_iterations {
            if it.dist <= eps {
                converged = true;
                break;
            }
            let (gu, gv) = (it.r.dot(&it.d.du), it.r.dot(&it.d.dv));
            if self.is_critical(&it, gu, gv) {
                converged = true;
                break;
            }
            let (du, dv, newton) = newton_direction(&it, gu, gv);
            if newton && self.predicted_move(&it, du, dv) <= self.eps {
                // at a minimum of the quadratic model, whose step would move the point by no
                // more than the point tolerance: the test a taken step makes
                // ([`SurfaceProjector::line_search`]), without the evaluation — and without
                // the halvings that rounding of a distance that no longer changes would cost
                // (on the lofted block 3.0 M line-search evaluations → 1.5 M). Gauss–Newton
                // and steepest descent steps still go through the line search, whose failure
                // to decrease the distance says "not converged" (a start stuck by a pole)
                converged = true;
                break;
            }
            let step = self.line_search(point, &mut it, du, dv);
            iterations += 1;
            match step {
                Some(false) => {}
                // a step that no longer moves the point
                Some(true) => {
                    converged = true;
                    break;
                }
                None => {
                    // no decrease along the Newton direction: a stationary point within rounding
                    converged = it.dist <= eps.max(self.stationary_tolerance);
                    break;
                }
            }
        }
        SurfaceProjection {
            u: it.u,
            v: it.v,
            point: it.d.point,
            distance: it.dist,
            converged,
            iterations,
        }
    }

    /// Whether r ⊥ S_u and r ⊥ S_v within the cosine tolerance (\[NB\] eq. 6.4), a direction
    /// whose gradient component (`gu`, `gv`) points out of the domain at a bound counting as
    /// met (a KKT multiplier, not a residual).
    fn is_critical(&self, it: &Iterate, gu: f64, gv: f64) -> bool {
        let (ua, ub) = self.surface.domain_u();
        let (va, vb) = self.surface.domain_v();
        let (u, v, tolerance) = (it.u, it.v, self.params.cosine_tolerance);
        let cos_u = gu.abs() / (it.dist * it.d.du.norm()).max(f64::MIN_POSITIVE);
        let cos_v = gv.abs() / (it.dist * it.d.dv.norm()).max(f64::MIN_POSITIVE);
        let free_u = !((u <= ua && gu > 0.0) || (u >= ub && gu < 0.0));
        let free_v = !((v <= va && gv > 0.0) || (v >= vb && gv < 0.0));
        (!free_u || cos_u <= tolerance) && (!free_v || cos_v <= tolerance)
    }

    /// How far the step (du, dv) from `it`, clamped to the domain, moves the point, by the
    /// terms of its Taylor expansion up to second order: |S_u Δu + S_v Δv| + ½ |S_uu Δu² +
    /// 2 S_uv Δu Δv + S_vv Δv²| (the second-order term carries the move where a tangent
    /// vanishes, at a pole).
    fn predicted_move(&self, it: &Iterate, du: f64, dv: f64) -> f64 {
        let (ua, ub) = self.surface.domain_u();
        let (va, vb) = self.surface.domain_v();
        let du = (it.u + du).clamp(ua, ub) - it.u;
        let dv = (it.v + dv).clamp(va, vb) - it.v;
        let d = &it.d;
        let second = d.duu * (du * du) + d.duv * (2.0 * du * dv) + d.dvv * (dv * dv);
        (d.du * du + d.dv * dv).norm() + 0.5 * second.norm()
    }

    /// Steps from `it` along (du, dv), clamped to the domain and halved until the distance to
    /// `point` does not grow (at most [`MAX_HALVINGS`] times); on success `it` moves there and
    /// the result says whether the point moved by at most the point tolerance, `None` when no
    /// step decreased the distance.
    fn line_search(&mut self, point: &Point3, it: &mut Iterate, du: f64, dv: f64) -> Option<bool> {
        let (ua, ub) = self.surface.domain_u();
        let (va, vb) = self.surface.domain_v();
        let (mut du, mut dv) = (du, dv);
        for _ in 0..MAX_HALVINGS {
            let (nu, nv) = ((it.u + du).clamp(ua, ub), (it.v + dv).clamp(va, vb));
            let nd = self.eval.derivatives(nu, nv);
            let nr = nd.point - point;
            let ndist = nr.norm();
            if ndist <= it.dist {
                let moved: Vector3 = nd.point - it.d.point;
                let tiny = moved.norm() <= self.eps;
                *it = Iterate {
                    u: nu,
                    v: nv,
                    d: nd,
                    r: nr,
                    dist: ndist,
                };
                return Some(tiny);
            }
            du *= 0.5;
            dv *= 0.5;
        }
        None
    }
}

/// Halvings of a Newton step before the line search gives up (2⁻³⁰ of the step: far below
/// any parameter resolution that moves the point).
const MAX_HALVINGS: usize = 30;

/// One Newton iterate: parameters, derivatives there, r = S − P and |r|.
struct Iterate {
    u: f64,
    v: f64,
    d: SurfaceDerivatives,
    r: Vector3,
    dist: f64,
}

/// The Newton step −H⁻¹ ∇f at `it` (∇f = (`gu`, `gv`)), with the Gauss–Newton matrix where H is
/// not positive definite and steepest descent where the metric is singular too; and whether it
/// is the Newton step of a positive definite H (a local minimum of the quadratic model).
fn newton_direction(it: &Iterate, gu: f64, gv: f64) -> (f64, f64, bool) {
    let (d, r) = (&it.d, &it.r);
    let (su, sv) = (d.du, d.dv);
    let (mut a, mut b, mut c) = (
        su.dot(&su) + r.dot(&d.duu),
        su.dot(&sv) + r.dot(&d.duv),
        sv.dot(&sv) + r.dot(&d.dvv),
    );
    let newton = a > 0.0 && a * c - b * b > 0.0;
    if !newton {
        (a, b, c) = (su.dot(&su), su.dot(&sv), sv.dot(&sv));
    }
    let det = a * c - b * b;
    if det > 0.0 {
        (-(c * gu - b * gv) / det, -(a * gv - b * gu) / det, newton)
    } else {
        // singular metric (e.g. at a pole): steepest descent scaled by the larger tangent
        let s = (su.norm_squared() + sv.norm_squared()).max(f64::MIN_POSITIVE);
        (-gu / s, -gv / s, false)
    }
}

/// Projects `point` onto `surface` from sampled starts.
pub fn project_to_surface(
    surface: &BSplineSurface,
    point: &Point3,
    params: &ProjectionParams,
) -> SurfaceProjection {
    SurfaceProjector::new(surface, *params).project(point)
}

/// Projects `point` onto `surface` by safeguarded Newton from the parameters `start`.
pub fn project_to_surface_from(
    surface: &BSplineSurface,
    point: &Point3,
    start: (f64, f64),
    params: &ProjectionParams,
) -> SurfaceProjection {
    SurfaceProjector::new(surface, *params).project_from(point, start)
}

/// Projects `point` onto `curve` (same safeguards as for surfaces, in one parameter).
pub fn project_to_curve(
    curve: &BSplineCurve,
    point: &Point3,
    params: &ProjectionParams,
) -> CurveProjection {
    let ts = span_samples(
        curve.knots(),
        params.samples_per_span,
        params.max_samples_per_direction,
    );
    let mut order: Vec<(f64, f64)> = ts
        .iter()
        .map(|&t| ((curve.point(t) - point).norm_squared(), t))
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let (a, b) = curve.domain();
    let scale =
        crate::homogeneous::bounding_diagonal(curve.control_points()).max(f64::MIN_POSITIVE);
    let eps = params.point_tolerance * scale;
    let mut best: Option<CurveProjection> = None;
    for &(_, t0) in order.iter().take(params.starts.max(1)) {
        let mut t = t0;
        let mut d = curve.derivatives(t, 2);
        let mut r = d.d[0] - point.coords;
        let mut dist = r.norm();
        let mut converged = false;
        let mut iterations = 0;
        while iterations < params.max_iterations {
            if dist <= eps {
                converged = true;
                break;
            }
            let g = r.dot(&d.d[1]);
            let cos = g.abs() / (dist * d.d[1].norm()).max(f64::MIN_POSITIVE);
            if cos <= params.cosine_tolerance || (t <= a && g > 0.0) || (t >= b && g < 0.0) {
                converged = true;
                break;
            }
            let mut h = d.d[1].norm_squared() + r.dot(&d.d[2]);
            if !(h > 0.0) {
                h = d.d[1].norm_squared().max(f64::MIN_POSITIVE);
            }
            let mut dt = -g / h;
            let mut step_ok = false;
            for _ in 0..30 {
                let nt = (t + dt).clamp(a, b);
                let nd = curve.derivatives(nt, 2);
                let nr = nd.d[0] - point.coords;
                if nr.norm() <= dist {
                    let tiny = (nd.d[0] - d.d[0]).norm() <= eps;
                    t = nt;
                    d = nd;
                    r = nr;
                    dist = nr.norm();
                    step_ok = !tiny;
                    converged |= tiny;
                    break;
                }
                dt *= 0.5;
            }
            iterations += 1;
            if !step_ok {
                break;
            }
        }
        let cand = CurveProjection {
            t,
            point: Point3::from(d.d[0]),
            distance: dist,
            converged,
            iterations,
        };
        if best.as_ref().is_none_or(|b| cand.distance < b.distance) {
            best = Some(cand);
        }
    }
    best.expect("at least one start")
}
