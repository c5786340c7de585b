//! Points along the 3D curves that bound a CURVE_BOUNDED_SURFACE (\[ISO42\] geometry_schema):
//! B-spline curves in any form, TRIMMED_CURVEs of lines, circles, ellipses and B-splines,
//! polylines, composite curves, and a SURFACE_CURVE's 3D curve; and the file's plane-angle
//! unit, in which a trimmed conic's parameters are given (\[ISO42\] `circle`, `ellipse`: a
//! conic's parameter is the angle).

use nurbs_core::{Point3, ProjectionParams};

use super::entities::{Model, R};
use super::knots::is_spline;
use super::lexer::Value;
use super::surfaces::spline_curve;
use super::{ARC_STEP, EDGE_SAMPLES, SPLINE_EDGE_SAMPLES};

/// Nesting of curves read (a composite curve of surface curves of trimmed curves is three): a
/// cycle of references in a corrupt file ends here with an error.
const MAX_NESTING: usize = 8;

/// Radians per unit of the file's plane angles: the conversion factor of a CONVERSION_BASED_UNIT
/// that is a PLANE_ANGLE_UNIT (its PLANE_ANGLE_MEASURE_WITH_UNIT, or π/180 for one named
/// DEGREE whose measure cannot be read), else 1 (the SI radian).
pub(super) fn angle_unit(m: &Model, ids: &[u64]) -> f64 {
    for &id in ids {
        let Ok(inst) = m.get(id) else { continue };
        if !inst.parts.iter().any(|(n, _)| n == "PLANE_ANGLE_UNIT") {
            continue;
        }
        let Some((_, p)) = inst
            .parts
            .iter()
            .find(|(n, _)| n == "CONVERSION_BASED_UNIT")
        else {
            continue;
        };
        let measured = match p.get(1) {
            Some(Value::Ref(r)) => m.get(*r).ok().and_then(|mu| {
                let (_, q) = mu.parts.first()?;
                m.num(*r, q.first()).ok()
            }),
            _ => None,
        };
        let named_degree =
            matches!(p.first(), Some(Value::Text(t)) if t.eq_ignore_ascii_case("degree"));
        return match measured {
            Some(f) if f > 0.0 => f,
            _ if named_degree => std::f64::consts::PI / 180.0,
            _ => 1.0,
        };
    }
    1.0
}

/// The 3D curve of a SURFACE_CURVE, SEAM_CURVE or INTERSECTION_CURVE (simple, or a part of a
/// complex instance, where the name is in REPRESENTATION_ITEM), `None` for another curve.
pub(super) fn surface_curve_3d(m: &Model, cid: u64) -> R<Option<u64>> {
    let inst = m.get(cid)?;
    let simple = inst.parts.len() == 1;
    for (k, p) in &inst.parts {
        if k == "SURFACE_CURVE" || k == "SEAM_CURVE" || k == "INTERSECTION_CURVE" {
            let at = if simple { 1 } else { 0 };
            return m.reference(cid, p.get(at)).map(Some);
        }
    }
    Ok(None)
}

/// Points along curve `cid` in its direction, `angle` radians per plane-angle unit.
pub(super) fn curve_points(m: &Model, cid: u64, angle: f64) -> R<Vec<Point3>> {
    nested_points(m, cid, angle, 0)
}

