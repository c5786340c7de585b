//! The surfaces a face lies on, with the closed form that inverts a point on them: PLANE,
//! CYLINDRICAL_SURFACE, CONICAL_SURFACE, SPHERICAL_SURFACE, TOROIDAL_SURFACE, SURFACE_OF_REVOLUTION
//! and SURFACE_OF_LINEAR_EXTRUSION of a B-spline curve, B_SPLINE_SURFACE_WITH_KNOTS; each built
//! as an exact NURBS surface over a parameter box (\[NB\] A7.1 / A8.1), and the B-spline curves
//! and surfaces of a file.

use nurbs_core::{BSplineCurve, BSplineSurface, KnotVector, Point3, ProjectionParams, Vector3};

use super::StepError;
use super::entities::{Model, R};
use super::knots::{implied_form, implied_knots, is_spline};
use super::lexer::Value;

/// An elementary or B-spline surface with its closed-form parametrization.
pub(super) enum Surface {
    Plane(Point3, Vector3, Vector3),
    /// origin, x, y, z, radius, semi-angle (0 for a cylinder)
    Cone(Point3, Vector3, Vector3, Vector3, f64, f64),
    /// origin, x, y, z, radius
    Sphere(Point3, Vector3, Vector3, Vector3, f64),
    /// origin, x, y, z, major, minor
    Torus(Point3, Vector3, Vector3, Vector3, f64, f64),
    Spline(BSplineSurface),
    /// a generatrix turned about the axis through the point with the unit direction; the
    /// generatrix's radial direction at its middle is angle 0 (it lies in a half-plane through
    /// the axis, as every surface of revolution a kernel writes)
    Revolution(BSplineCurve, Point3, Vector3, Vector3),
    /// a curve moved along a vector (magnitude included): S(u, v) = C(u) + v V; with the curve
    /// projected along V onto the plane through the origin perpendicular to it (the same
    /// weights: a linear map of the net), which inverts a point
    Extrusion(BSplineCurve, Vector3, BSplineCurve),
}

impl Surface {
    /// Parameters (u, v) of a point on the surface, u the angle where there is one.
    pub(super) fn invert(&self, p: &Point3) -> (f64, f64) {
        match self {
            Surface::Plane(o, x, y) => ((p - o).dot(x), (p - o).dot(y)),
            Surface::Cone(o, x, y, z, _, _) => {
                let d = p - o;
                (d.dot(y).atan2(d.dot(x)), d.dot(z))
            }
            Surface::Sphere(o, x, y, z, _) => {
                let d = p - o;
                let (a, b) = (d.dot(x), d.dot(y));
                (b.atan2(a), d.dot(z).atan2(a.hypot(b)))
            }
            Surface::Torus(o, x, y, z, major, _) => {
                let d = p - o;
                let (a, b) = (d.dot(x), d.dot(y));
                (b.atan2(a), d.dot(z).atan2(a.hypot(b) - major))
            }
            Surface::Spline(s) => {
                let f = nurbs_core::project_to_surface(s, p, &ProjectionParams::default());
                (f.u, f.v)
            }
            Surface::Extrusion(c, vector, flat) => {
                // the foot on the projected curve gives u; v is the offset along V from C(u)
                let unit = vector.normalize();
                let q = p - unit * unit.dot(&p.coords);
                let u = nurbs_core::project_to_curve(flat, &q, &ProjectionParams::default()).t;
                (u, (p - c.point(u)).dot(vector) / vector.norm_squared())
            }
            Surface::Revolution(c, o, z, x) => {
                let d = p - o;
                let y = z.cross(x);
                let u = d.dot(&y).atan2(d.dot(x));
                // turned back into the generatrix's half-plane, the point lies on it
                let h = z * d.dot(z);
                let back = o + h + x * (d - h).norm();
                (
                    u,
                    nurbs_core::project_to_curve(c, &back, &ProjectionParams::default()).t,
                )
            }
        }
    }
    /// The NURBS surface over [u0, u1] × [v0, v1].
    pub(super) fn build(&self, u: (f64, f64), v: (f64, f64)) -> nurbs_core::Result<BSplineSurface> {
        use nurbs_core::shapes::{arc, revolve_curve};
        let line = |a: Point3, b: Point3| {
            BSplineCurve::new(
                KnotVector::new(1, vec![v.0, v.0, v.1, v.1])?,
                vec![a, b],
                None,
            )
        };
        match self {
            Surface::Plane(o, x, y) => nurbs_core::shapes::plane_patch(*o, *x, *y, u, v),
            Surface::Cone(o, x, _, z, r, semi) => {
                let at = |h: f64| o + x * (r + h * semi.tan()) + z * h;
                let profile = line(at(v.0), at(v.1))?;
                // u the angle about z: the profile turned from u0 to u1; the result runs
                // (profile, angle), transposed to (angle, height)
                Ok(revolve_curve(&profile, *o, *z, u.0, u.1)?.transposed()?)
            }
            Surface::Sphere(o, x, _, z, r) => {
                let profile = arc(*o, *x, *z, *r, v.0, v.1)?;
                Ok(revolve_curve(&profile, *o, *z, u.0, u.1)?.transposed()?)
            }
            Surface::Torus(o, x, _, z, major, minor) => {
                let profile = arc(o + x * *major, *x, *z, *minor, v.0, v.1)?;
                Ok(revolve_curve(&profile, *o, *z, u.0, u.1)?.transposed()?)
            }
            Surface::Spline(s) => s.extract(u, v),
            Surface::Revolution(c, o, z, _) => {
                let part = c.extract(v.0, v.1)?;
                Ok(revolve_curve(&part, *o, *z, u.0, u.1)?.transposed()?)
            }
            Surface::Extrusion(c, vector, _) => {
                nurbs_core::shapes::extrude_curve(&c.extract(u.0, u.1)?, *vector, v)
            }
        }
    }
}

