//! Exact reference shapes: rational circles, cylinders, spheres, tori, and the paraboloid
//! z = x² + y² as a polynomial surface (\[NB\] §7.5 circles, §8.5 surfaces of revolution).
//!
//! They are used as closed-form truth in tests (curvature 1/r everywhere on a circle, K = 1/r² on a
//! sphere, …) and are handy for users checking their own pipelines.

use std::f64::consts::FRAC_1_SQRT_2;

use crate::Point3;
use crate::curve::BSplineCurve;
use crate::error::Result;
use crate::knots::KnotVector;
use crate::ops::Direction;
use crate::surface::BSplineSurface;

/// Control polygon (in the xy-plane, unit radius) and weights of a full circle as a rational
/// quadratic with 9 control points, knots [0,0,0,¼,¼,½,½,¾,¾,1,1,1].
fn unit_circle() -> (KnotVector, Vec<(f64, f64)>, Vec<f64>) {
    let kv = KnotVector::new(
        2,
        vec![0., 0., 0., 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1., 1., 1.],
    )
    .expect("valid");
    let pts = vec![
        (1., 0.),
        (1., 1.),
        (0., 1.),
        (-1., 1.),
        (-1., 0.),
        (-1., -1.),
        (0., -1.),
        (1., -1.),
        (1., 0.),
    ];
    let w = (0..9)
        .map(|i| if i % 2 == 1 { FRAC_1_SQRT_2 } else { 1.0 })
        .collect();
    (kv, pts, w)
}

/// A quarter circle (90° arc) of unit radius from (1, 0) to (0, 1).
fn unit_quarter() -> (KnotVector, Vec<(f64, f64)>, Vec<f64>) {
    (
        KnotVector::bezier(2).expect("valid"),
        vec![(1., 0.), (1., 1.), (0., 1.)],
        vec![1.0, FRAC_1_SQRT_2, 1.0],
    )
}

/// The full circle of radius `r` about the origin in the xy-plane (rational quadratic).
pub fn circle(r: f64) -> Result<BSplineCurve> {
    let (kv, pts, w) = unit_circle();
    BSplineCurve::new(
        kv,
        pts.iter()
            .map(|&(x, y)| Point3::new(r * x, r * y, 0.0))
            .collect(),
        Some(w),
    )
}

/// Surface of revolution about the z axis: profile points (ρ, z) with weights, revolved along the
/// given unit arc (\[NB\] A8.1 in tensor form: P_ij = (ρ_i a_j, ρ_i b_j, z_i), w_ij = w_i w_j).
fn revolve(
    profile: (KnotVector, Vec<(f64, f64)>, Vec<f64>),
    arc: (KnotVector, Vec<(f64, f64)>, Vec<f64>),
) -> Result<BSplineSurface> {
    let (ku, prof, wu) = profile;
    let (kv, rot, wv) = arc;
    let mut points = Vec::new();
    let mut weights = Vec::new();
    for (i, &(rho, z)) in prof.iter().enumerate() {
        for (j, &(a, b)) in rot.iter().enumerate() {
            points.push(Point3::new(rho * a, rho * b, z));
            weights.push(wu[i] * wv[j]);
        }
    }
    BSplineSurface::new(ku, kv, points, Some(weights))
}

/// A sphere patch of radius `r` about the origin: latitudes −45°…45° (u), longitudes 0…90° (v).
/// Its normal S_u × S_v points inward; curvatures are +1/r with respect to it.
pub fn sphere_patch(r: f64) -> Result<BSplineSurface> {
    let c = FRAC_1_SQRT_2;
    // 90° arc in the (ρ, z) plane from −45° to 45°: middle point at distance r/cos 45°
    let profile = (
        KnotVector::bezier(2)?,
        vec![(r * c, -r * c), (r * 2f64.sqrt(), 0.0), (r * c, r * c)],
        vec![1.0, c, 1.0],
    );
    revolve(profile, unit_quarter())
}

/// The octant of the sphere of radius `r` about the origin from its north pole (u = 0, the side
/// collapsed to a point, as a kernel's spherical vertex blend has it) to the equator (u = 1),
/// longitudes 0…90° (v): a rational biquadratic 3 × 3 net.
pub fn sphere_octant(r: f64) -> Result<BSplineSurface> {
    let profile = (
        KnotVector::bezier(2)?,
        vec![(0.0, r), (r, r), (r, 0.0)],
        vec![1.0, FRAC_1_SQRT_2, 1.0],
    );
    revolve(profile, unit_quarter())
}

