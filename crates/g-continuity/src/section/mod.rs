//! The one-hump section of a fillet: curvature that rises once and falls once across it.
//!
//! A rolling-ball fillet meets a plane with curvature 1/R against the plane's 0. G2 needs 0 at
//! the contact line (a curved master's own curvature across, in general), and a lead-in that
//! moves only control row 2 ([`crate::lead_in`]) must rejoin the unchanged arc beyond it: the
//! curvature overshoots and undershoots there, two extrema too many beside each side. The
//! whole section has to change instead (\[SV\] §1: "large, monotone curvature areas"): with
//! the contact lines and their tangent planes kept, a profile whose curvature ramps from 0 to a
//! plateau and back turns the same angle over a slightly shorter plateau of slightly higher
//! curvature — the railway easement between a straight and a circle, with the ends pinned. Its
//! deviation from the arc grows linearly with the ramp and with the ramp's deficit
//! ([`RampShape`]): for a 90° arc of radius R and ramps of length ℓ the middle of the section
//! moves by about 0.1 ℓ with the linear ramp and 0.2 ℓ with the flat one (measured in the
//! tests), the plateau's radius shrinking by about ℓ/4 or ℓ/2.
//!
//! # Construction
//! 1. The reference section: the iso-curve across the fillet at the middle of its length, in
//!    its plane (E0 at the origin, its start tangent along +x), with its arc length and signed
//!    curvature κ_ref(σ) at normalized arc length σ.
//! 2. The profile κ(σ) = ρ(σ)·(c + d(σ − ½))·κ_ref(σ) + (1 − ρ)·κ_contact, ρ a ramp from 0
//!    to 1 ([`RampShape`]) over the fraction f of the length at each ramped end and κ_contact
//!    that end's master's curvature across (0 for a plane or without a master); c, d and the
//!    length are solved (Newton) so that the curve from E0 ends at E1 with E1's tangent. For a
//!    circle between planes d = 0 and the profile is symmetric; for a conic the tilt d keeps
//!    the two ends' shares.
//! 3. A quintic B-spline fitted to it: three knots in each ramp, the rest in equal spans; the
//!    second and third control points on the end tangent at a ramped end with curvature 0 (as
//!    the profile), so that G1 and G2 to a plane hold already and the G2 step has little left;
//!    at a curved master's end the third is free and the fit carries the master's curvature.
//! 4. Every control column of the surface takes the fitted section through its own frame: the
//!    points E0, M, E1 of the column (first point, the end tangents' meeting point, last point)
//!    and the section's affine coordinates in that frame. The map is affine per column, so a
//!    surface whose columns are affine images of one section (a cylinder fillet: translates; a
//!    torus fillet: rotated and radially scaled copies; weights a product a_i·b_j with equal
//!    end factors) becomes the same sweep of the new section exactly, with the along-direction
//!    weights kept. Other weights are interpolated across between the two contact rows'.
//!
//! The contact curves (rows 0 and n) are kept exactly, and so are the directions of the
//! cross-boundary tangents (row 1 stays on the line from row 0 towards M).

mod profile;

use nalgebra::Vector3 as V3;
use nurbs_core::{BSplineSurface, Direction, KnotVector, Point3};

use crate::error::{Error, Result};
pub use profile::{RampShape, SECTION_DEGREE, SECTION_SAMPLES};
use profile::{Section, fit_profile, frame_coordinates, from_frame, meeting};

/// Widest ramp, as a fraction of the section's length at each end: a quarter. The profile
/// turns the section's angle with a mean factor of 1 − D·f per ramp (D the ramp's deficit,
/// [`RampShape`]: ¼ linear, ½ flat), so with both ends ramped its plateau is about 1/(1 − 2Df)
/// of the input's curvature — at a quarter 1.14 (linear) or 1.33 (flat), within the 1.6× a
/// fair result may peak at, with room for the G2 step's change at a curved master.
pub const MAX_RAMP: f64 = 0.25;

