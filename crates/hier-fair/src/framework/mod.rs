//! The hierarchical constrained fairing framework (\[SV\] §1.1, §3.2): every surface of a model,
//! masters before slaves, alternating fairing and continuity setting.
//!
//! # Order
//! Surfaces are grouped in *waves*: a surface with no links is in wave 0, a slave in wave
//! 1 + the largest wave of its masters. The waves run one after another; the surfaces of one wave
//! depend only on earlier waves and run in parallel (rayon). Every result is a function of the
//! input and the earlier waves only, so the output does not depend on the thread count.
//!
//! # One surface (\[SV\] §3.2)
//! 0. *prepare*: clamped, polynomial, degree ≥ r across a G_r side, and knots inserted (widest
//!    span halved) until every direction has [`FairParams::min_free_rows`] rows besides the fixed
//!    frames of both ends (step 1 of the paper);
//! 1. *set G0*: the boundary rows are fitted to the masters as they are now (faired), so the C0
//!    that step 2 keeps is C0 to the final masters;
//! 2. *fair keeping C0* (positional frame fixed on every side);
//! 3. *set G1* on the sides whose target is ≥ G1 (twists averaged, \[SV\] §3.3);
//! 4. *fair keeping G1* (tangential frame fixed on those sides, positional on the others);
//! 5. *set G2*; 6. *fair keeping G2*.
//!
//! Each side follows its link's target (capped by [`FairParams::target`]): a G0 link fixes one
//! row, G1 two, G2 three; an unlinked side keeps its boundary row. A primary without links is
//! faired once with its boundary kept.
//!
//! # Deviation
//! The deviation from the original surface never exceeds the tolerance τ (sampled on a
//! [`FairParams::deviation_grid`]² grid). Continuity comes first: the continuity steps alone
//! (0, 1, 3, 5 without fairing) are run once to find their deviation d_c. When d_c > τ the
//! highest step that stays within τ is kept and the report names the links of the first step
//! that does not, with the deviation it would need (a *conflict*). The fairing stages share the
//! rest: each gets a ball of radius ε = (σ·τ − d)/m around its input control points, d the
//! current deviation, m the fairing stages left, σ = [`DEVIATION_SAFETY`]. For a polynomial
//! B-spline a control-point move ≤ ε moves the surface ≤ ε (convex hull), so the stages cannot
//! add up past τ. A surface that is the master of some link plans with [`MASTER_SHARE`]·τ
//! instead of σ·τ: its slaves must follow its changes along their joins. If the sampled deviation still ends above τ the continuity-only result is used
//! instead (reported).
//!
//! A rational surface stays rational: with its weights fixed it is linear in its control points
//! through the rational basis R_ij ≥ 0, Σ R_ij = 1, so the row solves stay linear and a control
//! move ≤ ε still moves the surface ≤ ε. A fairing method that takes only polynomial surfaces
//! is skipped on it (reported as limited).
//!
//! # Failures
//! A surface whose continuity steps fail (a master that does not touch, a singular system) is
//! left as it was and named in the report's problems; its slaves still run against it. The run
//! never stops half-way without a report.

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use g_continuity::{ConnectParams, LinkMeasure};
use nurbs_core::{BSplineSurface, Continuity, SurfaceFairing};
use rayon::prelude::*;

use crate::error::Result;
use crate::methods::Fairers;
use crate::model::Model;

mod budget;
mod dry_run;
mod error;
mod follow;
mod group;
mod growth;
mod job;
mod masks;
mod plan;
mod polish;
mod report;
mod seams;
mod section;
mod slivers;
mod spread;
mod stages;
mod verify;
mod vertex;

pub use budget::{DEVIATION_SAFETY, DeviationBudget, GROUP_SHARE, LEAD_IN_SHARE, MASTER_SHARE};
pub use dry_run::{
    LEAD_IN_MARGIN, LEAD_IN_MAX_NARROWING, LEAD_IN_TRIALS, MIN_LEAD_IN, SLACK_ROUNDING,
};
pub use error::{StageError, StageResult};
pub use group::GroupFair;
pub use growth::{LinkGrowth, NEGLIGIBLE_GROWTH, worse_than};
pub use job::UNCHANGED_RELATIVE;
pub use masks::{smooth_join_points, stage_mask};
pub use plan::waves;
pub use report::{
    ENERGY_RISE_WHY, FairModelReport, LinkFair, Problem, ProblemKind, Progress, Stage, StageReport,
    SurfaceFair,
};
use report::{
    edge_reports, found_edge_reports, unmet_problems, worse_edge_problems, worse_link_problems,
};
pub use seams::LINKED_SEAM_FRACTION;
pub use section::{MIN_FREE_RAMP, MIN_RAMP, SECTION_TRIALS};
pub use slivers::SLIVER_MOVE_SHARE;
pub use verify::VERIFY_FACTOR;

