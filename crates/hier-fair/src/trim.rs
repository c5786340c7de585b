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

use nurbs_core::Point3;

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

#[cfg(test)]
mod tests {
    use super::*;

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
