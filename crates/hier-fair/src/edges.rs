//! Shared edges no link covers: a side of one surface that lies, over part of its length or all
//! of it, on another surface tangentially, where the model gives no link for it — within one
//! part of an assembly (two parts that touch are two shells and share no edge).
//!
//! A kernel exports such edges wherever a face is trimmed: a fillet trimmed by its vertex blend
//! runs, as an untrimmed surface, past the face it meets, so its side lies on that face only up
//! to the trim, and no link (which needs the whole side on the master, model-format.md) is
//! written; two halves of a fillet ring share their ends. Fairing with its boundary row alone
//! fixed moved the row next to it and opened the tangent join (a fillet's tangent row moved
//! 0.26 mm off its plane), and the trimmed fillet kept its curvature 1/R on the face while its
//! neighbour was G2 (flat) there, so the vertex blend between them met two masters that disagree
//! at its corner.
//!
//! - A side of a connecting or corner surface that lies on a surface higher in the hierarchy
//!   becomes a G2 link over the part that lies on it ([`link_edges`]; g-continuity's
//!   `SideLink::range`): the fillet is set G2 on its face up to the trim, as along the rest of
//!   its contact line (\[SV\] §3.2 — the slave follows its master), and the vertex blend after it
//!   meets masters of one curvature at its corner.
//! - Every other such edge — a primary's trimmed side on a fillet, two surfaces of one role —
//!   is kept as it came (\[SV\] §3.1: the fairing keeps the continuity it is not asked to set):
//!   both surfaces keep their tangential frame where the edge is, the surface whose side it is
//!   along that whole side (in the fairing masks and in the continuity steps), the other one at
//!   the control points that carry the edge ([`carrying_points`]).
//! - A seam — an edge between two surfaces of one role, as the two halves of a fillet ring — is
//!   kept by the fairing stages but left free to the continuity steps (`is_seam`): each half
//!   is set to the same masters the same way, so the two settings agree along the seam, and a
//!   kept seam column would hold each half's cross-section at its input curvature where it meets
//!   its masters. Each half's linked boundaries have their end tangents at the seam turned into
//!   their masters' tangent planes after the C0 steps (g-continuity's
//!   `SetParams::seam_end_tangents`): fitted by positions only, the two halves' boundaries tilt
//!   their corner normals by their slope errors in opposite senses, and the seam opens by the
//!   sum. A seam the free steps still open beyond its tolerance has its surfaces run again one
//!   after the other, each later one with its seams to the earlier ones linked G2
//!   (`framework/seams.rs`, ring by ring), or, where that leaves a seam open too, the whole ring
//!   with its seams kept.
//!
//! The fairing report measures every such edge before and after; the output model's links are
//! the input's.
//!
//! # Tolerance
//! - A sample of the side lies on the other surface when it projects within the model's G0
//!   tolerance (the gap at which a link counts as met) and the normals there are within
//!   [`TANGENT_EDGE_DEG`] (a sharp edge keeps its boundary row, which fairing
//!   never moves on an unlinked side, so its gap cannot open and only tangent edges need more).
//! - The side lies on it when [`MIN_RUN`] consecutive of its [`SIDE_SAMPLES`]
//!   samples do.

use nurbs_core::{BSplineSurface, ProjectionParams, Side, SurfaceDerivatives, SurfaceProjector};

use crate::model::Model;
use crate::topology::{JOIN_SAMPLES, SIDE_SAMPLES, TANGENT_EDGE_DEG, net_box, other_part};

/// Consecutive samples (of [`SIDE_SAMPLES`], an eighth of the side apart for
/// three) that must lie on the other surface: one is a shared vertex, two can be a tangent
/// neighbour that leaves the side within the tolerance just past that vertex (the gap grows with
/// the square of the distance from it), three mean the side runs along the other surface over an
/// eighth of its length.
pub const MIN_RUN: usize = 3;