/// [`curve_points`] at nesting `depth`.
fn nested_points(m: &Model, cid: u64, angle: f64, depth: usize) -> R<Vec<Point3>> {
    if depth > MAX_NESTING {
        return Err(m.bad(cid, format!("curves nested deeper than {MAX_NESTING}")));
    }
    if let Some(c3) = surface_curve_3d(m, cid)? {
        return nested_points(m, c3, angle, depth + 1);
    }
    let inst = m.get(cid)?;
    if is_spline(inst, false) {
        let c = spline_curve(m, cid)?;
        let (t0, t1) = c.domain();
        let k = SPLINE_EDGE_SAMPLES;
        return Ok((0..k)
            .map(|i| c.point(t0 + (t1 - t0) * i as f64 / (k - 1) as f64))
            .collect());
    }
    let kind = m.kind(cid)?;
    let p = m.part(cid, kind)?;
    match kind {
        "POLYLINE" => m
            .list(cid, p.get(1))?
            .iter()
            .map(|x| m.point(m.reference(cid, Some(x))?))
            .collect(),
        "COMPOSITE_CURVE" | "BOUNDARY_CURVE" | "OUTER_BOUNDARY_CURVE" => {
            let mut out: Vec<Point3> = Vec::new();
            for seg in m.list(cid, p.get(1))? {
                let sid = m.reference(cid, Some(seg))?;
                let sp = m.part(sid, "COMPOSITE_CURVE_SEGMENT")?;
                let path = nested_points(m, m.reference(sid, sp.get(2))?, angle, depth + 1)?;
                let reversed = matches!(sp.get(1), Some(Value::Enum(e)) if e == "F");
                append_path(&mut out, path, reversed);
            }
            close_path(&mut out);
            Ok(out)
        }
        "TRIMMED_CURVE" => trimmed(m, cid, p, angle),
        "CIRCLE" | "ELLIPSE" => {
            let conic = Conic::read(m, cid, kind, angle)?;
            Ok(conic.points(0.0, std::f64::consts::TAU / angle))
        }
        _ => Err(m.bad(cid, "a boundary curve of this type is not read")),
    }
}

/// A circle or ellipse: centre, axes, radii, radians per parameter unit.
pub(super) struct Conic {
    o: Point3,
    x: nurbs_core::Vector3,
    y: nurbs_core::Vector3,
    r: (f64, f64),
    angle: f64,
}

impl Conic {
    /// CIRCLE or ELLIPSE `cid` (`kind`).
    pub(super) fn read(m: &Model, cid: u64, kind: &str, angle: f64) -> R<Conic> {
        let c = m.part(cid, kind)?;
        let (o, x, y, _) = m.placement(m.reference(cid, c.get(1))?)?;
        let r1 = m.num(cid, c.get(2))?;
        let r2 = if kind == "ELLIPSE" {
            m.num(cid, c.get(3))?
        } else {
            r1
        };
        Ok(Conic {
            o,
            x,
            y,
            r: (r1, r2),
            angle,
        })
    }
    /// The point at parameter `t`.
    pub(super) fn at(&self, t: f64) -> Point3 {
        let a = t * self.angle;
        self.o + self.x * (self.r.0 * a.cos()) + self.y * (self.r.1 * a.sin())
    }
    /// The parameter of a point on it.
    pub(super) fn param(&self, q: &Point3) -> f64 {
        let d = q - self.o;
        (d.dot(&self.y) / self.r.1).atan2(d.dot(&self.x) / self.r.0) / self.angle
    }
    /// Points from parameter `t0` to `t1` (at most a turn apart), at most [`ARC_STEP`] apart.
    fn points(&self, t0: f64, t1: f64) -> Vec<Point3> {
        let sweep = ((t1 - t0) * self.angle).abs().min(std::f64::consts::TAU);
        let n = EDGE_SAMPLES.max((sweep / ARC_STEP).ceil() as usize + 1);
        (0..n)
            .map(|k| self.at(t0 + (t1 - t0) * k as f64 / (n - 1) as f64))
            .collect()
    }
}

