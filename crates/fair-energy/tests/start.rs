//! The solved start of the local scheme (`LocalStart::Solved`): where the free points'
//! unconstrained optimum lies inside every ε-ball it is the constrained minimizer the scheme
//! converges to from the original net, reached without the moves; where a ball holds a point
//! back the scheme runs from the original net exactly as without it.

mod common;

use common::{assert_contract, smooth_and_noisy};
use fair_energy::{EnergyParams, LocalStart, StopReason, fair_surface};
use nurbs_core::energy::thin_plate_energy;
use nurbs_core::shapes::torus;
use nurbs_core::{BSplineSurface, ControlMask, Direction, Vector3};

/// Moves the reference run may make: enough for the local scheme to converge on these small
/// nets (it stops by its decrease threshold long before).
const CONVERGED_MOVES: usize = 2_000_000;

fn params(start: LocalStart, max_iterations: usize) -> EnergyParams {
    EnergyParams {
        max_iterations,
        start,
        ..EnergyParams::default()
    }
}

/// Every point free but the two outer rings (the frames of \[SV\] §3.1 up to G1).
fn inner(s: &BSplineSurface) -> ControlMask {
    let (nu, nv) = (s.num_u(), s.num_v());
    let mut m = ControlMask::all_fixed(nu, nv);
    for i in 2..nu - 2 {
        for j in 2..nv - 2 {
            m.set_free(i, j, true);
        }
    }
    m
}

/// Largest distance between corresponding control points.
fn max_apart(a: &BSplineSurface, b: &BSplineSurface) -> f64 {
    a.control_points()
        .iter()
        .zip(b.control_points())
        .map(|(p, q)| (p - q).norm())
        .fold(0.0, f64::max)
}

/// Runs both starts on `s` with tolerance `eps` and checks that the solved start lands on the
/// converged scheme's minimizer (points within `close` of each other), with an energy no
/// higher, in far fewer moves, and within the contract.
fn same_minimizer(s: &BSplineSurface, eps: f64, close: f64) {
    let mask = inner(s);
    // the reference runs until a move gains less than 1e-20 of the energy (a distance of about
    // 1e-10 of the net's size from the minimizer)
    let original = EnergyParams {
        min_relative_decrease: 1e-20,
        ..params(LocalStart::Original, CONVERGED_MOVES)
    };
    let (slow, slow_report) = fair_surface(s, &mask, eps, &original).expect("fairs");
    assert_eq!(
        slow_report.stop,
        StopReason::Converged,
        "the reference converges"
    );
    let (fast, fast_report) =
        fair_surface(s, &mask, eps, &params(LocalStart::Solved, CONVERGED_MOVES)).expect("fairs");
    assert_contract(s, &fast, &mask, eps);
    assert!(
        max_apart(&slow, &fast) <= close,
        "the minimizers differ by {:.3e}",
        max_apart(&slow, &fast)
    );
    assert!(fast_report.energy_after <= slow_report.energy_after * (1.0 + 1e-9));
    assert_eq!(fast_report.energy_before, slow_report.energy_before);
    assert!(
        fast_report.iterations * 100 <= slow_report.iterations,
        "moves {} against {}",
        fast_report.iterations,
        slow_report.iterations
    );
    // the measured energy agrees with the reported one
    let measured = thin_plate_energy(&fast);
    assert!(measured <= thin_plate_energy(s));
}

#[test]
fn a_generous_tolerance_lands_on_the_converged_minimizer_of_a_noisy_net() {
    for seed in 0..3 {
        let (_, noisy) = smooth_and_noisy(seed, 12, 3, 0.01);
        // the minimizer moves points by a few noise amplitudes: a ball of 1 holds none back
        same_minimizer(&noisy, 1.0, 1e-7);
    }
}

#[test]
fn a_rational_torus_patch_with_a_dent_is_faired_back_to_the_same_minimizer() {
    // an exact rational torus (weights √2/2 on the middle rows), raised to 5 × 5 and refined
    // so that it has inner points, with one inner point dented by 0.05
    let t = torus(3.0, 1.0).expect("torus");
    let t = t
        .elevate_degree(Direction::U, 1)
        .and_then(|t| t.elevate_degree(Direction::V, 1))
        .expect("elevate");
    let mut t = t;
    for dir in [Direction::U, Direction::V] {
        let (a, b) = match dir {
            Direction::U => t.knots_u().domain(),
            Direction::V => t.knots_v().domain(),
        };
        for f in [0.05, 0.1, 0.15] {
            t = t.insert_knot(dir, a + f * (b - a), 1).expect("refine");
        }
    }
    assert!(t.is_rational());
    let mut dented = t.clone();
    let r = dented.index(4, 4);
    dented.control_points_mut()[r] += Vector3::new(0.0, 0.0, 0.05);
    // the minimizer flattens the inner region of the tube (moves of the order of its radius
    // 1): a ball of 10 holds none back
    same_minimizer(&dented, 10.0, 1e-7);
}

#[test]
fn where_a_ball_holds_a_point_back_the_run_is_the_scheme_from_the_original_net() {
    let (_, noisy) = smooth_and_noisy(7, 12, 3, 0.05);
    let mask = inner(&noisy);
    // ε far below the noise: the minimizer lies outside most balls
    let eps = 1e-3;
    let moves = 5_000;
    let (a, ra) =
        fair_surface(&noisy, &mask, eps, &params(LocalStart::Original, moves)).expect("fairs");
    let (b, rb) =
        fair_surface(&noisy, &mask, eps, &params(LocalStart::Solved, moves)).expect("fairs");
    assert_eq!(a.control_points(), b.control_points(), "bit-identical nets");
    assert_eq!(ra, rb);
}
