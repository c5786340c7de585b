//! What happens where two labels meet (\[VV18\], pairs of adjacent candidates): concatenation into
//! a multi-segment label, a real corner, a virtual corner, or no corner.
//!
//! With a = the first label's last segment, b = the second label's first segment, t_a and t_b
//! their end/start unit tangents in the best-fit plane and τ = ∠(t_a, t_b) the signed turning:
//! - shared end vertex: |τ| < smooth_join → concatenate; τ > 0 → real corner at the vertex;
//!   otherwise (a concave turn) no corner;
//! - gap (unlabeled segments between): with the chord c = b₀ − a₁, both |∠(t_a, c)| and
//!   |∠(c, t_b)| < connect_angle → concatenate (a connecting curve of low curvature variation
//!   exists: a line or a circular arc); otherwise the labels are extended along their end
//!   tangents, a₁ + s_a t_a = b₀ − s_b t_b. When τ ≤ 0, the rays do not meet ahead (s_a ≤ 0 or
//!   s_b ≤ 0) or the meeting point is farther than max_corner_distance·D from the region, there is
//!   no sensible extension: no corner. Otherwise a virtual corner.
//!
//! Strength of a corner: s = sin(τ) · 1/(1 + (d/(σD))²) ∈ [0, 1], with d the distance of the
//! corner from the outer loop (0 for a real corner); s = 0 for a virtual corner inside the
//! region (its extensions would cut the region). A right-angle corner on the region is 1.
//!
//! Concatenation is refused when the joined label would turn more than max_label_turning.
//!
//! # Deviation from the paper
//! \[VV18\] extends labels "smoothly" and "snaps" the curves; we extend along the end tangents
//! (first-order extension), which is exact for straight sides and conservative for arcs.

use nurbs_core::Point3;
use serde::Serialize;

use crate::candidates::{SegmentShape, signed_angle};
use crate::params::LabelParams;
use crate::region::{Point2, Region};
use crate::segments::Segment;

/// Rays closer to parallel than this (|sin| of the angle between them) do not intersect.
const PARALLEL_SIN: f64 = 1e-9;

/// Kind of a corner in the output.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CornerKind {
    /// the labels share an end vertex
    Real,
    /// the labels' extensions meet
    Virtual,
    /// no sensible extension
    None,
}

/// The junction between consecutive labels.
#[derive(Debug, Clone, PartialEq)]
pub enum Junction {
    /// the two labels form one multi-segment label; quality in [0, 1] (1 = perfectly smooth)
    Concatenate {
        /// smoothness of the connection
        quality: f64,
    },
    /// a corner (real, virtual or none)
    Corner(Corner),
}

/// A corner between two labels.
#[derive(Debug, Clone, PartialEq)]
pub struct Corner {
    /// real, virtual or none
    pub kind: CornerKind,
    /// position (None for no corner)
    pub position: Option<Point3>,
    /// position in the plane
    pub position_2d: Option<Point2>,
    /// strength in [0, 1] (0 for no corner)
    pub strength: f64,
    /// signed turning τ between the labels' tangents (radians)
    pub turning: f64,
    /// distance from the region (length units; 0 for real corners)
    pub distance: f64,
    /// plane points the extensions start from (end of the first label, start of the second)
    pub extension_from: Option<(Point2, Point2)>,
}

impl Corner {
    fn none(turning: f64) -> Self {
        Self {
            kind: CornerKind::None,
            position: None,
            position_2d: None,
            strength: 0.0,
            turning,
            distance: 0.0,
            extension_from: None,
        }
    }
    /// True for real and virtual corners.
    pub fn is_corner(&self) -> bool {
        self.kind != CornerKind::None
    }
}

/// Geometry shared by all junction tests.
pub struct JunctionContext<'r, 'a> {
    /// the region
    pub region: &'r Region<'a>,
    /// all segments
    pub segments: &'r [Segment],
    /// their shapes
    pub shapes: &'r [SegmentShape],
    /// settings
    pub params: &'r LabelParams,
}

