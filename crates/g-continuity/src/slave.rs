//! Setting continuity of one slave to all its masters: C0, then G1, then G2, side by side with
//! consistent twists (\[SV\] §3.3, §4), knot insertion when the tolerances are missed.
//!
//! Order (\[SV\] §3.1): the cross derivative of order r on a clamped side depends on rows 0..=r
//! only, so C0 (row 0) is set first on every linked side, then G1 (row 1), then G2 (row 2); a
//! later step never touches the rows of an earlier one, which therefore stay bit-identical.
//!
//! Row k of a side, at along index e from one end, is row e of the neighbouring side at that end.
//! Such a point is
//! - *fixed* when e < k and the neighbour is linked with a target ≥ G_e (its frame is set);
//! - *shared* (a twist, \[SV\] §3.3; for k = 0 a common corner) when e = k and the neighbour's
//!   target is ≥ G_k: both sides propose a position, the candidates are averaged, and every side
//!   is solved again with the shared points pinned;
//! - *free* otherwise (for an unlinked neighbour with e = 0 only when
//!   [`SetParams::move_unlinked_boundaries`] allows it).
//!
//! More freedom (\[SV\] §3.2 step 1): a slave whose degree across a G_r side is below r is degree
//! elevated; one with too few control rows for the frames of two opposite sides gets knots across.
//! A rational slave keeps its weights: with the weights fixed it is linear in its control points
//! through the rational basis, so the row equations stay linear ([`crate::sampling::SideBasis`]),
//! and knot insertion and degree elevation are exact in homogeneous coordinates.
//! When a side misses the tolerances after setting, the knot spans along it that hold failing
//! samples are halved and the whole slave is set again, up to
//! [`ConnectParams::max_refinements`] rounds.
//!
//! Modules: `status` (how each point of a side's row takes part in a step), `step` (one step
//! over all sides, twists averaged), `set` (the public steps: [`set_rows`], [`set_g1`], …,
//! [`set_step`] with its refinement rounds; its C0 step spreads the boundary's move into the
//! interior, `spread`), `prepare` ([`prepare_slave`]), `refine` (the knots
//! of the refinement rounds) and `connect` ([`connect_slave`]).
//!
//! # Tolerance
//! [`C0_CONVERGED`]: the C0 passes stop when no row point moves by more than this times the slave
//! size; [`C0_EXACT`](crate::rows::C0_EXACT): a row already this close to its master is not
//! refitted.
//!
//! [`SetParams::move_unlinked_boundaries`]: crate::SetParams::move_unlinked_boundaries
//! [`ConnectParams::max_refinements`]: crate::ConnectParams::max_refinements

use nurbs_core::{BSplineSurface, Continuity, Side};

use crate::error::{Error, Result};
pub(crate) use crate::link::SideLink;
use crate::measure::{LinkMeasure, MeasureParams};
/// The default net bound lives with [`ConnectParams`](crate::ConnectParams) (params.rs),
/// re-exported here.
pub use crate::params::MAX_CONTROL_POINTS;

mod connect;
mod pole;
mod prepare;
mod refine;
mod set;
mod spread;
mod status;
mod step;

pub use connect::connect_slave;
pub use prepare::{ZONE_KNOTS, prepare_slave};
pub use refine::{
    KNOT_MERGE_RELATIVE, REFINE_KNOTS_FACTOR, REFINE_MIN_GAIN, REFINE_MIN_KNOTS, REFINE_PATIENCE,
};
pub use set::{C0_FOR_G1_SHARE, StepReport, set_g0, set_g1, set_g2, set_rows, set_step};
pub use status::degenerate_corner_blocks;

/// C0 passes stop when the largest row movement is below this fraction of the slave size.
pub const C0_CONVERGED: f64 = 1e-12;

/// The end point of a row k ≥ 1 on an unlinked neighbouring side stays fixed (the free boundary
/// bit-identical) when the correction its corner sample alone asks for is below this fraction of
/// the slave size: the corner is continuous already, up to rounding of the construction.
pub const END_CONTINUOUS: f64 = 1e-9;

/// The least share of its along-side basis function's integral the part of a partial link
/// (`SideLink::range`) must hold for a point of the link's row to be decided by the part's
/// samples. Below it the function reaches the part only with the tail of an end span (cut at a
/// fraction x of a span, a degree-q tail holds of the order of x^(q+1) of the function), and the
/// least-squares solve moves the point by the residual over the tail's height. Listed on the
/// kernel models with partial links (the lofted block, a three-radii corner), every tail held at
/// most 1.5e-3 of its function (the lofted block's trimmed fillet: 8.5e-4 of a degree-13
/// function, which moved 1.1e5 mm) and every function that reaches a part with a span at least
/// 3e-2; 1 % lies in that gap (6.7 times the largest tail, a third of the smallest span),
/// chosen from the gap, not fitted to a result.
pub(crate) const PART_SHARE: f64 = 1e-2;

/// Before/after of one linked side.
#[derive(Debug, Clone, PartialEq)]
pub struct SideReport {
    /// the side
    pub side: Side,
    /// its target
    pub target: Continuity,
    /// continuity of the input slave
    pub before: LinkMeasure,
    /// continuity of the result
    pub after: LinkMeasure,
    /// whether `after` meets the tolerances up to the target
    pub met: bool,
}

/// What [`connect_slave`] did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ConnectReport {
    /// per linked side
    pub sides: Vec<SideReport>,
    /// knots inserted in total (across for row room, along for accuracy)
    pub knots_inserted: usize,
    /// rounds of knot insertion along failing sides
    pub refinements: usize,
    /// degree elevation (u, v)
    pub degree_elevation: (usize, usize),
    /// whether the slave's weights were all equal and were dropped (exact; a rational slave
    /// with unequal weights stays rational)
    pub made_polynomial: bool,
    /// twist (and shared corner) points set by averaging
    pub twists_averaged: usize,
    /// largest control point movement against the input refined the same way (model units)
    pub max_control_movement: f64,
}

/// An error when two links name the same side.
pub(crate) fn check_links(links: &[SideLink]) -> Result<()> {
    for (a, la) in links.iter().enumerate() {
        if links[..a].iter().any(|lb| lb.side == la.side) {
            return Err(Error::DuplicateSide { side: la.side });
        }
    }
    Ok(())
}

/// Whether `slave` has the control rows every link's frame needs across its side (rows 0..=r,
/// [`crate::rows::row_of`]): an error naming the side otherwise, so that no row index runs past
/// the net (a 2 × 3 net under a G2 link).
pub(crate) fn check_rows(slave: &BSplineSurface, links: &[SideLink]) -> Result<()> {
    for l in links {
        let rows = match l.side.cross_direction() {
            nurbs_core::Direction::U => slave.num_u(),
            nurbs_core::Direction::V => slave.num_v(),
        };
        let needed = crate::rows::row_of(l.target) + 1;
        if rows < needed {
            return Err(Error::TooFewRows {
                side: l.side,
                target: l.target,
                rows,
                needed,
            });
        }
    }
    Ok(())
}

/// Every link measured on `slave` (over its range), in order.
fn measure_links(
    links: &[SideLink],
    slave: &BSplineSurface,
    params: &MeasureParams,
) -> Result<Vec<LinkMeasure>> {
    links.iter().map(|l| l.measure(slave, params)).collect()
}
