//! Trim loops of a face closed around a seam, made one boundary for IGES (\[IGES\] §4.34).
//!
//! A face on a surface closed in one direction (a cylinder, a cone, a band of a torus) between
//! two loops that each wind once around it — two circles — has two loops that are closed in
//! space but open in parameter space: each runs from one end of the closed direction to the
//! other and jumps back across the seam ([`crate::bounds::is_seam_jump`]). A reader that takes
//! the parameter-space curves (PREF 1) sees two open curves and no region between them (Open
//! CASCADE read such faces with area 0). As ISO 10303-42 closes such a face with its seam edge
//! used both ways, the face's boundary here is one loop in parameter space: the first loop, the
//! seam from its end to the second loop, the second loop run the other way, and the seam back —
//! turned so that the face lies on its left.

use nurbs_core::{BSplineSurface, Point3};

use crate::bounds::is_seam_jump;

/// Whether B-spline surface `s` is closed in u and in v: its two boundary curves across that
/// direction coincide (at 9 points each, within `relative` of its size — the reader's
/// on-surface tolerance).
pub(crate) fn spline_closed(s: &BSplineSurface, relative: f64) -> [bool; 2] {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let tol = relative * s.size();
    let at = |k: usize, a: f64, b: f64| a + (b - a) * k as f64 / 8.0;
    [
        (0..=8).all(|k| (s.point(u0, at(k, v0, v1)) - s.point(u1, at(k, v0, v1))).norm() <= tol),
        (0..=8).all(|k| (s.point(at(k, u0, u1), v0) - s.point(at(k, u0, u1), v1)).norm() <= tol),
    ]
}

/// Per side of B-spline surface `s` (u = u0, u = u1, v = v0, v = v1), the point it collapses
/// to, where it does: its 9 points (ends included) within `relative` of the size of the first.
pub(crate) fn collapsed_sides(s: &BSplineSurface, relative: f64) -> [Option<Point3>; 4] {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let tol = relative * s.size();
    let at = |k: usize, a: f64, b: f64| a + (b - a) * k as f64 / 8.0;
    let side = |point: &dyn Fn(usize) -> Point3| {
        let q = point(0);
        (1..=8).all(|k| (point(k) - q).norm() <= tol).then_some(q)
    };
    [
        side(&|k| s.point(u0, at(k, v0, v1))),
        side(&|k| s.point(u1, at(k, v0, v1))),
        side(&|k| s.point(at(k, u0, u1), v0)),
        side(&|k| s.point(at(k, u0, u1), v1)),
    ]
}

/// Whether a face's `trim` is its surface's parameter box: one loop whose every point lies on
/// the surface at the box's boundary (within 10⁻⁵ of the size, `BOX_POINT_RELATIVE`, of the
/// side's point at the same parameter along it), each two consecutive points on one side of
/// the box — a loop whose corners lie on the boundary but whose edges cut across the box (a
/// trapezoid on a plane's rectangle) has a step between two sides. The two sides of a closed
/// direction are one side (a seam point's projection may give either), and a point on a side
/// collapsed to a pole lies on its two neighbours too. Such a face is written bounded by its
/// box — the boundary curves themselves, a closed side as the one seam edge used both ways and
/// a pole as a vertex — rather than by its trim: a writer that bounds a closed face by curves
/// through its trim points leaves the reader to guess on which side of the seam each run along
/// it lies (Open CASCADE read half of an I-DEAS cylinder that way, its face invalid).
pub fn trim_is_box(surface: &BSplineSurface, trim: &[Vec<Point3>]) -> bool {
    let [points] = trim else {
        return false;
    };
    if points.len() < 3 {
        return false;
    }
    let ((a, b), (c, d)) = (surface.domain_u(), surface.domain_v());
    let size = surface.size();
    let near = BOX_POINT_RELATIVE * size;
    let closed = spline_closed(surface, BOX_POINT_RELATIVE);
    // sides u = a, u = b, v = c, v = d; whether each is collapsed to a point
    let collapsed = collapsed_sides(surface, BOX_POINT_RELATIVE).map(|q| q.is_some());
    let mut projector =
        nurbs_core::SurfaceProjector::new(surface, nurbs_core::ProjectionParams::default());
    let mut sides_of = |p: &Point3| -> Option<[bool; 4]> {
        let f = projector.project(p);
        if f.distance > near {
            return None;
        }
        // on a side: within `near` of the side's point at the foot's other parameter
        let mut on = [
            surface.point(a, f.v),
            surface.point(b, f.v),
            surface.point(f.u, c),
            surface.point(f.u, d),
        ]
        .map(|q| (q - p).norm() <= near);
        for (k, other) in [(0, 1), (2, 3)] {
            if closed[k / 2] && (on[k] || on[other]) {
                (on[k], on[other]) = (true, true);
            }
        }
        // a pole: on its neighbours too
        for (k, neighbours) in [(0, [2, 3]), (1, [2, 3]), (2, [0, 1]), (3, [0, 1])] {
            if on[k] && collapsed[k] {
                for n in neighbours {
                    on[n] = true;
                }
            }
        }
        on.iter().any(|&x| x).then_some(on)
    };
    let Some(sides) = points.iter().map(&mut sides_of).collect::<Option<Vec<_>>>() else {
        return false;
    };
    sides
        .iter()
        .zip(sides.iter().cycle().skip(1))
        .all(|(p, q)| (0..4).any(|k| p[k] && q[k]))
}

