//! A face's bounds as data: each loop's points in order (EDGE_LOOP of oriented edges along their
//! lines, circles, ellipses and B-spline curves; POLY_LOOP; VERTEX_LOOP), the outer bound first,
//! and the parameters of all the points on the face's surface, whose box the face is read over.

use nurbs_core::{Point3, ProjectionParams};

use super::entities::{Model, R};
use super::lexer::Value;
use super::surfaces::{Surface, spline_curve};
use super::{ARC_STEP, EDGE_SAMPLES, ON_SURFACE_RELATIVE, SPLINE_EDGE_SAMPLES};

/// A face's bound loops (points in order) and the parameters of their points on its surface.
type Bounds = (Vec<Vec<Point3>>, Vec<(f64, f64)>);

/// The bounds of face `id` (its `bounds` list) as loops of points in order, the outer bound
/// first (a loop of fewer than three points, a vertex loop at a pole, is no trim loop), and the
/// parameters of all those points on `surface`: a B-spline's projector builds its grid of start
/// points once per face, not once per point.
pub(super) fn boundary_params(
    m: &Model,
    id: u64,
    bounds: Option<&Value>,
    surface: &Surface,
) -> R<Bounds> {
    // the face's boundary points, inverted on the surface (a B-spline's projector builds its
    // grid of start points once per face, not once per point)
    let mut params = Vec::new();
    let mut projector = match surface {
        Surface::Spline(s) => Some(nurbs_core::SurfaceProjector::new(
            s,
            ProjectionParams::default(),
        )),
        _ => None,
    };
    // consecutive boundary points are close: Newton from the previous foot first, the full
    // search from the grid only where that does not land on the surface
    let on_surface = match surface {
        Surface::Spline(s) => ON_SURFACE_RELATIVE * s.size(),
        _ => 0.0,
    };
    let mut previous: Option<(f64, f64)> = None;
    let mut loops: Vec<Vec<Point3>> = Vec::new();
    let mut named_outer = false;
    // per loop in `loops` order: the area of its parameter box
    let mut boxes: Vec<f64> = Vec::new();
    for b in m.list(id, bounds)? {
        let Value::Ref(bid) = b else { continue };
        let bound = m.get(*bid)?;
        let fb = &bound.parts[0].1;
        let loop_id = m.reference(*bid, fb.get(1))?;
        let points = loop_points(m, loop_id)?;
        let outer = bound.parts[0].0 == "FACE_OUTER_BOUND";
        named_outer |= outer;
        let slot = if outer { 0 } else { loops.len() };
        loops.insert(slot, points.clone());
        let first = params.len();
        for pt in points {
            params.push(match projector.as_mut() {
                Some(pr) => {
                    let warm = previous
                        .map(|start| pr.project_from(&pt, start))
                        .filter(|f| f.converged && f.distance <= on_surface);
                    let f = warm.unwrap_or_else(|| pr.project(&pt));
                    previous = Some((f.u, f.v));
                    (f.u, f.v)
                }
                None => surface.invert(&pt),
            });
        }
        boxes.insert(slot, box_area(&params[first..]));
    }
    // a file that names no FACE_OUTER_BOUND (OCCT writes FACE_BOUNDs only): the outer loop is
    // the one whose parameter box holds the others', the largest
    if !named_outer && loops.len() > 1 {
        let outer = (0..loops.len())
            .max_by(|&a, &b| boxes[a].total_cmp(&boxes[b]))
            .unwrap_or(0);
        let l = loops.remove(outer);
        loops.insert(0, l);
    }
    loops.retain(|l| l.len() >= 3);
    Ok((loops, params))
}

/// Area of the parameter box of `params` (0 for none).
fn box_area(params: &[(f64, f64)]) -> f64 {
    let span = |f: fn(&(f64, f64)) -> f64| {
        let (lo, hi) = params
            .iter()
            .map(f)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(x), hi.max(x))
            });
        (hi - lo).max(0.0)
    };
    span(|p| p.0) * span(|p| p.1)
}

