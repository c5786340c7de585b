//! The interface every fairing method implements, and the one runner that measures it.
//!
//! A method receives a [`FairingProblem`]: a surface, a [`ControlMask`] (only free control
//! points may move: the fixed frames of \[SV\] §3.1 must come back bit-identical), the deviation
//! tolerance ε, the continuity the calling stage keeps and an optional iteration limit. It
//! returns the faired surface and its iteration count ([`Faired`]), nothing else: the runner
//! [`FairingProblem::solve`] times the call, checks the result against the contract
//! ([`check_contract`]) and measures the [`FairingReport`] the same way for every method, so
//! that a caller (the framework, the CLI, a test) never takes a result that moved a fixed point
//! or left the tolerance. [`FairingProblem::run`] does the same without the measurements, for a
//! caller that measures what it needs itself.
//!
//! ```
//! use nurbs_core::{BSplineSurface, ControlMask, Faired, FairingProblem, KnotVector, Point3,
//!     SurfaceFairing};
//!
//! /// A method that moves every free point halfway to the centroid of the net, clamped to ε.
//! struct Shrink;
//! impl SurfaceFairing for Shrink {
//!     fn name(&self) -> &str { "shrink" }
//!     fn fair(&self, problem: &FairingProblem<'_>) -> nurbs_core::Result<Faired> {
//!         let (s, eps) = (problem.surface, problem.tolerance);
//!         let n = s.control_points().len() as f64;
//!         let c = s.control_points().iter().fold(Point3::origin(), |a, p| a + p.coords / n);
//!         let mut out = s.clone();
//!         let nv = s.num_v();
//!         for (k, p) in out.control_points_mut().iter_mut().enumerate() {
//!             if problem.mask.is_free(k / nv, k % nv) {
//!                 let d = (c - *p) * 0.5;
//!                 *p += d * (eps * 0.999 / d.norm().max(eps));
//!             }
//!         }
//!         Ok(Faired::new(out, 1))
//!     }
//! }
//!
//! let k = KnotVector::clamped_uniform(3, 6).unwrap();
//! let pts = (0..36).map(|r| Point3::new((r / 6) as f64, (r % 6) as f64, ((r * 7) % 5) as f64)).collect();
//! let s = BSplineSurface::new(k.clone(), k, pts, None).unwrap();
//! let mut mask = ControlMask::all_free(6, 6);
//! mask.set_free(0, 0, false);
//! let (faired, report) = FairingProblem::new(&s, &mask, 0.1).solve(&Shrink).unwrap();
//! assert_eq!(faired.control_points()[0], s.control_points()[0]);
//! assert!(report.max_control_move <= 0.1);
//! assert!(report.energy_after < report.energy_before);
//! ```

use crate::Point3;
use crate::energy::{max_deviation, thin_plate_energy};
use crate::error::{Error, Result};
use crate::frames::{Continuity, ControlMask};
use crate::surface::BSplineSurface;

/// Samples per direction of the sampled deviation in reports.
pub const REPORT_DEVIATION_SAMPLES: usize = 41;

/// Factor (just below 1) applied to ε when a fairing method puts a point onto its tolerance
/// sphere, so that the stored point is within ε despite rounding (one value for every method).
pub const BALL_SHRINK: f64 = 1.0 - 1e-12;

/// Largest distance between corresponding points of two equally long lists (the largest
/// control-point or vertex move of a run; 0 for empty lists).
pub fn max_displacement(before: &[Point3], after: &[Point3]) -> f64 {
    before
        .iter()
        .zip(after)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max)
}

/// What a fairing run achieved.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FairingReport {
    /// the method's name
    pub method: String,
    /// iterations (steps, sweeps or solves) performed
    pub iterations: usize,
    /// thin-plate energy before
    pub energy_before: f64,
    /// thin-plate energy after
    pub energy_after: f64,
    /// largest control-point displacement (model units)
    pub max_control_move: f64,
    /// largest sampled distance of the result from the original surface (model units)
    pub max_deviation: f64,
    /// wall-clock seconds
    pub seconds: f64,
}