/// The framework's [`g_continuity::SetParams::g2_move_factor`]: a lighter-weighted G2 solution
/// (closer to the exact scalar condition) is taken only when no control point moves more than the
/// paper's well-conditioned solution (\[SV\] §4.2, tangential weight 1) moves. Why 1: in the
/// framework a fairing stage follows every continuity step within a shrinking deviation budget, and
/// a move the paper's system did not need is deviation that stage no longer has — so the framework
/// takes nothing beyond the paper's own solution's largest move. `connect`, which no fairing
/// follows, allows 2×. Where G2 is missed with this bound, the dry run tries `connect`'s before
/// calling the link a conflict. Measured: on the fixtures 1× met as many links as 2× with every
/// slave's energy below its start (X-node fillet_s 18.31 → 17.74 instead of → 18.52); a vertex
/// blend between three faired fillets needs 2× next to its pole (a box's sphere corner: curvature
/// 2e-4 off at 1×, 2e-5 at 2×), which the dry run's retry gives it.
pub(crate) const FRAMEWORK_G2_MOVE_FACTOR: f64 = 1.0;

/// Share of the G1/G2 tolerances the patches of an n-sided corner group aim at when their
/// continuity is set (knots inserted until reached): around the centre vertex the patches are
/// set one after the other, each against the previous one, and the last patch must match both
/// its predecessor and the first — by the linkage-curve theorem their curvature tensors at the
/// centre all agree only up to the errors accumulated along the chain, so those must stay well
/// below the tolerance the closing patch has to meet.
pub(crate) const GROUP_CHAIN_SHARE: f64 = 0.1;

/// The frame a surface keeps, in all its fairing stages, along each side where a slave is linked
/// G1 or G2 to it: its tangent planes along the join stay as the slave's continuity was set
/// against, and its fairing cannot make the join wavy for the slaves that follow (on the X-node
/// the fillets' energy rose 2–15× while following the primaries' faired tangent rows). The
/// curvature row stays free, so the master's curvature across the join is still faired.
pub(crate) const MASTER_FRAME: nurbs_core::Frame = nurbs_core::Frame::Tangential;

/// Grid size of the sampled deviation (the same as the fairing reports), of `fair` and of
/// `connect` ([`mod@crate::connect`]).
pub(crate) const DEVIATION_GRID: usize = nurbs_core::fairing::REPORT_DEVIATION_SAMPLES;

/// Largest control net per direction the framework's knot refinement may create: 64, the
/// net of a 61-span cubic — far beyond what a fillet or corner of a kernel model needs once its
/// lead-in is placed, and a bound on the work (the row solves are dense in the samples along a
/// side) that keeps every surface of a model within seconds.
pub const MAX_NET: usize = 64;

/// The net bound per direction for refining `surface`: `bound`, or for a surface that comes in
/// with a direction near or above it (a kernel's degree-9 fillet with C0 joins has 66 columns)
/// its largest input count plus a quarter of `bound` — the room a lead-in and two halvings of the
/// spans next to each corner take — so that a dense input keeps room to be refined.
pub fn net_bound(bound: usize, surface: &BSplineSurface) -> usize {
    bound.max(surface.num_u().max(surface.num_v()) + bound / 4)
}

/// Settings of [`fair_model`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FairParams {
    /// Highest continuity set on any link (`None`: each link's own target).
    pub target: Option<Continuity>,
    /// Deviation tolerance (model units); `None`: the model's `tolerances.deviation`. A
    /// surface's own `deviation` and a role's ([`FairParams::role_tolerance`], or the model's
    /// per-role object) win over it ([`Model::deviation_of`]).
    pub tolerance: Option<f64>,
    /// Deviation tolerance per role (primary, connecting, corner; model units), over the
    /// model's per-role values; a surface's own `deviation` still wins.
    pub role_tolerance: [Option<f64>; 3],
    /// Continuity setting and measuring; its tolerances are replaced by the model's.
    pub connect: ConnectParams,
    /// Control rows per direction left free besides the fixed frames (default 2).
    pub min_free_rows: usize,
    /// Grid (per direction) of the sampled deviation (default 41).
    pub deviation_grid: usize,
    /// Run the surfaces of one wave in parallel (default true; the result is the same).
    pub parallel: bool,
    /// How each surface's deviation tolerance is shared ([`DeviationBudget`]).
    pub budget: DeviationBudget,
    /// Run the model once more with the surfaces of every unmet link at [`VERIFY_FACTOR`] times
    /// their deviation, and name each unmet link with the figure that run met it at (default
    /// true; costs one more run, only where a link is left unmet).
    pub verify_unmet: bool,
    /// Keep the continuity setting alone instead of the faired result of a surface (a master
    /// too: its slaves are then set against the setting) where the faired result's peak
    /// curvature is beyond [`crate::fairness::PEAK_FACTOR`] of its input's (after a one-hump
    /// section: where it is not fair by any figure of [`crate::fairness`]), the setting meets
    /// every link and is fairer (default true; false keeps every method's result where it meets
    /// the links, for a researcher who wants to see what the method does: `--keep-faired`).
    pub prefer_fairer: bool,
}

