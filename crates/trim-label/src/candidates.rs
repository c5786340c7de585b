//! Segment shape measures and the choice of label candidates (\[VV18\], first step of the
//! algorithm: "we exclude those segments that cannot serve as boundaries of the presumed TP
//! surface").
//!
//! Each segment is resampled at m + 1 points of equal arc length in the best-fit plane (m ≈
//! L / (0.02 D), 2 ≤ m ≤ 48, so that mesh noise below the sampling step is ignored); θ_k are the
//! signed turning angles between successive chords. Measures:
//! - total turning Θ = Σ θ_k (negative: a concave curve),
//! - absolute turning A = Σ |θ_k| (complexity: how much the curve bends),
//! - wiggle W = A − |Θ| (zero for curves of one-signed curvature: an inflection measure, the
//!   "curvature variation" of \[VV18\]).
//!
//! End tangents are chords over an arc window w = min(tangent_window_rel·D, 0.3 L), so a
//! discrete corner does not depend on one edge. A segment is dropped when a neighbour meets it at
//! a concave angle (junction turning < −concave_angle), when Θ < −concave_turning, when
//! A > max_segment_turning, when W > max_wiggle, or when it is shorter than min_candidate_rel·D.

use crate::params::LabelParams;
use crate::region::{Point2, Region};
use crate::segments::Segment;

/// Resampling step of the shape measures, relative to the region size.
const RESAMPLE_STEP_REL: f64 = 0.02;
/// Most chords in the resampled segment.
const RESAMPLE_MAX: usize = 48;

/// Signed angle from direction a to direction b (radians, counter-clockwise positive).
pub fn signed_angle(a: &Point2, b: &Point2) -> f64 {
    a.perp(b).atan2(a.dot(b))
}

/// Shape of one segment.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentShape {
    /// arc length (3D)
    pub length: f64,
    /// unit tangent at the start (plane)
    pub start_tangent: Point2,
    /// unit tangent at the end (plane)
    pub end_tangent: Point2,
    /// the 3D chord used for the end tangent (end − earlier point)
    pub end_tangent_3d: nurbs_core::Vector3,
    /// the 3D chord used for the start tangent (later point − start)
    pub start_tangent_3d: nurbs_core::Vector3,
    /// Θ (radians)
    pub total_turning: f64,
    /// A (radians)
    pub abs_turning: f64,
    /// W (radians)
    pub wiggle: f64,
}

/// Why a segment is not a label candidate (`None`: it is one).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Exclusion {
    /// meets a neighbour at a concave angle (the junction turning, radians)
    ConcaveJunction(f64),
    /// the curve itself is concave (total turning, radians)
    ConcaveCurve(f64),
    /// bends too much (absolute turning, radians)
    TooMuchTurning(f64),
    /// inflections (wiggle, radians)
    Wiggly(f64),
    /// too short for a tangent (length)
    TooShort(f64),
}

impl std::fmt::Display for Exclusion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Exclusion::ConcaveJunction(t) => {
                write!(
                    f,
                    "meets a neighbour at a concave angle (turning {:.1}°)",
                    t.to_degrees()
                )
            }
            Exclusion::ConcaveCurve(t) => {
                write!(
                    f,
                    "is a concave curve (total turning {:.1}°)",
                    t.to_degrees()
                )
            }
            Exclusion::TooMuchTurning(t) => {
                write!(
                    f,
                    "has complex geometry (turns {:.1}° in all)",
                    t.to_degrees()
                )
            }
            Exclusion::Wiggly(t) => write!(
                f,
                "has complex geometry (curvature changes sign: wiggle {:.1}°)",
                t.to_degrees()
            ),
            Exclusion::TooShort(l) => write!(f, "is too short ({l:.4})"),
        }
    }
}

/// Loop positions start..=end of a segment, as plane points and 3D points, with 3D arc lengths.
fn polyline(
    region: &Region<'_>,
    seg: &Segment,
) -> (Vec<Point2>, Vec<nurbs_core::Point3>, Vec<f64>) {
    let n = region.loop_len();
    let mut p2 = Vec::with_capacity(seg.edges + 1);
    let mut p3: Vec<nurbs_core::Point3> = Vec::with_capacity(seg.edges + 1);
    let mut s = Vec::with_capacity(seg.edges + 1);
    for e in 0..=seg.edges {
        let i = (seg.start + e) % n;
        let q = region.loop_point(i);
        s.push(match p3.last() {
            Some(prev) => s[e - 1] + (q - *prev).norm(),
            None => 0.0,
        });
        p2.push(region.outer_2d[i]);
        p3.push(q);
    }
    (p2, p3, s)
}