/// How near the surface, and its box's side, as a fraction of its size, a trim point lies on
/// that side ([`trim_is_box`]): 10⁻⁵, the usual accuracy of a CAD system's edges (10⁻³ mm on a
/// 100 mm part) — the edges of a file lie on their faces' surfaces only to it (EUCLID's run
/// 1.5·10⁻³ mm off a 520 mm surface's boundary), far below any face's own extent.
const BOX_POINT_RELATIVE: f64 = 1e-5;

/// The boundary that closes two winding loops through the seam: its parameters in order
/// (closed: the last the first) and the indices where its four pieces meet (first and last
/// included), and which two loops it replaces.
pub(crate) struct SeamBoundary {
    /// the parameters (u, v, 0), closed
    pub uv: Vec<Point3>,
    /// the ends of its pieces: the two loops and the two runs along the seam
    pub cuts: Vec<usize>,
    /// the loops it replaces
    pub loops: [usize; 2],
}

/// The seam boundary of `loops` (each a loop's parameters, closed: its last the first) on
/// `surface`, where exactly two of them wind once around the same closed direction (one jump
/// across the seam each); `None` otherwise.
pub(crate) fn close_winding_loops(
    surface: &BSplineSurface,
    loops: &[Vec<Point3>],
) -> Option<SeamBoundary> {
    let jump = |a: &Point3, b: &Point3| is_seam_jump(surface, (a.x, a.y), (b.x, b.y));
    let winding: Vec<(usize, usize)> = loops
        .iter()
        .enumerate()
        .filter_map(|(k, uv)| {
            let jumps: Vec<usize> = (0..uv.len() - 1)
                .filter(|&i| jump(&uv[i], &uv[i + 1]))
                .collect();
            (jumps.len() == 1).then(|| (k, jumps[0]))
        })
        .collect();
    let [(ka, ja), (kb, jb)] = winding[..] else {
        return None;
    };
    // the coordinate that jumps (0: u, 1: v), the same for both
    let axis = |uv: &[Point3], j: usize| {
        usize::from((uv[j + 1].x - uv[j].x).abs() < (uv[j + 1].y - uv[j].y).abs())
    };
    if axis(&loops[ka], ja) != axis(&loops[kb], jb) {
        return None;
    }
    let along = axis(&loops[ka], ja);
    let a = open_path(surface, &loops[ka], ja, along);
    let mut b = open_path(surface, &loops[kb], jb, along);
    // b starts on the side of the seam where a ends
    if (b[0] - a[a.len() - 1]).norm() > (b[b.len() - 1] - a[a.len() - 1]).norm() {
        b.reverse();
    }
    let mut uv = a.clone();
    let mut cuts = vec![0, uv.len() - 1];
    uv.extend(along_seam(surface, a[a.len() - 1], b[0]));
    cuts.push(uv.len());
    uv.extend(&b);
    cuts.push(uv.len() - 1);
    uv.extend(along_seam(surface, b[b.len() - 1], a[0]));
    uv.push(a[0]);
    cuts.push(uv.len() - 1);
    let area: f64 = uv
        .windows(2)
        .map(|w| w[0].x * w[1].y - w[1].x * w[0].y)
        .sum();
    if area < 0.0 {
        uv.reverse();
        let last = uv.len() - 1;
        cuts = cuts.iter().rev().map(|&c| last - c).collect();
    }
    Some(SeamBoundary {
        uv,
        cuts,
        loops: [ka, kb],
    })
}

