//! The settings of the labeling, with units and where each default comes from.
//!
//! \[VV18\] names the criteria (concave meeting, complex geometry, low-curvature-variation
//! connections, distance and angle of virtual corners) but not their values ("the computation of
//! the various qualifiers and thresholds … are discussed in details in the paper" — the full paper,
//! which we do not have). The defaults below are ours, chosen on the synthetic regions of the
//! tests and the Neon side panel; every one is a named field.

use crate::error::{LabelError, Result};
use crate::segments::SegmentationParams;

/// Settings of [`crate::label_region`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LabelParams {
    /// automatic segmentation (used when no segments are given)
    pub segmentation: SegmentationParams,
    /// Arc window for end tangents, relative to the region size D (default 0.03); capped at 30 %
    /// of the segment's length.
    pub tangent_window_rel: f64,
    /// Segments shorter than this fraction of D are not label candidates (default 0.01: too short
    /// to give a tangent).
    pub min_candidate_rel: f64,
    /// A junction turning by less than −this angle (degrees) is concave; the segments meeting
    /// there are dropped (default 15°).
    pub concave_angle_deg: f64,
    /// A segment whose total turning is below −this (degrees) is a concave curve and is dropped
    /// (default 20°).
    pub concave_turning_deg: f64,
    /// Segments turning more than this in total (Σ|θ|, degrees) are too complex (default 100°: a
    /// tensor-product side rarely bends more than a right angle).
    pub max_segment_turning_deg: f64,
    /// Inflection measure Σ|θ| − |Σθ| (degrees) above which a segment is too complex (default
    /// 40°: an S-shaped curve).
    pub max_wiggle_deg: f64,
    /// Labels joined smoothly at a shared end vertex (|turning| below this, degrees) are
    /// concatenated (default 25°).
    pub smooth_join_deg: f64,
    /// Across a gap, labels are concatenated when both end tangents make less than this angle
    /// (degrees) with the connecting chord: a connection of low curvature variation (default 20°).
    pub connect_angle_deg: f64,
    /// Concatenated labels may turn at most this much in total (degrees, default 100°).
    pub max_label_turning_deg: f64,
    /// A weak corner is killed (its labels concatenated) only if it turns at most this much
    /// (degrees, default 45°): joining labels across a sharper turn would not give a side.
    pub max_kill_turning_deg: f64,
    /// Virtual corners farther than this fraction of D from the region are no-corners (default
    /// 1.0: no sensible extension).
    pub max_corner_distance_rel: f64,
    /// Distance scale σ of the strength's distance factor 1/(1 + (d/(σD))²) (default 0.15).
    pub corner_distance_scale: f64,
    /// Corners at least this strong are "strong" in the log (default 0.5; strength is in [0, 1]).
    pub strong_strength: f64,
    /// Quality given to a no-corner junction when scoring reductions (default 0.45: between a
    /// weak and a strong corner).
    pub none_quality: f64,
    /// Weight w of the labeled fraction of the perimeter in the configuration score (default
    /// 0.5: keeping a label worth a quarter of the loop outweighs a 0.125 drop of mean quality).
    pub coverage_weight: f64,
    /// Configurations kept per level of the reduction search (default 32; L ≤ 12 labels are
    /// then searched almost exhaustively).
    pub beam_width: usize,
}

impl Default for LabelParams {
    fn default() -> Self {
        Self {
            segmentation: SegmentationParams::default(),
            tangent_window_rel: 0.03,
            min_candidate_rel: 0.01,
            concave_angle_deg: 15.0,
            concave_turning_deg: 20.0,
            max_segment_turning_deg: 100.0,
            max_wiggle_deg: 40.0,
            smooth_join_deg: 25.0,
            connect_angle_deg: 20.0,
            max_label_turning_deg: 100.0,
            max_kill_turning_deg: 45.0,
            max_corner_distance_rel: 1.0,
            corner_distance_scale: 0.15,
            strong_strength: 0.5,
            none_quality: 0.45,
            coverage_weight: 0.5,
            beam_width: 32,
        }
    }
}

impl LabelParams {
    /// Rejects NaN, negative or out-of-range settings.
    pub fn validate(&self) -> Result<()> {
        let s = &self.segmentation;
        let positive: [(&'static str, f64); 13] = [
            ("max_kill_turning_deg", self.max_kill_turning_deg),
            ("segmentation.corner_angle_deg", s.corner_angle_deg),
            ("segmentation.corner_window_rel", s.corner_window_rel),
            ("segmentation.curvature_change", s.curvature_change),
            ("segmentation.curvature_window_rel", s.curvature_window_rel),
            ("tangent_window_rel", self.tangent_window_rel),
            ("concave_angle_deg", self.concave_angle_deg),
            ("max_segment_turning_deg", self.max_segment_turning_deg),
            ("smooth_join_deg", self.smooth_join_deg),
            ("connect_angle_deg", self.connect_angle_deg),
            ("max_label_turning_deg", self.max_label_turning_deg),
            ("max_corner_distance_rel", self.max_corner_distance_rel),
            ("corner_distance_scale", self.corner_distance_scale),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(LabelError::InvalidParameter {
                    name,
                    value,
                    expected: "finite and > 0",
                });
            }
        }
        let non_negative: [(&'static str, f64); 7] = [
            ("segmentation.min_segment_rel", s.min_segment_rel),
            ("min_candidate_rel", self.min_candidate_rel),
            ("concave_turning_deg", self.concave_turning_deg),
            ("max_wiggle_deg", self.max_wiggle_deg),
            ("strong_strength", self.strong_strength),
            ("none_quality", self.none_quality),
            ("coverage_weight", self.coverage_weight),
        ];
        for (name, value) in non_negative {
            if !(value.is_finite() && value >= 0.0) {
                return Err(LabelError::InvalidParameter {
                    name,
                    value,
                    expected: "finite and ≥ 0",
                });
            }
        }
        Ok(())
    }
}
