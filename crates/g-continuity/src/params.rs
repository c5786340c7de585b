//! Settings of continuity setting (\[SV\] §4) and their defaults.

use nurbs_core::ProjectionParams;

use crate::measure::MeasureParams;

/// Weight of the G1 rows that keep the tangential part of the cross derivative, relative to the
/// rows of the G1 condition itself. The condition n·ê = 0 alone admits ê = 0 (a collapsed
/// cross derivative); the paper keeps the tangential part exactly (\[SV\] eq. (3)). A small weight
/// keeps it as far as the condition allows: the remaining normal residual is of order
/// weight² × the tangential change an exact join needs. Too small a weight lets the solve fit
/// noise with huge tangential moves (1e-6 moved a car-shell row by 3 units); 1e-2 is safe, and
/// the later passes shrink it where the moves stay plausible.
pub const G1_TANGENTIAL_WEIGHT: f64 = 1e-2;

/// Weight of the minimal-deviation G2 rows that keep the tangential part of the change of the
/// curvature row at each sample, relative to the rows of the G2 condition (default of
/// [`SetParams::g2_tangential_weight`]). With weight 1 the system is the paper's (\[SV\] §4.2):
/// the change Σ_j M_j(t_k) d_j is to be the normal vector β_k n_k, a well-conditioned fit.
pub const G2_TANGENTIAL_WEIGHT: f64 = 1.0;

/// Default of [`SetParams::g2_move_factor`]: a lighter-weighted G2 solution is accepted only while
/// no point moves more than this factor times the largest move of the first (weight 1) solution.
pub const G2_MOVE_FACTOR: f64 = 2.0;

/// Passes of the G1 solve (default of [`SetParams::g1_passes`]): the first with the tangential
/// weight of the parameters, each further one from the previous result with the weight divided
/// by [`crate::rows::G1_WEIGHT_STEP`] (a continuation towards the exact G1 condition).
pub const G1_PASSES: usize = 3;

/// Largest number of control points per direction knot insertion may create (a guard against
/// runaway refinement on joins that cannot be made continuous).
pub const MAX_CONTROL_POINTS: usize = 1024;

/// How the G2 row equations are solved (\[SV\] §4.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum G2Method {
    /// Each curvature-row point moves along the slave normal at its Greville abscissa (the
    /// paper's "solution by fixed directions"); QR.
    FixedDirections,
    /// Each point moves freely in 3D, minimum total movement (the paper's "solution by minimal
    /// deviation", solved as a minimum-norm least-squares problem); SVD.
    #[default]
    MinimalDeviation,
}

/// Settings of the row solves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SetParams {
    /// Solve samples per knot span along the side (default 10: for bicubic pieces with matching
    /// parametrization the G1 condition (M_u × M_v) · S_u is a polynomial of degree 8 per span, so
    /// 9 samples make it vanish on the whole span, not only at the samples).
    pub samples_per_span: usize,
    /// At least this many solve samples per side (default 101, as [`MeasureParams::samples`]).
    pub min_samples: usize,
    /// G2 variant (default minimal deviation: exact where an exact join exists).
    pub g2_method: G2Method,
    /// Whether the end points of a row may move when the neighbouring side of the slave is not
    /// linked (they lie on that free boundary). Default true: an end point whose corner sample is
    /// already continuous stays where it is anyway (the free boundary bit-identical, see
    /// [`crate::slave::END_CONTINUOUS`]); the others move, changing the free boundary by what the
    /// corner needs. False: they never move, and such corner samples keep their original error.
    pub move_unlinked_boundaries: bool,
    /// Weight of the rows that keep the tangential part of the cross derivative in the G1 solve,
    /// relative to the G1 condition (default [`G1_TANGENTIAL_WEIGHT`]).
    pub g1_tangential_weight: f64,
    /// Weight of the rows that keep the tangential part of the curvature-row change in the
    /// minimal-deviation G2 solve, relative to the G2 condition (default
    /// [`G2_TANGENTIAL_WEIGHT`]: the paper's system).
    pub g2_tangential_weight: f64,
    /// The minimal-deviation G2 solve relaxes the tangential rows only while no point moves more
    /// than this factor times the largest move of the first solution (default
    /// [`G2_MOVE_FACTOR`]; 0 keeps the first solution).
    pub g2_move_factor: f64,
    /// G1 passes, each from the previous result (default [`G1_PASSES`]).
    pub g1_passes: usize,
    /// C0 passes (each re-projects the boundary onto the master; default 4, the foot points
    /// converge linearly with a factor of the gap curvature, so 2–3 usually suffice).
    pub c0_iterations: usize,
    /// Projection onto the masters (kernel defaults).
    pub projection: ProjectionParams,
    /// After each C0 step, turn the end tangents of the boundary rows into the tangent plane of
    /// the neighbouring side's master where that side carries G1 or more (default off: it moves
    /// a point the boundary fit chose, which costs curvature accuracy at the corner; callers
    /// turn it on where a corner's normal misses, see `slave::tangent_corners`).
    pub tangent_corners: bool,
    /// Unlinked sides whose tangential frame (boundary row and the row next to it) no step
    /// moves, in the order u0, u1, v0, v1 (default none): a side the slave shares with another
    /// surface that no link covers keeps its join as it came. The rows of the linked sides end
    /// on it there, so their end points stay too.
    pub kept_sides: [bool; 4],
    /// Unlinked sides the slave shares with a surface that is faired in the same wave (a seam
    /// of a closed fillet cut into parts), in the order u0, u1, v0, v1 (default none): after
    /// each C0 step, a linked side's boundary row that ends on one has its end tangent turned
    /// into its own master's tangent plane there (see `slave::seam_end_tangents`), so that both
    /// parts of the seam take the master's normal at its end.
    pub seam_end_tangents: [bool; 4],
    /// Per side (u0, u1, v0, v1) and end (start, end of the side's parameter): the direction
    /// in which a contact line leaves that corner (default none) — where the neighbouring
    /// side's master is itself linked to this side's master along a boundary through the
    /// corner, the curve the two masters touch along. After each C0 step the side's boundary
    /// row is turned there to leave the corner along it where the line continues the boundary
    /// (within 45°; see `slave::contact_line_tangents`).
    pub contact_lines: [[Option<[f64; 3]>; 2]; 4],
    /// Whether the C0 step moves the interior control points with the boundary rows it moves:
    /// the Coons blend of the boundary's moves (`slave::spread`), so that a master that changed
    /// shape is followed by the whole slave, not by a strip beside the side. Default false: a
    /// caller that knows its masters changed turns it on (hier-fair's framework does, for the
    /// slaves of a master that took a one-hump section).
    pub spread_boundary_move: bool,
}

