//! A face's trim edge written as a curve ([`fitted_edge`]): its two ends where it is straight,
//! else a cubic B-spline through its points within a tolerance, else the polyline through them
//! ([`polyline`]); and a curve sampled within a sag ([`sample_within`]), the boundary curves the
//! readers sample and the exact edges the STEP writer compares.

use nurbs_core::{BSplineCurve, KnotVector, Point3};

/// The degree-1 B-spline curve through `points` (at least two, distinct in a row), its knots the
/// chord lengths scaled to [0, 1].
pub fn polyline(points: &[Point3]) -> Result<BSplineCurve, nurbs_core::Error> {
    let mut t = vec![0.0];
    for w in points.windows(2) {
        t.push(t[t.len() - 1] + (w[1] - w[0]).norm());
    }
    let total = t[t.len() - 1];
    // a point whose chord-length parameter equals its predecessor's — repeated, or nearer to
    // it than the parameter resolves (a loop of an I-DEAS export's faces in parameter space:
    // 0.5861111111136063 twice after a jump across its seam) — would be a knot of multiplicity
    // 2, which a degree-1 curve cannot carry: it is dropped (the end point stays, in place of
    // its predecessor if that one coincides with it)
    let n = points.len();
    let mut kept: Vec<Point3> = Vec::with_capacity(n);
    let mut knots = vec![0.0];
    for (k, p) in points.iter().enumerate() {
        let x = if k + 1 == n { 1.0 } else { t[k] / total };
        match knots.last() {
            Some(&last) if !kept.is_empty() && x <= last => {
                if k + 1 == n {
                    kept.pop();
                    knots.pop();
                    kept.push(*p);
                    knots.push(1.0);
                }
            }
            _ => {
                kept.push(*p);
                knots.push(x);
            }
        }
    }
    knots.push(1.0);
    BSplineCurve::new(KnotVector::new(1, knots)?, kept, None)
}

/// Whether every point of `points` lies within `tolerance` of the chord between its ends.
fn straight(points: &[Point3], tolerance: f64) -> bool {
    let chord = [points[0], points[points.len() - 1]];
    points
        .iter()
        .all(|p| distance_to_polyline(p, &chord) <= tolerance)
}

/// A trim edge through `points` as compact as `tolerance` allows: a straight edge (every point
/// within `tolerance` of its chord) its two ends, else a cubic B-spline at
/// chord-length parameters, its end points the edge's (so that the edges meeting at a vertex
/// still meet), from one span, each span holding a point farther than `tolerance` from the curve
/// at its parameter halved and the curve fitted again — so that knots gather where the edge
/// turns fast (a kink between two faces' boundaries meeting at a few degrees, which no number
/// of uniform spans follows within a fraction of a micrometre short of one span per point) —
/// until every point lies within `tolerance`; the [`polyline`] where `tolerance` is 0, where
/// the edge has too few points, or where the fit would need more than half as many control
/// points as the polyline has (no gain).
pub fn fitted_edge(points: &[Point3], tolerance: f64) -> Result<BSplineCurve, nurbs_core::Error> {
    let n = points.len();
    if tolerance > 0.0 && n > 2 && straight(points, tolerance) {
        return polyline(&[points[0], points[n - 1]]);
    }
    fitted_cubic(points, tolerance)
}

