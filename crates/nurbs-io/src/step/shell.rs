//! The topology of a written shell: every face's bounds as vertices, edges and loops, and —
//! where a join tolerance is given — faces that meet along a boundary sharing that edge and its
//! vertices, as the B-rep they came from did (ISO 10303-42 §5.4: an edge of a closed shell is
//! used by exactly two faces, once in each direction).
//!
//! A face's own bounds come from [`crate::bounds::face_bounds`] (its trim loops) or from its
//! parameter box (the four boundary curves, exact; a collapsed side a vertex, a closed side one
//! seam edge used both ways). Across faces:
//! 1. vertices within the join tolerance of each other are one vertex (never two of one face);
//! 2. an edge with another face's vertex within the join tolerance of its interior is split
//!    there (a plane's long edge along a fillet and the corner blend after it: a T-junction);
//! 3. two edges of different faces between the same two vertices whose points lie within the
//!    join tolerance of each other are one edge, written once (the first face's, an exact
//!    boundary curve preferred), used by both;
//! 4. each connected set of faces is oriented so that every shared edge is used once in each
//!    direction: a face whose surface normal points the other way is written with
//!    `same_sense` false. Each connected set is one shell, closed where every edge of it is
//!    used twice, consistently.
//!
//! Without a join tolerance every face keeps its own vertices and edges (each face then bounds
//! itself; readers sew, or not).

use nurbs_core::{BSplineCurve, BSplineSurface, Direction, Point3};

use crate::bounds::{BoundLoop, Face, distance_to_polyline, face_bounds};
use crate::edge_fit::foot_on_polyline;

use super::writer::DISTANCE_ACCURACY;

/// Samples per control point with which an exact boundary curve is first sampled for the
/// comparisons with other faces' edges (refined by halving where a chord leaves the curve by
/// more than [`crate::bounds::ON_FACE_RELATIVE`] of the size): four — a cubic span's chords.
const SAMPLES_PER_CONTROL_POINT: usize = 4;

/// Points of an edge compared with the other edge to decide that two edges are one (spread
/// evenly along it, ends excluded): nine — a fillet's edge and a plane's edge that merely share
/// both vertices (a half cylinder's two sides) part in the middle, which any odd count sees.
const MATCH_SAMPLES: usize = 9;

/// Share of the shortest edge at a vertex that the vertex reaches when faces are joined: a
/// quarter. A part with edges at the size of the join tolerance (a kernel's 1 µm step between
/// two faces) must not have two vertices of one face merged through a third face's vertex, nor
/// an edge split a join tolerance from its end; a quarter keeps two vertices of an edge apart
/// however they are joined, and a split leaves pieces at least [`SPLIT_PIECE`] reaches long.
const EDGE_SHARE: f64 = 0.25;

/// The shortest piece a split leaves, in reaches of the splitting vertex: four — a piece as
/// long as the edges the vertex's reach was taken from, at the least.
const SPLIT_PIECE: f64 = 4.0;

/// One edge of the shell: its points from its start vertex to its end vertex, and the exact
/// curve it is (a parameter box's boundary curve, same direction) where it has one.
#[derive(Debug, Clone)]
pub(super) struct PlanEdge {
    /// points on the face it came from, first and last at its vertices
    pub(super) points: Vec<Point3>,
    /// the exact curve, start to end
    pub(super) exact: Option<BSplineCurve>,
    /// start and end vertex (indices into [`ShellPlan::vertices`])
    pub(super) start: usize,
    pub(super) end: usize,
    /// the face it came from
    face: usize,
    /// uses by loops of the shell (0: merged into another edge, not written)
    pub(super) uses: usize,
}

/// One face of the shell: its loops (edges of [`ShellPlan::edges`] with their sense, outer
/// first) and whether it is written against its surface's normal.
#[derive(Debug, Clone, Default)]
pub(super) struct PlanFace {
    pub(super) loops: Vec<BoundLoop>,
    pub(super) flipped: bool,
}