/// Points of an EDGE_LOOP (or POLY_LOOP, VERTEX_LOOP) in order along it: each oriented edge
/// from its start to its end with points along its curve, every joint once.
fn loop_points(m: &Model, lid: u64) -> R<Vec<Point3>> {
    let kind = m.kind(lid)?;
    let p = m.part(lid, kind)?;
    let mut out: Vec<Point3> = Vec::new();
    match kind {
        "EDGE_LOOP" => {
            for oe in m.list(lid, p.get(1))? {
                let oe = m.reference(lid, Some(oe))?;
                let o = m.part(oe, "ORIENTED_EDGE")?;
                let edge = m.reference(oe, o.get(3))?;
                let mut path = edge_points(m, edge)?;
                if matches!(o.get(4), Some(Value::Enum(e)) if e == "F") {
                    path.reverse();
                }
                // the joint of two edges once
                for q in path {
                    if out.last() != Some(&q) {
                        out.push(q);
                    }
                }
            }
            if out.len() > 1 && out.first() == out.last() {
                out.pop();
            }
        }
        "POLY_LOOP" => {
            for x in m.list(lid, p.get(1))? {
                out.push(m.point(m.reference(lid, Some(x))?)?);
            }
        }
        "VERTEX_LOOP" => out.push(vertex(m, m.reference(lid, p.get(1))?)?),
        _ => return Err(m.bad(lid, "not a loop of edges")),
    }
    Ok(out)
}

/// The point of a VERTEX_POINT.
fn vertex(m: &Model, vid: u64) -> R<Point3> {
    m.point(m.reference(vid, m.part(vid, "VERTEX_POINT")?.get(1))?)
}

/// An EDGE_CURVE's points in order from its start vertex to its end vertex, along its geometry.
fn edge_points(m: &Model, eid: u64) -> R<Vec<Point3>> {
    let p = m.part(eid, "EDGE_CURVE")?;
    let (a, b) = (
        vertex(m, m.reference(eid, p.get(1))?)?,
        vertex(m, m.reference(eid, p.get(2))?)?,
    );
    let same = !matches!(p.get(4), Some(Value::Enum(e)) if e == "F");
    let mut cid = m.reference(eid, p.get(3))?;
    // a SURFACE_CURVE / SEAM_CURVE carries its 3D curve first
    for _ in 0..4 {
        let k = m.kind(cid)?;
        if k == "SURFACE_CURVE" || k == "SEAM_CURVE" || k == "INTERSECTION_CURVE" {
            cid = m.reference(cid, m.part(cid, k)?.get(1))?;
        } else {
            break;
        }
    }
    let mut out = vec![a];
    let kind = m.kind(cid)?;
    let n = EDGE_SAMPLES;
    match kind {
        "CIRCLE" | "ELLIPSE" => {
            let c = m.part(cid, kind)?;
            let (o, x, y, _) = m.placement(m.reference(cid, c.get(1))?)?;
            let r1 = m.num(cid, c.get(2))?;
            let r2 = if kind == "ELLIPSE" {
                m.num(cid, c.get(3))?
            } else {
                r1
            };
            let angle = |p: &Point3| {
                let d = p - o;
                (d.dot(&y) / r2).atan2(d.dot(&x) / r1)
            };
            // the curve runs counterclockwise; the edge from a to b along it, or against it
            let (s, e) = if same { (a, b) } else { (b, a) };
            let t0 = angle(&s);
            let mut t1 = angle(&e);
            while t1 <= t0 + 1e-12 {
                t1 += std::f64::consts::TAU;
            }
            let n = n.max(((t1 - t0) / ARC_STEP).ceil() as usize + 1);
            let mut between: Vec<Point3> = (1..n - 1)
                .map(|k| {
                    let t = t0 + (t1 - t0) * k as f64 / (n - 1) as f64;
                    o + x * (r1 * t.cos()) + y * (r2 * t.sin())
                })
                .collect();
            if !same {
                between.reverse();
            }
            out.extend(between);
        }
        "LINE" | "POLYLINE" => {}
        _ if m
            .get(cid)?
            .parts
            .iter()
            .any(|(k, _)| k == "B_SPLINE_CURVE_WITH_KNOTS") =>
        {
            let c = spline_curve(m, cid)?;
            // the points of the curve between the vertices, found on it by projection: an edge
            // uses part of its curve, and a sample past a vertex widens the face's box (the
            // nearest of 69 samples put a fillet's box 0.3 mm past its end)
            let params = ProjectionParams::default();
            let ta = nurbs_core::project_to_curve(&c, &a, &params).t;
            let tb = nurbs_core::project_to_curve(&c, &b, &params).t;
            let k = SPLINE_EDGE_SAMPLES;
            out.extend((1..k - 1).map(|i| c.point(ta + (tb - ta) * i as f64 / (k - 1) as f64)));
        }
        _ => {}
    }
    out.push(b);
    Ok(out)
}
