//! The global variant: normal equations, clamping, monotone energy, solvers, bad input.

mod common;

use common::{assert_contract, smooth_and_noisy};
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
            let nv = s.num_v();
            let free: Vec<usize> = mask.free_indices().map(|(i, j)| i * nv + j).collect();
            let w = params.deviation_weight
                * free
                    .iter()
                    .map(|&r| k.entry((r / nv, r % nv), (r / nv, r % nv)))
                    .sum::<f64>()
                / free.len() as f64;
            let mut g = vec![Vector3::zeros(); s.control_points().len()];
            k.multiply(out.control_points(), &mut g);
            let scale = g.iter().map(|v| v.norm()).fold(0.0, f64::max).max(1.0);
            for &r in &free {
                let residual = g[r] + w * (out.control_points()[r] - s.control_points()[r]);
                assert!(
                    residual.norm() <= 1e-8 * scale,
                    "{solver:?} seed {seed}: residual {:e}",
                    residual.norm()
                );
            }
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