/// The loop `uv` (closed) as an open path from the seam to the seam: from where its jump `j`
/// (uv[j] → uv[j + 1], across the seam in coordinate `axis`, 0: u, 1: v) crosses the seam, on
/// the seam's one side, through its points after the jump, to the same crossing on the other
/// side (the crossing where the segment, unwrapped by the period, meets the domain's end).
fn open_path(surface: &BSplineSurface, uv: &[Point3], j: usize, axis: usize) -> Vec<Point3> {
    let m = uv.len() - 1;
    let (lo, hi) = if axis == 0 {
        surface.domain_u()
    } else {
        surface.domain_v()
    };
    let coord = |p: &Point3| if axis == 0 { (p.x, p.y) } else { (p.y, p.x) };
    let point = |c: f64, o: f64| {
        if axis == 0 {
            Point3::new(c, o, 0.0)
        } else {
            Point3::new(o, c, 0.0)
        }
    };
    let ((cp, op), (cq, oq)) = (coord(&uv[j]), coord(&uv[j + 1]));
    // uv[j] runs to the end `to`; uv[j + 1] comes back in from the other end
    let (to, from, cq) = if cq < cp {
        (hi, lo, cq + (hi - lo))
    } else {
        (lo, hi, cq - (hi - lo))
    };
    let t = if cq != cp {
        ((to - cp) / (cq - cp)).clamp(0.0, 1.0)
    } else {
        0.5
    };
    let other = op + t * (oq - op);
    let mut out = vec![point(from, other)];
    out.extend((0..m).map(|i| uv[(j + 1 + i) % m]));
    out.push(point(to, other));
    out
}

/// Pieces a run along the seam is cut into before halving: each a quarter of the run, so that
/// none spans half the domain (a longer step would read as a jump and not be halved).
const SEAM_PIECES: usize = 4;