/// A cylinder of radius `r` about the z axis, height `h`, a quarter turn (u along z, v around).
pub fn cylinder(r: f64, h: f64) -> Result<BSplineSurface> {
    cylinder_around(r, h, unit_quarter())
}

/// A full cylinder of radius `r` about the z axis, height `h` (u along z on [0, 1], v a full
/// turn from the x axis): closed in v, its seam the generator through (r, 0).
pub fn full_cylinder(r: f64, h: f64) -> Result<BSplineSurface> {
    cylinder_around(r, h, unit_circle())
}

/// The segment from (r, 0) to (r, h) in the (ρ, z) plane turned along the unit arc `around`.
fn cylinder_around(
    r: f64,
    h: f64,
    around: (KnotVector, Vec<(f64, f64)>, Vec<f64>),
) -> Result<BSplineSurface> {
    let profile = (
        KnotVector::bezier(1)?,
        vec![(r, 0.0), (r, h)],
        vec![1.0, 1.0],
    );
    revolve(profile, around)
}

/// The full torus about the z axis with major radius `major` and tube radius `minor`: u runs
/// around the tube starting outside (angle θ), v around the axis (angle φ).
pub fn torus(major: f64, minor: f64) -> Result<BSplineSurface> {
    let (kv, pts, w) = unit_circle();
    // tube circle in the (ρ, z) plane centred at (major, 0)
    let profile = (
        kv,
        pts.iter()
            .map(|&(x, y)| (major + minor * x, minor * y))
            .collect(),
        w,
    );
    revolve(profile, unit_circle())
}

/// The paraboloid z = x² + y² over [−1, 1]² as a polynomial bicubic B-spline with the interior
/// knots `interior` in both directions (parameters u, v ∈ [0, 1], x = 2u − 1, y = 2v − 1).
pub fn paraboloid_bicubic(interior: &[f64]) -> Result<BSplineSurface> {
    // biquadratic Bézier: x = −1, 0, 1; (2s − 1)² has Bernstein coefficients 1, −1, 1
    let xs = [-1.0, 0.0, 1.0];
    let cz = [1.0, -1.0, 1.0];
    let mut points = Vec::new();
    for i in 0..3 {
        for j in 0..3 {
            points.push(Point3::new(xs[i], xs[j], cz[i] + cz[j]));
        }
    }
    let quad = BSplineSurface::new(KnotVector::bezier(2)?, KnotVector::bezier(2)?, points, None)?;
    quad.elevate_degree(Direction::U, 1)?
        .elevate_degree(Direction::V, 1)?
        .refine(Direction::U, interior)?
        .refine(Direction::V, interior)
}

/// Knots, control coefficients (cos, sin) and weights of a unit arc ([`unit_arc`]).
pub type UnitArc = (KnotVector, Vec<(f64, f64)>, Vec<f64>);

/// Relative overshoot of a full turn that [`unit_arc`] accepts (see there).
pub const FULL_TURN_SLACK: f64 = 1e-4;