impl FairingReport {
    /// Measures energies, control moves and the sampled deviation of `faired` against
    /// `original`.
    pub fn measure(
        method: &str,
        original: &BSplineSurface,
        faired: &BSplineSurface,
        iterations: usize,
        seconds: f64,
    ) -> Self {
        let max_control_move =
            if original.num_u() == faired.num_u() && original.num_v() == faired.num_v() {
                max_displacement(original.control_points(), faired.control_points())
            } else {
                f64::NAN
            };
        Self {
            method: method.to_string(),
            iterations,
            energy_before: thin_plate_energy(original),
            energy_after: thin_plate_energy(faired),
            max_control_move,
            max_deviation: max_deviation(original, faired, REPORT_DEVIATION_SAMPLES),
            seconds,
        }
    }
}

/// What a fairing method returns: the faired surface (same degrees, knots and weights) and the
/// iterations (moves, sweeps or solves) it made. The runner adds the wall-clock time.
#[derive(Debug, Clone, PartialEq)]
pub struct Faired {
    /// the faired surface
    pub surface: BSplineSurface,
    /// iterations performed
    pub iterations: usize,
    /// wall-clock seconds of the call, set by [`FairingProblem::run`] (0 as a method returns it)
    pub seconds: f64,
}

impl Faired {
    /// A method's result: `surface` after `iterations` iterations.
    pub fn new(surface: BSplineSurface, iterations: usize) -> Self {
        Self {
            surface,
            iterations,
            seconds: 0.0,
        }
    }
}

/// A surface fairing method, pluggable into the framework: only its own algorithm. Timing,
/// the contract check and the report are the runner's ([`FairingProblem::solve`]).
pub trait SurfaceFairing: Send + Sync {
    /// Short name, e.g. "energy".
    fn name(&self) -> &str;

    /// Fairs `problem.surface` moving only the control points `problem.mask` frees, keeping
    /// every control point within `problem.tolerance` (model units) of its original, in at most
    /// `problem.max_iterations` iterations when that is given. Method failures are returned as
    /// [`crate::Error::FairingFailed`].
    fn fair(&self, problem: &FairingProblem<'_>) -> Result<Faired>;
}

/// Rounding allowance of [`check_contract`]'s tolerance test, in units of ε_mach × the largest
/// coordinate: the three coordinates of a stored point round by half an ulp each, and |a − b|
/// adds its own rounding, together below 2√3 + 1 < 8 ulps.
pub const CONTRACT_ROUNDING_ULPS: f64 = 8.0;

/// One fairing run as the framework poses it: the surface, the control points that may move,
/// the tolerance ε (model units) every moved point must stay within, the stage and the limit
/// of iterations.
#[derive(Debug, Clone, Copy)]
pub struct FairingProblem<'a> {
    /// the surface to fair
    pub surface: &'a BSplineSurface,
    /// which control points may move (the frames of \[SV\] §3.1 are fixed)
    pub mask: &'a ControlMask,
    /// the largest move of a control point (model units)
    pub tolerance: f64,
    /// the continuity the calling stage keeps along the linked sides (\[SV\] §3.2: fair keeping
    /// C0, G1 or G2; its frames are the fixed rows of `mask`); `None` for a surface faired on
    /// its own
    pub keeps: Option<Continuity>,
    /// the most iterations the caller allows; `None`: the method's own limit. A direct solve
    /// (the curvature methods) has none and ignores it.
    pub max_iterations: Option<usize>,
}

impl<'a> FairingProblem<'a> {
    /// A surface faired on its own with the method's iteration limit.
    pub fn new(surface: &'a BSplineSurface, mask: &'a ControlMask, tolerance: f64) -> Self {
        Self {
            surface,
            mask,
            tolerance,
            keeps: None,
            max_iterations: None,
        }
    }

    /// The problem as the stage that keeps `level` poses it.
    pub fn keeping(self, level: Continuity) -> Self {
        Self {
            keeps: Some(level),
            ..self
        }
    }

    /// The problem with at most `n` iterations.
    pub fn with_max_iterations(self, n: usize) -> Self {
        Self {
            max_iterations: Some(n),
            ..self
        }
    }

    /// The number of control points the mask frees.
    pub fn free_count(&self) -> usize {
        self.mask.free_count()
    }