impl Default for SetParams {
    fn default() -> Self {
        Self {
            samples_per_span: 10,
            min_samples: crate::measure::DEFAULT_SAMPLES,
            g2_method: G2Method::default(),
            move_unlinked_boundaries: true,
            g1_tangential_weight: G1_TANGENTIAL_WEIGHT,
            g1_passes: G1_PASSES,
            g2_tangential_weight: G2_TANGENTIAL_WEIGHT,
            g2_move_factor: G2_MOVE_FACTOR,
            c0_iterations: 4,
            projection: ProjectionParams::default(),
            tangent_corners: false,
            kept_sides: [false; 4],
            seam_end_tangents: [false; 4],
            contact_lines: [[None; 2]; 4],
            spread_boundary_move: false,
        }
    }
}

/// Continuity tolerances: the targets that decide whether more freedom (knot insertion) is
/// needed. Defaults: Class-A values (0.001 mm, 0.01°, 0.02).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// largest gap (model units)
    pub g0: f64,
    /// largest normal angle (degrees)
    pub g1_deg: f64,
    /// largest relative normal-curvature difference
    pub g2_rel: f64,
}

impl Default for Tolerances {
    fn default() -> Self {
        Self {
            g0: 1e-3,
            g1_deg: 1e-2,
            g2_rel: 2e-2,
        }
    }
}

/// Settings of [`crate::connect_slave`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConnectParams {
    /// the row solves
    pub set: SetParams,
    /// measurement before/after (and of the refinement test)
    pub measure: MeasureParams,
    /// targets; a side above them gets knots inserted and is solved again
    pub tolerances: Tolerances,
    /// rounds of knot insertion along failing sides (default 6: each halves the spans where the
    /// tolerance is missed, so a span can shrink to 1/64; the trimmed-master test needs 4–6)
    pub max_refinements: usize,
    /// Smallest gap (model units) worth aiming at in [`crate::set_step`]'s C0 step when G1/G2
    /// follow (see [`crate::C0_FOR_G1_SHARE`]), e.g. a known error of the masters below which
    /// the joins cannot get. Default 0.
    pub c0_floor: f64,
    /// Width of the curvature lead-in [`crate::prepare_slave`] places at every G2 side, as a
    /// fraction of the cross domain ([`crate::lead_in`]); `None` (default): none, the freedom
    /// comes from knots inserted where the tolerances are missed.
    pub lead_in: Option<f64>,
    /// Largest number of control points per direction that knot insertion along failing sides
    /// may create (default [`MAX_CONTROL_POINTS`]); a side that would need more
    /// keeps its best round.
    pub max_control_points: usize,
    /// Whether [`crate::prepare_slave`] first makes each side's along spline space compatible
    /// with its master's ([`crate::transfer`]: degree and the master's knots along the join),
    /// where the slave's along direction is a single polynomial piece. Default `true`.
    pub transfer_knots: bool,
}

impl Default for ConnectParams {
    fn default() -> Self {
        Self {
            set: SetParams::default(),
            measure: MeasureParams::default(),
            tolerances: Tolerances::default(),
            max_refinements: 6,
            c0_floor: 0.0,
            lead_in: None,
            max_control_points: MAX_CONTROL_POINTS,
            transfer_knots: true,
        }
    }
}