/// The surface of instance `sid`, `None` for a type that is not read.
pub(super) fn surface(m: &Model, sid: u64) -> R<Option<Surface>> {
    let kind = m.kind(sid)?;
    let inst = m.get(sid)?;
    Ok(Some(match kind {
        "PLANE" => {
            let (o, x, y, _) = m.placement(m.reference(sid, m.part(sid, kind)?.get(1))?)?;
            Surface::Plane(o, x, y)
        }
        "CYLINDRICAL_SURFACE" | "CONICAL_SURFACE" | "SPHERICAL_SURFACE" | "TOROIDAL_SURFACE" => {
            quadric(m, sid, kind)?
        }
        "SURFACE_OF_REVOLUTION" => match revolution(m, sid, kind)? {
            Some(s) => s,
            None => return Ok(None),
        },
        "SURFACE_OF_LINEAR_EXTRUSION" => match extrusion(m, sid, kind)? {
            Some(s) => s,
            None => return Ok(None),
        },
        _ if is_spline(inst, true) => Surface::Spline(spline_surface(m, sid)?),
        _ => return Ok(None),
    }))
}

/// A CYLINDRICAL_, CONICAL_, SPHERICAL_ or TOROIDAL_SURFACE (`kind`): its placement and radii.
fn quadric(m: &Model, sid: u64, kind: &str) -> R<Surface> {
    let p = m.part(sid, kind)?;
    let (o, x, y, z) = m.placement(m.reference(sid, p.get(1))?)?;
    let a = m.num(sid, p.get(2))?;
    Ok(match kind {
        "CYLINDRICAL_SURFACE" => Surface::Cone(o, x, y, z, a, 0.0),
        "CONICAL_SURFACE" => {
            // the semi-angle in the file's plane-angle unit: radians, or degrees when
            // it is above π/2 (no cone opens that wide)
            let semi = m.num(sid, p.get(3))?;
            let semi = if semi.abs() > std::f64::consts::FRAC_PI_2 {
                semi.to_radians()
            } else {
                semi
            };
            Surface::Cone(o, x, y, z, a, semi)
        }
        "SPHERICAL_SURFACE" => Surface::Sphere(o, x, y, z, a),
        _ => Surface::Torus(o, x, y, z, a, m.num(sid, p.get(3))?),
    })
}

/// A SURFACE_OF_REVOLUTION of a B-spline curve (`None` for another generatrix), angle 0 at the
/// generatrix's middle.
fn revolution(m: &Model, sid: u64, kind: &str) -> R<Option<Surface>> {
    let p = m.part(sid, kind)?;
    let cid = m.reference(sid, p.get(1))?;
    let curve = match m.kind(cid)? {
        _ if is_spline(m.get(cid)?, false) => spline_curve(m, cid)?,
        _ => return Ok(None),
    };
    let aid = m.reference(sid, p.get(2))?;
    let a = m.part(aid, "AXIS1_PLACEMENT")?;
    let o = m.point(m.reference(aid, a.get(1))?)?;
    let z = match a.get(2) {
        Some(Value::Ref(r)) => m.direction(*r)?,
        _ => Vector3::z(),
    };
    let (t0, t1) = curve.knots().domain();
    let mid = curve.point(0.5 * (t0 + t1)) - o;
    let x = (mid - z * z.dot(&mid))
        .try_normalize(0.0)
        .ok_or_else(|| m.bad(sid, "the generatrix lies on the axis"))?;
    Ok(Some(Surface::Revolution(curve, o, z, x)))
}

