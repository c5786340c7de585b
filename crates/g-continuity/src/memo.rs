//! Master points of a whole side, remembered: the continuity steps solve a side's rows many
//! times over the same boundary (the G1 polishing passes, the variants of a step, the weights of
//! the G2 ladder's callers, the trials of a lead-in search). From the G1 step on the boundary row
//! does not move, so the slave points of the samples repeat bit for bit, and so would their
//! projections onto the master ([`MasterTracker`], \[NB\] §6.1). Measurements repeat too (a link
//! measured after a step and again by its caller).
//!
//! The memo is exact: an entry is used only when the master (its degrees, knots, weights and
//! control points, bit for bit), the projection settings and every sample point are the same as
//! when it was made. A side's projections are a function of exactly these (the tracker starts
//! afresh per side and warm-starts each sample from the feet before it), so a hit returns what the
//! projections would have returned, and results do not depend on the memo or on the thread a
//! side runs on.
//!
//! # Bound
//! At most [`MEMO_SIDES`] sides are kept (first in, first out), each as its master's bits, its
//! sample points and their foot points: about 100 kB for a master of 64 × 64 points (the
//! framework's largest net), a few MB in all. The memo lives for the process.

use std::collections::VecDeque;
use std::sync::Mutex;

use nurbs_core::{BSplineSurface, Point3, ProjectionParams, SurfaceProjection};

use crate::sampling::MasterTracker;

/// Sides kept. A surface's repeats come within its own run: its four sides, each with the row
/// samples and the measures' samples, eight entries per surface being set; 64 serve eight
/// surfaces at once (one per core on an eight-core machine).
pub(crate) const MEMO_SIDES: usize = 64;

/// One remembered side.
struct Entry {
    hash: u64,
    master: Vec<u64>,
    points: Vec<[u64; 3]>,
    feet: Vec<SurfaceProjection>,
}

/// The remembered sides, oldest first (shared by all threads: a side's repeat may run on
/// another worker).
static MEMO: Mutex<VecDeque<Entry>> = Mutex::new(VecDeque::new());

/// FNV-1a over 64-bit words.
fn fnv(words: impl Iterator<Item = u64>) -> u64 {
    words.fold(0xcbf2_9ce4_8422_2325, |h, w| {
        (h ^ w).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Every bit of `master` and the projection settings that a projection reads.
fn master_key(master: &BSplineSurface, params: &ProjectionParams) -> Vec<u64> {
    // every field, named: a new setting must be added here
    let ProjectionParams {
        point_tolerance,
        cosine_tolerance,
        max_iterations,
        samples_per_span,
        starts,
        max_samples_per_direction,
    } = *params;
    let words = [
        master.degree_u() as u64,
        master.degree_v() as u64,
        master.num_u() as u64,
        master.num_v() as u64,
        point_tolerance.to_bits(),
        cosine_tolerance.to_bits(),
        max_iterations as u64,
        samples_per_span as u64,
        starts as u64,
        max_samples_per_direction as u64,
    ];
    let knots = master
        .knots_u()
        .knots()
        .iter()
        .chain(master.knots_v().knots())
        .chain(master.weights().unwrap_or(&[]))
        .map(|x| x.to_bits());
    let points = master
        .control_points()
        .iter()
        .flat_map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]);
    words.into_iter().chain(knots).chain(points).collect()
}

/// The side's master points from the memo, if the same side was projected before.
fn remembered(master: &[u64], hash: u64, points: &[[u64; 3]]) -> Option<Vec<SurfaceProjection>> {
    let memo = MEMO.lock().ok()?;
    memo.iter()
        .find(|e| e.hash == hash && e.points == points && e.master == master)
        .map(|e| e.feet.clone())
}

/// The bits of `points`.
fn point_bits(points: &[Point3]) -> Vec<[u64; 3]> {
    points
        .iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
        .collect()
}

/// The master points of `points` (a side's samples in order), as a fresh [`MasterTracker`]
/// would find them one after the other, from the memo where the same side was projected before.
pub(crate) fn project_side(
    master: &BSplineSurface,
    params: ProjectionParams,
    points: &[Point3],
) -> Vec<SurfaceProjection> {
    let key = master_key(master, &params);
    let hash = fnv(key.iter().copied());
    let bits = point_bits(points);
    if let Some(feet) = remembered(&key, hash, &bits) {
        return feet;
    }
    let mut tracker = MasterTracker::new(master, params);
    let feet: Vec<SurfaceProjection> = points.iter().map(|p| tracker.project(p)).collect();
    if let Ok(mut memo) = MEMO.lock() {
        if memo.len() == MEMO_SIDES {
            memo.pop_front();
        }
        memo.push_back(Entry {
            hash,
            master: key,
            points: bits,
            feet: feet.clone(),
        });
    }
    feet
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs_core::shapes::plane_patch;
    use nurbs_core::{Point3, Vector3};

    /// A quarter cylinder of radius 2 about the z axis, exact (rational).
    fn cylinder() -> BSplineSurface {
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let ring = [(2.0, 0.0, 1.0), (2.0, 2.0, w), (0.0, 2.0, 1.0)];
        let mut pts = Vec::new();
        let mut weights = Vec::new();
        for &(x, y, wi) in &ring {
            for z in [0.0, 3.0] {
                pts.push(Point3::new(x, y, z));
                weights.push(wi);
            }
        }
        BSplineSurface::new(
            nurbs_core::KnotVector::bezier(2).unwrap(),
            nurbs_core::KnotVector::bezier(1).unwrap(),
            pts,
            Some(weights),
        )
        .unwrap()
    }

    fn fresh(master: &BSplineSurface, points: &[Point3]) -> Vec<SurfaceProjection> {
        let mut t = MasterTracker::new(master, ProjectionParams::default());
        points.iter().map(|p| t.project(p)).collect()
    }

    #[test]
    fn a_remembered_side_is_what_a_fresh_projection_gives() {
        let master = cylinder();
        let points: Vec<Point3> = (0..20)
            .map(|k| {
                let a = 0.07 * k as f64;
                Point3::new(2.1 * a.cos(), 2.1 * a.sin(), 0.1 * k as f64)
            })
            .collect();
        let params = ProjectionParams::default();
        let first = project_side(&master, params, &points);
        let key = master_key(&master, &params);
        let hash = fnv(key.iter().copied());
        let kept = remembered(&key, hash, &point_bits(&points));
        assert_eq!(kept.as_ref(), Some(&first), "the side is remembered");
        assert_eq!(first, fresh(&master, &points));
        assert_eq!(project_side(&master, params, &points), first);
        // the feet are the cylinder's: 0.1 off the radius-2 surface
        for f in &first {
            assert!((f.distance - 0.1).abs() < 1e-12, "{}", f.distance);
        }
        // one point moved by a rounding unit: projected afresh, not taken from the memo
        let mut moved = points.clone();
        moved[7].x = f64::from_bits(moved[7].x.to_bits() + 1);
        assert_eq!(remembered(&key, hash, &point_bits(&moved)), None);
        assert_eq!(
            project_side(&master, ProjectionParams::default(), &moved),
            fresh(&master, &moved)
        );
        // another master with the same points: its own feet
        let plane = plane_patch(
            Point3::new(0.0, 0.0, 0.0),
            Vector3::x(),
            Vector3::y(),
            (0.0, 3.0),
            (0.0, 3.0),
        )
        .unwrap();
        let on_plane = project_side(&plane, ProjectionParams::default(), &points);
        assert_eq!(on_plane, fresh(&plane, &points));
        assert_ne!(on_plane, first);
    }
}
