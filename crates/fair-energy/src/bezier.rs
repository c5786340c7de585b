//! The Bézier-spline extension of \[H\] part ② as one flow: surfaces whose interior knots have full
//! multiplicity (C⁰-joined Bézier patches) come back C¹ at those knots.
//!
//! \[H\] slide "Extension to Bézier-spline surfaces":
//! 1. check every joint (interior knot of multiplicity p) for C¹ continuity ([`crate::joints`]);
//! 2. where it is C¹, remove the knot once (exact: nurbs-core's knot removal with a round-off
//!    tolerance, \[NB\] A5.8) — optional, see [`KnotRemoval`];
//! 3. fair with Φ = (1 − λ) Π + λ Σ (cross-derivative jumps at the remaining joints)²
//!    ([`crate::stiffness`], the local scheme of [`crate::local`]) within ε − m, where m is the
//!    largest move of the smallest C¹ correction of the input (reserved for step 4, at most
//!    [`JOINT_RESERVE_MAX`] ε; without the reserve the fairing fills the ε-balls and the finish
//!    has no room left — a noisy or curved surface then kept its kinks);
//! 4. finish: project the free points minimally so that every joint is exactly C¹ inside the
//!    ε-balls ([`crate::c1_finish`]); joints that ε does not allow to close are reported with their
//!    remaining jump, never hidden;
//! 5. optionally remove the now-C¹ knots as in 2: the surface is then C¹ by construction.
//!
//! Step 3 never raises Φ; step 4 ignores the energy (it moves the joint triples the least
//! distance), so the thin-plate energy of the result is not guaranteed below the input's — the
//! report carries both values (on the C⁰-joined test surface: 19.9 → 6.3).
//!
//! # Knot removal and the mask
//! Removing a knot of multiplicity p once deletes exactly the control row (column) on the joint
//! and leaves every other point bit-identical (the polygon P_{j−1}, P_{j+1} already describes the
//! C¹ curve); the returned [`ControlMask`] is the input mask without that row, and
//! [`BezierSplineReport::kept_u`] / [`BezierSplineReport::kept_v`] map the output net back to the
//! input. Which joints may go is the caller's choice ([`KnotRemoval`]); every kept fixed point
//! stays bit-identical either way, and ε is measured against each kept point's original.
//!
//! # Tolerance
//! C¹ means a relative jump ≤ [`C1_JUMP_REL`]; the removal itself is accepted by nurbs-core only
//! within [`EXACT_REMOVAL_REL_TOL`] × the net's size (a round-off-level bound on the surface
//! change).

use nurbs_core::energy::thin_plate_energy;
use nurbs_core::knot_ops::EXACT_REMOVAL_REL_TOL;
use nurbs_core::{BSplineSurface, ControlMask, Direction, Faired, FairingProblem, SurfaceFairing};

use crate::c1_finish::project_to_c1;
use crate::error::{EnergyError, Result, check_tolerance};
use crate::joints::{C1_JUMP_REL, SurfaceJoint, surface_joints};
use crate::local::LocalOutcome;
use crate::surface::{EnergyParams, fair_surface};

/// Which C¹ joints may lose their knot (to multiplicity p − 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KnotRemoval {
    /// keep every knot: the net keeps its shape (C¹ by the control-point condition only)
    Keep,
    /// remove only joints whose whole control row (column) is free: no fixed point is deleted
    WhereFree,
    /// also remove joints that fixed points lie on, provided each such point's two neighbours
    /// across the joint are fixed too (a fixed frame crossing the joint, e.g. the positional
    /// frame of the sides V0/V1 crossing a u-joint): the frame keeps its rows, its curve is
    /// unchanged up to round-off and holds one control point fewer. Knot vectors along those
    /// sides change, which matters when a neighbour must share them.
    ThroughFixedFrames,
}

/// Settings of the Bézier-spline flow.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BezierSplineParams {
    /// The local scheme; its `joint_weight` is λ. Default: [`EnergyParams::default`] with
    /// λ = 0.9, the middle of \[H\]'s examples (0.85–0.95, \[H\] "Examples (4)–(6)").
    pub energy: EnergyParams,
    /// Step 2, before fairing. Default [`KnotRemoval::ThroughFixedFrames`]: \[H\] removes
    /// every C¹ joint (\[H\] "Extension", ②) and the removal is exact.
    pub initial_removal: KnotRemoval,
    /// Step 5, after the finishing projection. Default [`KnotRemoval::Keep`]: the joints are C¹
    /// by their control points already; removing them is the caller's choice.
    pub final_removal: KnotRemoval,
}