/// A side of `surface` that lies tangentially on `other` over the samples `ts`.
#[derive(Debug, Clone, PartialEq)]
pub struct SharedEdge {
    /// the surface whose side it is
    pub surface: usize,
    /// its side
    pub side: Side,
    /// the surface it lies on
    pub other: usize,
    /// the along-side parameters of the samples on `other`, increasing (one contiguous run)
    pub ts: Vec<f64>,
    /// the share of the side's parameter range the run covers
    pub fraction: f64,
}

/// Gap and normal angle along a shared edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeMeasure {
    /// largest gap over the edge's samples
    pub gap: f64,
    /// largest normal angle (degrees) over the samples where both normals are defined
    pub angle_deg: f64,
}

impl EdgeMeasure {
    /// Whether this measure leaves the edge worse than `before`: a gap or angle larger by more
    /// than `g0` or `g1_deg` (the model's tolerances: a change below them is none a link could
    /// see).
    pub fn worse_than(&self, before: &EdgeMeasure, g0: f64, g1_deg: f64) -> bool {
        self.gap > before.gap + g0 || self.angle_deg > before.angle_deg + g1_deg
    }
}

/// Before/after of one shared edge.
#[derive(Debug, Clone, PartialEq)]
pub struct EdgeFair {
    /// the surface whose side it is
    pub surface: String,
    /// "surface.side ~ other", or the found link's label
    pub label: String,
    /// the share of the side the edge covers
    pub fraction: f64,
    /// measured on the input
    pub before: EdgeMeasure,
    /// measured on the result
    pub after: EdgeMeasure,
    /// whether it leaves with a larger gap or angle than it came in with (beyond the model's
    /// G0 / G1 tolerances)
    pub worse: bool,
}

impl EdgeFair {
    /// An edge's record; `worse` when the result's gap or angle exceed the input's by more than
    /// `g0` or `g1_deg` (the model's tolerances: a change below them is none a link could see).
    pub fn new(
        surface: String,
        label: String,
        fraction: f64,
        (before, after): (EdgeMeasure, EdgeMeasure),
        (g0, g1_deg): (f64, f64),
    ) -> Self {
        let worse = after.worse_than(&before, g0, g1_deg);
        Self {
            surface,
            label,
            fraction,
            before,
            after,
            worse,
        }
    }
}

/// Normal angle in degrees, orientation ignored (the two surfaces' parametrisations need not
/// agree on it), `None` where a normal is undefined (a pole).
fn angle_deg(a: Option<nurbs_core::Vector3>, b: Option<nurbs_core::Vector3>) -> Option<f64> {
    let (a, b) = (a?, b?);
    Some(a.dot(&b).abs().clamp(0.0, 1.0).acos().to_degrees())
}

/// Every shared edge of `model` no link covers (see the module docs): sides of a surface that are
/// no linked side of it, on a surface that is not its slave (a slave follows its master anyway).
pub fn shared_edges(model: &Model) -> Vec<SharedEdge> {
    let tol = model.tolerances.g0;
    let n = model.surfaces.len();
    let boxes: Vec<_> = model
        .surfaces
        .iter()
        .map(|s| net_box(&s.surface, tol))
        .collect();
    let mut projectors: Vec<Option<SurfaceProjector>> = (0..n).map(|_| None).collect();
    let mut out = Vec::new();
    for k in 0..n {
        for side in Side::ALL {
            let Some(samples) = SideSamples::unlinked(model, k, side) else {
                continue;
            };
            for (m, other) in model.surfaces.iter().enumerate() {
                // two parts of an assembly that merely touch share no edge: each is its own
                // shell (no link joins them either, [`crate::build`])
                if m == k
                    || model.links.iter().any(|l| l.slave == m && l.master == k)
                    || other_part(model, k, m)
                {
                    continue;
                }
                let on = samples.on(&other.surface, boxes[m], &mut projectors[m], tol);
                if let Some(edge) = samples.edge(m, &on) {
                    out.push(edge);
                }
            }
        }
    }
    out
}