impl Default for FairParams {
    fn default() -> Self {
        Self {
            target: None,
            tolerance: None,
            role_tolerance: [None; 3],
            connect: ConnectParams {
                set: g_continuity::SetParams {
                    g2_move_factor: FRAMEWORK_G2_MOVE_FACTOR,
                    // the slaves of a master that took its one-hump section follow it with
                    // their whole interior ([`spread`]); the framework turns it off elsewhere
                    spread_boundary_move: true,
                    ..g_continuity::SetParams::default()
                },
                max_control_points: MAX_NET,
                ..ConnectParams::default()
            },
            min_free_rows: 2,
            deviation_grid: DEVIATION_GRID,
            parallel: true,
            budget: DeviationBudget::default(),
            verify_unmet: true,
            prefer_fairer: true,
        }
    }
}

/// Fairs `model` with the workspace methods of `methods` (see [`fair_model_with`]).
pub fn fair_model(
    model: &Model,
    methods: &crate::methods::RoleMethods,
    iterations: Option<usize>,
    params: &FairParams,
) -> Result<(Model, FairModelReport)> {
    let built = crate::methods::BuiltMethods::new(methods, iterations);
    fair_model_with(model, built.fairers(), params, &|_| {})
}

/// Fairs every surface of `model` in hierarchy order with the given methods (\[SV\] §3.2), calling
/// `progress` after each surface. An invalid model is an error; anything that goes wrong with a
/// single surface is a problem in the report (the surface is left as it was).
pub fn fair_model_with(
    model: &Model,
    fairers: Fairers<'_>,
    params: &FairParams,
    progress: &(dyn Fn(Progress<'_>) + Sync),
) -> Result<(Model, FairModelReport)> {
    let start = Instant::now();
    model.validate()?;
    let tolerance = params.tolerance.unwrap_or(model.tolerances.deviation);
    let mut connect = params.connect;
    connect.tolerances = model.tolerances.continuity();
    let cap = |c: Continuity| params.target.map_or(c, |t| c.min(t));
    // shared edges no link covers: those down the hierarchy become links (over the part of the
    // side that lies on the other surface; kept out of the output model and reported with the
    // edges), the rest are kept as they came
    let given = model;
    let all_edges = crate::edges::shared_edges(given);
    let (work, found, ranges) = crate::edges::link_edges(given, &all_edges);
    let model = &work;
    let edges = crate::edges::not_linked(all_edges, model);
    let edges_before = measure_edges(model, &edges);
    let plan = Plan {
        model,
        fairers,
        params,
        connect: &connect,
        cap: &cap,
        before: &measure_links(model, &ranges, &connect),
        edges: &edges,
        edges_before: &edges_before,
        ranges: &ranges,
        no_section: &[],
        sectioned: &[],
    };
    let mut start_model = model.clone();
    let slivers = slivers::merge_slivers(&mut start_model, connect.tolerances.g0, |m, k| {
        m.deviation_of(k, &params.role_tolerance, params.tolerance)
    });
    let (mut out, mut report, links) =
        plan.run_following(&start_model, &slivers, tolerance, progress)?;
    report.links = links;
    report
        .edges
        .extend(found_edge_reports(model, &found, &report.links));
    report.links.truncate(given.links.len());
    // the zones named on the model with its found links: a corner a found link's master makes
    // a conflict is one too ([`crate::zones`])
    let zoned = vertex::zone_problems(&out, &ranges, &report.links, connect.tolerances.g2_rel);
    out.links.truncate(given.links.len());
    let unmet = unmet_problems(model, &report.links);
    report.problems.extend(unmet);
    report.problems.extend(zoned);
    let worse = worse_link_problems(model, &out, &report.links);
    report.problems.extend(worse);
    let after_edges = measure_edges(&out, &edges);
    report
        .edges
        .extend(edge_reports(model, &edges, edges_before, after_edges));
    let worse = worse_edge_problems(&report.edges);
    report.problems.extend(worse);
    if params.verify_unmet {
        let needed = verify::verify_unmet(given, fairers, params, &report);
        report.problems.extend(needed);
    }
    report.seconds_total = start.elapsed().as_secs_f64();
    Ok((out, report))
}

/// Every shared edge measured on the surfaces of `on`.
fn measure_edges(on: &Model, edges: &[crate::edges::SharedEdge]) -> Vec<crate::edges::EdgeMeasure> {
    edges
        .iter()
        .map(|e| {
            crate::edges::measure_edge(
                e,
                &on.surfaces[e.surface].surface,
                &on.surfaces[e.other].surface,
            )
        })
        .collect()
}

/// What a run of [`fair_model_with`] works from: the model with its found links, the methods,
/// the settings, and the input's measures every result is held against.
#[derive(Clone, Copy)]
struct Plan<'a> {
    model: &'a Model,
    fairers: Fairers<'a>,
    params: &'a FairParams,
    connect: &'a ConnectParams,
    cap: &'a (dyn Fn(Continuity) -> Continuity + Sync),
    /// every link measured on the input
    before: &'a [Option<LinkMeasure>],
    /// the shared edges no link covers, and their measures on the input
    edges: &'a [crate::edges::SharedEdge],
    edges_before: &'a [crate::edges::EdgeMeasure],
    /// per link, the part of the slave's side it holds on
    ranges: &'a [Option<(f64, f64)>],
    /// per surface, whether its one-hump section is withdrawn ([`follow`]; empty: none is)
    no_section: &'a [bool],
    /// per surface, whether it took its one-hump section in this run (set as each finishes;
    /// its slaves then spread their boundary's move, [`spread`]; empty: none did)
    sectioned: &'a [AtomicBool],
}

/// Every link of `model` measured (over its part of the side, `ranges`, [`crate::edges`]).
fn measure_links(
    model: &Model,
    ranges: &[Option<(f64, f64)>],
    connect: &ConnectParams,
) -> Vec<Option<LinkMeasure>> {
    (0..model.links.len())
        .into_par_iter()
        .map(|k| {
            let l = &model.links[k];
            let zones = crate::zones::link_zones(model, ranges, k, &connect.tolerances);
            g_continuity::measure::measure_link_zoned(
                &model.surfaces[l.master].surface,
                &model.surfaces[l.slave].surface,
                l.side,
                ranges.get(k).copied().flatten(),
                zones,
                &connect.measure,
            )
            .ok()
        })
        .collect()
}

struct Outcome {
    surface: BSplineSurface,
    report: SurfaceFair,
    problems: Vec<Problem>,
}

#[derive(Clone, Copy)]
struct Job<'a> {
    model: &'a Model,
    current: &'a Model,
    /// where the stages start: the input, or the corner group's refitted patch
    start: &'a BSplineSurface,
    surface: usize,
    fairing: &'a dyn SurfaceFairing,
    tolerance: f64,
    connect: &'a ConnectParams,
    params: &'a FairParams,
    cap: &'a (dyn Fn(Continuity) -> Continuity + Sync),
    /// every link of the model measured on the input (the "never worse" reference)
    before: &'a [Option<LinkMeasure>],
    /// the model's shared edges no link covers ([`crate::edges`]): kept as they came
    edges: &'a [crate::edges::SharedEdge],
    /// per link of the model, the part of the slave's side it holds on (`None`: all of it)
    ranges: &'a [Option<(f64, f64)>],
    /// whether the continuity steps may move the frame of a shared edge with a surface of the
    /// same role ([`crate::edges::is_seam`]); the fairing stages keep it either way
    free_seams: bool,
    /// whether the one-hump section may be tried ([`section`]; withdrawn by [`follow`])
    section_allowed: bool,
    /// whether the C0 steps spread the boundary's move into the interior ([`spread`])
    spread: bool,
}

