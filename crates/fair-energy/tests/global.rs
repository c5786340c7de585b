//! The global variant: normal equations, clamping, monotone energy, solvers, bad input.

mod common;

use common::{assert_contract, smooth_and_noisy, with_interior_noise};
use fair_energy::{
    EnergyError, GlobalEnergyFairing, GlobalParams, SeparableStiffness, SparseSolver,
    fair_surface_global,
};
use nurbs_core::energy::thin_plate_energy;
use nurbs_core::testing::random_surface;
use nurbs_core::{ControlMask, FairingProblem, Frame, SurfaceFairing, Vector3};

fn solvers() -> Vec<SparseSolver> {
    #[allow(unused_mut)]
    let mut v = vec![SparseSolver::NalgebraSparse];
    #[cfg(feature = "faer")]
    v.push(SparseSolver::Faer);
    v
}

#[test]
fn unclamped_solution_solves_the_normal_equations() {
    for solver in solvers() {
        for seed in 0..4 {
            let s = random_surface(seed, 2..=4, 12, false);
            let mask = ControlMask::with_boundary_frame(&s, Frame::Tangential);
            if mask.free_count() == 0 {
                continue;
            }
            let params = GlobalParams {
                solver,
                ..GlobalParams::default()
            };
            let (out, report) = fair_surface_global(&s, &mask, 1e6, &params).expect("fairs");
            assert_eq!((report.clamped_points, report.step), (0, 1.0), "{report:?}");
            let k = SeparableStiffness::thin_plate(s.knots_u(), s.knots_v()).expect("stiffness");
            assert_solves_normal_equations(
                &s,
                &out,
                &mask,
                &params,
                &|a, b| k.entry(a, b),
                &|x, g| k.multiply(x, g),
                &format!("{solver:?} seed {seed}"),
            );
        }
    }
}

#[test]
fn solvers_agree() {
    let (_, s) = smooth_and_noisy(2, 24, 4, 0.01);
    let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
    let results: Vec<_> = solvers()
        .into_iter()
        .map(|solver| {
            fair_surface_global(
                &s,
                &mask,
                0.02,
                &GlobalParams {
                    solver,
                    ..GlobalParams::default()
                },
            )
            .expect("fairs")
            .0
        })
        .collect();
    for r in &results[1..] {
        for (a, b) in r.control_points().iter().zip(results[0].control_points()) {
            assert!((a - b).norm() < 1e-10);
        }
    }
}

#[test]
fn noisy_surface_loses_ninety_percent_of_its_excess_energy() {
    let (smooth, noisy) = smooth_and_noisy(42, 20, 3, 0.004);
    let mask = ControlMask::with_boundary_frame(&noisy, Frame::Positional);
    let eps = 0.02;
    let (out, report) =
        fair_surface_global(&noisy, &mask, eps, &GlobalParams::default()).expect("fairs");
    assert_contract(&noisy, &out, &mask, eps);
    let (e_smooth, e_noisy, e_out) = (
        thin_plate_energy(&smooth),
        thin_plate_energy(&noisy),
        thin_plate_energy(&out),
    );
    assert!(
        e_out - e_smooth <= 0.1 * (e_noisy - e_smooth),
        "energy {e_noisy} -> {e_out}, smooth {e_smooth} ({report:?})"
    );
}

#[test]
fn clamping_never_increases_the_energy() {
    for seed in 30..36 {
        let s = random_surface(seed, 2..=4, 14, false);
        for frame in [Frame::Positional, Frame::Curvature] {
            let mask = ControlMask::with_boundary_frame(&s, frame);
            for eps in [1e-4, 1e-3, 1e-2] {
                let params = GlobalParams {
                    polish_iterations: 50,
                    ..GlobalParams::default()
                };
                let (out, report) = fair_surface_global(&s, &mask, eps, &params).expect("fairs");
                assert_contract(&s, &out, &mask, eps);
                assert!(
                    report.energy_after <= report.energy_before * (1.0 + 1e-12),
                    "seed {seed} ε {eps}: {report:?}"
                );
                assert!(thin_plate_energy(&out) <= thin_plate_energy(&s) * (1.0 + 1e-9));
            }
        }
    }
}

#[test]
fn bad_input_is_an_error_or_a_report_that_nothing_moved() {
    let s = random_surface(1, 3..=3, 8, false);
    let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
    assert!(matches!(
        fair_surface_global(&s, &mask, 0.0, &GlobalParams::default()),
        Err(EnergyError::InvalidTolerance { .. })
    ));
    let bad = GlobalParams {
        deviation_weight: 0.0,
        ..GlobalParams::default()
    };
    assert!(matches!(
        fair_surface_global(&s, &mask, 0.1, &bad),
        Err(EnergyError::InvalidParameter { .. })
    ));
    let none = ControlMask::all_fixed(s.num_u(), s.num_v());
    let (out, report) =
        fair_surface_global(&s, &none, 0.1, &GlobalParams::default()).expect("not an error");
    assert_eq!(report.free_points, 0);
    assert_eq!(out, s);
    let method = GlobalEnergyFairing::default();
    assert_eq!(method.name(), "energy-global");
    assert!(matches!(
        method.fair(&FairingProblem::new(&s, &mask, -1.0)),
        Err(nurbs_core::Error::FairingFailed { .. })
    ));
}