impl Default for BezierSplineParams {
    fn default() -> Self {
        Self {
            energy: EnergyParams {
                joint_weight: 0.9,
                ..EnergyParams::default()
            },
            initial_removal: KnotRemoval::ThroughFixedFrames,
            final_removal: KnotRemoval::Keep,
        }
    }
}

/// A joint the run could not make C¹.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointGap {
    /// the knot's direction
    pub direction: Direction,
    /// the knot value
    pub knot: f64,
    /// largest cross-derivative jump left (model units per parameter unit)
    pub jump: f64,
    /// the same relative to the joint's largest one-sided derivative (unit-free)
    pub relative_jump: f64,
}

/// What a Bézier-spline run achieved.
#[derive(Debug, Clone, PartialEq)]
pub struct BezierSplineReport {
    /// joints (interior knots of full multiplicity) of the input
    pub joints: usize,
    /// knots removed in step 2 (already C¹)
    pub knots_removed_before: usize,
    /// the local fairing run (values of Φ on the net after step 2)
    pub fairing: LocalOutcome,
    /// joints that were not C¹ before fairing and are C¹ at the end (removed in step 5 or not)
    pub joints_made_c1: usize,
    /// knots removed in step 5
    pub knots_removed_after: usize,
    /// largest cross-derivative jump over the input's joints (model units per parameter unit)
    pub max_jump_before: f64,
    /// largest jump over the joints left at the end (0 when none is left)
    pub max_jump_after: f64,
    /// the joints left non-C¹ (empty when every joint was closed)
    pub open_joints: Vec<JointGap>,
    /// thin-plate energy Π of the input
    pub energy_before: f64,
    /// thin-plate energy Π of the output (the same functional: knot removal is exact)
    pub energy_after: f64,
    /// largest distance of a kept control point from its original (model units)
    pub max_control_move: f64,
    /// for each row i of the output net, its row in the input net
    pub kept_u: Vec<usize>,
    /// for each column j of the output net, its column in the input net
    pub kept_v: Vec<usize>,
}

/// The net being worked on, with its mask and the map back to the input.
struct Net {
    surface: BSplineSurface,
    mask: ControlMask,
    kept_u: Vec<usize>,
    kept_v: Vec<usize>,
}

impl Net {
    fn shape(&self) -> (usize, usize) {
        (self.surface.num_u(), self.surface.num_v())
    }

    /// Whether `policy` lets the knot of `joint` go (C¹ is checked separately).
    fn may_remove(&self, joint: &SurfaceJoint, policy: KnotRemoval) -> bool {
        let (nu, nv) = self.shape();
        let lines = joint.lines(nu, nv);
        let fixed = |r: usize| !self.mask.as_slice()[r];
        match policy {
            KnotRemoval::Keep => false,
            KnotRemoval::WhereFree => (0..lines).all(|k| !fixed(joint.triple(k, nv)[1])),
            KnotRemoval::ThroughFixedFrames => (0..lines).all(|k| {
                let [a, b, c] = joint.triple(k, nv);
                !fixed(b) || (fixed(a) && fixed(c))
            }),
        }
    }

