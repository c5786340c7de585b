//! A trimmed or bounded surface's boundaries (142 curves on surface and 141 boundaries, \[IGES\]
//! §4.32–§4.34): the composite
//! (102) and simple model-space curves sampled, the parameter box of a B-spline face's outer
//! boundary, and the outer and inner boundaries as loops of points on the face's surface.

use nurbs_core::{BSplineCurve, BSplineSurface, Point3};

use super::entities::{Cursor, Reader};
use super::records::{DirEntry, entity_params};
use super::seam_box::{cut_to_box, seam_range};
use super::{
    BOUNDARY_SAG_RELATIVE, BOUNDARY_SAMPLES, FACE_BOX_SAMPLES, MAX_SAG_HALVINGS,
    MAX_TRANSFORM_CHAIN, ON_SURFACE_RELATIVE,
};
use crate::error::IgesError;

impl Reader<'_> {
    /// Points along a model-space boundary curve: a composite (102) of lines, arcs and
    /// B-splines, each sampled at [`BOUNDARY_SAMPLES`] points; every transformation from the
    /// member up to `e` applied, not the model scale.
    pub(super) fn boundary_points(
        &self,
        e: &DirEntry,
        depth: usize,
    ) -> Result<Vec<Point3>, IgesError> {
        self.boundary_samples(e, depth, BOUNDARY_SAMPLES)
    }

    /// [`Self::boundary_points`] with `samples` points per member.
    pub(super) fn boundary_samples(
        &self,
        e: &DirEntry,
        depth: usize,
        samples: usize,
    ) -> Result<Vec<Point3>, IgesError> {
        if depth > MAX_TRANSFORM_CHAIN {
            return Err(IgesError::Entity {
                de: e.seq,
                entity_type: e.entity_type,
                detail: "composite curves nest too deep (a cycle?)".into(),
            });
        }
        let local = match e.entity_type {
            102 => {
                let params = entity_params(e, &self.p, &self.global)?;
                let mut c = Cursor {
                    params: &params,
                    next: 1,
                    e,
                };
                let n = c.count("N (number of curves of the composite)", 0)?;
                let mut out = Vec::new();
                for _ in 0..n {
                    let member = self.entry(c.int()?, e)?;
                    out.extend(self.boundary_samples(member, depth + 1, samples)?);
                }
                // the members carry their own transformations; the composite's applies on top
                return Ok(match self.transform(e)? {
                    Some(a) => out.iter().map(|p| a.apply(p)).collect(),
                    None => out,
                });
            }
            // a boundary (141, [IGES] §4.33) used as a loop: its model-space curves in order,
            // each run backwards where its sense is 2; its own transformation is the caller's
            // to apply, as for the 142 it stands in for ([`Self::curve_on_surface`])
            141 => {
                let params = entity_params(e, &self.p, &self.global)?;
                let mut c = Cursor {
                    params: &params,
                    next: 1,
                    e,
                };
                let (_type, _pref, _surface) = (c.int()?, c.int()?, c.int()?);
                let n = c.count("N (number of curves of the boundary)", 0)?;
                let mut out = Vec::new();
                for _ in 0..n {
                    let member = self.entry(c.int()?, e)?;
                    let sense = c.int()?;
                    let k = c.count("K (parameter-space curves of a boundary curve)", 0)?;
                    for _ in 0..k {
                        c.int()?;
                    }
                    let mut pts = self.boundary_samples(member, depth + 1, samples)?;
                    if sense == 2 {
                        pts.reverse();
                    }
                    out.extend(pts);
                }
                return Ok(out);
            }
            // a loop of a B-rep face (508, [IGES] §4.149): its edges in order, each run
            // backwards where it is against its model-space curve
            508 => return self.loop_samples(e, depth, samples),
            _ => self.any_curve(e, 1.0)?,
        };
        Ok(sample_within_sag(&local, samples))
    }

    /// The pointers of a curve on a surface (142, \[IGES\] §4.32): to its parameter-space curve
    /// and to its model-space curve (0 where absent).
    /// A boundary (141) has no single curve of each kind: it is its own model-space curve
    /// (its curves in order, [`Self::boundary_samples`]) and has no parameter-space one here.
    /// A loop (508) is its own model-space curve too ([`Self::loop_samples`]).
    pub(super) fn curve_on_surface(&self, e: &DirEntry) -> Result<(i64, i64), IgesError> {
        if matches!(e.entity_type, 141 | 508) {
            return Ok((0, e.seq as i64));
        }
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let (_crtn, _surface) = (c.int()?, c.int()?);
        Ok((c.int()?, c.int()?))
    }

    /// `surface` cut to the parameter box of the outer boundary `boundary` (142) of the trimmed
    /// surface `face`: the box of its parameter-space curve, or where the 142 has none, of its
    /// model-space curve projected onto the surface; clamped to the surface's domain (`None`
    /// where the 142 has neither curve, or the box is the whole domain to [`BOX_RELATIVE`]). A
    /// kernel trims a face on its underlying surface, which may run far beyond it (a fillet past
    /// the faces it ends on); the face's box is the surface the face uses, as the kernel's own
    /// UV bounds give it. The curves are sampled densely ([`FACE_BOX_SAMPLES`]): a box short of
    /// the trim leaves the fillet that bounds the face off its master.
    pub(super) fn face_box(
        &self,
        surface: &BSplineSurface,
        boundary: &DirEntry,
        face: &DirEntry,
        scale: f64,
    ) -> Result<(Option<BSplineSurface>, Vec<Point3>), IgesError> {
        let (parametric, model) = self.curve_on_surface(boundary)?;
        if parametric == 0 && model == 0 {
            return Ok((None, Vec::new()));
        }
        // the boundary's points on the surface, in order (the face's trim as data)
        let mut trim: Vec<Point3> = Vec::new();
        let (du, dv) = (surface.domain_u(), surface.domain_v());
        // a parameter of a closed direction is a place on the surface whichever period it
        // names (a trim on a closed torus may run from −90° to 90°); elsewhere it is clamped
        let closed = crate::seam::spline_closed(surface, ON_SURFACE_RELATIVE);
        let onto = |x: f64, (a, b): (f64, f64), closed: bool| {
            if closed && !(a..=b).contains(&x) {
                a + (x - a).rem_euclid(b - a)
            } else {
                x.clamp(a, b)
            }
        };
        let mut b = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        if parametric != 0 {
            let curve = self.entry(parametric, boundary)?;
            for p in &self.boundary_samples(curve, 0, FACE_BOX_SAMPLES)? {
                b = [b[0].min(p.x), b[1].max(p.x), b[2].min(p.y), b[3].max(p.y)];
                if p.x.is_finite() && p.y.is_finite() {
                    let (u, v) = (onto(p.x, du, closed[0]), onto(p.y, dv, closed[1]));
                    trim.push(surface.point(u, v));
                }
            }
        }
        if parametric == 0 {
            for (u, v) in self.model_space_feet(surface, model, boundary, scale)? {
                b = [b[0].min(u), b[1].max(u), b[2].min(v), b[3].max(v)];
                trim.push(surface.point(u, v));
            }
        }
        if !b.iter().all(|x| x.is_finite()) {
            return Ok((None, trim));
        }
        let (ru, rv) = (
            seam_range((b[0], b[1]), du, closed[0]),
            seam_range((b[2], b[3]), dv, closed[1]),
        );
        if ru.is_empty() || rv.is_empty() {
            return Err(IgesError::Entity {
                de: face.seq,
                entity_type: face.entity_type,
                detail: format!(
                    "the outer boundary's parameter box [{}, {}] × [{}, {}] misses the surface's domain",
                    b[0], b[1], b[2], b[3]
                ),
            });
        }
        let cut = cut_to_box(surface, ru, rv).map_err(Self::geometry_err(face))?;
        Ok((cut, trim))
    }

    /// The feet on `surface` (parameters, in order) of the samples of the model-space curve
    /// `model` of the boundary (142) `boundary`: a point of the trim lies on the surface, so one
    /// that projects farther than the rounding of the file is no point of this face (a broken
    /// curve) and is left out. Consecutive samples are close: each starts from the last one's
    /// parameters, and from the sampled starts where that does not land on the surface.
    pub(super) fn model_space_feet(
        &self,
        surface: &BSplineSurface,
        model: i64,
        boundary: &DirEntry,
        scale: f64,
    ) -> Result<Vec<(f64, f64)>, IgesError> {
        let curve = self.entry(model, boundary)?;
        let mut pts = self.boundary_samples(curve, 0, FACE_BOX_SAMPLES)?;
        if let Some(a) = self.transform(boundary)? {
            pts = pts.iter().map(|p| a.apply(p)).collect();
        }
        let near = ON_SURFACE_RELATIVE * surface.size();
        let mut projector =
            nurbs_core::SurfaceProjector::new(surface, nurbs_core::ProjectionParams::default());
        let mut last: Option<(f64, f64)> = None;
        let mut feet = Vec::new();
        for p in &pts {
            let p = Point3::from(p.coords / scale);
            let mut pr = match last {
                Some(uv) => projector.project_from(&p, uv),
                None => projector.project(&p),
            };
            if pr.distance > near {
                pr = projector.project(&p);
            }
            if pr.distance <= near {
                feet.push((pr.u, pr.v));
                last = Some((pr.u, pr.v));
            } else {
                last = None;
            }
        }
        Ok(feet)
    }

    /// The outer boundary (142) `boundary` of a face on `surface` (an exact surface read over
    /// its own range: a revolution, a tabulated cylinder, a ruled surface) as points on it, from
    /// the boundary's model-space curve; empty where the boundary has none.
    pub(super) fn model_trim(
        &self,
        surface: &BSplineSurface,
        boundary: &DirEntry,
        scale: f64,
    ) -> Result<Vec<Point3>, IgesError> {
        let (_, model) = self.curve_on_surface(boundary)?;
        if model == 0 {
            return Ok(Vec::new());
        }
        Ok(self
            .model_space_feet(surface, model, boundary, scale)?
            .into_iter()
            .map(|(u, v)| surface.point(u, v))
            .collect())
    }

    /// The boundaries of a trimmed surface (144, \[IGES\] §4.34) after its surface pointer: N1
    /// (whether the outer boundary is the domain's), N2 (the number of inner boundaries), the
    /// outer boundary's 142 (`None` where PTO is 0) and the N2 inner boundaries' 142s.
    pub(super) fn face_boundaries<'r>(
        &'r self,
        c: &mut Cursor<'_>,
        e: &DirEntry,
    ) -> Result<(Option<&'r DirEntry>, Vec<&'r DirEntry>), IgesError> {
        let _n1 = c.int()?;
        let n2 = c.int()?;
        let outer = c.int()?;
        let outer = if outer == 0 {
            None
        } else {
            Some(self.entry(outer, e)?)
        };
        let mut inner = Vec::new();
        for _ in 0..n2.max(0) {
            inner.push(self.entry(c.int()?, e)?);
        }
        Ok((outer, inner))
    }

    /// The boundaries of a bounded surface (143, \[IGES\] §4.33) after its surface pointer: N and
    /// the N boundaries (141), the outer one and the inner ones. The standard names none the
    /// outer one, and writers differ (I-DEAS lists a plate's hole before its rim): the outer
    /// boundary holds the others, so its model-space box is the largest — the one with the
    /// longest diagonal is taken (the first of equals, the first where a box cannot be found).
    pub(super) fn bounded_boundaries<'r>(
        &'r self,
        c: &mut Cursor<'_>,
        e: &DirEntry,
    ) -> Result<(Option<&'r DirEntry>, Vec<&'r DirEntry>), IgesError> {
        let n = c.count("N (number of boundaries of the bounded surface)", 0)?;
        let mut all = Vec::with_capacity(n);
        for _ in 0..n {
            all.push(self.entry(c.int()?, e)?);
        }
        let diagonal = |b: &DirEntry| -> f64 {
            self.boundary_samples(b, 0, BOUNDARY_SAMPLES)
                .map(|pts| nurbs_core::homogeneous::bounding_diagonal(&pts))
                .ok()
                .filter(|d| d.is_finite())
                .unwrap_or(f64::NEG_INFINITY)
        };
        if all.len() > 1 {
            let sizes: Vec<f64> = all.iter().map(|b| diagonal(b)).collect();
            let outer =
                (1..all.len()).fold(0, |best, k| if sizes[k] > sizes[best] { k } else { best });
            let o = all.remove(outer);
            all.insert(0, o);
        }
        let mut all = all.into_iter();
        Ok((all.next(), all.collect()))
    }

    /// The loops of a face of a B-rep solid (510, \[IGES\] §4.150) after its surface pointer: N,
    /// OF (the first loop is the outer one; without it the face has no outer loop and is its
    /// surface's whole domain) and the N loops (508).
    pub(super) fn loop_boundaries<'r>(
        &'r self,
        c: &mut Cursor<'_>,
        e: &DirEntry,
    ) -> Result<(Option<&'r DirEntry>, Vec<&'r DirEntry>), IgesError> {
        let n = c.count("N (number of loops of the face)", 0)?;
        let outer_first = c.int()? == 1;
        let mut all = Vec::with_capacity(n);
        for _ in 0..n {
            all.push(self.entry(c.int()?, e)?);
        }
        let mut all = all.into_iter();
        let outer = if outer_first { all.next() } else { None };
        Ok((outer, all.collect()))
    }

    /// Points along a loop (508, \[IGES\] §4.149): per edge TYPE (0 an edge, 1 a vertex: a
    /// point, no curve), the edge list (504, §4.148) and the edge's index in it (from 1), OF
    /// (1: the edge runs along its model-space curve, 0: against it) and K parameter-space
    /// curves (ISOP, CURV pairs, not read: the model-space curve is the edge); each edge's
    /// curve sampled with `samples` points per member, as [`Self::boundary_samples`] does.
    fn loop_samples(
        &self,
        e: &DirEntry,
        depth: usize,
        samples: usize,
    ) -> Result<Vec<Point3>, IgesError> {
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let n = c.count("N (number of edges of the loop)", 0)?;
        let mut out = Vec::new();
        for _ in 0..n {
            let kind = c.int()?;
            let list = self.entry(c.int()?, e)?;
            let index = c.int()?;
            let along = c.int()? != 0;
            let k = c.count("K (parameter-space curves of a loop edge)", 0)?;
            for _ in 0..2 * k {
                c.int()?;
            }
            if kind != 0 {
                continue;
            }
            let mut pts = self.edge_points(list, index, e, (depth, samples))?;
            if !along {
                pts.reverse();
            }
            out.extend(pts);
        }
        Ok(out)
    }

    /// Points along edge `index` (from 1) of the edge list (504, \[IGES\] §4.148) `list`, named
    /// by the loop `from`: its entries are CURV, SVP, SV, TVP, TV — the model-space curve and
    /// the start and terminate vertices (502 lists and indices from 1). An edge is the part of
    /// its curve between its vertices, which a writer may put inside a longer curve (Inventor's
    /// spring: a helix edge on a curve past its end face): a line, arc or B-spline is cut at the
    /// vertices' feet on it, across its closing point where the curve is closed and the end
    /// comes before the start; an edge whose vertices are one point, and a composite curve,
    /// are taken whole. The points run in the curve's sense (the loop's flag OF says whether
    /// the loop runs that way).
    fn edge_points(
        &self,
        list: &DirEntry,
        index: i64,
        from: &DirEntry,
        (depth, samples): (usize, usize),
    ) -> Result<Vec<Point3>, IgesError> {
        let bad = |detail: String| IgesError::Entity {
            de: from.seq,
            entity_type: from.entity_type,
            detail,
        };
        if list.entity_type != 504 {
            return Err(bad(format!(
                "an edge of the loop names entity {} (D{}), not an edge list (504)",
                list.entity_type, list.seq
            )));
        }
        let params = entity_params(list, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e: list,
        };
        let n = c.count("N (number of edges of the edge list)", 0)?;
        if index < 1 || index as usize > n {
            return Err(bad(format!(
                "edge {index} of the edge list D{} that has {n}",
                list.seq
            )));
        }
        c.next += 5 * (index as usize - 1);
        let curve = self.entry(c.int()?, list)?;
        let start = self.vertex(c.int()?, c.int()?, list)?;
        let end = self.vertex(c.int()?, c.int()?, list)?;
        if !matches!(curve.entity_type, 100 | 110 | 126) {
            return self.boundary_samples(curve, depth + 1, samples);
        }
        let whole = self.any_curve(curve, 1.0)?;
        let size = whole
            .control_points()
            .iter()
            .fold(0.0f64, |m, p| m.max((p - whole.control_points()[0]).norm()));
        if (end - start).norm() <= ON_SURFACE_RELATIVE * size {
            return Ok(sample_within_sag(&whole, samples));
        }
        let feet = nurbs_core::ProjectionParams::default();
        let t0 = nurbs_core::projection::project_to_curve(&whole, &start, &feet).t;
        let t1 = nurbs_core::projection::project_to_curve(&whole, &end, &feet).t;
        let piece = |a: f64, b: f64| -> Result<Vec<Point3>, IgesError> {
            let part = whole.extract(a, b).map_err(Self::geometry_err(curve))?;
            Ok(sample_within_sag(&part, samples))
        };
        let (a, b) = whole.domain();
        let closed = (whole.point(a) - whole.point(b)).norm() <= ON_SURFACE_RELATIVE * size;
        Ok(if t0 < t1 {
            piece(t0, t1)?
        } else if closed {
            let mut out = if t0 < b { piece(t0, b)? } else { Vec::new() };
            if t1 > a {
                out.extend(piece(a, t1)?);
            }
            out
        } else {
            // an open curve whose start vertex lies after its end: the edge runs against it,
            // which the standard does not let an edge do; its points stay in the curve's sense
            // as every edge's do, and the loop's flag orients them
            piece(t1, t0)?
        })
    }

    /// Vertex `index` (from 1) of the vertex list (502, \[IGES\] §4.147) at `pointer`, named by
    /// the edge list `from`: its N, then X, Y, Z per vertex.
    fn vertex(&self, pointer: i64, index: i64, from: &DirEntry) -> Result<Point3, IgesError> {
        let list = self.entry(pointer, from)?;
        let params = entity_params(list, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e: list,
        };
        let n = c.count("N (number of vertices of the vertex list)", 0)?;
        if list.entity_type != 502 || index < 1 || index as usize > n {
            return Err(IgesError::Entity {
                de: from.seq,
                entity_type: from.entity_type,
                detail: format!(
                    "vertex {index} of D{} (entity {}, {n} vertices) is not a vertex",
                    list.seq, list.entity_type
                ),
            });
        }
        c.next += 3 * (index as usize - 1);
        let xyz = c.reals(3)?;
        Ok(Point3::new(xyz[0], xyz[1], xyz[2]))
    }

    /// The inner boundaries (142s) `inner` of a face on the B-spline surface `surface` as
    /// points on it in order, as [`Self::face_box`] takes the outer one: the parameter-space
    /// curve through the surface where the 142 has one, else the model-space curve's feet on
    /// the surface; sampled at [`FACE_BOX_SAMPLES`] points per member. A boundary with fewer
    /// than 3 points on the surface is left out.
    pub(super) fn spline_holes(
        &self,
        surface: &BSplineSurface,
        inner: &[&DirEntry],
        scale: f64,
    ) -> Result<Vec<Vec<Point3>>, IgesError> {
        let (du, dv) = (surface.domain_u(), surface.domain_v());
        let mut holes = Vec::new();
        for &boundary in inner {
            let (parametric, model) = self.curve_on_surface(boundary)?;
            let hole: Vec<Point3> = if parametric != 0 {
                let curve = self.entry(parametric, boundary)?;
                self.boundary_samples(curve, 0, FACE_BOX_SAMPLES)?
                    .iter()
                    .filter(|p| p.x.is_finite() && p.y.is_finite())
                    .map(|p| surface.point(p.x.clamp(du.0, du.1), p.y.clamp(dv.0, dv.1)))
                    .collect()
            } else if model != 0 {
                self.model_space_feet(surface, model, boundary, scale)?
                    .into_iter()
                    .map(|(u, v)| surface.point(u, v))
                    .collect()
            } else {
                Vec::new()
            };
            if hole.len() >= 3 {
                holes.push(hole);
            }
        }
        Ok(holes)
    }

    /// The inner boundaries (142s) `inner` of a face on a plane (108) as points in order: the
    /// samples of each model-space curve ([`FACE_BOX_SAMPLES`] per member, the 142's
    /// transformation and the model scale applied), which lie in the plane. A boundary without
    /// a model-space curve, or with fewer than 3 points, is left out: a 108 defines no
    /// parameter space its parameter-space curve could be mapped through.
    pub(super) fn plane_holes(
        &self,
        inner: &[&DirEntry],
        scale: f64,
    ) -> Result<Vec<Vec<Point3>>, IgesError> {
        let mut holes = Vec::new();
        for &boundary in inner {
            let (_, model) = self.curve_on_surface(boundary)?;
            if model == 0 {
                continue;
            }
            let curve = self.entry(model, boundary)?;
            let mut pts = self.boundary_samples(curve, 0, FACE_BOX_SAMPLES)?;
            if let Some(a) = self.transform(boundary)? {
                pts = pts.iter().map(|p| a.apply(p)).collect();
            }
            if pts.len() >= 3 {
                holes.push(pts.iter().map(|p| Point3::from(p.coords / scale)).collect());
            }
        }
        Ok(holes)
    }
}