/// The unit arc from angle `start` to `end` (radians, counterclockwise; `end` > `start`, at most
/// a full turn and [`FULL_TURN_SLACK`]) as rational quadratic Bézier segments of at most 90° joined with double knots
/// (\[NB\] A7.1): control coefficients (a, b) with cos θ = Σ R_k a_k, sin θ = Σ R_k b_k exactly, and
/// the knots running from `start` to `end` (the parameter is not the angle inside a segment,
/// but the ends are). A sweep past a full turn (within the slack) is a full turn: the knots
/// still run to `end`, the arc closes exactly on its start.
pub fn unit_arc(start: f64, end: f64) -> Result<UnitArc> {
    let sweep = end - start;
    // a kernel writes a closed surface's terminate angle with a small overshoot (OCCT:
    // 6.28320989 for 2π, 4e-6 relative): a sweep past a full turn can only be a full turn, so
    // the arc is one, closed exactly — overlapping itself by the excess (0.6 µm on a pipe of
    // radius 25), a closed surface had two boundary curves 0.6 µm apart and no seam, and
    // Open CASCADE called its face exported to STEP with the seam used both ways invalid
    if !(sweep > 0.0 && sweep <= std::f64::consts::TAU * (1.0 + FULL_TURN_SLACK)) {
        return Err(crate::error::Error::Degenerate {
            detail: format!("arc sweep {sweep} rad from {start} to {end}, expected in (0, 2π]"),
        });
    }
    let full = sweep > std::f64::consts::TAU;
    let turn = sweep.min(std::f64::consts::TAU);
    let segments = (turn / std::f64::consts::FRAC_PI_2 - 1e-9).ceil().max(1.0) as usize;
    // the angle and the knot of each segment's end
    let step = turn / segments as f64;
    let knot_step = sweep / segments as f64;
    let w = (step / 2.0).cos();
    let mut pts = vec![(start.cos(), start.sin())];
    let mut weights = vec![1.0];
    let mut knots = vec![start; 3];
    for k in 0..segments {
        let (a, b) = (start + k as f64 * step, start + (k + 1) as f64 * step);
        let mid = 0.5 * (a + b);
        // the tangents at the segment's ends meet at distance 1 / cos(step / 2) on the bisector
        pts.push((mid.cos() / w, mid.sin() / w));
        weights.push(w);
        let last = k + 1 == segments;
        pts.push(match (last, full) {
            (true, true) => pts[0],
            (true, false) => (end.cos(), end.sin()),
            _ => (b.cos(), b.sin()),
        });
        weights.push(1.0);
        if !last {
            let kb = start + (k + 1) as f64 * knot_step;
            knots.extend([kb, kb]);
        }
    }
    knots.extend([end; 3]);
    Ok((KnotVector::new(2, knots)?, pts, weights))
}

/// The arc of radius `r` about `center` in the plane spanned by the orthonormal `x` and `y`,
/// from angle `start` to `end` (radians, counterclockwise from `x` towards `y`), rational
/// quadratic (\[NB\] A7.1).
///
/// ```
/// use nurbs_core::{Point3, Vector3, shapes::arc};
/// // three quarters of a circle of radius 2 about (1, 0, 0)
/// let c = arc(Point3::new(1.0, 0.0, 0.0), Vector3::x(), Vector3::y(), 2.0, 0.0, 4.71238898038469)
///     .unwrap();
/// let (t0, t1) = c.knots().domain();
/// for k in 0..=10 {
///     let p = c.point(t0 + (t1 - t0) * k as f64 / 10.0);
///     assert!(((p - Point3::new(1.0, 0.0, 0.0)).norm() - 2.0).abs() < 1e-12);
/// }
/// ```
pub fn arc(
    center: Point3,
    x: crate::Vector3,
    y: crate::Vector3,
    r: f64,
    start: f64,
    end: f64,
) -> Result<BSplineCurve> {
    let (kv, pts, w) = unit_arc(start, end)?;
    let points = pts
        .iter()
        .map(|&(a, b)| center + x * (r * a) + y * (r * b))
        .collect();
    BSplineCurve::new(kv, points, Some(w))
}

