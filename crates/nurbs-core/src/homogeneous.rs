//! Conversions between Euclidean control points with weights and homogeneous points
//! P^w = (w·x, w·y, w·z, w) (\[NB\] §4.2), on which the knot algorithms work.

use crate::Point3;

/// Joins points and optional weights into homogeneous points.
pub fn join(points: &[Point3], weights: Option<&[f64]>) -> Vec<[f64; 4]> {
    points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let w = weights.map_or(1.0, |w| w[i]);
            [w * p.x, w * p.y, w * p.z, w]
        })
        .collect()
}

/// Splits homogeneous points; weights are `None` when all are exactly 1.
pub fn split(pw: &[[f64; 4]]) -> (Vec<Point3>, Option<Vec<f64>>) {
    split_as(pw, pw.iter().any(|q| q[3] != 1.0))
}

/// Splits homogeneous points into a rational or polynomial result. Algorithms run on polynomial
/// geometry keep w = 1 only up to rounding, so they say which one they produce: polynomial
/// results take (x, y, z) as the point and drop w.
pub fn split_as(pw: &[[f64; 4]], rational: bool) -> (Vec<Point3>, Option<Vec<f64>>) {
    if rational {
        let points = pw
            .iter()
            .map(|q| Point3::new(q[0] / q[3], q[1] / q[3], q[2] / q[3]))
            .collect();
        (points, Some(pw.iter().map(|q| q[3]).collect()))
    } else {
        (
            pw.iter().map(|q| Point3::new(q[0], q[1], q[2])).collect(),
            None,
        )
    }
}

/// Diagonal of the axis-aligned bounding box of points (0 for an empty set).
pub fn bounding_diagonal(points: &[Point3]) -> f64 {
    let Some(first) = points.first() else {
        return 0.0;
    };
    let (mut lo, mut hi) = (*first, *first);
    for p in points {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    (hi - lo).norm()
}

/// Euclidean distance of two homogeneous points in R⁴ (\[NB\] A5.8 uses it for the removal test).
pub(crate) fn distance4(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2) + (a[3] - b[3]).powi(2))
        .sqrt()
}

/// a·s + b·t for homogeneous points.
#[inline]
pub(crate) fn lerp4(a: &[f64; 4], s: f64, b: &[f64; 4], t: f64) -> [f64; 4] {
    [
        a[0] * s + b[0] * t,
        a[1] * s + b[1] * t,
        a[2] * s + b[2] * t,
        a[3] * s + b[3] * t,
    ]
}
