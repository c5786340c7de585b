//! A face's trim loops made ready for writing ([`face_bounds`]): every point moved to its foot on
//! the surface that is written, each loop turned so that the face lies on its left (outer loop
//! counterclockwise in (u, v), inner loops clockwise: the face's normal is S_u × S_v), split into
//! edges at its sharpest corners, the edges densified until their chords lie on the surface, and
//! the vertices and seam edges a loop visits twice shared. The STEP writer writes the edges as
//! B-spline edge curves ([`fitted_edge`]), the IGES writer each loop as a curve on surface (142)
//! under a trimmed surface (144), its model-space and parameter-space curves composites (102) of
//! one fitted piece per edge.
//!
//! The trim points lie on the surface they were imported with; after fairing, the surface has
//! moved by up to its deviation tolerance, and the foot of each point on the written surface
//! (nearest point, \[NB\] §6.1) puts the written edges on the written face.
//!
//! # Tolerance
//! [`ON_FACE_RELATIVE`] (of the surface size) bounds how far a chord's midpoint may lie off the
//! surface; [`SAME_POINT_RELATIVE`] merges vertices; [`SEAM_RELATIVE`] finds a seam edge a loop
//! runs along twice. All scale with the surface's size (its control net's diagonal).

use nurbs_core::{BSplineSurface, Point3, ProjectionParams, SurfaceProjector};

pub use crate::edge_fit::{distance_to_polyline, fitted_edge, polyline};

/// Turning angle (radians) at a loop point above which the loop is split into two edges there:
/// 30°. A kernel's edges meet at corners of 90° or so, and a loop thinned to the G0 tolerance
/// turns by about √(8 g0 / R) between points (2.3° on a 5 mm radius at 1 µm), so smooth runs stay
/// one edge.
pub(crate) const CORNER_ANGLE: f64 = std::f64::consts::PI / 6.0;

/// A chord of a written edge whose midpoint lies farther than this fraction of the surface size
/// from the surface gets that midpoint's foot as a new point: 10⁻⁶ (0.1 µm on a 100 mm part), a
/// hundredth of the default G0 tolerance, so that the edges lie on the face for every reader
/// while a 5 mm fillet arc needs about one point per 0.06 mm.
pub const ON_FACE_RELATIVE: f64 = 1e-6;

/// Halvings of one chord at most while densifying (64 pieces): a chord of a loop thinned to the
/// G0 tolerance needs a few.
pub const MAX_HALVINGS: usize = 6;

/// Two loop points within this fraction of the surface size are one point (one vertex; a
/// repeated point is dropped): the rounding of two projections of the same point.
pub const SAME_POINT_RELATIVE: f64 = 1e-9;

/// An edge whose points all lie within this fraction of the surface size of another edge of the
/// face run backwards between the same vertices is that edge used twice (the seam of a face
/// closed around an axis): 10⁻⁵, ten times [`ON_FACE_RELATIVE`], since both runs are densified
/// independently.
pub const SEAM_RELATIVE: f64 = 1e-5;

/// A surface point where a first derivative is below this fraction of the size is a pole (a
/// collapsed side; the rounding of exact kernel geometry is far below).
pub(crate) const POLE_RELATIVE: f64 = 1e-9;

/// Edges a loop is split into at least: a closed edge (one vertex at both ends) is not read by
/// every reader.
pub(crate) const MIN_EDGES: usize = 2;

/// A surface to write, its name and its trim loops.
#[derive(Debug, Clone, Copy)]
pub struct Face<'a> {
    /// the face's name (STEP: the face's name; IGES: the label of its 128 and 144)
    pub name: &'a str,
    /// the surface
    pub surface: &'a BSplineSurface,
    /// the face's boundary loops, outer first, points near the surface in order (at least three
    /// each); empty: the face is the whole surface, bounded by its parameter box
    pub trim: &'a [Vec<Point3>],
}

impl<'a> Face<'a> {
    /// A face that is the whole surface.
    pub fn untrimmed(name: &'a str, surface: &'a BSplineSurface) -> Self {
        Self {
            name,
            surface,
            trim: &[],
        }
    }
}

/// One edge of a written face: its points from its start vertex to its end vertex.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundEdge {
    /// points on the surface, first and last the vertices
    pub points: Vec<Point3>,
    /// index of the start vertex in [`FaceBounds::vertices`]
    pub start: usize,
    /// index of the end vertex
    pub end: usize,
}