/// The surface swept by `curve` turning about the axis through `origin` with unit direction
/// `axis` from angle `start` to `end` (radians, right-handed about `axis`): u is the curve's
/// parameter, v the turn (\[NB\] A8.1). Exact: a point P turned by θ is
/// O + cos θ (P − O) + sin θ (axis × (P − O)) with O its foot on the axis, and the rational arc
/// reproduces (cos θ, sin θ), so P_ij = O_i + a_j X_i + b_j (axis × X_i), w_ij = w_i w_j. A
/// control point on the axis gives a row collapsed to that point (a sphere's pole).
///
/// ```
/// use nurbs_core::{BSplineCurve, KnotVector, Point3, Vector3, shapes::revolve_curve};
/// // a segment parallel to the z axis at distance 3, turned a half turn: a half cylinder
/// let line = BSplineCurve::new(
///     KnotVector::bezier(1).unwrap(),
///     vec![Point3::new(3.0, 0.0, 0.0), Point3::new(3.0, 0.0, 5.0)],
///     None,
/// )
/// .unwrap();
/// let s = revolve_curve(&line, Point3::origin(), Vector3::z(), 0.0, std::f64::consts::PI).unwrap();
/// let (v0, v1) = s.domain_v();
/// let p = s.point(0.5, 0.5 * (v0 + v1));
/// assert!((p.x.hypot(p.y) - 3.0).abs() < 1e-12 && (p.z - 2.5).abs() < 1e-12);
/// ```
pub fn revolve_curve(
    curve: &BSplineCurve,
    origin: Point3,
    axis: crate::Vector3,
    start: f64,
    end: f64,
) -> Result<BSplineSurface> {
    let axis = axis
        .try_normalize(0.0)
        .ok_or_else(|| crate::error::Error::Degenerate {
            detail: "the axis of revolution has zero length".to_string(),
        })?;
    let (kv, rot, wv) = unit_arc(start, end)?;
    let cw = curve.weights();
    let mut points = Vec::new();
    let mut weights = Vec::new();
    for (i, p) in curve.control_points().iter().enumerate() {
        let foot = origin + axis * axis.dot(&(p - origin));
        let x = p - foot;
        let y = axis.cross(&x);
        let wi = cw.map_or(1.0, |w| w[i]);
        for (&(a, b), &wj) in rot.iter().zip(&wv) {
            points.push(foot + x * a + y * b);
            weights.push(wi * wj);
        }
    }
    BSplineSurface::new(curve.knots().clone(), kv, points, Some(weights))
}

/// The bilinear 2 × 2 patch S(u, v) = `origin` + u `x` + v `y` over [u0, u1] × [v0, v1]: a plane
/// exactly, parametrized by length when `x` and `y` are unit vectors (as a kernel's plane is).
pub fn plane_patch(
    origin: Point3,
    x: crate::Vector3,
    y: crate::Vector3,
    (u0, u1): (f64, f64),
    (v0, v1): (f64, f64),
) -> Result<BSplineSurface> {
    let at = |a: f64, b: f64| origin + x * a + y * b;
    BSplineSurface::new(
        KnotVector::new(1, vec![u0, u0, u1, u1])?,
        KnotVector::new(1, vec![v0, v0, v1, v1])?,
        vec![at(u0, v0), at(u0, v1), at(u1, v0), at(u1, v1)],
        None,
    )
}

/// The surface swept by `curve` moved along `direction`: S(u, v) = C(u) + v `direction` for v in
/// [v0, v1], u the curve's parameter (\[NB\] §8.3, the general cylinder; IGES 122 and STEP's
/// SURFACE_OF_LINEAR_EXTRUSION). Exact for rational curves too: with row j = C's control
/// points moved by v_j `direction` and the weights of C in both rows,
/// Σ w_i N_i (P_i + v d) / Σ w_i N_i = C(u) + v d.
///
/// ```
/// use nurbs_core::{Point3, Vector3, shapes::{arc, extrude_curve}};
/// // a quarter circle of radius 2 extruded 5 along z: a quarter cylinder
/// let c = arc(Point3::origin(), Vector3::x(), Vector3::y(), 2.0, 0.0, 1.5).unwrap();
/// let s = extrude_curve(&c, Vector3::z(), (0.0, 5.0)).unwrap();
/// let (u0, u1) = s.domain_u();
/// let p = s.point(0.3 * u0 + 0.7 * u1, 2.5);
/// assert!((p.x.hypot(p.y) - 2.0).abs() < 1e-12 && (p.z - 2.5).abs() < 1e-12);
/// ```
pub fn extrude_curve(
    curve: &BSplineCurve,
    direction: crate::Vector3,
    (v0, v1): (f64, f64),
) -> Result<BSplineSurface> {
    if !(direction.norm() > 0.0) {
        return Err(crate::error::Error::Degenerate {
            detail: "the extrusion direction has zero length".to_string(),
        });
    }
    let mut points = Vec::with_capacity(2 * curve.control_points().len());
    for p in curve.control_points() {
        points.push(p + direction * v0);
        points.push(p + direction * v1);
    }
    let weights = curve
        .weights()
        .map(|w| w.iter().flat_map(|&x| [x, x]).collect());
    BSplineSurface::new(
        curve.knots().clone(),
        KnotVector::new(1, vec![v0, v0, v1, v1])?,
        points,
        weights,
    )
}