/// Per-surface state while the stages run.
struct Run<'a> {
    original: &'a BSplineSurface,
    grid: usize,
    stages: Vec<StageReport>,
    /// when the last stage was recorded (or the run began): a stage's seconds run from here
    last: std::time::Instant,
}

/// The continuity steps alone from one prepared surface.
struct DryRun {
    /// each step with its result and its sampled deviation from the original
    steps: Vec<(Continuity, BSplineSurface, f64)>,
    /// whether the last step met every link's tolerances
    met: bool,
    /// per step, whether it met every link up to its level
    met_steps: Vec<bool>,
    /// the links (in the order given) measured on the last step's result
    after: Vec<LinkMeasure>,
    /// the prepared surface the steps started from
    prepared: BSplineSurface,
    /// whether a step met only with turned corner tangents (`SetParams::tangent_corners`);
    /// the stages then turn them too, or their C0 rows undo the corners the dry run made
    tangent_corners: bool,
    /// the ramp (fraction of the section at each G2 end) where the steps started from the
    /// one-hump section ([`section`]): the section is the surface's G2 lead-in, so the stages
    /// fair its setting once keeping G2 — a fairing keeping only C0 or G1 first would move the
    /// ramps the section placed
    section_ramp: Option<f64>,
    /// whether the C0 step spread its boundary move into the interior
    /// (`SetParams::spread_boundary_move`); the stages' set steps do the same
    spread: bool,
}