/// Steps of the profile's integration: the midpoint-heading rule is exact for curvature linear
/// on a step, so its error is O(h²) in the curvature's second derivative — below 1e-9 of the
/// length for a quarter ramp at 2000 steps.
pub(crate) const PROFILE_STEPS: usize = 2000;

/// Least spans of the section's middle (between its ramps): three, the fewest with which a
/// quarter circle's section keeps one hump at every ramp width and shape (two leave three
/// extrema at the narrowest linear ramp, 1/64, where the middle is nearly the whole section);
/// its plateau is then even to 0.06 % at most (the flat ramp at a quarter; four spans: 0.1 %).
pub(crate) const MIDDLE_SPANS: usize = 3;

/// `s` with its section across `cross` replaced by the one-hump profile with ramps of the
/// fractions `ramps` (start side, end side; 0: no ramp, that end bends as the profile does) of
/// its length and of the `shape`, as the module docs describe. A ramped end with a master in
/// `masters` (the surfaces the start and the end side are G2 to) rises from the master's normal
/// curvature across at the middle section's contact point instead of from 0 (G2 to a curved
/// master; 0 for a plane, as without one). An error where the surface has no such section: a
/// column whose end tangents do not meet ahead of it, a straight or singular section, or a
/// profile that cannot join its ends.
pub fn one_hump_section(
    s: &BSplineSurface,
    cross: Direction,
    ramps: (f64, f64),
    shape: RampShape,
    masters: [Option<&BSplineSurface>; 2],
) -> Result<BSplineSurface> {
    let f = (ramps.0.clamp(0.0, MAX_RAMP), ramps.1.clamp(0.0, MAX_RAMP));
    let s = s.clamped()?;
    let section = Section::read(&s, cross)?.with_contacts(masters);
    let points = section.profile(f, shape, PROFILE_STEPS)?;
    let middle = MIDDLE_SPANS.max(section.spans + 1);
    let (kv, ctrl) = fit_profile(
        &points,
        f,
        middle,
        section.end_tangent(),
        section.flat_ends(),
    )?;
    let (corner, end) = (section.corner, section.end());
    let coords: Vec<(f64, f64)> = ctrl
        .iter()
        .map(|q| frame_coordinates(q, &corner, &end))
        .collect::<Option<_>>()
        .ok_or_else(|| bad("the section's frame is degenerate"))?;
    let kv = across_knots(&s, cross, &kv)?;
    let (na, nc) = match cross {
        Direction::V => (s.num_u(), s.num_v()),
        Direction::U => (s.num_v(), s.num_u()),
    };
    let at = |a: usize, c: usize| match cross {
        Direction::V => s.control_point(a, c),
        Direction::U => s.control_point(c, a),
    };
    let m = coords.len();
    let weights_new = new_weights(&s, cross, &kv.greville_fractions());
    let mut columns = Vec::with_capacity(na);
    for a in 0..na {
        let (e0, e1) = (at(a, 0), at(a, nc - 1));
        let corner = column_corner(&e0, &at(a, 1), &e1, &at(a, nc - 2))?;
        let mut column: Vec<Point3> = coords
            .iter()
            .map(|&ab| from_frame(ab, &e0, &corner, &e1))
            .collect();
        // the contact points themselves, not their images through the frame (a rounding off)
        column[0] = e0;
        column[m - 1] = e1;
        columns.push(column);
    }
    net_of(&s, cross, kv, &columns, weights_new.as_deref())
}