/// One loop of a written face: its edges in order, each with its sense.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundLoop {
    /// whether this is the outer loop
    pub outer: bool,
    /// (index into [`FaceBounds::edges`], whether the edge runs forward in the loop)
    pub edges: Vec<(usize, bool)>,
}

/// A face's loops as vertices and edges on the surface that is written.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FaceBounds {
    /// the distinct vertices
    pub vertices: Vec<Point3>,
    /// the distinct edges (a seam edge once)
    pub edges: Vec<BoundEdge>,
    /// the loops, outer first
    pub loops: Vec<BoundLoop>,
}

impl FaceBounds {
    /// The points of loop `k` in order along it, each once (the loop closes back to the first),
    /// starting in the middle of its longest edge: off its vertices, so that a walk along it
    /// starts away from a seam.
    pub fn loop_points(&self, k: usize) -> Vec<Point3> {
        let mut out: Vec<Point3> = Vec::new();
        let mut start = (0, 0);
        for &(e, forward) in &self.loops[k].edges {
            let pts = &self.edges[e].points;
            if pts.len() > start.1 {
                start = (out.len().saturating_sub(1) + pts.len() / 2, pts.len());
            }
            let run: Box<dyn Iterator<Item = &Point3>> = if forward {
                Box::new(pts.iter())
            } else {
                Box::new(pts.iter().rev())
            };
            for p in run {
                if out.last() != Some(p) {
                    out.push(*p);
                }
            }
        }
        if out.len() > 1 && out.first() == out.last() {
            out.pop();
        }
        let at = start.0.min(out.len().saturating_sub(1));
        out.rotate_left(at);
        out
    }
}

/// The parameters of `points` (a loop on `surface`, in order) walked along it: each point's
/// foot from the previous point's parameters, from the sampled starts where those land nearer,
/// so that a loop crossing a closed surface's seam runs on in parameter space across it from
/// the side it came. A point at a pole (a collapsed side, where one parameter is free) becomes
/// two: the free parameter of the point before it and of the point after it, so that the loop
/// runs along the collapsed side in parameter space instead of cutting across the face. A
/// segment whose image on the surface leaves the chord between its ends (a parametrization
/// that is not linear along it) is halved until its midpoint's image lies within
/// [`ON_FACE_RELATIVE`] of the surface size of the chord's midpoint.
pub fn loop_params(surface: &BSplineSurface, points: &[Point3]) -> Vec<(f64, f64)> {
    let size = surface.size().max(f64::MIN_POSITIVE);
    let mut projector = SurfaceProjector::new(surface, ProjectionParams::default());
    let mut walk: Vec<(f64, f64)> = Vec::with_capacity(points.len());
    for p in points {
        let global = projector.project(p);
        let f = match walk.last() {
            Some(&start) => {
                let warm = projector.project_from(p, start);
                if warm.distance <= global.distance + SAME_POINT_RELATIVE * size {
                    warm
                } else {
                    global
                }
            }
            None => global,
        };
        walk.push((f.u, f.v));
    }
    let n = walk.len();
    let mut out = Vec::with_capacity(n + 4);
    for (k, &(u, v)) in walk.iter().enumerate() {
        let (before, after) = (walk[(k + n - 1) % n], walk[(k + 1) % n]);
        let d = surface.derivatives(u, v);
        if d.du.norm() <= POLE_RELATIVE * size {
            out.extend([(before.0, v), (after.0, v)]);
        } else if d.dv.norm() <= POLE_RELATIVE * size {
            out.extend([(u, before.1), (u, after.1)]);
        } else {
            out.push((u, v));
        }
    }
    out.dedup();
    let tol = ON_FACE_RELATIVE * size;
    let mut refined = Vec::with_capacity(out.len());
    for (k, &a) in out.iter().enumerate() {
        refined.push(a);
        halve_params(
            surface,
            a,
            out[(k + 1) % out.len()],
            tol,
            MAX_HALVINGS,
            &mut refined,
        );
    }
    refined
}