/// An unlinked side of one surface, sampled for [`shared_edges`].
struct SideSamples {
    /// the surface's index
    surface: usize,
    /// its side
    side: Side,
    /// the side's along-side parameter domain
    domain: (f64, f64),
    /// the along-side parameters of the samples
    ts: Vec<f64>,
    /// the surface's derivatives at them
    samples: Vec<SurfaceDerivatives>,
}

impl SideSamples {
    /// The [`SIDE_SAMPLES`] samples of `side` of surface `k` of `model`; `None`
    /// when the side is collapsed, linked, or cannot be sampled.
    fn unlinked(model: &Model, k: usize, side: Side) -> Option<Self> {
        let s = &model.surfaces[k].surface;
        if g_continuity::measure::is_collapsed(s, side)
            || model.links.iter().any(|l| l.slave == k && l.side == side)
        {
            return None;
        }
        let ts = g_continuity::sampling::uniform_side_params(s, side, SIDE_SAMPLES).ok()?;
        let samples = ts
            .iter()
            .map(|&t| {
                let (u, v) = side.params(s, t);
                s.derivatives(u, v)
            })
            .collect();
        Some(Self {
            surface: k,
            side,
            domain: side.along_domain(s),
            ts,
            samples,
        })
    }

    /// Which samples lie on `other` (within `tol` and [`TANGENT_EDGE_DEG`]); none when fewer
    /// than [`MIN_RUN`] lie in its control net's box `(lo, hi)`. `projector` is `other`'s,
    /// made on first use.
    fn on<'o>(
        &self,
        other: &'o BSplineSurface,
        (lo, hi): ([f64; 3], [f64; 3]),
        projector: &mut Option<SurfaceProjector<'o>>,
        tol: f64,
    ) -> Vec<bool> {
        let inside = |p: &nurbs_core::Point3| (0..3).all(|c| p[c] >= lo[c] && p[c] <= hi[c]);
        if self.samples.iter().filter(|d| inside(&d.point)).count() < MIN_RUN {
            return Vec::new();
        }
        let projector = projector
            .get_or_insert_with(|| SurfaceProjector::new(other, ProjectionParams::default()));
        self.samples
            .iter()
            .map(|d| {
                if !inside(&d.point) {
                    return false;
                }
                let f = projector.project(&d.point);
                f.distance <= tol
                    && angle_deg(d.normal(), other.derivatives(f.u, f.v).normal())
                        .is_some_and(|a| a <= TANGENT_EDGE_DEG)
            })
            .collect()
    }

    /// The shared edge on surface `other` over the longest run of samples `on` it, if that run
    /// holds at least [`MIN_RUN`] samples.
    fn edge(&self, other: usize, on: &[bool]) -> Option<SharedEdge> {
        let (first, end) = longest_run(on);
        if end - first < MIN_RUN {
            return None;
        }
        let (a, b) = self.domain;
        let run = self.ts[first..end].to_vec();
        let fraction = (run[run.len() - 1] - run[0]) / (b - a);
        Some(SharedEdge {
            surface: self.surface,
            side: self.side,
            other,
            ts: run,
            fraction,
        })
    }
}

/// The longest run of consecutive `true`s in `on`, as the index range `(first, end)` (the first
/// of equally long runs; `(0, 0)` when there is none).
fn longest_run(on: &[bool]) -> (usize, usize) {
    let (mut best, mut start) = ((0, 0), None);
    for (i, &yes) in on.iter().chain(std::iter::once(&false)).enumerate() {
        match (yes, start) {
            (true, None) => start = Some(i),
            (false, Some(a)) => {
                if i - a > best.1 - best.0 {
                    best = (a, i);
                }
                start = None;
            }
            _ => {}
        }
    }
    best
}

/// The edges of `edges` that `model` (the model with its found links, [`link_edges`]) does not
/// link: the side is no linked side, and the other surface is no slave of it — what
/// [`shared_edges`] finds on that model, without searching again.
pub fn not_linked(edges: Vec<SharedEdge>, model: &Model) -> Vec<SharedEdge> {
    edges
        .into_iter()
        .filter(|e| {
            !model.links.iter().any(|l| {
                (l.slave == e.surface && l.side == e.side)
                    || (l.slave == e.other && l.master == e.surface)
            })
        })
        .collect()
}