/// Points of `curve` at `samples` uniform parameters (both ends included), each interval halved
/// until its middle and quarter points lie within [`BOUNDARY_SAG_RELATIVE`] × the curve's size
/// of its chord, at most [`MAX_SAG_HALVINGS`] times ([`crate::edge_fit::sample_within`]): a fixed
/// count cut a circle of radius 25 on a plane's boundary into 16 chords, 0.48 mm inside the
/// circle.
fn sample_within_sag(curve: &BSplineCurve, samples: usize) -> Vec<Point3> {
    let pts = curve.control_points();
    let (lo, hi) = pts.iter().fold(
        (
            Point3::from([f64::INFINITY; 3]),
            Point3::from([f64::NEG_INFINITY; 3]),
        ),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    );
    let tol = BOUNDARY_SAG_RELATIVE * (hi - lo).norm();
    crate::edge_fit::sample_within(curve, samples, tol, MAX_SAG_HALVINGS)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A full circle of radius 25 (a plane's round boundary) from 17 first samples: every chord
    /// within the sag tolerance of the circle (the fixed 17 left 0.48 mm), the ends exact, and
    /// no more points than the sag needs: a chord of angle θ sags 25 (1 − cos θ/2), so about
    /// 2π / √(8 tol / 25) chords, rounded up to a power of two per first interval.
    #[test]
    fn a_circle_is_sampled_within_its_sag() {
        let r = 25.0;
        let c = nurbs_core::shapes::circle(r).unwrap();
        let pts = sample_within_sag(&c, BOUNDARY_SAMPLES);
        let (t0, t1) = c.knots().domain();
        assert_eq!(pts[0], c.point(t0));
        assert_eq!(pts[pts.len() - 1], c.point(t1));
        // the control square of the rational circle: side 2r, the size its diagonal
        let tol = BOUNDARY_SAG_RELATIVE * (2.0 * r) * 2f64.sqrt();
        let mut worst: f64 = 0.0;
        for w in pts.windows(2) {
            let mid = nurbs_core::Point3::from((w[0].coords + w[1].coords) * 0.5);
            let sag = r - (mid - nurbs_core::Point3::origin()).norm();
            worst = worst.max(sag);
        }
        assert!(worst <= tol, "sag {worst} beyond {tol}");
        let needed = std::f64::consts::TAU / (8.0 * tol / r).sqrt();
        let chords = (pts.len() - 1) as f64;
        assert!(
            chords >= needed && chords <= 4.0 * needed,
            "{chords} chords, {needed} needed"
        );
    }
}
