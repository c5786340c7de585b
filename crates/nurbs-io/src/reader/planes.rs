//! Planes (108) bounded by their faces: the smallest rectangle in the plane that holds the
//! outer boundary of the trimmed surface (144) over it, grown to hold the boundaries of other
//! surfaces that lie in it (\[IGES\] §4.12).

use nurbs_core::Point3;

use super::entities::{Cursor, Reader};
use super::records::{DirEntry, entity_params};
use super::{IN_PLANE_RELATIVE, IgesSurface};
use crate::error::IgesError;

impl Reader<'_> {
    /// A plane (108) under a trimmed surface (144) whose outer boundary (142, its model-space
    /// curve) bounds it (\[IGES\] §4.12, §4.32): the bilinear 2 × 2 patch over the smallest
    /// rectangle in the plane that holds the boundary, its sides along one of the boundary's
    /// chords (the minimum-area rectangle of a polygon has a side along one of its edges: exact
    /// for a face bounded by lines, tight for one bounded by arcs), u and v by length.
    pub(super) fn bounded_plane(
        &self,
        plane: &DirEntry,
        boundary: &DirEntry,
        face: &DirEntry,
        scale: f64,
    ) -> Result<IgesSurface, IgesError> {
        let err = |detail: &str| face_err(face, detail.into());
        let (origin, n) = self.plane_frame(plane, face)?;
        let pts = self.plane_outer_points(boundary, face)?;
        // a frame in the plane: any unit x ⟂ n, then y = n × x
        let helper = if n.x.abs() < 0.9 {
            nurbs_core::Vector3::x()
        } else {
            nurbs_core::Vector3::y()
        };
        let e1 = n.cross(&helper).normalize();
        let e2 = n.cross(&e1);
        let flat: Vec<(f64, f64)> = pts
            .iter()
            .map(|p| {
                let d = p - origin;
                (d.dot(&e1), d.dot(&e2))
            })
            .collect();
        let Some((angle, b)) = smallest_rectangle(&flat) else {
            return Err(err("the plane's boundary is a single point"));
        };
        let (x, y) = (
            e1 * angle.cos() + e2 * angle.sin(),
            -e1 * angle.sin() + e2 * angle.cos(),
        );
        let corner = origin + x * b[0] + y * b[2];
        let (lu, lv) = ((b[1] - b[0]) / scale, (b[3] - b[2]) / scale);
        let surface = nurbs_core::shapes::plane_patch(
            Point3::from(corner.coords / scale),
            x,
            y,
            (0.0, lu),
            (0.0, lv),
        )
        .map_err(Self::geometry_err(face))?;
        Ok(IgesSurface {
            de: plane.seq,
            name: Self::name(plane),
            surface,
            trimmed: true,
            param_range: [0.0, lu, 0.0, lv],
            underlying: None,
            trim: pts.iter().map(|p| Point3::from(p.coords / scale)).collect(),
            holes: Vec::new(),
        })
    }

    /// The plane 108 `plane` as a point on it and its unit normal, its transformation applied
    /// (errors name the trimmed surface `face`).
    fn plane_frame(
        &self,
        plane: &DirEntry,
        face: &DirEntry,
    ) -> Result<(Point3, nurbs_core::Vector3), IgesError> {
        if plane.entity_type == 190 {
            return self.plane_surface_frame(plane, face);
        }
        let params = entity_params(plane, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e: plane,
        };
        let abcd = c.reals(4)?;
        let mut n = nurbs_core::Vector3::new(abcd[0], abcd[1], abcd[2]);
        let len = n.norm();
        if !(len > 0.0) {
            return Err(face_err(
                face,
                "the plane's normal (A, B, C) is zero".into(),
            ));
        }
        n /= len;
        let mut origin = Point3::from(n * (abcd[3] / len));
        if let Some(a) = self.transform(plane)? {
            let tip = a.apply(&(origin + n));
            origin = a.apply(&origin);
            n = (tip - origin)
                .try_normalize(0.0)
                .ok_or_else(|| face_err(face, "the plane's transformation is singular".into()))?;
        }
        Ok((origin, n))
    }

    /// The plane surface (entity 190 of \[IGES\]) `plane` as a point on it and its unit normal:
    /// its point (116) and normal direction (123), each with its own transformation, then the
    /// plane's (errors name the face `face`). The reference direction of form 1 is not needed:
    /// the plane is framed by its boundary ([`Self::bounded_plane`]).
    fn plane_surface_frame(
        &self,
        plane: &DirEntry,
        face: &DirEntry,
    ) -> Result<(Point3, nurbs_core::Vector3), IgesError> {
        let params = entity_params(plane, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e: plane,
        };
        let (at, normal) = (self.entry(c.int()?, plane)?, self.entry(c.int()?, plane)?);
        let read = |e: &DirEntry, kind: i64| -> Result<Point3, IgesError> {
            if e.entity_type != kind {
                return Err(face_err(
                    face,
                    format!(
                        "the plane surface D{} names entity {} (D{}) where a {kind} belongs",
                        plane.seq, e.entity_type, e.seq
                    ),
                ));
            }
            let params = entity_params(e, &self.p, &self.global)?;
            let xyz = Cursor {
                params: &params,
                next: 1,
                e,
            }
            .reals(3)?;
            Ok(Point3::new(xyz[0], xyz[1], xyz[2]))
        };
        let mut origin = read(at, 116)?;
        if let Some(a) = self.transform(at)? {
            origin = a.apply(&origin);
        }
        let mut tip = origin + read(normal, 123)?.coords;
        if let Some(a) = self.transform(normal)? {
            // a direction moves by the map's linear part: the image of the tip less the origin's
            tip = origin + (a.apply(&Point3::from(tip - origin)) - a.apply(&Point3::origin()));
        }
        if let Some(a) = self.transform(plane)? {
            tip = a.apply(&tip);
            origin = a.apply(&origin);
        }
        let n = (tip - origin)
            .try_normalize(0.0)
            .ok_or_else(|| face_err(face, "the plane surface's normal is zero".into()))?;
        Ok((origin, n))
    }

    /// The samples of the model-space curve of the plane's outer boundary (142) `boundary`,
    /// its transformation applied, not the model scale: at least 3 points.
    fn plane_outer_points(
        &self,
        boundary: &DirEntry,
        face: &DirEntry,
    ) -> Result<Vec<Point3>, IgesError> {
        let (_, model_curve) = self.curve_on_surface(boundary)?;
        if model_curve == 0 {
            return Err(face_err(
                face,
                "the plane's boundary has no model-space curve".into(),
            ));
        }
        let curve = self.entry(model_curve, boundary)?;
        let mut pts = self.boundary_points(curve, 0)?;
        if let Some(a) = self.transform(boundary)? {
            pts = pts.iter().map(|p| a.apply(p)).collect();
        }
        if pts.len() < 3 {
            return Err(face_err(
                face,
                "the plane's boundary has fewer than 3 points".into(),
            ));
        }
        Ok(pts)
    }
}