/// Gap and normal angle of `edge` between `surface` and `other` (as they are now), over the
/// edge's samples.
pub fn measure_edge(
    edge: &SharedEdge,
    surface: &BSplineSurface,
    other: &BSplineSurface,
) -> EdgeMeasure {
    let mut projector = SurfaceProjector::new(other, ProjectionParams::default());
    let mut m = EdgeMeasure {
        gap: 0.0,
        angle_deg: 0.0,
    };
    for &t in &edge.ts {
        let (u, v) = edge.side.params(surface, t);
        let d = surface.derivatives(u, v);
        let f = projector.project(&d.point);
        m.gap = m.gap.max(f.distance);
        if let Some(a) = angle_deg(d.normal(), other.derivatives(f.u, f.v).normal()) {
            m.angle_deg = m.angle_deg.max(a);
        }
    }
    m
}

/// Control points of `me` (surface `k` as its stages have it) that carry the shared edges lying on
/// it: at every one of [`JOIN_SAMPLES`] + 1 points along each edge's run, the
/// rows 0 and 1 of the boundary the foot point lies on within the basis support there, or the
/// full (p + 1) × (q + 1) support where it lies inside `me`. Kept, they leave `me`'s position and
/// tangent plane along the edge exactly as they were.
pub fn carrying_points(
    edges: &[SharedEdge],
    k: usize,
    me: &BSplineSurface,
    model: &Model,
) -> Vec<(usize, usize)> {
    let mut out: Vec<(usize, usize)> = Vec::new();
    let (p, q) = (me.degree_u(), me.degree_v());
    let (nu, nv) = (me.num_u(), me.num_v());
    let ((u0, u1), (v0, v1)) = (me.knots_u().domain(), me.knots_v().domain());
    // a foot point on a boundary: within 1e-9 of the domain (rounding of the projection's clamp)
    let on = |x: f64, a: f64, b: f64| (x - a).abs() <= 1e-9 * (b - a).abs();
    let mut projector: Option<SurfaceProjector> = None;
    for e in edges.iter().filter(|e| e.other == k) {
        let s = &model.surfaces[e.surface].surface;
        let projector =
            projector.get_or_insert_with(|| SurfaceProjector::new(me, ProjectionParams::default()));
        let (a, b) = (e.ts[0], e.ts[e.ts.len() - 1]);
        let steps = JOIN_SAMPLES;
        for i in 0..=steps {
            let t = a + (b - a) * i as f64 / steps as f64;
            let (u, v) = e.side.params(s, t);
            let f = projector.project(&s.point(u, v));
            let (su, sv) = (me.knots_u().span(f.u), me.knots_v().span(f.v));
            let us: Vec<usize> = (su - p..=su).collect();
            let vs: Vec<usize> = (sv - q..=sv).collect();
            let mut push = |i: usize, j: usize| {
                if !out.contains(&(i, j)) {
                    out.push((i, j));
                }
            };
            let rows = |n: usize, start: bool| -> Vec<usize> {
                if start {
                    vec![0, 1.min(n - 1)]
                } else {
                    vec![n - 1, n.saturating_sub(2)]
                }
            };
            // on a boundary: its rows 0 and 1 within the support along it
            let mut boundary = false;
            for (hit, rows, along_u) in [
                (on(f.u, u0, u1), rows(nu, true), false),
                (on(f.u, u1, u0), rows(nu, false), false),
                (on(f.v, v0, v1), rows(nv, true), true),
                (on(f.v, v1, v0), rows(nv, false), true),
            ] {
                if hit {
                    boundary = true;
                    for &r in &rows {
                        if along_u {
                            us.iter().for_each(|&i| push(i, r));
                        } else {
                            vs.iter().for_each(|&j| push(r, j));
                        }
                    }
                }
            }
            if !boundary {
                us.iter().for_each(|&i| vs.iter().for_each(|&j| push(i, j)));
            }
        }
    }
    out
}

