//! A trimmed face's boundary kept as data: loops of points on the surface, in order
//! ([`crate::model::ModelSurface::trim`]), thinned to what their accuracy needs.
//!
//! # Tolerance
//! [`TRIM_SHARE`]: a loop is thinned (Douglas–Peucker) to within this share of the model's G0
//! tolerance — the gap at which two boundaries count as the same line. The samples a reader takes
//! along a kernel's edges (257 per B-spline edge) are already that far from the true edge where
//! it bends (a 70 mm edge of radius 5 sampled at 0.27 mm: chord error 1.8e-3 mm), so a tighter
//! thinning would keep every sample without being truer to the edge; at the G0 tolerance a
//! lofted block's loops shrink from about 1,000 points to about 400.

use nurbs_core::{BSplineSurface, Point3, ProjectionParams, SurfaceProjector};

use crate::error::{Error, Result};

/// Share of the G0 tolerance a thinned trim loop may deviate from the points it came from (the
/// module docs say why the whole of it).
pub const TRIM_SHARE: f64 = 1.0;

/// `points` (a closed loop) thinned so that every dropped point lies within `tol` of the
/// polyline that is kept (Douglas–Peucker; the first point and the point farthest from it are
/// always kept, so a loop keeps at least three points when it had them and was not a line).
pub fn thin_loop(points: &[Point3], tol: f64) -> Vec<Point3> {
    let n = points.len();
    if n <= 3 {
        return points.to_vec();
    }
    let far = (1..n)
        .max_by(|&a, &b| {
            (points[a] - points[0])
                .norm_squared()
                .total_cmp(&(points[b] - points[0]).norm_squared())
        })
        .unwrap_or(n / 2);
    let mut keep = vec![false; n];
    keep[0] = true;
    keep[far] = true;
    // the two halves of the loop, the second closing back to the first point
    let mut stack = vec![(0, far), (far, n)];
    while let Some((a, b)) = stack.pop() {
        let (p, q) = (points[a], points[b % n]);
        let worst = (a + 1..b)
            .map(|k| (k, distance_to_segment(&points[k], &p, &q)))
            .max_by(|x, y| x.1.total_cmp(&y.1));
        if let Some((k, d)) = worst
            && d > tol
        {
            keep[k] = true;
            stack.push((a, k));
            stack.push((k, b));
        }
    }
    let mut out: Vec<Point3> = (0..n).filter(|&k| keep[k]).map(|k| points[k]).collect();
    if out.len() < 3 {
        // a loop that is a line to the tolerance keeps a third point to stay a loop
        out.insert(1, points[far / 2]);
    }
    out
}

/// Distance from `x` to the segment from `p` to `q`.
fn distance_to_segment(x: &Point3, p: &Point3, q: &Point3) -> f64 {
    let d = q - p;
    let len2 = d.norm_squared();
    if len2 == 0.0 {
        return (x - p).norm();
    }
    let t = ((x - p).dot(&d) / len2).clamp(0.0, 1.0);
    (x - (p + d * t)).norm()
}

/// Two trim points closer than this fraction of the surface size are one point: the rounding of
/// two projections of the same point (nurbs-io's export merges vertices at the same share).
const TRIM_SAME_POINT_RELATIVE: f64 = 1e-9;