/// Whether the loop's step from `a` to `b` in parameter space is a jump across a closed
/// surface's seam: more than half the domain in either direction (a walk that reaches the end
/// of the domain starts again at its other end), between points nearer each other on the
/// surface than either is to the image of the step's middle — which lies across the face for a
/// jump, and on the chord for a long straight step of a coarse loop (a plane's triangle, whose
/// corners are its only points).
pub fn is_seam_jump(surface: &BSplineSurface, a: (f64, f64), b: (f64, f64)) -> bool {
    let (u0, u1) = surface.domain_u();
    let (v0, v1) = surface.domain_v();
    if !((b.0 - a.0).abs() > 0.5 * (u1 - u0) || (b.1 - a.1).abs() > 0.5 * (v1 - v0)) {
        return false;
    }
    let (pa, pb) = (surface.point(a.0, a.1), surface.point(b.0, b.1));
    let pm = surface.point(0.5 * (a.0 + b.0), 0.5 * (a.1 + b.1));
    (pa - pb).norm() < (pa - pm).norm()
}

/// Pushes the parameters strictly between `a` and `b` that keep the image of the segment a–b
/// within `tol` of its chord (`depth` halvings left). A jump across a seam
/// ([`is_seam_jump`]) is not halved: its midpoint in parameter space lies across the face,
/// and halving towards it drew a detour of 64 points over the face and back into the loop.
pub(crate) fn halve_params(
    surface: &BSplineSurface,
    a: (f64, f64),
    b: (f64, f64),
    tol: f64,
    depth: usize,
    out: &mut Vec<(f64, f64)>,
) {
    if is_seam_jump(surface, a, b) {
        return;
    }
    let m = (0.5 * (a.0 + b.0), 0.5 * (a.1 + b.1));
    let chord =
        Point3::from((surface.point(a.0, a.1).coords + surface.point(b.0, b.1).coords) * 0.5);
    if depth == 0 || (surface.point(m.0, m.1) - chord).norm() <= tol {
        return;
    }
    halve_params(surface, a, m, tol, depth - 1, out);
    out.push(m);
    halve_params(surface, m, b, tol, depth - 1, out);
}

/// The trim loops `trim` (outer first) of a face on `surface` as vertices and edges on it (module
/// docs); a loop that keeps fewer than three distinct points on the surface is left out.
pub fn face_bounds(surface: &BSplineSurface, trim: &[Vec<Point3>]) -> FaceBounds {
    let size = surface.size().max(f64::MIN_POSITIVE);
    let mut projector = SurfaceProjector::new(surface, ProjectionParams::default());
    let mut out = FaceBounds::default();
    for (k, points) in trim.iter().enumerate() {
        let (mut pts, mut uv) = feet(&mut projector, points, SAME_POINT_RELATIVE * size);
        if pts.len() < 3 {
            continue;
        }
        let outer = k == 0;
        if (signed_area(&uv) > 0.0) != outer {
            pts.reverse();
            uv.reverse();
        }
        let splits = splits(&pts, SAME_POINT_RELATIVE * size);
        let mut edges = Vec::new();
        for (a, b) in splits.iter().zip(splits.iter().cycle().skip(1)) {
            let run: Vec<usize> = cyclic_range(*a, *b, pts.len());
            let mut dense = densify(
                &mut projector,
                surface,
                &run,
                &pts,
                &uv,
                ON_FACE_RELATIVE * size,
            );
            dense.dedup_by(|p, q| (*p - *q).norm() <= SAME_POINT_RELATIVE * size);
            edges.push(out.add_edge(dense, size));
        }
        out.loops.push(BoundLoop { outer, edges });
    }
    out
}

impl FaceBounds {
    /// The vertex at `p` (an existing one within [`SAME_POINT_RELATIVE`] of the size, or new).
    fn vertex(&mut self, p: Point3, size: f64) -> usize {
        let tol = SAME_POINT_RELATIVE * size;
        match self.vertices.iter().position(|q| (q - p).norm() <= tol) {
            Some(k) => k,
            None => {
                self.vertices.push(p);
                self.vertices.len() - 1
            }
        }
    }

    /// Adds the edge through `points` (or finds it as an earlier edge run backwards: a seam);
    /// returns its index and sense.
    fn add_edge(&mut self, mut points: Vec<Point3>, size: f64) -> (usize, bool) {
        let last = points.len() - 1;
        let start = self.vertex(points[0], size);
        let end = self.vertex(points[last], size);
        // the ends exactly at the vertices, so that the edges of a loop join exactly
        (points[0], points[last]) = (self.vertices[start], self.vertices[end]);
        let tol = SEAM_RELATIVE * size;
        let seam = self.edges.iter().position(|e| {
            e.start == end
                && e.end == start
                && points
                    .iter()
                    .all(|p| distance_to_polyline(p, &e.points) <= tol)
                && e.points
                    .iter()
                    .all(|p| distance_to_polyline(p, &points) <= tol)
        });
        if let Some(k) = seam {
            return (k, false);
        }
        self.edges.push(BoundEdge { points, start, end });
        (self.edges.len() - 1, true)
    }
}