/// A SURFACE_OF_LINEAR_EXTRUSION of a B-spline curve (`None` for another curve), with the curve
/// projected along the vector that inverts a point.
fn extrusion(m: &Model, sid: u64, kind: &str) -> R<Option<Surface>> {
    // (name, swept curve, extrusion axis: a VECTOR of a direction and a magnitude)
    let p = m.part(sid, kind)?;
    let cid = m.reference(sid, p.get(1))?;
    if !is_spline(m.get(cid)?, false) {
        return Ok(None);
    }
    let curve = spline_curve(m, cid)?;
    let vid = m.reference(sid, p.get(2))?;
    let v = m.part(vid, "VECTOR")?;
    let dir = m.direction(m.reference(vid, v.get(1))?)?;
    let vector = dir * m.num(vid, v.get(2))?;
    if !(vector.norm() > 0.0) {
        return Err(m.bad(sid, "the extrusion vector has zero length"));
    }
    let unit = vector.normalize();
    let flat_points = curve
        .control_points()
        .iter()
        .map(|q| q - unit * unit.dot(&q.coords))
        .collect();
    let flat = BSplineCurve::new(
        curve.knots().clone(),
        flat_points,
        curve.weights().map(<[f64]>::to_vec),
    )
    .map_err(|source| StepError::Geometry { id: sid, source })?;
    Ok(Some(Surface::Extrusion(curve, vector, flat)))
}

/// The knot vector of STEP's distinct knots and their multiplicities (instance `id`): each
/// multiplicity a whole number from 1 to [`MAX_DEGREE`] + 1 (\[ISO42\]
/// `b_spline_curve_with_knots`: at most the degree + 1), one per knot.
pub(super) fn expand_knots(m: &Model, id: u64, mults: &[f64], values: &[f64]) -> R<Vec<f64>> {
    if mults.len() != values.len() {
        return Err(m.bad(
            id,
            format!(
                "{} knot multiplicities for {} knots",
                mults.len(),
                values.len()
            ),
        ));
    }
    let mut out = Vec::new();
    for (&k, &n) in values.iter().zip(mults) {
        if n.fract() != 0.0 || !(1.0..=(MAX_DEGREE + 1) as f64).contains(&n) {
            return Err(m.bad(id, format!("knot multiplicity {n}")));
        }
        out.extend(std::iter::repeat_n(k, n as usize));
    }
    Ok(out)
}

/// A B-spline surface in any of its forms (\[ISO42\] geometry_schema): B_SPLINE_SURFACE_WITH_KNOTS,
/// or UNIFORM_, QUASI_UNIFORM_ or BEZIER_SURFACE with their knots implied ([`implied_knots`]);
/// simple, or in a complex instance with B_SPLINE_SURFACE and RATIONAL_B_SPLINE_SURFACE.
/// Control points are listed row by row, u the outer index, as the crate's flat net
/// P[i · n_v + j].
pub(super) fn spline_surface(m: &Model, sid: u64) -> R<BSplineSurface> {
    let inst = m.get(sid)?;
    let implied = implied_form(inst, true);
    let (base, knots): (&[Value], Option<&[Value]>) = if inst.parts.len() == 1 {
        // simple instance: name, du, dv, points, form, closed u, closed v, self-intersect,
        // then (with knots) mults u, mults v, knots u, knots v, spec
        let p = &inst.parts[0].1;
        let need = if implied.is_some() { 8 } else { 13 };
        if p.len() < need {
            return Err(m.bad(sid, format!("{} parameters, expected {need}", p.len())));
        }
        (&p[1..], implied.is_none().then(|| &p[8..]))
    } else {
        (
            m.part(sid, "B_SPLINE_SURFACE")?,
            match implied {
                Some(_) => None,
                None => Some(m.part(sid, "B_SPLINE_SURFACE_WITH_KNOTS")?),
            },
        )
    };
    let (du, dv) = (degree(m, sid, base.first())?, degree(m, sid, base.get(1))?);
    let rows = m.list(sid, base.get(2))?;
    let mut points = Vec::new();
    let mut nv = 0;
    for row in rows {
        let r = m.list(sid, Some(row))?;
        nv = r.len();
        for x in r {
            points.push(m.point(m.reference(sid, Some(x))?)?);
        }
    }
    if nv == 0 || points.len() != rows.len() * nv {
        return Err(m.bad(sid, "the control point rows differ in length"));
    }
    let (ku, kv) = match (knots, implied) {
        (Some(k), _) => (
            expand_knots(
                m,
                sid,
                &m.numbers(sid, k.first())?,
                &m.numbers(sid, k.get(2))?,
            )?,
            expand_knots(
                m,
                sid,
                &m.numbers(sid, k.get(1))?,
                &m.numbers(sid, k.get(3))?,
            )?,
        ),
        (None, Some(form)) => (
            implied_knots(form, du, rows.len()).map_err(|e| m.bad(sid, format!("u: {e}")))?,
            implied_knots(form, dv, nv).map_err(|e| m.bad(sid, format!("v: {e}")))?,
        ),
        (None, None) => return Err(m.bad(sid, "expected B_SPLINE_SURFACE_WITH_KNOTS")),
    };
    let weights = match inst
        .parts
        .iter()
        .find(|(n, _)| n == "RATIONAL_B_SPLINE_SURFACE")
    {
        Some((_, w)) => {
            let mut out = Vec::new();
            for row in m.list(sid, w.first())? {
                out.extend(m.numbers(sid, Some(row))?);
            }
            Some(out)
        }
        None => None,
    };
    let g = |source| StepError::Geometry { id: sid, source };
    BSplineSurface::new(
        KnotVector::new(du, ku).map_err(g)?,
        KnotVector::new(dv, kv).map_err(g)?,
        points,
        weights,
    )
    .map_err(g)
}