    /// Removes every C¹ joint `policy` allows; returns how many.
    fn remove_c1_joints(&mut self, policy: KnotRemoval) -> Result<usize> {
        if policy == KnotRemoval::Keep {
            return Ok(0);
        }
        let mut removed = 0;
        // indices shift after each removal: rescan until nothing more goes
        'scan: loop {
            let (nu, nv) = self.shape();
            for joint in surface_joints(&self.surface) {
                let points = self.surface.control_points();
                if !(self.may_remove(&joint, policy) && joint.is_c1(points, nu, nv)) {
                    continue;
                }
                let tolerance = EXACT_REMOVAL_REL_TOL * self.surface.size().max(f64::MIN_POSITIVE);
                let (next, count) =
                    self.surface
                        .remove_knot(joint.direction, joint.joint.knot, 1, tolerance)?;
                if count != 1 || next.num_u() * next.num_v() + joint.lines(nu, nv) != nu * nv {
                    continue;
                }
                self.drop_line(joint.direction, joint.joint.index);
                self.surface = next;
                removed += 1;
                continue 'scan;
            }
            return Ok(removed);
        }
    }

    /// Largest distance of a kept control point from its original in `input`.
    fn max_move_from(&self, input: &BSplineSurface) -> f64 {
        let out_nv = self.kept_v.len();
        self.surface
            .control_points()
            .iter()
            .enumerate()
            .map(|(r, p)| {
                let (i, j) = (self.kept_u[r / out_nv], self.kept_v[r % out_nv]);
                (p - input.control_point(i, j)).norm()
            })
            .fold(0.0, f64::max)
    }

    /// Drops row (u) or column (v) `index` from the mask and the index maps.
    fn drop_line(&mut self, direction: Direction, index: usize) {
        let (nu, nv) = self.shape();
        let (mu, mv) = match direction {
            Direction::U => (nu - 1, nv),
            Direction::V => (nu, nv - 1),
        };
        let mut mask = ControlMask::all_free(mu, mv);
        for i in 0..mu {
            for j in 0..mv {
                let (si, sj) = match direction {
                    Direction::U => (i + usize::from(i >= index), j),
                    Direction::V => (i, j + usize::from(j >= index)),
                };
                mask.set_free(i, j, self.mask.is_free(si, sj));
            }
        }
        self.mask = mask;
        match direction {
            Direction::U => self.kept_u.remove(index),
            Direction::V => self.kept_v.remove(index),
        };
    }
}

fn largest_jump(surface: &BSplineSurface) -> f64 {
    let (nu, nv) = (surface.num_u(), surface.num_v());
    surface_joints(surface)
        .iter()
        .map(|j| j.measure(surface.control_points(), nu, nv).0)
        .fold(0.0, f64::max)
}

/// Largest share of ε reserved for the C¹ finish (see [`fair_bezier_spline`]); a larger
/// correction means the joints cannot be closed within ε anyway, and the fairing gets all of ε.
pub const JOINT_RESERVE_MAX: f64 = 0.9;

/// Fairs a Bézier-spline surface and makes its joints C¹ (module docs), moving only points `mask`
/// frees, each within `tolerance` (model units) of its original. Returns the surface, its mask
/// (the input mask without removed rows) and the report.
pub fn fair_bezier_spline(
    surface: &BSplineSurface,
    mask: &ControlMask,
    tolerance: f64,
    params: &BezierSplineParams,
) -> Result<(BSplineSurface, ControlMask, BezierSplineReport)> {
    check_tolerance(tolerance)?;
    params.energy.check()?;
    mask.check_shape(surface)?;
    if surface.is_rational() {
        return Err(EnergyError::Rational { what: "surface" });
    }
    let joints = surface_joints(surface).len();
    let max_jump_before = largest_jump(surface);
    let energy_before = thin_plate_energy(surface);
    let mut net = Net {
        surface: surface.clone(),
        mask: mask.clone(),
        kept_u: (0..surface.num_u()).collect(),
        kept_v: (0..surface.num_v()).collect(),
    };
    // 2. exact removal of the joints that are C¹ already
    let knots_removed_before = net.remove_c1_joints(params.initial_removal)?;
    // 3. fairing with Φ; the origin of the ε-balls is the (bit-identical) kept input points
    // with part of ε reserved for the joints
    let origin = net.surface.clone();
    let (nu, nv) = (origin.num_u(), origin.num_v());
    let joints_left = surface_joints(&origin);
    let reserve = joint_reserve(&origin, &joints_left, &net.mask, tolerance)?;
    let (mut faired, fairing) =
        fair_surface(&origin, &net.mask, tolerance - reserve, &params.energy)?;
    // 4. the C¹ finish
    let was_c1: Vec<bool> = joints_left
        .iter()
        .map(|j| j.is_c1(origin.control_points(), nu, nv))
        .collect();
    project_to_c1(
        &joints_left,
        faired.control_points_mut(),
        origin.control_points(),
        net.mask.as_slice(),
        (nu, nv),
        tolerance,
    )?;
    let (joints_made_c1, open_joints) = joints_after_finish(&joints_left, &was_c1, &faired);
    // 5. optional exact removal of the now-C¹ joints
    net.surface = faired;
    let knots_removed_after = net.remove_c1_joints(params.final_removal)?;
    let energy_after = thin_plate_energy(&net.surface);
    let max_control_move = net.max_move_from(surface);
    let report = BezierSplineReport {
        joints,
        knots_removed_before,
        fairing,
        joints_made_c1,
        knots_removed_after,
        max_jump_before,
        max_jump_after: largest_jump(&net.surface),
        open_joints,
        energy_before,
        energy_after,
        max_control_move,
        kept_u: net.kept_u,
        kept_v: net.kept_v,
    };
    Ok((net.surface, net.mask, report))
}