/// The feet on the surface of `points` in order (and their parameters), a point repeating the
/// one before it (within `same`) dropped. Each point is projected from the sampled starts and
/// from the previous foot, the nearer foot kept and the previous one's neighbour on a tie, so
/// that a loop crossing a closed surface's seam keeps running on the side it came from.
fn feet(
    projector: &mut SurfaceProjector<'_>,
    points: &[Point3],
    same: f64,
) -> (Vec<Point3>, Vec<(f64, f64)>) {
    let mut pts: Vec<Point3> = Vec::with_capacity(points.len());
    let mut uv: Vec<(f64, f64)> = Vec::with_capacity(points.len());
    for p in points {
        let global = projector.project(p);
        let f = match uv.last() {
            Some(&start) => {
                let warm = projector.project_from(p, start);
                if warm.distance <= global.distance + same {
                    warm
                } else {
                    global
                }
            }
            None => global,
        };
        if pts.last().is_some_and(|q| (q - f.point).norm() <= same) {
            continue;
        }
        pts.push(f.point);
        uv.push((f.u, f.v));
    }
    while pts.len() > 1 && (pts[0] - pts[pts.len() - 1]).norm() <= same {
        pts.pop();
        uv.pop();
    }
    (pts, uv)
}

/// Twice the signed area of the closed polygon `uv` (positive counterclockwise).
fn signed_area(uv: &[(f64, f64)]) -> f64 {
    uv.iter()
        .zip(uv.iter().cycle().skip(1))
        .map(|(a, b)| a.0 * b.1 - b.0 * a.1)
        .sum()
}

/// Where a closed loop of `pts` is split into edges: every point where it turns by more than
/// [`CORNER_ANGLE`], at least [`MIN_EDGES`] points (the sharpest, else spread along the loop),
/// and an edge whose two ends coincide (within `same`) split in its middle. Sorted indices.
fn splits(pts: &[Point3], same: f64) -> Vec<usize> {
    let n = pts.len();
    let turn = |i: usize| {
        let a = pts[i] - pts[(i + n - 1) % n];
        let b = pts[(i + 1) % n] - pts[i];
        a.angle(&b)
    };
    let mut out: Vec<usize> = (0..n).filter(|&i| turn(i) > CORNER_ANGLE).collect();
    if out.is_empty() {
        out.push(
            (0..n)
                .max_by(|&a, &b| turn(a).total_cmp(&turn(b)))
                .unwrap_or(0),
        );
    }
    while out.len() < MIN_EDGES.min(n) {
        out.push((out[0] + n / 2) % n);
        out.sort_unstable();
        out.dedup();
    }
    // a closed edge: split it in the middle
    loop {
        let closed = (0..out.len()).find(|&k| {
            let (a, b) = (out[k], out[(k + 1) % out.len()]);
            (pts[a] - pts[b]).norm() <= same && (b + n - a) % n > 1
        });
        let Some(k) = closed else { break };
        let (a, b) = (out[k], out[(k + 1) % out.len()]);
        let len = (b + n - a) % n;
        let len = if len == 0 { n } else { len };
        out.push((a + len / 2) % n);
        out.sort_unstable();
        out.dedup();
    }
    out
}

/// Indices from `a` to `b` (both included) going forward around a loop of `n` points; the
/// whole loop back to `a` where `a == b`.
fn cyclic_range(a: usize, b: usize, n: usize) -> Vec<usize> {
    let len = (b + n - a) % n;
    let len = if len == 0 { n } else { len };
    (0..=len).map(|k| (a + k) % n).collect()
}