/// A degree parameter: a whole number from 1 to [`MAX_DEGREE`].
fn degree(m: &Model, id: u64, v: Option<&Value>) -> R<usize> {
    let d = m.num(id, v)?;
    if d.fract() != 0.0 || !(1.0..=MAX_DEGREE as f64).contains(&d) {
        return Err(m.bad(
            id,
            format!("degree {d}, expected a whole number from 1 to {MAX_DEGREE}"),
        ));
    }
    Ok(d as usize)
}

/// The largest degree read: far above what CAD systems write (degree 25 in CATIA V5, 14 in
/// Parasolid), low enough that a garbled number cannot ask for an absurd basis.
pub(super) const MAX_DEGREE: usize = 64;

/// A B-spline curve in any of its forms (B_SPLINE_CURVE_WITH_KNOTS, or UNIFORM_,
/// QUASI_UNIFORM_ or BEZIER_CURVE with implied knots), simple or in a complex instance with
/// RATIONAL_B_SPLINE_CURVE.
pub(super) fn spline_curve(m: &Model, cid: u64) -> R<BSplineCurve> {
    let inst = m.get(cid)?;
    let implied = implied_form(inst, false);
    let (base, knots): (&[Value], Option<&[Value]>) = if inst.parts.len() == 1 {
        // name, degree, points, form, closed, self-intersect, then (with knots) the knots
        let p = &inst.parts[0].1;
        let need = if implied.is_some() { 6 } else { 9 };
        if p.len() < need {
            return Err(m.bad(cid, format!("{} parameters, expected {need}", p.len())));
        }
        (&p[1..], implied.is_none().then(|| &p[6..]))
    } else {
        (
            m.part(cid, "B_SPLINE_CURVE")?,
            match implied {
                Some(_) => None,
                None => Some(m.part(cid, "B_SPLINE_CURVE_WITH_KNOTS")?),
            },
        )
    };
    let d = degree(m, cid, base.first())?;
    let points = m
        .list(cid, base.get(1))?
        .iter()
        .map(|x| m.point(m.reference(cid, Some(x))?))
        .collect::<R<Vec<_>>>()?;
    let kv = match (knots, implied) {
        (Some(k), _) => expand_knots(
            m,
            cid,
            &m.numbers(cid, k.first())?,
            &m.numbers(cid, k.get(1))?,
        )?,
        (None, Some(form)) => {
            implied_knots(form, d, points.len()).map_err(|e| m.bad(cid, e.to_string()))?
        }
        (None, None) => return Err(m.bad(cid, "expected B_SPLINE_CURVE_WITH_KNOTS")),
    };
    let weights = match inst
        .parts
        .iter()
        .find(|(n, _)| n == "RATIONAL_B_SPLINE_CURVE")
    {
        Some((_, w)) => Some(m.numbers(cid, w.first())?),
        None => None,
    };
    let g = |source| StepError::Geometry { id: cid, source };
    BSplineCurve::new(KnotVector::new(d, kv).map_err(g)?, points, weights).map_err(g)
}