/// The shell's vertices, edges and faces.
#[derive(Debug, Clone, Default)]
pub(super) struct ShellPlan {
    pub(super) vertices: Vec<Point3>,
    /// for each vertex, the faces that use it
    vertex_faces: Vec<Vec<usize>>,
    /// for each vertex, the part (of an assembly) of the faces that use it
    vertex_part: Vec<usize>,
    /// for each face, its part
    face_part: Vec<usize>,
    /// for each vertex, how far it reaches: the join tolerance, capped at [`EDGE_SHARE`] of
    /// the shortest edge at it in any face that uses it
    reach: Vec<f64>,
    pub(super) edges: Vec<PlanEdge>,
    pub(super) faces: Vec<PlanFace>,
    /// the shells: sets of faces connected through shared edges (faces in order), each with
    /// whether every edge of it is used twice, once each way
    pub(super) shells: Vec<(Vec<usize>, bool)>,
}

impl ShellPlan {
    /// The plan of `faces`, joined within `join` (model units; 0: every face on its own), faces
    /// only with faces of their own part (`parts`, one per face; empty: one part) — two parts
    /// of an assembly that touch are two solids, not one.
    pub(super) fn new(
        faces: &[Face<'_>],
        join: f64,
        parts: &[usize],
    ) -> Result<Self, nurbs_core::Error> {
        let mut plan = Self {
            face_part: (0..faces.len())
                .map(|k| parts.get(k).copied().unwrap_or(0))
                .collect(),
            ..Self::default()
        };
        for (k, f) in faces.iter().enumerate() {
            plan.add_face(k, f, join)?;
        }
        if join > 0.0 {
            plan.split_at_vertices(join);
            plan.share_edges(join);
        }
        plan.orient();
        Ok(plan)
    }

    /// The vertex at local vertex `p` of face `face`, reaching `reach`: the nearest earlier
    /// one within both reaches that `face` does not use yet, else a new one (each distinct
    /// vertex of a face its own).
    fn vertex(&mut self, face: usize, p: Point3, reach: f64) -> usize {
        let part = self.face_part[face];
        let near = (0..self.vertices.len())
            .filter(|&k| self.vertex_part[k] == part && !self.vertex_faces[k].contains(&face))
            .map(|k| (k, (self.vertices[k] - p).norm()))
            .filter(|&(k, d)| reach > 0.0 && d <= reach.min(self.reach[k]))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match near {
            Some((k, _)) => {
                self.vertex_faces[k].push(face);
                self.reach[k] = self.reach[k].min(reach);
                k
            }
            None => {
                self.vertices.push(p);
                self.vertex_faces.push(vec![face]);
                self.vertex_part.push(part);
                self.reach.push(reach);
                self.vertices.len() - 1
            }
        }
    }

    fn add_edge(
        &mut self,
        face: usize,
        points: Vec<Point3>,
        exact: Option<BSplineCurve>,
        ends: (usize, usize),
    ) -> usize {
        self.edges.push(PlanEdge {
            points,
            exact,
            start: ends.0,
            end: ends.1,
            face,
            uses: 0,
        });
        self.edges.len() - 1
    }

    /// Adds face `k`: its trim loops' vertices and edges, or its parameter box's.
    fn add_face(&mut self, k: usize, f: &Face<'_>, join: f64) -> Result<(), nurbs_core::Error> {
        let boxed = crate::seam::trim_is_box(f.surface, f.trim);
        let b = face_bounds(f.surface, if boxed { &[] } else { f.trim });
        if b.loops.is_empty() {
            let lp = self.box_loop(k, f.surface, join)?;
            self.faces.push(PlanFace {
                loops: vec![lp],
                flipped: false,
            });
            return Ok(());
        }
        let mut shortest = vec![f64::INFINITY; b.vertices.len()];
        for e in &b.edges {
            let len = length(&e.points);
            for v in [e.start, e.end] {
                shortest[v] = shortest[v].min(len);
            }
        }
        let ids: Vec<usize> = b
            .vertices
            .iter()
            .zip(&shortest)
            .map(|(p, &l)| self.vertex(k, *p, join.min(EDGE_SHARE * l)))
            .collect();
        let first = self.edges.len();
        for e in &b.edges {
            let mut points = e.points.clone();
            let last = points.len() - 1;
            (points[0], points[last]) = (self.vertices[ids[e.start]], self.vertices[ids[e.end]]);
            self.add_edge(k, points, None, (ids[e.start], ids[e.end]));
        }
        let loops = b
            .loops
            .iter()
            .map(|l| BoundLoop {
                outer: l.outer,
                edges: l.edges.iter().map(|&(e, fw)| (first + e, fw)).collect(),
            })
            .collect();
        self.faces.push(PlanFace {
            loops,
            flipped: false,
        });
        Ok(())
    }

    /// The outer loop of `s`'s parameter box (face `k`): u0 (v increasing), v1 (u increasing),
    /// u1 (v decreasing), v0 (u decreasing), each side its exact boundary curve; a side collapsed
    /// to a point has no edge, and a side that is its opposite side (a seam) is that side's edge
    /// used the other way — written as two separate edges along one curve, the loop of a sphere
    /// enclosed nothing and read back with zero area.
    fn box_loop(
        &mut self,
        k: usize,
        s: &BSplineSurface,
        join: f64,
    ) -> Result<BoundLoop, nurbs_core::Error> {
        let (u0, u1) = s.domain_u();
        let (v0, v1) = s.domain_v();
        let corners = [
            s.point(u0, v0),
            s.point(u0, v1),
            s.point(u1, v1),
            s.point(u1, v0),
        ];
        let sides = [
            (Direction::U, u0, 0, 1, true),
            (Direction::V, v1, 1, 2, true),
            (Direction::U, u1, 3, 2, false),
            (Direction::V, v0, 0, 3, false),
        ];
        let tol = crate::bounds::ON_FACE_RELATIVE * s.size().max(f64::MIN_POSITIVE);
        let curves: Vec<BSplineCurve> = sides
            .iter()
            .map(|&(dir, t, ..)| s.isocurve(dir, t))
            .collect::<Result<_, _>>()?;
        let samples: Vec<Vec<Point3>> = curves.iter().map(|c| sampled(c, tol)).collect();
        // a corner's reach from the sides at it that are not collapsed
        let mut shortest = [f64::INFINITY; 4];
        for (&(_, _, a, b, _), pts) in sides.iter().zip(&samples) {
            let len = length(pts);
            if len > DISTANCE_ACCURACY {
                shortest[a] = shortest[a].min(len);
                shortest[b] = shortest[b].min(len);
            }
        }
        // corners within the distance accuracy are one vertex of the face (a pole, a closed
        // side's two ends)
        let mut ids: Vec<usize> = Vec::with_capacity(4);
        for (n, p) in corners.iter().enumerate() {
            let same = (0..n).find(|&j| (corners[j] - p).norm() <= DISTANCE_ACCURACY);
            let id = match same {
                Some(j) => ids[j],
                None => self.vertex(k, *p, join.min(EDGE_SHARE * shortest[n])),
            };
            ids.push(id);
        }
        let mut written: Vec<(BSplineCurve, Option<usize>)> = Vec::with_capacity(4);
        let mut edges = Vec::new();
        for (n, ((_, _, a, b, forward), (c, pts))) in sides
            .into_iter()
            .zip(curves.into_iter().zip(samples))
            .enumerate()
        {
            let collapsed = c
                .control_points()
                .iter()
                .all(|p| (p - corners[a]).norm() <= DISTANCE_ACCURACY);
            let seam = n.checked_sub(2).and_then(|o| {
                written[o]
                    .1
                    .filter(|_| super::writer::same_curve(&written[o].0, &c))
            });
            let e = match (collapsed, seam) {
                (true, _) => None,
                (false, Some(e)) => Some(e),
                (false, None) => {
                    let mut points = pts;
                    let last = points.len() - 1;
                    (points[0], points[last]) = (self.vertices[ids[a]], self.vertices[ids[b]]);
                    Some(self.add_edge(k, points, Some(c.clone()), (ids[a], ids[b])))
                }
            };
            if let Some(e) = e {
                edges.push((e, forward));
            }
            written.push((c, e));
        }
        Ok(BoundLoop { outer: true, edges })
    }

    /// Splits every edge at the vertices of other faces that lie within their reach of its
    /// interior, [`SPLIT_PIECE`] reaches or more from its ends.
    fn split_at_vertices(&mut self, join: f64) {
        let mut e = 0;
        while e < self.edges.len() {
            let edge = &self.edges[e];
            let (lo, hi) = bounding_box(&edge.points, join);
            let (first, last) = (edge.points[0], edge.points[edge.points.len() - 1]);
            let hit = (0..self.vertices.len()).find_map(|v| {
                let p = self.vertices[v];
                if v == edge.start
                    || v == edge.end
                    || self.vertex_part[v] != self.face_part[edge.face]
                    || self.vertex_faces[v].contains(&edge.face)
                    || (0..3).any(|i| p[i] < lo[i] || p[i] > hi[i])
                {
                    return None;
                }
                let reach = self.reach[v];
                let (at, d) = foot_on_polyline(&p, &edge.points);
                let interior = (p - first).norm() > SPLIT_PIECE * reach
                    && (p - last).norm() > SPLIT_PIECE * reach;
                (d <= reach && interior).then_some((v, at))
            });
            match hit {
                Some((v, at)) => self.split(e, v, at),
                None => e += 1,
            }
        }
    }

    /// Splits edge `e` at vertex `v`, whose foot lies on segment `at.0` at fraction `at.1`:
    /// `e` keeps the part up to `v`, a new edge the rest, and every loop that uses `e` uses both.
    fn split(&mut self, e: usize, v: usize, at: (usize, f64)) {
        let p = self.vertices[v];
        let edge = self.edges[e].clone();
        let mut head: Vec<Point3> = edge.points[..=at.0].to_vec();
        head.push(p);
        let mut tail = vec![p];
        tail.extend_from_slice(&edge.points[at.0 + 1..]);
        // a foot at a point of the polyline: that point once
        let same = |a: &Point3, b: &Point3| (a - b).norm() <= DISTANCE_ACCURACY;
        if head.len() > 2 && same(&head[head.len() - 2], &p) {
            head.remove(head.len() - 2);
        }
        if tail.len() > 2 && same(&tail[1], &p) {
            tail.remove(1);
        }
        // the exact curve split at the parameter nearest the vertex; where that is one of its
        // ends (a closed curve whose end the vertex is near) the two parts keep their points
        let exact = edge.exact.as_ref().and_then(|c| {
            let t = closest_parameter(c, &p);
            let (t0, t1) = c.domain();
            let margin = 1e-9 * (t1 - t0);
            (t > t0 + margin && t < t1 - margin)
                .then(|| Some((c.extract(t0, t).ok()?, c.extract(t, t1).ok()?)))
                .flatten()
        });
        let (exact_head, exact_tail) = exact.map_or((None, None), |(a, b)| (Some(a), Some(b)));
        let face = edge.face;
        self.vertex_faces[v].push(face);
        self.edges[e].points = head;
        self.edges[e].exact = exact_head;
        self.edges[e].end = v;
        let new = self.add_edge(face, tail, exact_tail, (v, edge.end));
        for f in &mut self.faces {
            for l in &mut f.loops {
                let mut edges = Vec::with_capacity(l.edges.len() + 1);
                for &(x, fw) in &l.edges {
                    match (x == e, fw) {
                        (false, _) => edges.push((x, fw)),
                        (true, true) => edges.extend([(e, true), (new, true)]),
                        (true, false) => edges.extend([(new, false), (e, false)]),
                    }
                }
                l.edges = edges;
            }
        }
    }

    /// Makes edges of different faces that are one edge (module docs, step 3) one.
    fn share_edges(&mut self, join: f64) {
        self.count_uses();
        for b in 0..self.edges.len() {
            let a = (0..b).find(|&a| {
                let (ea, eb) = (&self.edges[a], &self.edges[b]);
                ea.face != eb.face
                    && ea.uses == 1
                    && eb.uses == 1
                    && ((ea.start, ea.end) == (eb.start, eb.end)
                        || (ea.start, ea.end) == (eb.end, eb.start))
                    && {
                        let tol = join.min(self.reach[ea.start]).min(self.reach[ea.end]);
                        close(&ea.points, &eb.points, tol) && close(&eb.points, &ea.points, tol)
                    }
            });
            let Some(a) = a else { continue };
            let same = same_direction(&self.edges[a], &self.edges[b]);
            // the exact curve where one of the two has it
            if self.edges[a].exact.is_none() && self.edges[b].exact.is_some() {
                let (exact, mut points) =
                    (self.edges[b].exact.clone(), self.edges[b].points.clone());
                if !same {
                    points.reverse();
                }
                self.edges[a].exact = exact
                    .map(|c| if same { Ok(c) } else { c.reversed() })
                    .and_then(Result::ok);
                self.edges[a].points = points;
            }
            for f in &mut self.faces {
                for l in &mut f.loops {
                    for x in &mut l.edges {
                        if x.0 == b {
                            *x = (a, if same { x.1 } else { !x.1 });
                        }
                    }
                }
            }
            self.edges[a].uses += 1;
            self.edges[b].uses = 0;
        }
    }

    fn count_uses(&mut self) {
        for e in &mut self.edges {
            e.uses = 0;
        }
        for f in &self.faces {
            for l in &f.loops {
                for &(e, _) in &l.edges {
                    self.edges[e].uses += 1;
                }
            }
        }
    }

    /// Orients each connected set of faces (module docs, step 4): the shells, each closed or
    /// not.
    fn orient(&mut self) {
        self.count_uses();
        // per edge, its uses: (face, sense)
        let mut uses: Vec<Vec<(usize, bool)>> = vec![Vec::new(); self.edges.len()];
        for (k, f) in self.faces.iter().enumerate() {
            for l in &f.loops {
                for &(e, fw) in &l.edges {
                    uses[e].push((k, fw));
                }
            }
        }
        let mut flip: Vec<Option<bool>> = vec![None; self.faces.len()];
        let mut shells = Vec::new();
        for root in 0..self.faces.len() {
            if flip[root].is_some() {
                continue;
            }
            flip[root] = Some(false);
            let (mut members, mut consistent) = (vec![root], true);
            let mut stack = vec![root];
            while let Some(f) = stack.pop() {
                let mine = flip[f].unwrap_or(false);
                for u in uses.iter().filter(|u| u.len() == 2 && u[0].0 != u[1].0) {
                    let (me, other) = if u[0].0 == f {
                        (u[0], u[1])
                    } else if u[1].0 == f {
                        (u[1], u[0])
                    } else {
                        continue;
                    };
                    // used once each way: sense ^ flip differs between the two faces
                    let want = mine ^ me.1 ^ other.1 ^ true;
                    match flip[other.0] {
                        None => {
                            flip[other.0] = Some(want);
                            members.push(other.0);
                            stack.push(other.0);
                        }
                        Some(x) if x != want => consistent = false,
                        Some(_) => {}
                    }
                }
            }
            members.sort_unstable();
            let closed = consistent
                && members.iter().all(|&f| {
                    self.faces[f]
                        .loops
                        .iter()
                        .flat_map(|l| &l.edges)
                        .all(|&(e, _)| uses[e].len() == 2)
                });
            shells.push((members, closed));
        }
        for (f, x) in self.faces.iter_mut().zip(flip) {
            f.flipped = x.unwrap_or(false);
        }
        self.shells = shells;
    }
}

/// Whether edges `a` and `b`, one edge between the same vertices, run the same way: from the
/// same start vertex, or for a closed edge (one vertex at both ends) towards the same side.
fn same_direction(a: &PlanEdge, b: &PlanEdge) -> bool {
    if a.start != a.end {
        return a.start == b.start;
    }
    let probe = a.points[a.points.len() / 4];
    let (ahead, behind) = (
        distance_to_polyline(&probe, &b.points[..=b.points.len() / 2]),
        distance_to_polyline(&probe, &b.points[b.points.len() / 2..]),
    );
    ahead <= behind
}

/// Points of `c` from its start to its end: [`SAMPLES_PER_CONTROL_POINT`] per control point,
/// each interval halved while it leaves its chord by more than `tol`.
fn sampled(c: &BSplineCurve, tol: f64) -> Vec<Point3> {
    let n = SAMPLES_PER_CONTROL_POINT * c.control_points().len() + 1;
    crate::edge_fit::sample_within(c, n, tol, crate::bounds::MAX_HALVINGS)
}

/// The parameter of `c` nearest `p` (nurbs-core's projection).
fn closest_parameter(c: &BSplineCurve, p: &Point3) -> f64 {
    nurbs_core::project_to_curve(c, p, &nurbs_core::ProjectionParams::default()).t
}

/// The length of the polyline `pts`.
fn length(pts: &[Point3]) -> f64 {
    pts.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}

/// The axis-aligned box of `pts`, grown by `margin`.
fn bounding_box(pts: &[Point3], margin: f64) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in pts {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i] - margin);
            hi[i] = hi[i].max(p[i] + margin);
        }
    }
    (lo, hi)
}

/// Whether [`MATCH_SAMPLES`] points spread along `a` (ends excluded) lie within `join` of the
/// polyline `b`.
fn close(a: &[Point3], b: &[Point3], join: f64) -> bool {
    let n = a.len();
    (1..=MATCH_SAMPLES).all(|k| {
        let i = (k * (n - 1)) / (MATCH_SAMPLES + 1);
        distance_to_polyline(&a[i], b) <= join
    })
}
