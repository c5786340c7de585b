//! A face's bounds as data: each loop's points in order (EDGE_LOOP of oriented edges along their
//! lines, circles, ellipses and B-spline curves; POLY_LOOP; VERTEX_LOOP), the outer bound first,
//! and the parameters of all the points on the face's surface, whose box the face is read over.

use nurbs_core::{BSplineCurve, Point3, ProjectionParams};

use super::curves::surface_curve_3d;
use super::entities::{Model, R};
use super::knots::is_spline;
use super::lexer::Value;
use super::surfaces::{Surface, spline_curve};
use super::{ARC_STEP, EDGE_SAMPLES, ON_SURFACE_RELATIVE, SPLINE_EDGE_SAMPLES};

/// One bound of a face: its loop's points in order and their parameters on the face's surface.
pub(super) struct BoundLoop {
    /// the points in order along the loop (one for a VERTEX_LOOP)
    pub(super) points: Vec<Point3>,
    /// their (u, v) on the surface
    pub(super) params: Vec<(f64, f64)>,
    /// per point, whether its parameters are its foot ([`Inverter::invert_loop`]): those that
    /// are not stay out of the face's box and take their predecessor's value when a closed
    /// direction is unwrapped (their parameters say nothing of where the face is)
    pub(super) found: Vec<bool>,
    /// named FACE_OUTER_BOUND in the file
    pub(super) outer: bool,
    /// the bound's orientation flag: the loop runs as listed (`.T.`) or against it
    pub(super) forward: bool,
}

/// The bounds of face `id` (its `bounds` list) in the file's order, each loop's points in
/// order with their parameters on `surface`: a B-spline's projector builds its grid of start
/// points once per face, not once per point.
pub(super) fn bound_loops(
    m: &Model,
    id: u64,
    bounds: Option<&Value>,
    surface: &Surface,
) -> R<Vec<BoundLoop>> {
    let mut inverter = Inverter::new(surface);
    let mut out = Vec::new();
    for b in m.list(id, bounds)? {
        let Value::Ref(bid) = b else { continue };
        let bound = m.get(*bid)?;
        let (kind, fb) = &bound.parts[0];
        let loop_id = m.reference(*bid, fb.get(1))?;
        let points = loop_points(m, loop_id)?;
        let (params, found) = inverter.invert_loop(&points);
        out.push(BoundLoop {
            points,
            params,
            found,
            outer: kind == "FACE_OUTER_BOUND",
            forward: !matches!(fb.get(2), Some(Value::Enum(e)) if e == "F"),
        });
    }
    Ok(out)
}

/// A bound point whose projection onto its face's B-spline ends farther than this fraction of
/// the surface's size from it has not found its foot ([`Inverter::invert_loop`]). A point of a
/// bound lies on the surface to the file's accuracy — 10⁻⁵ of the size for the usual 10⁻³ mm
/// on a 100 mm part, and files sloppier than that exist (some bound points of an AP209 file lie
/// more than 10⁻⁴ of the size off their surface: that bound took them for misses) — while a
/// search that misses the foot ends at another part of the surface, a distance of the order of
/// the face's features (1.7 mm on a 164 mm dome, 10⁻²); 10⁻³ lies between the two.
const FOOT_RELATIVE: f64 = 1e-3;

/// Inverts points on a surface: in closed form, or on a B-spline by projection — its grid of
/// start points built once, and Newton from the previous point's foot first (consecutive
/// boundary points are close), the full search only where that does not land on the surface.
pub(super) struct Inverter<'s> {
    surface: &'s Surface,
    projector: Option<nurbs_core::SurfaceProjector<'s>>,
    on_surface: f64,
    /// the distance within which a projection has found its foot ([`FOOT_RELATIVE`])
    foot: f64,
    previous: Option<(f64, f64)>,
}

impl<'s> Inverter<'s> {
    /// An inverter for `surface`.
    pub(super) fn new(surface: &'s Surface) -> Self {
        let (projector, size) = match surface {
            Surface::Spline(s) => (
                Some(nurbs_core::SurfaceProjector::new(
                    s,
                    ProjectionParams::default(),
                )),
                s.size(),
            ),
            _ => (None, 0.0),
        };
        Inverter {
            surface,
            projector,
            on_surface: ON_SURFACE_RELATIVE * size,
            foot: FOOT_RELATIVE * size,
            previous: None,
        }
    }
    /// The parameters of `pt`, and whether they are its foot (closed form, or a projection
    /// that lands within [`FOOT_RELATIVE`] of the surface's size).
    pub(super) fn invert(&mut self, pt: &Point3) -> ((f64, f64), bool) {
        let Some(pr) = self.projector.as_mut() else {
            return (self.surface.invert(pt), true);
        };
        let warm = self
            .previous
            .map(|start| pr.project_from(pt, start))
            .filter(|f| f.converged && f.distance <= self.on_surface);
        let f = warm.unwrap_or_else(|| pr.project(pt));
        self.previous = Some((f.u, f.v));
        ((f.u, f.v), f.distance <= self.foot)
    }