/// [`one_hump_section`] taken section by section: at the Greville abscissa of every control
/// column along, the iso-curve across gets its own one-hump profile, and the columns interpolate
/// those curves ([module docs](self) step 4 carries one section through every column's frame,
/// which is exact for a sweep only). A fillet whose section changes along it (a pipe tee's,
/// around the junction) keeps its shape: on the kernel's pipe tee the framed section deviated
/// 0.20 mm from the fillet at any ramp, this one 0.022 mm at a ramp of 1/72. The result is
/// polynomial; both contact curves are interpolated from their own points, so a polynomial
/// surface keeps them exactly (a rational one to the interpolation's accuracy: the caller
/// measures the deviation). Each section's ramps rise from its own contact points' curvatures
/// on `masters`.
pub fn one_hump_section_by_sections(
    s: &BSplineSurface,
    cross: Direction,
    ramps: (f64, f64),
    shape: RampShape,
    masters: [Option<&BSplineSurface>; 2],
) -> Result<BSplineSurface> {
    let f = (ramps.0.clamp(0.0, MAX_RAMP), ramps.1.clamp(0.0, MAX_RAMP));
    let s = s.clamped()?;
    let cross_kv = match cross {
        Direction::V => s.knots_v(),
        Direction::U => s.knots_u(),
    };
    // the spans of the middle, as [`one_hump_section`] takes them from its section
    let middle = MIDDLE_SPANS.max(cross_kv.spans().count() + 1);
    let (kv, columns) = sections_interpolated(&s, cross, f, shape, middle, masters)?;
    let kv = across_knots(&s, cross, &kv)?;
    net_of(&s, cross, kv, &columns, None)
}

/// The profile's knot vector `kv` (over [0, 1]) mapped onto `s`'s domain across `cross`.
fn across_knots(s: &BSplineSurface, cross: Direction, kv: &KnotVector) -> Result<KnotVector> {
    let (c0, c1) = match cross {
        Direction::V => s.domain_v(),
        Direction::U => s.domain_u(),
    };
    Ok(KnotVector::new(
        kv.degree(),
        kv.knots().iter().map(|&x| c0 + (c1 - c0) * x).collect(),
    )?)
}

/// The surface with `s`'s knots along, `kv` across `cross`, and the net of `columns` (one per
/// control index along, each running across), with the `weights` laid out as the columns
/// (`None`: polynomial).
fn net_of(
    s: &BSplineSurface,
    cross: Direction,
    kv: KnotVector,
    columns: &[Vec<Point3>],
    weights: Option<&[Vec<f64>]>,
) -> Result<BSplineSurface> {
    let (na, m) = (columns.len(), columns[0].len());
    let (ku, kvv, nu, nv) = match cross {
        Direction::V => (s.knots_u().clone(), kv, na, m),
        Direction::U => (kv, s.knots_v().clone(), m, na),
    };
    let index = |i: usize, j: usize| match cross {
        Direction::V => (i, j),
        Direction::U => (j, i),
    };
    let mut points = Vec::with_capacity(nu * nv);
    let mut ws = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            let (a, c) = index(i, j);
            points.push(columns[a][c]);
            ws.push(weights.map_or(1.0, |w| w[a][c]));
        }
    }
    Ok(BSplineSurface::new(
        ku,
        kvv,
        points,
        weights.is_some().then_some(ws),
    )?)
}