/// Point at arc length t along a polyline with cumulative lengths s.
fn at_arc(p: &[Point2], s: &[f64], t: f64) -> Point2 {
    let k = s.partition_point(|&x| x < t).clamp(1, s.len() - 1);
    let span = s[k] - s[k - 1];
    let a = if span > 0.0 {
        (t - s[k - 1]) / span
    } else {
        0.0
    };
    p[k - 1] + (p[k] - p[k - 1]) * a.clamp(0.0, 1.0)
}

impl SegmentShape {
    /// Measures `seg`.
    pub fn new(region: &Region<'_>, seg: &Segment, params: &LabelParams) -> Self {
        let (p2, p3, s) = polyline(region, seg);
        let length = *s.last().unwrap_or(&0.0);
        let w = (params.tangent_window_rel * region.size).min(0.3 * length);
        let last = p2.len() - 1;
        // end tangent: back from the end by arc w
        let kb = s.partition_point(|&x| x < length - w).min(last - 1);
        let ks = s.partition_point(|&x| x <= w).clamp(1, last);
        let end_tangent_3d = p3[last] - p3[kb];
        let start_tangent_3d = p3[ks] - p3[0];
        let unit = |v: Point2| {
            v.try_normalize(0.0)
                .unwrap_or_else(|| Point2::new(1.0, 0.0))
        };
        let end_tangent = unit(p2[last] - p2[kb]);
        let start_tangent = unit(p2[ks] - p2[0]);
        let m =
            ((length / (RESAMPLE_STEP_REL * region.size)).round() as usize).clamp(2, RESAMPLE_MAX);
        let pts: Vec<Point2> = (0..=m)
            .map(|k| at_arc(&p2, &s, length * k as f64 / m as f64))
            .collect();
        let (mut total, mut abs) = (0.0, 0.0);
        for k in 1..m {
            let (a, b) = (pts[k] - pts[k - 1], pts[k + 1] - pts[k]);
            if a.norm() > 0.0 && b.norm() > 0.0 {
                let t = signed_angle(&a, &b);
                total += t;
                abs += t.abs();
            }
        }
        Self {
            length,
            start_tangent,
            end_tangent,
            end_tangent_3d,
            start_tangent_3d,
            total_turning: total,
            abs_turning: abs,
            wiggle: abs - total.abs(),
        }
    }
}

/// Decides which segments are label candidates: `None` for a candidate, else the reason.
pub fn classify(
    region: &Region<'_>,
    segments: &[Segment],
    shapes: &[SegmentShape],
    params: &LabelParams,
) -> Vec<Option<Exclusion>> {
    let m = segments.len();
    (0..m)
        .map(|k| {
            let sh = &shapes[k];
            if m > 1 {
                let prev = &shapes[(k + m - 1) % m];
                let next = &shapes[(k + 1) % m];
                let at_start = signed_angle(&prev.end_tangent, &sh.start_tangent);
                let at_end = signed_angle(&sh.end_tangent, &next.start_tangent);
                let worst = at_start.min(at_end);
                if worst < -params.concave_angle_deg.to_radians() {
                    return Some(Exclusion::ConcaveJunction(worst));
                }
            }
            if sh.length < params.min_candidate_rel * region.size {
                return Some(Exclusion::TooShort(sh.length));
            }
            if sh.total_turning < -params.concave_turning_deg.to_radians() {
                return Some(Exclusion::ConcaveCurve(sh.total_turning));
            }
            if sh.abs_turning > params.max_segment_turning_deg.to_radians() {
                return Some(Exclusion::TooMuchTurning(sh.abs_turning));
            }
            if sh.wiggle > params.max_wiggle_deg.to_radians() {
                return Some(Exclusion::Wiggly(sh.wiggle));
            }
            None
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signed_angle_is_counter_clockwise_positive() {
        let x = Point2::new(1.0, 0.0);
        assert!(
            (signed_angle(&x, &Point2::new(0.0, 2.0)) - std::f64::consts::FRAC_PI_2).abs() < 1e-15
        );
        assert!(
            (signed_angle(&x, &Point2::new(0.0, -1.0)) + std::f64::consts::FRAC_PI_2).abs() < 1e-15
        );
        assert!((signed_angle(&x, &Point2::new(-1.0, 1e-12)) - std::f64::consts::PI).abs() < 1e-11);
    }
}