/// The part of a side a link holds on: an along-side parameter interval, `None` for all of it.
pub type Range = Option<(f64, f64)>;

/// A link found for a shared edge ([`link_edges`]).
#[derive(Debug, Clone, PartialEq)]
pub struct FoundLink {
    /// index of the link in the augmented model
    pub link: usize,
    /// "slave.side -> master"
    pub label: String,
    /// the part of the side it holds on (along-side parameters; `None`: the whole side)
    pub range: Option<(f64, f64)>,
    /// the share of the side it covers
    pub fraction: f64,
}

/// Bisection steps that place the end of a partial edge between its last sample on the other
/// surface and the first one off it: 2⁻³⁰ of a sixteenth of the side, far below any tolerance.
pub(crate) const END_BISECTIONS: usize = 30;

/// Whether the point at `t` of `side` of `s` lies on `other` (within `tol`, normals within
/// [`TANGENT_EDGE_DEG`]).
fn lies_at(s: &BSplineSurface, side: Side, t: f64, other: &BSplineSurface, tol: f64) -> bool {
    let (u, v) = side.params(s, t);
    let d = s.derivatives(u, v);
    let f = nurbs_core::project_to_surface(other, &d.point, &ProjectionParams::default());
    f.distance <= tol
        && angle_deg(d.normal(), other.derivatives(f.u, f.v).normal())
            .is_some_and(|a| a <= TANGENT_EDGE_DEG)
}

/// The part of the side `e` lies on: its run of samples, each end moved out to where the side
/// leaves the other surface (bisection towards the neighbouring sample off it).
fn edge_range(model: &Model, e: &SharedEdge) -> (f64, f64) {
    let s = &model.surfaces[e.surface].surface;
    let other = &model.surfaces[e.other].surface;
    let tol = model.tolerances.g0;
    let (a, b) = e.side.along_domain(s);
    let step = (b - a) / (SIDE_SAMPLES - 1) as f64;
    let mut ends = [e.ts[0], e.ts[e.ts.len() - 1]];
    for (end, dir) in ends.iter_mut().zip([-1.0, 1.0]) {
        let (mut on, mut off) = (*end, (*end + dir * step).clamp(a, b));
        if on == off {
            continue;
        }
        for _ in 0..END_BISECTIONS {
            let mid = 0.5 * (on + off);
            if lies_at(s, e.side, mid, other, tol) {
                on = mid;
            } else {
                off = mid;
            }
        }
        *end = on;
    }
    (ends[0], ends[1])
}

/// `model` with links for its shared edges that go down the hierarchy, and the part of its side
/// each holds on (`None` for the model's own links). An edge becomes a link when its side belongs
/// to a connecting or corner surface and the other surface is higher in the hierarchy; the
/// target is G2 (the edge is tangent). Primaries keep their design intent (\[SV\] §1.1) and are no
/// slave here; two surfaces of one role are not ordered (linked, the later half of a fillet ring
/// had to meet the earlier one and its own masters at the same corners, and its curvature to
/// them ended 4× the input's). A link that would close a cycle of the hierarchy is not added.
/// Edges that become no link are kept as they came.
pub fn link_edges(model: &Model, edges: &[SharedEdge]) -> (Model, Vec<FoundLink>, Vec<Range>) {
    let mut work = model.clone();
    let mut ranges = vec![None; model.links.len()];
    let mut found = Vec::new();
    for e in edges {
        let whole = e.ts.len() >= SIDE_SAMPLES;
        let (me, other) = (&model.surfaces[e.surface], &model.surfaces[e.other]);
        if me.role == crate::model::Role::Primary || other.role.rank() >= me.role.rank() {
            continue;
        }
        let linked = work.links.iter().any(|l| {
            (l.slave == e.surface && l.side == e.side)
                || (l.slave == e.other && l.master == e.surface)
        });
        if linked {
            continue;
        }
        work.links.push(crate::model::Link {
            slave: e.surface,
            side: e.side,
            master: e.other,
            continuity: nurbs_core::Continuity::G2,
        });
        if work.hierarchy_order().is_err() {
            work.links.pop();
            continue;
        }
        let range = (!whole).then(|| edge_range(model, e));
        let fraction = range.map_or(1.0, |(x, y)| {
            let (a, b) = e.side.along_domain(&me.surface);
            (y - x) / (b - a)
        });
        ranges.push(range);
        found.push(FoundLink {
            link: work.links.len() - 1,
            label: work.link_label(work.links.len() - 1),
            range,
            fraction,
        });
    }
    (work, found, ranges)
}