/// TRIMMED_CURVE `cid` (parameters `p`: name, basis curve, trim 1, trim 2, sense, preference):
/// points from trim 1 to trim 2, along the basis curve's direction when the sense is `.T.`;
/// a trim is a parameter value, or else a point, inverted on the basis curve.
fn trimmed(m: &Model, cid: u64, p: &[Value], angle: f64) -> R<Vec<Point3>> {
    let basis = m.reference(cid, p.get(1))?;
    let forward = !matches!(p.get(4), Some(Value::Enum(e)) if e == "F");
    let trim = |k: usize| -> R<(Option<f64>, Option<Point3>)> {
        let mut out = (None, None);
        for v in m.list(cid, p.get(k))? {
            match v {
                Value::Number(x) => out.0 = Some(*x),
                Value::Typed(_, inner) => out.0 = Some(m.num(cid, inner.first())?),
                Value::Ref(r) => out.1 = Some(m.point(*r)?),
                _ => {}
            }
        }
        Ok(out)
    };
    let (t1, t2) = (trim(2)?, trim(3)?);
    let kind = m.kind(basis)?;
    match kind {
        "LINE" => {
            let l = m.part(basis, kind)?;
            let o = m.point(m.reference(basis, l.get(1))?)?;
            let vid = m.reference(basis, l.get(2))?;
            let vp = m.part(vid, "VECTOR")?;
            let dir = m.direction(m.reference(vid, vp.get(1))?)? * m.num(vid, vp.get(2))?;
            let param = |t: (Option<f64>, Option<Point3>)| match t {
                (Some(x), _) => Ok(x),
                (None, Some(q)) => Ok((q - o).dot(&dir) / dir.norm_squared()),
                _ => Err(m.bad(cid, "a trim with neither parameter nor point")),
            };
            Ok(vec![o + dir * param(t1)?, o + dir * param(t2)?])
        }
        "CIRCLE" | "ELLIPSE" => {
            let c = Conic::read(m, basis, kind, angle)?;
            let param = |t: (Option<f64>, Option<Point3>)| match t {
                (Some(x), _) => Ok(x),
                (None, Some(q)) => Ok(c.param(&q)),
                _ => Err(m.bad(cid, "a trim with neither parameter nor point")),
            };
            let (a, b) = (param(t1)?, param(t2)?);
            if !(a.is_finite() && b.is_finite()) {
                return Err(m.bad(cid, "a trim parameter is not finite"));
            }
            let period = std::f64::consts::TAU / angle;
            // the conic runs counterclockwise; against it the parameter decreases; at most
            // one turn either way (equal trims: the whole conic)
            let ahead = (b - a).rem_euclid(period);
            let b = if forward {
                a + if ahead > 0.0 { ahead } else { period }
            } else {
                a - if ahead > 0.0 { period - ahead } else { period }
            };
            Ok(c.points(a, b))
        }
        _ if is_spline(m.get(basis)?, false) => {
            let c = spline_curve(m, basis)?;
            let params = ProjectionParams::default();
            let param = |t: (Option<f64>, Option<Point3>)| match t {
                (Some(x), _) => Ok(x),
                (None, Some(q)) => Ok(nurbs_core::project_to_curve(&c, &q, &params).t),
                _ => Err(m.bad(cid, "a trim with neither parameter nor point")),
            };
            // trims beyond the curve's domain are held at its ends
            let (t0, t1d) = c.domain();
            let (a, b) = (param(t1)?.clamp(t0, t1d), param(t2)?.clamp(t0, t1d));
            let k = SPLINE_EDGE_SAMPLES;
            Ok((0..k)
                .map(|i| c.point(a + (b - a) * i as f64 / (k - 1) as f64))
                .collect())
        }
        _ => Err(m.bad(basis, "a trimmed curve of this type is not read")),
    }
}

/// Appends `path` (reversed where its sense is false) to the polyline `out`, the joint of two
/// pieces once.
pub(super) fn append_path(out: &mut Vec<Point3>, mut path: Vec<Point3>, reversed: bool) {
    if reversed {
        path.reverse();
    }
    for q in path {
        if out.last() != Some(&q) {
            out.push(q);
        }
    }
}

/// Drops the last point of a closed polyline that repeats its first (a loop lists each point
/// once).
pub(super) fn close_path(out: &mut Vec<Point3>) {
    if out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
}