/// The points of `run` (indices into `pts`, parameters `uv`) with points inserted wherever a
/// chord leaves the surface or the curve between its ends by more than `tol` (each chord halved
/// at most [`MAX_HALVINGS`] times).
fn densify(
    projector: &mut SurfaceProjector<'_>,
    surface: &BSplineSurface,
    run: &[usize],
    pts: &[Point3],
    uv: &[(f64, f64)],
    tol: f64,
) -> Vec<Point3> {
    let mut out = vec![pts[run[0]]];
    for w in run.windows(2) {
        let (a, b) = (w[0], w[1]);
        halve(
            projector,
            surface,
            (pts[a], uv[a]),
            (pts[b], uv[b]),
            tol,
            MAX_HALVINGS,
            &mut out,
        );
    }
    out
}

/// Pushes the points after `a` up to `b` (each a point and its parameters) of the chord a–b,
/// halved at the image of the parameters' midpoint — the curve between the ends that the
/// parameter line follows (an isoline edge: its arc) — where that lies farther than `tol` from
/// the chord's midpoint, else at the midpoint's foot where that lies farther than `tol` from the
/// midpoint (`depth` halvings left). A parameter midpoint farther from the chord than its
/// length is across a seam and not used.
fn halve(
    projector: &mut SurfaceProjector<'_>,
    surface: &BSplineSurface,
    a: (Point3, (f64, f64)),
    b: (Point3, (f64, f64)),
    tol: f64,
    depth: usize,
    out: &mut Vec<Point3>,
) {
    if depth == 0 {
        out.push(b.0);
        return;
    }
    let mid = Point3::from((a.0.coords + b.0.coords) * 0.5);
    let m = (0.5 * (a.1.0 + b.1.0), 0.5 * (a.1.1 + b.1.1));
    let image = surface.point(m.0, m.1);
    let off = (image - mid).norm();
    let regular = |(u, v): (f64, f64)| {
        let d = surface.derivatives(u, v);
        let size = surface.size();
        d.du.norm() > POLE_RELATIVE * size && d.dv.norm() > POLE_RELATIVE * size
    };
    let next = if off > tol && off <= (b.0 - a.0).norm() && regular(a.1) && regular(b.1) {
        Some((image, m))
    } else {
        let mut foot = projector.project_from(&mid, a.1);
        if (foot.point - mid).norm() > tol {
            // a chord from a seam point starts from the seam's other side: the sampled starts
            let global = projector.project(&mid);
            if global.distance < foot.distance {
                foot = global;
            }
        }
        ((foot.point - mid).norm() > tol).then_some((foot.point, (foot.u, foot.v)))
    };
    match next {
        Some(c) => {
            halve(projector, surface, a, c, tol, depth - 1, out);
            halve(projector, surface, c, b, tol, depth - 1, out);
        }
        None => out.push(b.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs_core::Vector3;

    fn square(c: f64, h: f64) -> Vec<Point3> {
        vec![
            Point3::new(c - h, c - h, 0.0),
            Point3::new(c + h, c - h, 0.0),
            Point3::new(c + h, c + h, 0.0),
            Point3::new(c - h, c + h, 0.0),
        ]
    }

    /// A plane with a square hole: the outer loop counterclockwise, the inner clockwise (both
    /// given counterclockwise), four edges each split at the corners.
    #[test]
    fn loops_are_turned_and_split_at_corners() {
        let plane = nurbs_core::shapes::plane_patch(
            Point3::origin(),
            Vector3::x(),
            Vector3::y(),
            (0.0, 10.0),
            (0.0, 10.0),
        )
        .unwrap();
        let trim = vec![square(5.0, 5.0), square(5.0, 2.0)];
        let b = face_bounds(&plane, &trim);
        assert_eq!(b.loops.len(), 2);
        assert_eq!(b.vertices.len(), 8);
        assert_eq!(b.edges.len(), 8);
        let area =
            |pts: Vec<Point3>| signed_area(&pts.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>());
        assert!(area(b.loop_points(0)) > 0.0);
        assert!(area(b.loop_points(1)) < 0.0);
        assert!(b.loops.iter().all(|l| l.edges.len() == 4));
    }

    /// A circle with no corner is split into two edges, none closed.
    #[test]
    fn a_smooth_loop_has_two_open_edges() {
        let pts: Vec<Point3> = (0..40)
            .map(|k| {
                let t = std::f64::consts::TAU * f64::from(k) / 40.0;
                Point3::new(t.cos(), t.sin(), 0.0)
            })
            .collect();
        let s = splits(&pts, 1e-12);
        assert_eq!(s.len(), 2);
        assert_ne!(pts[s[0]], pts[s[1]]);
    }
}