/// Whether `edge` is a seam: a shared edge between two surfaces of one role (the two halves of
/// a fillet ring a kernel splits). Neither is the other's master, so each is set to its own
/// masters in the same way; where those masters agree along the seam, the two settings agree
/// there too, and the continuity steps need not keep the seam's frame — kept, it holds each
/// half's seam column at its input cross-section, which cannot be G2 to the masters at the
/// seam's ends (\[SV\] §3.2: the corner of a G2 side needs its curvature free).
pub(crate) fn is_seam(model: &Model, edge: &SharedEdge) -> bool {
    model.surfaces[edge.surface].role == model.surfaces[edge.other].role
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::model::Role;
    use nurbs_core::{Point3, Vector3, shapes::plane_patch};

    /// Three unit squares side by side along x, each of `role`, sharing the edges x = 1 and
    /// x = 2 (tangentially: they are one plane).
    pub(crate) fn strip(role: Role) -> (Model, Vec<SharedEdge>) {
        let square = |x0: f64| {
            plane_patch(
                Point3::new(x0, 0.0, 0.0),
                Vector3::x(),
                Vector3::y(),
                (0.0, 1.0),
                (0.0, 1.0),
            )
            .unwrap()
        };
        let mut model = Model::from_primaries(vec![square(0.0), square(1.0), square(2.0)]);
        for s in &mut model.surfaces {
            s.role = role;
        }
        let ts: Vec<f64> = (0..=8).map(|i| f64::from(i) / 8.0).collect();
        let edge = |surface, side, other| SharedEdge {
            surface,
            side,
            other,
            ts: ts.clone(),
            fraction: 1.0,
        };
        let edges = vec![
            edge(0, Side::U1, 1),
            edge(1, Side::U0, 0),
            edge(1, Side::U1, 2),
            edge(2, Side::U0, 1),
        ];
        (model, edges)
    }

    /// `surface` with its control points on side u0 lifted by `dz`.
    pub(crate) fn lifted(surface: &BSplineSurface, dz: f64) -> BSplineSurface {
        let mut s = surface.clone();
        let nv = s.num_v();
        for p in &mut s.control_points_mut()[..nv] {
            p.z += dz;
        }
        s
    }

    #[test]
    fn two_parts_of_an_assembly_share_no_edge() {
        let (mut model, _) = strip(Role::Primary);
        let found = |m: &Model| {
            let mut pairs: Vec<(usize, usize)> = shared_edges(m)
                .iter()
                .map(|e| (e.surface, e.other))
                .collect();
            pairs.sort_unstable();
            pairs
        };
        assert_eq!(found(&model), vec![(0, 1), (1, 0), (1, 2), (2, 1)]);
        for s in &mut model.surfaces {
            s.part = Some("A".into());
        }
        assert_eq!(found(&model).len(), 4);
        model.surfaces[2].part = Some("B".into());
        assert_eq!(found(&model), vec![(0, 1), (1, 0)]);
    }

    #[test]
    fn a_seam_is_an_edge_between_two_surfaces_of_one_role() {
        let (mut model, edges) = strip(Role::Connecting);
        assert!(edges.iter().all(|e| is_seam(&model, e)));
        model.surfaces[1].role = Role::Corner;
        assert!(edges.iter().all(|e| !is_seam(&model, e)));
    }
}
