//! Exact reference shapes: rational circles, cylinders, spheres, tori, and the paraboloid
//! z = x² + y² as a polynomial surface ([NB] §7.5 circles, §8.5 surfaces of revolution).
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
/// given unit arc ([NB] A8.1 in tensor form: P_ij = (ρ_i a_j, ρ_i b_j, z_i), w_ij = w_i w_j).
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
    let profile = (
        KnotVector::bezier(1)?,
        vec![(r, 0.0), (r, h)],
        vec![1.0, 1.0],
    );
    revolve(profile, unit_quarter())
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