/// The quarter cylinder of radius 1 and height 2 (rational, degree 2 around the axis), bicubic
/// in the other direction and refined so that it has interior control points, with seeded
/// noise of `amplitude` on its interior points.
fn noisy_rational_cylinder(seed: u64, amplitude: f64) -> nurbs_core::BSplineSurface {
    use nurbs_core::Direction;
    let s = nurbs_core::shapes::cylinder(1.0, 2.0)
        .and_then(|s| s.elevate_degree(Direction::U, 2))
        .and_then(|s| s.refine(Direction::U, &[0.25, 0.5, 0.75]))
        .and_then(|s| s.refine(Direction::V, &[0.2, 0.4, 0.6, 0.8]))
        .expect("cylinder");
    assert!(s.is_rational());
    with_interior_noise(&s, seed, amplitude)
}

/// Asserts that `out` solves the normal equations of the global step from `s`,
/// (K + w I) δ = −K o on the free points of `mask` (w the deviation weight of `params` times the
/// mean diagonal entry of K over them), to 1e-8 of the largest K·x entry: K given by its
/// `entry` and its `multiply`.
#[track_caller]
fn assert_solves_normal_equations(
    s: &nurbs_core::BSplineSurface,
    out: &nurbs_core::BSplineSurface,
    mask: &ControlMask,
    params: &GlobalParams,
    entry: &dyn Fn((usize, usize), (usize, usize)) -> f64,
    multiply: &dyn Fn(&[nurbs_core::Point3], &mut [Vector3]),
    label: &str,
) {
    let nv = s.num_v();
    let free: Vec<usize> = mask.free_indices().map(|(i, j)| i * nv + j).collect();
    let w = params.deviation_weight
        * free
            .iter()
            .map(|&r| entry((r / nv, r % nv), (r / nv, r % nv)))
            .sum::<f64>()
        / free.len() as f64;
    let mut g = vec![Vector3::zeros(); s.control_points().len()];
    multiply(out.control_points(), &mut g);
    let scale = g.iter().map(|v| v.norm()).fold(0.0, f64::max).max(1.0);
    for &r in &free {
        let residual = g[r] + w * (out.control_points()[r] - s.control_points()[r]);
        assert!(
            residual.norm() <= 1e-8 * scale,
            "{label}: residual {:e}",
            residual.norm()
        );
    }
}

#[test]
fn a_rational_surface_keeps_its_weights_and_solves_its_own_normal_equations() {
    let s = noisy_rational_cylinder(7, 0.01);
    let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
    let params = GlobalParams::default();
    let (out, report) = fair_surface_global(&s, &mask, 1e6, &params).expect("fairs");
    assert_eq!((report.clamped_points, report.step), (0, 1.0), "{report:?}");
    let (wa, wb) = (
        s.weights().expect("rational"),
        out.weights().expect("rational"),
    );
    assert!(wa.iter().zip(wb).all(|(a, b)| a.to_bits() == b.to_bits()));
    // the residual of (K + w I) δ = −K o with the rational form K
    let k = fair_energy::RationalStiffness::thin_plate(&s);
    assert_solves_normal_equations(
        &s,
        &out,
        &mask,
        &params,
        &|a, b| k.entry(a, b),
        &|x, g| k.multiply(x, g),
        "rational cylinder",
    );
    assert!(thin_plate_energy(&out) < thin_plate_energy(&s));
}

#[test]
fn active_set_rounds_stay_in_the_balls_and_end_no_higher_than_one_clamp() {
    let mut rounds_used = 0;
    for seed in 40..46 {
        // noise of 4e-3 against balls of 1e-3 … 4e-3: some points leave their balls, not all
        let (_, noisy) = smooth_and_noisy(seed, 16, 3, 0.004);
        let rational = noisy_rational_cylinder(seed, 0.004);
        for s in [noisy, rational] {
            let mask = ControlMask::with_boundary_frame(&s, Frame::Tangential);
            for eps in [1e-3, 2e-3, 4e-3] {
                let run = |rounds: usize| {
                    let params = GlobalParams {
                        active_set_rounds: rounds,
                        ..GlobalParams::default()
                    };
                    fair_surface_global(&s, &mask, eps, &params).expect("fairs")
                };
                let (one, r1) = run(0);
                let (many, rm) = run(fair_energy::ACTIVE_SET_ROUNDS);
                assert_contract(&s, &one, &mask, eps);
                assert_contract(&s, &many, &mask, eps);
                assert_eq!(r1.solves, 1);
                assert!(rm.solves <= fair_energy::ACTIVE_SET_ROUNDS + 1);
                if rm.solves > 1 {
                    rounds_used += 1;
                }
                let (e1, em) = (thin_plate_energy(&one), thin_plate_energy(&many));
                assert!(em <= e1 * (1.0 + 1e-9), "seed {seed} ε {eps}: {e1} -> {em}");
            }
        }
    }
    assert!(rounds_used > 0, "no case bound the balls");
}
