//! Bare multi-patch files (several surfaces, no model): fairing keeps the continuity their
//! shared edges already have.
//!
//! A side of one patch that lies on a side of another (sampled, as a link's side lies on its
//! master, [`crate::framework`]) is a shared edge. Where the two patches meet tangentially —
//! every sampled normal angle within [`TANGENT_EDGE_DEG`] — both keep their tangential frame
//! there (boundary row and the row next to it: the edge, and the normals along it, stay exactly
//! as they are, \[SV\] §3.1); at a sharper edge the boundary row alone. A side collapsed to a
//! point (a pole) keeps its two rows and a degenerate corner its 2 × 2 block, as in the
//! framework's stages. Where a patch has too few rows for its frames plus free ones (a bicubic
//! Bézier patch has four), knots are inserted first, which leaves its shape as it is.

use g_continuity::measure::is_collapsed;
use g_continuity::{MeasureParams, measure_link};
use nurbs_core::{BSplineSurface, ControlMask, Direction, Frame, PerSide, Side};

use crate::topology::{TANGENT_EDGE_DEG, lies_on_side, net_box};

/// Distance within which a side lies on another patch's side, relative to the size of the
/// file's bounding box: patches that share an edge share it to round-off of their export
/// (1e-12 of the size in a Bézier teapot, 1e-9 in an IGES file), and 1e-6 of the part is below
/// any modelling gap a user means.
pub(crate) const SHARED_EDGE_RELATIVE: f64 = 1e-6;

/// A side of one patch that lies on a side of another.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SharedSide {
    /// the other patch
    pub other: usize,
    /// its side
    pub other_side: Side,
    /// largest normal angle along the edge (degrees), `None` where no sample has both normals
    pub angle_deg: Option<f64>,
}

impl SharedSide {
    /// Whether the two patches meet tangentially there ([`TANGENT_EDGE_DEG`]).
    pub fn tangent(&self) -> bool {
        self.angle_deg.is_some_and(|a| a <= TANGENT_EDGE_DEG)
    }
}

/// The shared side of every side of every patch (`None`: a free boundary).
pub fn shared_sides(surfaces: &[BSplineSurface]) -> Vec<PerSide<Option<SharedSide>>> {
    let points: Vec<nurbs_core::Point3> = surfaces
        .iter()
        .flat_map(|s| s.control_points().iter().copied())
        .collect();
    let size = nurbs_core::homogeneous::bounding_diagonal(&points);
    let tol = SHARED_EDGE_RELATIVE * size;
    let measure = MeasureParams::default();
    let mut out = vec![PerSide([None; 4]); surfaces.len()];
    // control-net boxes (a surface lies in its net's hull): only patches whose boxes, grown by
    // the tolerance, overlap are compared, so a file of many patches costs its neighbours only
    let boxes: Vec<([f64; 3], [f64; 3])> = surfaces.iter().map(|s| net_box(s, tol)).collect();
    let overlap = |a: usize, b: usize| {
        (0..3).all(|d| boxes[a].0[d] <= boxes[b].1[d] && boxes[b].0[d] <= boxes[a].1[d])
    };
    for (a, sa) in surfaces.iter().enumerate() {
        for side in Side::ALL {
            if is_collapsed(sa, side) {
                continue;
            }
            'search: for (b, sb) in surfaces.iter().enumerate() {
                if b == a || !overlap(a, b) {
                    continue;
                }
                for other_side in Side::ALL {
                    if is_collapsed(sb, other_side) || !lies_on_side(sa, side, sb, other_side, tol)
                    {
                        continue;
                    }
                    let angle_deg = measure_link(sb, sa, side, &measure)
                        .ok()
                        .and_then(|m| m.g1_deg);
                    out[a][side] = Some(SharedSide {
                        other: b,
                        other_side,
                        angle_deg,
                    });
                    break 'search;
                }
            }
        }
    }
    out
}

/// The frame each side keeps: at least `keep`; a tangent shared edge or a pole its tangential
/// frame; a sharp shared edge its boundary row.
pub fn kept_frames(
    surface: &BSplineSurface,
    shared: &PerSide<Option<SharedSide>>,
    keep: Frame,
) -> PerSide<Frame> {
    PerSide::from_fn(|side| {
        let needed = if is_collapsed(surface, side) {
            Frame::Tangential
        } else {
            match shared[side] {
                Some(s) if s.tangent() => Frame::Tangential,
                _ => Frame::Positional,
            }
        };
        keep.max(needed)
    })
}

/// The patch with enough rows for `frames` plus `min_free` free rows in each direction (knots
/// inserted where needed, the shape unchanged), its mask, and the number of inserted knots.
pub fn prepared_patch(
    surface: &BSplineSurface,
    frames: PerSide<Frame>,
    min_free: usize,
) -> nurbs_core::Result<(BSplineSurface, ControlMask, usize)> {
    let rows = |side: Side| frames[side].rows();
    let mut s = surface.clone();
    let mut inserted = 0;
    for (dir, a, b) in [
        (Direction::U, Side::U0, Side::U1),
        (Direction::V, Side::V0, Side::V1),
    ] {
        let (more, k) = s.with_smooth_control_count(dir, rows(a) + rows(b) + min_free)?;
        s = more;
        inserted += k;
    }
    let mut mask = ControlMask::for_surface(&s);
    for (side, &frame) in frames.iter() {
        mask.fix_frame(side, frame);
    }
    for (i, j) in g_continuity::degenerate_corner_blocks(&s) {
        mask.set_free(i, j, false);
    }
    Ok((s, mask, inserted))
}