/// A surface entry's `trim` loops as points: each loop at least three finite points, three of
/// them distinct, none farther from the box of the surface's control net than the surface's
/// size (a trim lies on its surface, which lies in that box; the margin leaves room for a
/// surface moved in fairing, and only a loop of another part or of other units is refused).
pub(crate) fn checked_loops(
    name: &str,
    loops: &[Vec<[f64; 3]>],
    surface: &BSplineSurface,
) -> Result<Vec<Vec<Point3>>> {
    let size = surface.size();
    let (lo, hi) = surface.control_points().iter().fold(
        ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
        |(mut lo, mut hi), p| {
            for c in 0..3 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
            (lo, hi)
        },
    );
    let outside = |p: &[f64; 3]| {
        (0..3)
            .map(|c| (lo[c] - p[c]).max(p[c] - hi[c]).max(0.0).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let bad = |k: usize, why: String| Error::Format {
        detail: format!("surface {name}: trim loop {k} {why}"),
    };
    loops
        .iter()
        .enumerate()
        .map(|(k, l)| {
            if l.len() < 3 || l.iter().flatten().any(|x| !x.is_finite()) {
                return Err(bad(
                    k,
                    format!(
                        "needs at least three finite points, got {} point(s)",
                        l.len()
                    ),
                ));
            }
            let points: Vec<Point3> = l.iter().map(|p| Point3::new(p[0], p[1], p[2])).collect();
            let mut distinct: Vec<Point3> = Vec::new();
            for p in &points {
                if distinct.len() < 3
                    && distinct
                        .iter()
                        .all(|q| (p - q).norm() > TRIM_SAME_POINT_RELATIVE * size)
                {
                    distinct.push(*p);
                }
            }
            if distinct.len() < 3 {
                return Err(bad(k, "has fewer than three distinct points".into()));
            }
            if let Some((j, d)) = l
                .iter()
                .map(outside)
                .enumerate()
                .find(|&(_, d)| d > size)
            {
                return Err(bad(
                    k,
                    format!(
                        "point {j} lies {d:.3e} outside the surface's control net box (size {size:.3e})"
                    ),
                ));
            }
            Ok(points)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square plate with a square hole: the mask holds the plate and not the hole (even–odd),
    /// at any resolution, and the cells' centres decide.
    #[test]
    fn a_mask_holds_the_face_and_not_its_hole() {
        let plane = nurbs_core::shapes::plane_patch(
            Point3::origin(),
            nurbs_core::Vector3::x(),
            nurbs_core::Vector3::y(),
            (0.0, 10.0),
            (0.0, 10.0),
        )
        .expect("plane");
        let square = |a: f64, b: f64| {
            vec![
                Point3::new(a, a, 0.0),
                Point3::new(b, a, 0.0),
                Point3::new(b, b, 0.0),
                Point3::new(a, b, 0.0),
            ]
        };
        let loops = [square(1.0, 9.0), square(4.0, 6.0)];
        for res in [10, 37, 200] {
            let m = ParameterMask::new(&plane, &loops, res).expect("mask");
            assert!(m.contains((0.2, 0.5)) && m.contains((0.5, 0.85)));
            assert!(!m.contains((0.5, 0.5)), "the hole, at {res}");
            assert!(!m.contains((0.05, 0.5)) && !m.contains((0.5, 0.95)));
            let inside = m.bits.iter().filter(|&&b| b).count() as f64 / (res * res) as f64;
            // 0.8² − 0.2² = 0.6 of the square, up to a row of cells at each edge
            assert!((inside - 0.6).abs() < 8.0 / res as f64, "{inside} at {res}");
        }
        assert_eq!(ParameterMask::new(&plane, &[], 10), None);
    }

    /// A circle of radius 5 sampled by 1024 points, thinned to 1e-4: every dropped point within
    /// the tolerance of the kept polyline, and the count near what the sagitta needs
    /// (chord c with c²/(8R) = tol: 2πR/c ≈ 50).
    #[test]
    fn a_densely_sampled_circle_keeps_what_its_curvature_needs() {
        let r = 5.0;
        let pts: Vec<Point3> = (0..1024)
            .map(|k| {
                let t = std::f64::consts::TAU * f64::from(k) / 1024.0;
                Point3::new(r * t.cos(), r * t.sin(), 0.0)
            })
            .collect();
        let tol = 1e-4;
        let thin = thin_loop(&pts, tol);
        let need = std::f64::consts::TAU * r / (8.0 * r * tol).sqrt();
        assert!(
            thin.len() as f64 >= 0.9 * need && (thin.len() as f64) <= 2.5 * need,
            "{} points, the sagitta needs {need:.0}",
            thin.len()
        );
        let closed: Vec<Point3> = thin.iter().chain(thin.first()).copied().collect();
        for p in &pts {
            let d = closed
                .windows(2)
                .map(|w| distance_to_segment(p, &w[0], &w[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= tol * (1.0 + 1e-9), "{d}");
        }
    }

    #[test]
    fn a_square_keeps_its_corners() {
        let mut pts = Vec::new();
        for (a, b) in [
            ((0.0, 0.0), (1.0, 0.0)),
            ((1.0, 0.0), (1.0, 1.0)),
            ((1.0, 1.0), (0.0, 1.0)),
            ((0.0, 1.0), (0.0, 0.0)),
        ] {
            for k in 0..10 {
                let t = f64::from(k) / 10.0;
                pts.push(Point3::new(
                    a.0 + (b.0 - a.0) * t,
                    a.1 + (b.1 - a.1) * t,
                    0.0,
                ));
            }
        }
        let thin = thin_loop(&pts, 1e-9);
        assert_eq!(thin.len(), 4, "{thin:?}");
    }
}

/// Two neighbouring points of a trim loop cross a seam when the surface point at the middle of
/// their parameters lies farther from the middle of their chord than this many chord lengths
/// (plus the projection tolerance): along the face, the parameter middle of a chord maps near
/// the chord — within half its length even for a half circle through two points — while across
/// a seam it maps to the far side of the surface. Such loops do not bound a region of the
/// parameter square, and the face is drawn untrimmed (its loops over it) rather than cut wrongly.
pub const SEAM_CHORDS: f64 = 1.0;

/// The region a face's trim loops bound in its unit parameter square, as a `res` × `res` bitmap
/// (u slowest): a cell is inside when its centre is, by the even–odd rule over all loops (outer
/// and holes alike), filled row by row from the loops' crossings of the row's centre line.
#[derive(Debug, Clone, PartialEq)]
pub struct ParameterMask {
    /// cells per direction
    pub res: usize,
    /// `res`² cells, u slowest
    pub bits: Vec<bool>,
}

impl ParameterMask {
    /// The mask of `surface`'s trim `loops`; `None` where they do not bound a region of the
    /// parameter square cleanly ([`parameter_loops`]) or there are none.
    pub fn new(surface: &BSplineSurface, loops: &[Vec<Point3>], res: usize) -> Option<Self> {
        if loops.is_empty() || res == 0 {
            return None;
        }
        let polys = parameter_loops(surface, loops)?;
        let mut bits = vec![false; res * res];
        let mut crossings = Vec::new();
        for i in 0..res {
            let x = (i as f64 + 0.5) / res as f64;
            crossings.clear();
            for poly in &polys {
                for (a, b) in poly.iter().zip(poly.iter().cycle().skip(1)) {
                    if (a.0 > x) != (b.0 > x) {
                        crossings.push(a.1 + (x - a.0) * (b.1 - a.1) / (b.0 - a.0));
                    }
                }
            }
            crossings.sort_by(f64::total_cmp);
            for pair in crossings.chunks_exact(2) {
                // the cells whose centre (j + ½)/res lies in [pair[0], pair[1])
                let from = (pair[0] * res as f64 - 0.5).ceil().max(0.0) as usize;
                let to = ((pair[1] * res as f64 - 0.5).ceil().max(0.0) as usize).min(res);
                for j in from..to {
                    bits[i * res + j] = true;
                }
            }
        }
        Some(Self { res, bits })
    }

    /// Whether the point at shares `(s, t)` of the domain lies inside.
    pub fn contains(&self, (s, t): (f64, f64)) -> bool {
        let cell = |x: f64| ((x * self.res as f64).floor().max(0.0) as usize).min(self.res - 1);
        self.bits[cell(s) * self.res + cell(t)]
    }
}

/// The cells of an `n` × `n` grid over `surface`'s domain ((n − 1)², u slowest) whose centre
/// lies inside the region `loops` bound ([`ParameterMask`] at the grid's resolution): what a
/// tessellation of the trimmed face draws. `None` as [`ParameterMask::new`].
pub fn cell_mask(surface: &BSplineSurface, loops: &[Vec<Point3>], n: usize) -> Option<Vec<bool>> {
    (n >= 2)
        .then(|| ParameterMask::new(surface, loops, n - 1))
        .flatten()
        .map(|m| m.bits)
}

/// The trim loops projected into the unit parameter square, `None` when a loop crosses a seam
/// ([`SEAM_CHORDS`]) or a point does not project.
pub fn parameter_loops(s: &BSplineSurface, loops: &[Vec<Point3>]) -> Option<Vec<Vec<(f64, f64)>>> {
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    let mut projector = SurfaceProjector::new(s, ProjectionParams::default());
    let tol = 1e-3 * s.size();
    let mut out = Vec::with_capacity(loops.len());
    for l in loops {
        let mut poly = Vec::with_capacity(l.len());
        for p in l {
            let f = projector.project(p);
            if !(f.distance <= tol) {
                return None;
            }
            poly.push(((f.u - u0) / (u1 - u0), (f.v - v0) / (v1 - v0)));
        }
        let at = |(a, b): (f64, f64)| s.point(u0 + a * (u1 - u0), v0 + b * (v1 - v0));
        let seam = (0..poly.len()).any(|k| {
            let (i, j) = (k, (k + 1) % poly.len());
            let mid = ((poly[i].0 + poly[j].0) / 2.0, (poly[i].1 + poly[j].1) / 2.0);
            let chord = (l[j] - l[i]).norm();
            let off =
                (at(mid) - nurbs_core::Point3::from((l[i].coords + l[j].coords) / 2.0)).norm();
            off > SEAM_CHORDS * chord + tol
        });
        if seam {
            return None;
        }
        out.push(poly);
    }
    Some(out)
}