    /// The parameters of the points of a loop, in order, and per point whether they are its
    /// foot. A bound's point lies on its face's surface (\[ISO42\] topology_schema: an edge of
    /// a face lies on the face's surface); a projection that ends farther than
    /// [`FOOT_RELATIVE`] of the size has not found its foot — next to a collapsed boundary,
    /// where a sliver span of the surface past the face folds back beside it, the search can
    /// end at the domain's corner (a CATIA V4 dome, 1.7 mm off) — and its parameters would
    /// widen the face's box.
    pub(super) fn invert_loop(&mut self, points: &[Point3]) -> (Vec<(f64, f64)>, Vec<bool>) {
        points.iter().map(|p| self.invert(p)).unzip()
    }
}

/// The trim loops of a face's bounds: each loop's points, the outer bound first (a file that
/// names no FACE_OUTER_BOUND — OCCT writes FACE_BOUNDs only — has as outer loop the one whose
/// parameter box holds the others', the largest); a loop of fewer than three points (a vertex
/// loop at a pole) is no trim loop.
pub(super) fn trim_loops(bounds: &[BoundLoop]) -> Vec<Vec<Point3>> {
    let outer = bounds.iter().position(|b| b.outer).unwrap_or_else(|| {
        (0..bounds.len())
            .max_by(|&a, &b| box_area(&bounds[a].params).total_cmp(&box_area(&bounds[b].params)))
            .unwrap_or(0)
    });
    let mut loops: Vec<Vec<Point3>> = bounds.iter().map(|b| b.points.clone()).collect();
    if outer < loops.len() {
        let l = loops.remove(outer);
        loops.insert(0, l);
    }
    loops.retain(|l| l.len() >= 3);
    loops
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
                let path = edge_points(m, edge)?;
                let reversed = matches!(o.get(4), Some(Value::Enum(e)) if e == "F");
                super::curves::append_path(&mut out, path, reversed);
            }
            super::curves::close_path(&mut out);
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
        match surface_curve_3d(m, cid)? {
            Some(c3) => cid = c3,
            None => break,
        }
    }
    let mut out = vec![a];
    let kind = m.kind(cid)?;
    let n = EDGE_SAMPLES;
    match kind {
        "CIRCLE" | "ELLIPSE" => {
            // parameters in radians (angle unit 1): the edge's points, not the curve's unit
            let conic = super::curves::Conic::read(m, cid, kind, 1.0)?;
            // the curve runs counterclockwise; the edge from a to b along it, or against it
            let (s, e) = if same { (a, b) } else { (b, a) };
            let t0 = conic.param(&s);
            let mut t1 = conic.param(&e);
            while t1 <= t0 + 1e-12 {
                t1 += std::f64::consts::TAU;
            }
            let n = n.max(((t1 - t0) / ARC_STEP).ceil() as usize + 1);
            let mut between: Vec<Point3> = (1..n - 1)
                .map(|k| conic.at(t0 + (t1 - t0) * k as f64 / (n - 1) as f64))
                .collect();
            if !same {
                between.reverse();
            }
            out.extend(between);
        }
        "LINE" | "POLYLINE" => {}
        _ if is_spline(m.get(cid)?, false) => {
            let closed_edge = p.get(1) == p.get(2) || a == b;
            out.extend(spline_edge_points(
                &spline_curve(m, cid)?,
                &a,
                &b,
                same,
                closed_edge,
            ));
        }
        _ => {}
    }
    out.push(b);
    Ok(out)
}

/// The points of B-spline curve `c` strictly between the edge's vertices `a` and `b`, found on
/// it by projection: an edge uses part of its curve, and a sample past a vertex widens the
/// face's box (the nearest of 69 samples put a fillet's box 0.3 mm past its end). A closed edge
/// (one vertex at both ends: a full circle as a rational B-spline) runs once around the whole
/// curve from its vertex; on a closed curve an edge whose vertex sits at the curve's seam
/// starts or ends at whichever end of the domain puts it along the edge's sense (`same`: with
/// the curve's direction).
fn spline_edge_points(
    c: &BSplineCurve,
    a: &Point3,
    b: &Point3,
    same: bool,
    closed_edge: bool,
) -> Vec<Point3> {
    let params = ProjectionParams::default();
    let (t0, t1) = c.domain();
    let period = t1 - t0;
    let mut ta = nurbs_core::project_to_curve(c, a, &params).t;
    let mut tb = nurbs_core::project_to_curve(c, b, &params).t;
    let size = c
        .control_points()
        .iter()
        .fold(0.0_f64, |d, q| d.max((q - c.control_points()[0]).norm()));
    let closed_curve = (c.point(t0) - c.point(t1)).norm() <= ON_SURFACE_RELATIVE * size;
    let k = SPLINE_EDGE_SAMPLES;
    if closed_edge {
        // once around, with the curve's direction or against it
        let turn = if same { period } else { -period };
        return (1..k - 1)
            .map(|i| {
                let t = ta + turn * i as f64 / (k - 1) as f64;
                c.point(t0 + (t - t0).rem_euclid(period))
            })
            .collect();
    }
    if closed_curve {
        let near = |t: f64, end: f64| (t - end).abs() <= ON_SURFACE_RELATIVE * period;
        if same && ta > tb {
            if near(ta, t1) {
                ta = t0;
            } else if near(tb, t0) {
                tb = t1;
            }
        } else if !same && ta < tb {
            if near(ta, t0) {
                ta = t1;
            } else if near(tb, t1) {
                tb = t0;
            }
        }
    }
    (1..k - 1)
        .map(|i| c.point(ta + (tb - ta) * i as f64 / (k - 1) as f64))
        .collect()
}