/// The parameters strictly between `a` and `b` along the seam (a straight run in parameter
/// space), as many as keep its image's chords on the surface
/// ([`crate::bounds::ON_FACE_RELATIVE`]).
fn along_seam(surface: &BSplineSurface, a: Point3, b: Point3) -> Vec<Point3> {
    let tol = crate::bounds::ON_FACE_RELATIVE * surface.size().max(f64::MIN_POSITIVE);
    let at = |k: usize| {
        let t = k as f64 / SEAM_PIECES as f64;
        (a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t)
    };
    let mut out = Vec::new();
    for k in 0..SEAM_PIECES {
        if k > 0 {
            out.push(at(k));
        }
        crate::bounds::halve_params(
            surface,
            at(k),
            at(k + 1),
            tol,
            crate::bounds::MAX_HALVINGS,
            &mut out,
        );
    }
    out.into_iter()
        .map(|(u, v)| Point3::new(u, v, 0.0))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The loop round a full cylinder's box — the circle at one end, the seam, the other
    /// circle, the seam back (as an importer keeps a closed face's bound) — is the box; a band
    /// of it between two circles inside is not, nor a plane rectangle's trapezoid whose
    /// corners are on the box but whose slanted side cuts across it, nor a loop with a hole.
    #[test]
    fn a_trim_round_the_parameter_box_is_the_box() {
        use nurbs_core::Vector3;
        let cylinder = nurbs_core::shapes::full_cylinder(4.0, 10.0).unwrap();
        let ((a, b), (c, d)) = (cylinder.domain_u(), cylinder.domain_v());
        let along = |u: f64, from: f64, to: f64, n: usize| -> Vec<Point3> {
            (0..n)
                .map(|k| cylinder.point(u, from + (to - from) * k as f64 / n as f64))
                .collect()
        };
        let across = |v: f64, from: f64, to: f64| -> Vec<Point3> {
            (0..4)
                .map(|k| cylinder.point(from + (to - from) * k as f64 / 4.0, v))
                .collect()
        };
        let mut round = along(a, c, d, 90);
        round.extend(across(d, a, b));
        round.extend(along(b, d, c, 90));
        round.extend(across(c, b, a));
        assert!(trim_is_box(&cylinder, &[round.clone()]));
        assert!(
            !trim_is_box(&cylinder, &[round.clone(), round.clone()]),
            "holes"
        );
        let (u1, u2) = (a + 0.2 * (b - a), a + 0.6 * (b - a));
        let mut band = along(u1, c, d, 90);
        band.extend(along(u2, d, c, 90));
        assert!(!trim_is_box(&cylinder, &[band]));
        let plane = nurbs_core::shapes::plane_patch(
            Point3::origin(),
            Vector3::x(),
            Vector3::y(),
            (0.0, 10.0),
            (0.0, 4.0),
        )
        .unwrap();
        let rectangle = [(0.0, 0.0), (10.0, 0.0), (10.0, 4.0), (0.0, 4.0)]
            .map(|(x, y)| Point3::new(x, y, 0.0))
            .to_vec();
        assert!(trim_is_box(&plane, &[rectangle]));
        let trapezoid = [(0.0, 0.0), (10.0, 0.0), (6.0, 4.0), (0.0, 4.0)]
            .map(|(x, y)| Point3::new(x, y, 0.0))
            .to_vec();
        assert!(!trim_is_box(&plane, &[trapezoid]));
    }

    /// A full cylinder of radius 4 (u along the axis, z = 10 u; v around) and a band of it
    /// between the circles z = 2 and z = 6, each a loop of 90 points: the two loops wind once
    /// around, and their seam boundary is one closed loop in parameter space without a jump,
    /// counterclockwise, enclosing the band's parameter rectangle 0.4 × (v1 − v0).
    #[test]
    fn two_circles_on_a_cylinder_close_through_the_seam() {
        let s = nurbs_core::shapes::full_cylinder(4.0, 10.0).unwrap();
        let circle = |z: f64| -> Vec<Point3> {
            (0..90)
                .map(|k| {
                    let a = std::f64::consts::TAU * (k as f64 + 0.5) / 90.0;
                    Point3::new(4.0 * a.cos(), 4.0 * a.sin(), z)
                })
                .collect()
        };
        let loops: Vec<Vec<Point3>> = [2.0, 6.0]
            .iter()
            .map(|&z| {
                let mut uv: Vec<Point3> = crate::bounds::loop_params(&s, &circle(z))
                    .into_iter()
                    .map(|(u, v)| Point3::new(u, v, 0.0))
                    .collect();
                uv.push(uv[0]);
                uv
            })
            .collect();
        let b = close_winding_loops(&s, &loops).expect("a seam boundary");
        assert_eq!(b.loops, [0, 1]);
        assert_eq!(b.cuts.len(), 5);
        assert_eq!((b.cuts[0], b.cuts[4]), (0, b.uv.len() - 1));
        assert_eq!(b.uv[0], b.uv[b.uv.len() - 1]);
        for w in b.uv.windows(2) {
            assert!(!is_seam_jump(&s, (w[0].x, w[0].y), (w[1].x, w[1].y)));
        }
        let area: f64 = 0.5
            * b.uv
                .windows(2)
                .map(|w| w[0].x * w[1].y - w[1].x * w[0].y)
                .sum::<f64>();
        let (v0, v1) = s.domain_v();
        let band = 0.4 * (v1 - v0);
        assert!(
            (area - band).abs() <= 1e-9 * band,
            "area {area} against {band}"
        );
        // one loop alone (a face bounded by one circle and a pole elsewhere) is left as it is
        assert!(close_winding_loops(&s, &loops[..1]).is_none());
    }
}