/// The share of ε reserved for the C¹ finish: the largest move m of the smallest C¹ correction
/// of `origin`, which is about what the finish will need (the λ-terms shrink the jumps while
/// fairing), so that the fairing stays within ε − m and does not use up the balls the finish
/// has to move in; 0 when m ≥ [`JOINT_RESERVE_MAX`] ε.
fn joint_reserve(
    origin: &BSplineSurface,
    joints: &[SurfaceJoint],
    mask: &ControlMask,
    tolerance: f64,
) -> Result<f64> {
    let mut trial = origin.clone();
    project_to_c1(
        joints,
        trial.control_points_mut(),
        origin.control_points(),
        mask.as_slice(),
        (origin.num_u(), origin.num_v()),
        tolerance,
    )?;
    let m = trial
        .control_points()
        .iter()
        .zip(origin.control_points())
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max);
    Ok(if m < JOINT_RESERVE_MAX * tolerance {
        m
    } else {
        0.0
    })
}

/// After the finish: how many of `joints` that were not C¹ (`was_c1`) are C¹ on `faired`, and
/// the joints left open with their remaining jump.
fn joints_after_finish(
    joints: &[SurfaceJoint],
    was_c1: &[bool],
    faired: &BSplineSurface,
) -> (usize, Vec<JointGap>) {
    let (nu, nv) = (faired.num_u(), faired.num_v());
    let mut joints_made_c1 = 0;
    let mut open_joints = Vec::new();
    for (joint, &before) in joints.iter().zip(was_c1) {
        let (jump, scale) = joint.measure(faired.control_points(), nu, nv);
        if jump <= C1_JUMP_REL * scale {
            joints_made_c1 += usize::from(!before);
        } else {
            open_joints.push(JointGap {
                direction: joint.direction,
                knot: joint.joint.knot,
                jump,
                relative_jump: if scale > 0.0 {
                    jump / scale
                } else {
                    f64::INFINITY
                },
            });
        }
    }
    (joints_made_c1, open_joints)
}

/// The Bézier-spline flow as a framework method (`energy-bezier`). The fairing contract keeps
/// the net ([`nurbs_core::check_contract`]): with a removal policy other than
/// [`KnotRemoval::Keep`] the returned net may be smaller than the input, which the runner
/// refuses; call [`fair_bezier_spline`] directly for that flow.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BezierSplineFairing {
    /// its settings
    pub params: BezierSplineParams,
}

/// Name of the Bézier-spline method.
pub const BEZIER_METHOD: &str = "energy-bezier";

impl SurfaceFairing for BezierSplineFairing {
    fn name(&self) -> &str {
        BEZIER_METHOD
    }

    /// `max_iterations` limits the local moves (the per-free-point floor then does not apply).
    fn fair(&self, problem: &FairingProblem<'_>) -> nurbs_core::Result<Faired> {
        let mut params = self.params;
        if let Some(n) = problem.max_iterations {
            params.energy.max_iterations = n;
            params.energy.min_iterations_per_free_point = 0;
        }
        let (out, _, r) =
            fair_bezier_spline(problem.surface, problem.mask, problem.tolerance, &params)
                .map_err(|e| e.into_core(BEZIER_METHOD))?;
        Ok(Faired::new(out, r.fairing.iterations))
    }
}