/// [`fitted_edge`] of an edge that is not straight.
fn fitted_cubic(points: &[Point3], tolerance: f64) -> Result<BSplineCurve, nurbs_core::Error> {
    let n = points.len();
    if !(tolerance > 0.0) || n < 8 {
        return polyline(points);
    }
    let mut t = vec![0.0];
    for w in points.windows(2) {
        t.push(t[t.len() - 1] + (w[1] - w[0]).norm());
    }
    let total = t[n - 1];
    if !(total > 0.0) {
        return polyline(points);
    }
    let params: Vec<f64> = t.iter().map(|x| x / total).collect();
    // the distinct knots: one span to start with
    let mut breaks = vec![0.0, 1.0];
    loop {
        let count = breaks.len() + 2;
        if 2 * count > n {
            return polyline(points);
        }
        let mut knots = vec![0.0; 3];
        knots.extend(&breaks);
        knots.extend([1.0; 3]);
        let knots = KnotVector::new(3, knots)?;
        // the template's interior points are the data points nearest their Greville fractions;
        // they are free, only the two ends are kept
        let mut ends: Vec<Point3> = knots
            .greville()
            .iter()
            .map(|&g| points[params.partition_point(|&p| p < g).min(n - 1)])
            .collect();
        let mut free = vec![true; count];
        free[0] = false;
        free[count - 1] = false;
        ends[0] = points[0];
        ends[count - 1] = points[n - 1];
        let start = BSplineCurve::new(knots, ends, None)?;
        let fit = nurbs_core::fit::fit_curve(
            &start,
            &free,
            &params,
            points,
            &nurbs_core::fit::FitParams::default(),
        );
        // the spans to halve: those holding a point beyond the tolerance (every span where the
        // system had no solution)
        let mut halve = vec![fit.is_err(); breaks.len() - 1];
        if let Ok((curve, report)) = &fit {
            if report.max_error <= tolerance {
                return Ok(curve.clone());
            }
            for (x, p) in params.iter().zip(points) {
                if (curve.point(*x) - p).norm() > tolerance {
                    let span = breaks
                        .partition_point(|&b| b <= *x)
                        .clamp(1, breaks.len() - 1);
                    halve[span - 1] = true;
                }
            }
        }
        let mut next = Vec::with_capacity(2 * breaks.len());
        for (k, w) in breaks.windows(2).enumerate() {
            next.push(w[0]);
            // a half with no point of its own would leave the system without a solution
            let mid = 0.5 * (w[0] + w[1]);
            let holds = |a: f64, b: f64| params.iter().any(|&x| x > a && x < b);
            if halve[k] && holds(w[0], mid) && holds(mid, w[1]) {
                next.push(mid);
            }
        }
        next.push(1.0);
        if next.len() == breaks.len() {
            // nothing left to halve: the points are too few for the turns
            return polyline(points);
        }
        breaks = next;
    }
}

/// Points of `curve` at `samples` uniform parameters (both ends included), each interval halved
/// until its middle and quarter points lie within `tol` of its chord, at most `max_halvings`
/// times.
pub(crate) fn sample_within(
    curve: &BSplineCurve,
    samples: usize,
    tol: f64,
    max_halvings: usize,
) -> Vec<Point3> {
    let (t0, t1) = curve.knots().domain();
    let n = samples.max(2);
    let mut out = vec![curve.point(t0)];
    for k in 1..n {
        let (a, b) = (
            t0 + (t1 - t0) * (k - 1) as f64 / (n - 1) as f64,
            t0 + (t1 - t0) * k as f64 / (n - 1) as f64,
        );
        let pb = curve.point(b);
        let a = (a, out[out.len() - 1]);
        halve(curve, a, (b, pb), tol, max_halvings, &mut out);
    }
    out
}

/// Pushes the points of `curve` after `a` up to and including `b`, halving [a, b] (`depth`
/// halvings left) while a point between lies farther than `tol` from the chord.
fn halve(
    curve: &BSplineCurve,
    a: (f64, Point3),
    b: (f64, Point3),
    tol: f64,
    depth: usize,
    out: &mut Vec<Point3>,
) {
    let chord = b.1 - a.1;
    let len2 = chord.norm_squared();
    let off = |p: Point3| {
        let w = p - a.1;
        let s = if len2 > 0.0 {
            (w.dot(&chord) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (w - chord * s).norm()
    };
    let h = b.0 - a.0;
    let m = a.0 + 0.5 * h;
    let pm = (m, curve.point(m));
    let far = off(pm.1) > tol
        || [0.25, 0.75]
            .iter()
            .any(|&f| off(curve.point(a.0 + f * h)) > tol);
    if far && depth > 0 {
        halve(curve, a, pm, tol, depth - 1, out);
        halve(curve, pm, b, tol, depth - 1, out);
    } else {
        out.push(b.1);
    }
}

/// Distance from `x` to the polyline through `pts`.
pub fn distance_to_polyline(x: &Point3, pts: &[Point3]) -> f64 {
    if pts.len() == 1 {
        return (x - pts[0]).norm();
    }
    foot_on_polyline(x, pts).1
}

/// The foot of `x` on the polyline `pts` (two points at least): (segment, fraction along it)
/// and the distance.
pub(crate) fn foot_on_polyline(x: &Point3, pts: &[Point3]) -> ((usize, f64), f64) {
    let mut best = ((0, 0.0), f64::INFINITY);
    for (i, w) in pts.windows(2).enumerate() {
        let d = w[1] - w[0];
        let len2 = d.norm_squared();
        let t = if len2 > 0.0 {
            ((x - w[0]).dot(&d) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let dist = (x - (w[0] + d * t)).norm();
        if dist < best.1 {
            best = ((i, t), dist);
        }
    }
    best
}