impl JunctionContext<'_, '_> {
    /// Junction from segment `a` (end of a label turning `turn_a` in total) to segment `b` (start
    /// of a label turning `turn_b`); `allow_concat` false forces a corner decision.
    pub fn junction(
        &self,
        a: usize,
        b: usize,
        turn_a: f64,
        turn_b: f64,
        allow_concat: bool,
    ) -> Junction {
        let (r, p) = (self.region, self.params);
        let n = r.loop_len();
        let (sa, sb) = (&self.shapes[a], &self.shapes[b]);
        let (ta, tb) = (sa.end_tangent, sb.start_tangent);
        let tau = signed_angle(&ta, &tb);
        let can_join =
            allow_concat && (turn_a + tau + turn_b).abs() <= p.max_label_turning_deg.to_radians();
        let end_a = self.segments[a].end() % n;
        let start_b = self.segments[b].start;
        if end_a == start_b {
            return self.at_shared_vertex(end_a, tau, can_join);
        }
        let (pa, pb) = (r.outer_2d[end_a], r.outer_2d[start_b]);
        let chord = pb - pa;
        if can_join && chord.norm() > 0.0 {
            let worst = signed_angle(&ta, &chord)
                .abs()
                .max(signed_angle(&chord, &tb).abs());
            let limit = p.connect_angle_deg.to_radians();
            if worst < limit {
                return Junction::Concatenate {
                    quality: 1.0 - worst / limit,
                };
            }
        }
        if tau <= 0.0 {
            return Junction::Corner(Corner::none(tau));
        }
        self.virtual_corner((a, end_a), (b, start_b), tau)
    }

    /// Labels that share the loop vertex `v` and turn by `tau` there: concatenated when
    /// `can_join` and smooth, a real corner at a convex turn, no corner at a concave one.
    fn at_shared_vertex(&self, v: usize, tau: f64, can_join: bool) -> Junction {
        let smooth = self.params.smooth_join_deg.to_radians();
        if can_join && tau.abs() < smooth {
            return Junction::Concatenate {
                quality: 1.0 - tau.abs() / smooth,
            };
        }
        if tau <= 0.0 {
            return Junction::Corner(Corner::none(tau));
        }
        Junction::Corner(Corner {
            kind: CornerKind::Real,
            position: Some(self.region.loop_point(v)),
            position_2d: Some(self.region.outer_2d[v]),
            strength: tau.sin().max(0.0),
            turning: tau,
            distance: 0.0,
            extension_from: None,
        })
    }

    /// Where the extensions of segment `a` beyond its end (loop position `end_a`) and of `b`
    /// before its start (`start_b`), turning by `tau` > 0, meet: a virtual corner, or no corner
    /// when they do not meet ahead or meet too far from the region.
    fn virtual_corner(
        &self,
        (a, end_a): (usize, usize),
        (b, start_b): (usize, usize),
        tau: f64,
    ) -> Junction {
        let (r, p) = (self.region, self.params);
        let (sa, sb) = (&self.shapes[a], &self.shapes[b]);
        let (ta, tb) = (sa.end_tangent, sb.start_tangent);
        let (pa, pb) = (r.outer_2d[end_a], r.outer_2d[start_b]);
        let chord = pb - pa;
        let det = ta.perp(&tb);
        if det.abs() < PARALLEL_SIN {
            return Junction::Corner(Corner::none(tau));
        }
        let s_a = chord.perp(&tb) / det;
        let s_b = ta.perp(&chord) / det;
        if !(s_a > 0.0 && s_b > 0.0) {
            return Junction::Corner(Corner::none(tau));
        }
        let q = pa + ta * s_a;
        let inside = r.winding(&q) != 0;
        let distance = if inside { 0.0 } else { r.distance_to_loop(&q) };
        if distance > p.max_corner_distance_rel * r.size {
            return Junction::Corner(Corner::none(tau));
        }
        let falloff = 1.0 / (1.0 + (distance / (p.corner_distance_scale * r.size)).powi(2));
        let strength = if inside {
            0.0
        } else {
            tau.sin().max(0.0) * falloff
        };
        // lift to 3D along the 3D chords whose projections are the plane tangents
        let lift = |from: Point3, t3: nurbs_core::Vector3, s: f64| {
            let l2 = r.frame.project_dir(&t3).norm();
            if l2 > 0.0 { from + t3 * (s / l2) } else { from }
        };
        let qa = lift(r.loop_point(end_a), sa.end_tangent_3d, s_a);
        let qb = lift(r.loop_point(start_b), -sb.start_tangent_3d, s_b);
        Junction::Corner(Corner {
            kind: CornerKind::Virtual,
            position: Some(Point3::from((qa.coords + qb.coords) / 2.0)),
            position_2d: Some(q),
            strength,
            turning: tau,
            distance,
            extension_from: Some((pa, pb)),
        })
    }
}