    /// Runs `method` on the problem, times it and checks the result ([`check_contract`]),
    /// measuring nothing else. A method that breaks the contract gives
    /// [`Error::ContractBroken`], never its result.
    pub fn run(&self, method: &dyn SurfaceFairing) -> Result<Faired> {
        self.mask.check_shape(self.surface)?;
        let start = std::time::Instant::now();
        let mut out = method.fair(self)?;
        out.seconds = start.elapsed().as_secs_f64();
        check_contract(
            method.name(),
            self.surface,
            &out.surface,
            self.mask,
            self.tolerance,
        )?;
        Ok(out)
    }

    /// [`FairingProblem::run`], then the report measured the one way every method is measured
    /// ([`FairingReport::measure`]).
    pub fn solve(&self, method: &dyn SurfaceFairing) -> Result<(BSplineSurface, FairingReport)> {
        let out = self.run(method)?;
        let report = FairingReport::measure(
            method.name(),
            self.surface,
            &out.surface,
            out.iterations,
            out.seconds,
        );
        Ok((out.surface, report))
    }
}

/// Checks a fairing result against the contract of [`SurfaceFairing`]: the same degrees, knots
/// and weights (bit for bit) as `original`, every control point `mask` fixes bit-identical, and
/// every point within `tolerance` of its original (up to the rounding of its coordinates,
/// [`CONTRACT_ROUNDING_ULPS`]). Returns the number of points that moved;
/// the first violation as [`Error::ContractBroken`].
pub fn check_contract(
    method: &str,
    original: &BSplineSurface,
    faired: &BSplineSurface,
    mask: &ControlMask,
    tolerance: f64,
) -> Result<usize> {
    let broken = |detail: String| Error::ContractBroken {
        method: method.to_string(),
        detail,
    };
    let bits = |xs: &[f64]| xs.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    if (faired.degree_u(), faired.degree_v()) != (original.degree_u(), original.degree_v())
        || bits(faired.knots_u().knots()) != bits(original.knots_u().knots())
        || bits(faired.knots_v().knots()) != bits(original.knots_v().knots())
    {
        return Err(broken(format!(
            "it returned a {}×{} net of degree ({}, {}) for a {}×{} net of degree ({}, {}), or other knots",
            faired.num_u(),
            faired.num_v(),
            faired.degree_u(),
            faired.degree_v(),
            original.num_u(),
            original.num_v(),
            original.degree_u(),
            original.degree_v()
        )));
    }
    if faired.weights().map(bits) != original.weights().map(bits) {
        return Err(broken("it changed the weights".to_string()));
    }
    let nv = original.num_v();
    let mut moved = 0;
    for (r, (a, b)) in original
        .control_points()
        .iter()
        .zip(faired.control_points())
        .enumerate()
    {
        let (i, j) = (r / nv, r % nv);
        let same = (0..3).all(|c| a[c].to_bits() == b[c].to_bits());
        if !mask.is_free(i, j) && !same {
            return Err(broken(format!(
                "fixed control point ({i}, {j}) moved by {:.3e}",
                (a - b).norm()
            )));
        }
        let d = (a - b).norm();
        // a point put onto its tolerance sphere is stored rounded: each coordinate within half
        // an ulp of its magnitude, which |a − b| cannot resolve below ~ε_mach·|a|
        let rounding = CONTRACT_ROUNDING_ULPS * f64::EPSILON * a.coords.amax().max(b.coords.amax());
        if !(d <= tolerance + rounding) {
            return Err(broken(format!(
                "control point ({i}, {j}) moved {d:.6e}, beyond the tolerance {tolerance:.6e}"
            )));
        }
        if !same {
            moved += 1;
        }
    }
    Ok(moved)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::KnotVector;
    use crate::Vector3;

    fn net() -> BSplineSurface {
        let k = KnotVector::clamped_uniform(3, 5).expect("knots");
        let pts = (0..25)
            .map(|r| Point3::new((r / 5) as f64 * 100.0, (r % 5) as f64 * 100.0, 3.0))
            .collect();
        BSplineSurface::new(k.clone(), k, pts, None).expect("surface")
    }

    /// A "method" that adds a fixed displacement to one control point.
    struct Nudge(usize, Vector3);
    impl SurfaceFairing for Nudge {
        fn name(&self) -> &str {
            "nudge"
        }
        fn fair(&self, problem: &FairingProblem<'_>) -> Result<Faired> {
            let mut out = problem.surface.clone();
            out.control_points_mut()[self.0] += self.1;
            Ok(Faired::new(out, 1))
        }
    }

    #[test]
    fn a_result_within_the_contract_is_taken_and_counted() {
        let s = net();
        let mut mask = ControlMask::all_free(5, 5);
        mask.set_free(0, 0, false);
        let problem = FairingProblem::new(&s, &mask, 0.5);
        let (out, report) = problem
            .solve(&Nudge(12, Vector3::new(0.0, 0.0, 0.4)))
            .expect("kept");
        assert_eq!(check_contract("t", &s, &out, &mask, 0.5).expect("ok"), 1);
        assert!((report.max_control_move - 0.4).abs() < 1e-12);
        // exactly on the tolerance sphere, stored with rounding: still within
        let d = Vector3::new(0.3, 0.4, 0.0) * (0.5 / 0.5);
        assert!(problem.solve(&Nudge(24, d)).is_ok());
    }

    #[test]
    fn the_runner_measures_the_report_and_passes_the_stage_on() {
        /// Nudges point 12 by 0.1 per iteration it is allowed, and says which stage it was in.
        struct Steps;
        impl SurfaceFairing for Steps {
            fn name(&self) -> &str {
                "steps"
            }
            fn fair(&self, problem: &FairingProblem<'_>) -> Result<Faired> {
                let n = problem.max_iterations.unwrap_or(1);
                let mut out = problem.surface.clone();
                out.control_points_mut()[12].z += 0.1 * n as f64;
                if problem.keeps != Some(Continuity::G1) {
                    return Err(Error::FairingFailed {
                        method: "steps".into(),
                        message: format!("told {:?}", problem.keeps),
                    });
                }
                Ok(Faired::new(out, n))
            }
        }
        let s = net();
        let mask = ControlMask::all_free(5, 5);
        let problem = FairingProblem::new(&s, &mask, 0.5)
            .keeping(Continuity::G1)
            .with_max_iterations(3);
        assert_eq!(problem.free_count(), 25);
        let (out, report) = problem.solve(&Steps).expect("within ε");
        assert_eq!(report.method, "steps");
        assert_eq!(report.iterations, 3);
        assert!((report.max_control_move - 0.3).abs() < 1e-12);
        assert_eq!(report.energy_before, thin_plate_energy(&s));
        assert_eq!(report.energy_after, thin_plate_energy(&out));
        assert!(report.max_deviation > 0.0 && report.max_deviation <= 0.3 + 1e-12);
        assert!(report.seconds >= 0.0);
        let e = FairingProblem::new(&s, &mask, 0.5).run(&Steps);
        assert!(e.expect_err("no stage").to_string().contains("told None"));
        // a mask of another shape is refused before the method runs
        let wrong = ControlMask::all_free(4, 5);
        assert!(FairingProblem::new(&s, &wrong, 0.5).run(&Steps).is_err());
    }

    #[test]
    fn a_moved_fixed_point_or_a_move_beyond_epsilon_is_refused() {
        let s = net();
        let mut mask = ControlMask::all_free(5, 5);
        mask.set_free(2, 2, false);
        let problem = FairingProblem::new(&s, &mask, 0.5);
        let fixed = problem.solve(&Nudge(12, Vector3::new(1e-13, 0.0, 0.0)));
        let e = fixed.expect_err("a fixed point moved by 1e-13").to_string();
        assert!(
            e.contains("nudge") && e.contains("fixed control point (2, 2)"),
            "{e}"
        );
        let far = problem.solve(&Nudge(6, Vector3::new(0.0, 0.0, 0.5 + 1e-9)));
        let e = far.expect_err("beyond ε").to_string();
        assert!(
            e.contains("(1, 1)") && e.contains("beyond the tolerance"),
            "{e}"
        );
    }

    #[test]
    fn another_net_or_other_weights_is_refused() {
        let s = net();
        let mask = ControlMask::all_free(5, 5);
        let refined = s.refine(crate::Direction::U, &[0.3]).expect("refine");
        assert!(check_contract("t", &s, &refined, &mask, 1.0).is_err());
        let weighted = BSplineSurface::new(
            s.knots_u().clone(),
            s.knots_v().clone(),
            s.control_points().to_vec(),
            Some(vec![1.0; 25]),
        )
        .expect("rational");
        let e = check_contract("t", &s, &weighted, &mask, 1.0).expect_err("weights");
        assert!(e.to_string().contains("weights"), "{e}");
    }
}