/// Relative difference below which two weight sequences count as proportional in
/// [`ruled_surface`]: far above the rounding of knot insertion and degree elevation (a few
/// hundred ulps), far below any weight a modeller sets.
pub(crate) const PROPORTIONAL_WEIGHTS_RELATIVE: f64 = 1e-12;

/// The ruled surface S(u, v) = (1 − v) C₁(u) + v C₂(u), u ∈ [0, 1] the two curves' parameters
/// mapped linearly onto [0, 1] (IGES 118 form 1, \[NB\] §8.2): the curves are made compatible —
/// the lower degree elevated, the knots of each inserted into the other — and the two
/// control polygons are the rows v = 0 and v = 1.
///
/// Exact when both curves are polynomial or their weights are proportional after that (then
/// one weight function W divides both rows); two rational curves with different weight
/// functions have no ruling of this degree (it needs W₁ W₂ in the denominator) and are refused
/// with [`crate::Error::Degenerate`] rather than approximated.
///
/// ```
/// use nurbs_core::{Point3, Vector3, shapes::{arc, ruled_surface}};
/// // two coaxial quarter circles of radii 1 and 3, 4 apart: a frustum of a cone
/// let a = arc(Point3::origin(), Vector3::x(), Vector3::y(), 1.0, 0.0, 1.5).unwrap();
/// let b = arc(Point3::new(0.0, 0.0, 4.0), Vector3::x(), Vector3::y(), 3.0, 0.0, 1.5).unwrap();
/// let s = ruled_surface(&a, &b).unwrap();
/// let p = s.point(0.4, 0.25);
/// assert!((p.x.hypot(p.y) - 1.5).abs() < 1e-12 && (p.z - 1.0).abs() < 1e-12);
/// ```
pub fn ruled_surface(c1: &BSplineCurve, c2: &BSplineCurve) -> Result<BSplineSurface> {
    let unit = |c: &BSplineCurve| -> Result<BSplineCurve> {
        let (a, b) = c.knots().domain();
        let knots = c
            .knots()
            .knots()
            .iter()
            .map(|t| (t - a) / (b - a))
            .collect();
        BSplineCurve::new(
            KnotVector::new(c.degree(), knots)?,
            c.control_points().to_vec(),
            c.weights().map(<[f64]>::to_vec),
        )
    };
    let (mut a, mut b) = (unit(c1)?, unit(c2)?);
    let p = a.degree().max(b.degree());
    if a.degree() < p {
        a = a.elevate_degree(p - a.degree())?;
    }
    if b.degree() < p {
        b = b.elevate_degree(p - b.degree())?;
    }
    // the knots each lacks (multiplicities counted), inserted so that both share one vector
    let lacking = |x: &BSplineCurve, y: &BSplineCurve| -> Vec<f64> {
        let mut out = Vec::new();
        for (t, m) in y.knots().interior_knots() {
            let have = x.knots().multiplicity(t);
            out.extend(std::iter::repeat_n(t, m.saturating_sub(have)));
        }
        out
    };
    let (more_a, more_b) = (lacking(&a, &b), lacking(&b, &a));
    if !more_a.is_empty() {
        a = a.refine(&more_a)?;
    }
    if !more_b.is_empty() {
        b = b.refine(&more_b)?;
    }
    let n = a.control_points().len();
    let weights = match (a.weights(), b.weights()) {
        (None, None) => None,
        (wa, wb) => {
            let wa: Vec<f64> = wa.map_or_else(|| vec![1.0; n], <[f64]>::to_vec);
            let wb: Vec<f64> = wb.map_or_else(|| vec![1.0; n], <[f64]>::to_vec);
            let ratio = wb[0] / wa[0];
            if wa
                .iter()
                .zip(&wb)
                .any(|(x, y)| (y / x - ratio).abs() > PROPORTIONAL_WEIGHTS_RELATIVE * ratio)
            {
                return Err(crate::error::Error::Degenerate {
                    detail: "the two curves of a ruled surface are rational with different weight functions: no exact ruling of their degree".to_string(),
                });
            }
            Some(wa.iter().flat_map(|&x| [x, x]).collect())
        }
    };
    let mut points = Vec::with_capacity(2 * n);
    for (p, q) in a.control_points().iter().zip(b.control_points()) {
        points.push(*p);
        points.push(*q);
    }
    BSplineSurface::new(a.knots().clone(), KnotVector::bezier(1)?, points, weights)
}