/// The control columns of a surface's one-hump section taken section by section: at
/// the Greville abscissa of every control column, the iso-curve across is read and given its
/// own one-hump profile (every one with the same knots, those of `f` and `middle`), and the
/// columns are the interpolation of those curves along the surface (the collocation of the
/// along basis at its Greville abscissae, which Schoenberg–Whitney makes regular). A fillet whose
/// section changes along it (a pipe tee's, around the junction) keeps its shape: the middle
/// section carried through every column's frame deviated 0.20 mm from the kernel's pipe-tee
/// fillet whatever the ramp. Both contact curves are interpolated from their own points, so
/// they stay exactly.
fn sections_interpolated(
    s: &BSplineSurface,
    cross: Direction,
    f: (f64, f64),
    shape: RampShape,
    middle: usize,
    masters: [Option<&BSplineSurface>; 2],
) -> Result<(KnotVector, Vec<Vec<Point3>>)> {
    let along = match cross {
        Direction::V => s.knots_u(),
        Direction::U => s.knots_v(),
    };
    // the Greville abscissae, clamped to the domain: the averages of the end knots can round
    // past them by an ulp
    let (d0, d1) = along.domain();
    let abscissae: Vec<f64> = along.greville().iter().map(|g| g.clamp(d0, d1)).collect();
    let mut kv = None;
    let mut curves: Vec<Vec<Point3>> = Vec::with_capacity(abscissae.len());
    for &g in &abscissae {
        let section = Section::read_at(s, cross, g)?.with_contacts(masters);
        let points = section.profile(f, shape, PROFILE_STEPS)?;
        let (k, ctrl) = fit_profile(
            &points,
            f,
            middle,
            section.end_tangent(),
            section.flat_ends(),
        )?;
        kv.get_or_insert(k);
        curves.push(ctrl.iter().map(|q| section.to_space(q)).collect());
    }
    let kv = kv.ok_or_else(|| bad("the surface has no control column"))?;
    // each row across interpolated along through the sections' points (nurbs-core's fit at as
    // many abscissae as control points: the interpolation)
    let na = abscissae.len();
    let m = curves[0].len();
    let template = nurbs_core::BSplineCurve::new(along.clone(), vec![Point3::origin(); na], None)?;
    let free = vec![true; na];
    let mut columns = vec![Vec::with_capacity(m); na];
    for c in 0..m {
        let row: Vec<Point3> = curves.iter().map(|curve| curve[c]).collect();
        let (fitted, _) = nurbs_core::fit_curve(
            &template,
            &free,
            &abscissae,
            &row,
            &nurbs_core::FitParams::default(),
        )?;
        for (column, p) in columns.iter_mut().zip(fitted.control_points()) {
            column.push(*p);
        }
    }
    Ok((kv, columns))
}

fn bad(reason: &str) -> Error {
    Error::NoSection {
        reason: reason.to_string(),
    }
}

/// The weights of the new net (`m` rows across, column-major by along index): per column the
/// weights of its two contact points, interpolated across at the rows' Greville fractions
/// (`None` for a polynomial surface). Both contact curves keep their control points and
/// weights, so they stay exactly; where the weights are a product a_i·b_j with b_0 = b_n (a
/// cylinder's or torus's circle weights) every row of a column has the column's weight and
/// the new surface is the exact sweep of the new section (module docs); other weights (a
/// freeform NURBS fillet) give a surface near that, whose deviation the caller measures.
fn new_weights(s: &BSplineSurface, cross: Direction, greville: &[f64]) -> Option<Vec<Vec<f64>>> {
    if !s.is_rational() {
        return None;
    }
    let (na, nc) = match cross {
        Direction::V => (s.num_u(), s.num_v()),
        Direction::U => (s.num_v(), s.num_u()),
    };
    let w = |a: usize, c: usize| match cross {
        Direction::V => s.weight(a, c),
        Direction::U => s.weight(c, a),
    };
    Some(
        (0..na)
            .map(|a| {
                let (w0, w1) = (w(a, 0), w(a, nc - 1));
                greville.iter().map(|&t| w0 + (w1 - w0) * t).collect()
            })
            .collect(),
    )
}

/// The meeting point of a control column's end tangents: from `e0` towards `p1` and from `e1`
/// towards `p_last` (both ahead of their ends).
fn column_corner(e0: &Point3, p1: &Point3, e1: &Point3, p_last: &Point3) -> Result<Point3> {
    let (t0, t1) = (p1 - e0, p_last - e1);
    if t0.norm() == 0.0 || t1.norm() == 0.0 {
        return Err(bad("a control column has no end tangent"));
    }
    let (t0, t1): (V3<f64>, V3<f64>) = (t0.normalize(), t1.normalize());
    let (s, t) = meeting(&e0.coords, &t0, &e1.coords, &t1)
        .ok_or_else(|| bad("a control column's end tangents are parallel"))?;
    if s <= 0.0 || t <= 0.0 {
        return Err(bad(
            "a control column's end tangents do not meet ahead of it",
        ));
    }
    // the midpoint of the closest points: the meeting point where the column is plane
    Ok(Point3::from(
        0.5 * ((e0.coords + t0 * s) + (e1.coords + t1 * t)),
    ))
}

#[cfg(test)]
mod tests;