/// An error of the trimmed surface `face`.
fn face_err(face: &DirEntry, detail: String) -> IgesError {
    IgesError::Entity {
        de: face.seq,
        entity_type: face.entity_type,
        detail,
    }
}

/// The smallest rectangle that holds the points `flat` with a side along one of their chords:
/// its angle and its bounds [a0, a1, c0, c1] along that direction and across it; `None` where
/// the points are all one.
fn smallest_rectangle(flat: &[(f64, f64)]) -> Option<(f64, [f64; 4])> {
    let mut best: Option<(f64, f64, [f64; 4])> = None;
    for w in flat.windows(2) {
        let (dx, dy) = (w[1].0 - w[0].0, w[1].1 - w[0].1);
        let l = dx.hypot(dy);
        if !(l > 0.0) {
            continue;
        }
        let (cx, cy) = (dx / l, dy / l);
        let mut b = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for &(x, y) in flat {
            let (a, c) = (x * cx + y * cy, -x * cy + y * cx);
            b = [b[0].min(a), b[1].max(a), b[2].min(c), b[3].max(c)];
        }
        let area = (b[1] - b[0]) * (b[3] - b[2]);
        if best.is_none_or(|(ar, _, _)| area < ar) {
            best = Some((area, cy.atan2(cx), b));
        }
    }
    best.map(|(_, angle, b)| (angle, b))
}

/// Grows each plane read from a 108 (by directory number in `planes`) to hold every boundary of
/// another surface that lies in it and reaches its rectangle: a kernel's surfaces run past the
/// face they bound (a fillet beyond the plane's corner, into the vertex blend), and a side that
/// lies on the plane must project onto it. A boundary lies in the plane when its whole control
/// row does (convex hull) within [`IN_PLANE_RELATIVE`] of the model size.
pub(super) fn grow_planes(surfaces: &mut [IgesSurface], planes: &[usize]) {
    let size = surfaces
        .iter()
        .map(|s| s.surface.size())
        .fold(0.0, f64::max);
    let tol = IN_PLANE_RELATIVE * size;
    for k in 0..surfaces.len() {
        if !planes.contains(&surfaces[k].de) {
            continue;
        }
        let s = &surfaces[k].surface;
        let cp = s.control_points();
        let (o, px, py) = (cp[0], cp[2], cp[1]);
        let (lx, ly) = ((px - o).norm(), (py - o).norm());
        let (x, y) = ((px - o) / lx, (py - o) / ly);
        let n = x.cross(&y);
        let mut b = [0.0, lx, 0.0, ly];
        let inside = |p: &Point3, b: &[f64; 4]| {
            let d = p - o;
            let (a, c) = (d.dot(&x), d.dot(&y));
            a >= b[0] - tol && a <= b[1] + tol && c >= b[2] - tol && c <= b[3] + tol
        };
        let mut grown = b;
        for (j, other) in surfaces.iter().enumerate() {
            if j == k {
                continue;
            }
            let g = &other.surface;
            for side in [
                nurbs_core::Side::U0,
                nurbs_core::Side::U1,
                nurbs_core::Side::V0,
                nurbs_core::Side::V1,
            ] {
                let row: Vec<Point3> = side
                    .row(0, g.num_u(), g.num_v())
                    .into_iter()
                    .map(|(i, j)| g.control_point(i, j))
                    .collect();
                let flat = row.iter().all(|p| n.dot(&(p - o)).abs() <= tol);
                if !flat || !row.iter().any(|p| inside(p, &b)) {
                    continue;
                }
                for p in &row {
                    let d = p - o;
                    let (a, c) = (d.dot(&x), d.dot(&y));
                    grown = [
                        grown[0].min(a),
                        grown[1].max(a),
                        grown[2].min(c),
                        grown[3].max(c),
                    ];
                }
            }
        }
        if grown == b {
            continue;
        }
        b = grown;
        let (lu, lv) = (b[1] - b[0], b[3] - b[2]);
        let corner = o + x * b[0] + y * b[2];
        if let Ok(plane) = nurbs_core::shapes::plane_patch(corner, x, y, (0.0, lu), (0.0, lv)) {
            surfaces[k].surface = plane;
            surfaces[k].param_range = [0.0, lu, 0.0, lv];
        }
    }
}
