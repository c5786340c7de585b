//! The local scheme on surfaces: closed-form truth, masks, tolerance, monotone energy, bad input.

mod common;

use common::{assert_contract, smooth_and_noisy};
use fair_energy::{
    EnergyError, EnergyParams, LocalEnergyFairing, LocalStart, SeparableStiffness, StopReason,
    fair_surface,
};
use nurbs_core::energy::thin_plate_energy;
use nurbs_core::testing::{assert_close, random_surface};
use nurbs_core::{ControlMask, FairingProblem, Frame, Point3, SurfaceFairing, Vector3};

/// \[H\]'s scheme as the slides have it: moves from the original net (the solved start of
/// `tests/start.rs` would leave these single-point cases nothing to do).
fn params(iterations: usize) -> EnergyParams {
    EnergyParams {
        max_iterations: iterations,
        start: LocalStart::Original,
        ..EnergyParams::default()
    }
}

#[test]
fn quadratic_form_equals_the_quadrature_energy() {
    for seed in 0..6 {
        let s = random_surface(seed, 2..=5, 12, false);
        let k = SeparableStiffness::thin_plate(s.knots_u(), s.knots_v()).expect("stiffness");
        let e = thin_plate_energy(&s);
        assert_close(
            k.energy(s.control_points()),
            e,
            1e-9 * e.max(1.0),
            "x^T K x vs quadrature",
        );
    }
}

#[test]
fn one_free_point_reaches_the_closed_form_optimum() {
    // with every other point fixed and a large ε, ∂E/∂d_r must vanish: central differences of the
    // quadratic energy are exact up to rounding
    for seed in 10..14 {
        let s = random_surface(seed, 2..=4, 9, false);
        let mut mask = ControlMask::all_fixed(s.num_u(), s.num_v());
        let (i, j) = (s.num_u() / 2, s.num_v() / 2);
        mask.set_free(i, j, true);
        let (out, report) = fair_surface(&s, &mask, 1e3, &params(5)).expect("fairs");
        assert_eq!(
            report.iterations, 1,
            "one move reaches the optimum, then nothing is left to gain"
        );
        let h = 1e-3;
        let scale = thin_plate_energy(&out).max(1.0);
        for c in 0..3 {
            let mut plus = out.clone();
            let mut minus = out.clone();
            let r = out.index(i, j);
            plus.control_points_mut()[r][c] += h;
            minus.control_points_mut()[r][c] -= h;
            let slope = (thin_plate_energy(&plus) - thin_plate_energy(&minus)) / (2.0 * h);
            assert!(
                slope.abs() <= 1e-6 * scale,
                "seed {seed}: dE/dd[{c}] = {slope}"
            );
        }
        assert!(thin_plate_energy(&out) <= thin_plate_energy(&s));
    }
}

#[test]
fn tolerance_projects_onto_the_sphere_towards_the_optimum() {
    let (_, s) = smooth_and_noisy(3, 10, 3, 0.05);
    let mut mask = ControlMask::all_fixed(10, 10);
    mask.set_free(4, 5, true);
    let r = s.index(4, 5);
    let (free_opt, _) = fair_surface(&s, &mask, 1e3, &params(1)).expect("fairs");
    let to_opt = free_opt.control_points()[r] - s.control_points()[r];
    let eps = 0.25 * to_opt.norm();
    let (clamped, report) = fair_surface(&s, &mask, eps, &params(1)).expect("fairs");
    assert_eq!(report.iterations, 1);
    let moved = clamped.control_points()[r] - s.control_points()[r];
    assert_close(moved.norm(), eps, 1e-9 * eps, "lands on the sphere");
    assert_close(
        moved.normalize().dot(&to_opt.normalize()),
        1.0,
        1e-12,
        "towards the optimum",
    );
}

#[test]
fn masked_points_stay_bit_identical_and_moves_stay_within_tolerance() {
    for seed in 20..26 {
        let s = random_surface(seed, 2..=5, 14, false);
        for frame in [Frame::Positional, Frame::Tangential, Frame::Curvature] {
            let mask = ControlMask::with_boundary_frame(&s, frame);
            let eps = 0.01;
            let (out, report) = fair_surface(&s, &mask, eps, &params(3000)).expect("fairs");
            assert_contract(&s, &out, &mask, eps);
            assert!(report.energy_after <= report.energy_before);
            assert!(report.max_control_move <= eps);
        }
    }
}

#[test]
fn energy_never_increases_step_by_step() {
    let (_, s) = smooth_and_noisy(5, 14, 4, 0.01);
    let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
    let mut last = thin_plate_energy(&s);
    for n in [0, 1, 2, 3, 5, 8, 13, 40, 100, 300, 1000, 3000] {
        let (out, report) = fair_surface(&s, &mask, 0.02, &params(n)).expect("fairs");
        let e = thin_plate_energy(&out);
        assert!(e <= last * (1.0 + 1e-12), "after {n} moves: {e} > {last}");
        assert_close(report.energy_after, e, 1e-9 * e, "reported energy");
        last = e;
    }
}

#[test]
fn every_move_is_the_best_ranked_point() {
    // replay the run one move at a time and compare the moved point with a full rescan of the
    // constrained energy decreases (checks the incremental gradient and the priority tree)
    let (_, s) = smooth_and_noisy(8, 9, 3, 0.02);
    let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
    let eps = 0.015;
    let k = SeparableStiffness::thin_plate(s.knots_u(), s.knots_v()).expect("stiffness");
    let nv = s.num_v();
    let mut prev = s.clone();
    for m in 1..=40 {
        let (next, _) = fair_surface(&s, &mask, eps, &params(m)).expect("fairs");
        let changed: Vec<usize> = (0..s.control_points().len())
            .filter(|&r| next.control_points()[r] != prev.control_points()[r])
            .collect();
        assert_eq!(changed.len(), 1, "move {m} changes one point");
        let mut g = vec![Vector3::zeros(); s.control_points().len()];
        k.multiply(prev.control_points(), &mut g);
        let decrease = |r: usize| {
            let kr = k.entry((r / nv, r % nv), (r / nv, r % nv));
            let d = prev.control_points()[r];
            let o = s.control_points()[r];
            let opt = d - g[r] / kr;
            let w = opt - o;
            let new: Point3 = if w.norm() <= eps {
                opt
            } else {
                o + w * (eps / w.norm())
            };
            let delta = new - d;
            -(2.0 * delta.dot(&g[r]) + kr * delta.norm_squared())
        };
        let best = mask
            .free_indices()
            .map(|(i, j)| i * nv + j)
            .max_by(|&a, &b| decrease(a).total_cmp(&decrease(b)))
            .expect("free points");
        assert_close(
            decrease(changed[0]),
            decrease(best),
            1e-9 * decrease(best),
            "moved point has the best rank",
        );
        prev = next;
    }
}

#[test]
fn noisy_surface_loses_ninety_percent_of_its_excess_energy() {
    let (smooth, noisy) = smooth_and_noisy(42, 20, 3, 0.004);
    let mask = ControlMask::with_boundary_frame(&noisy, Frame::Positional);
    let eps = 0.02;
    let (out, report) = fair_surface(&noisy, &mask, eps, &params(20_000)).expect("fairs");
    assert_contract(&noisy, &out, &mask, eps);
    let (e_smooth, e_noisy, e_out) = (
        thin_plate_energy(&smooth),
        thin_plate_energy(&noisy),
        thin_plate_energy(&out),
    );
    let excess = e_noisy - e_smooth;
    assert!(excess > 0.0);
    assert!(
        e_out - e_smooth <= 0.1 * excess,
        "energy {e_noisy} -> {e_out}, smooth {e_smooth} ({report:?})"
    );
}

#[test]
fn bad_input_is_an_error_or_a_report_that_nothing_moved() {
    let s = random_surface(1, 3..=3, 8, false);
    let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
    for eps in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(
            matches!(
                fair_surface(&s, &mask, eps, &params(10)),
                Err(EnergyError::InvalidTolerance { .. })
            ),
            "ε = {eps}"
        );
    }
    let none = ControlMask::all_fixed(s.num_u(), s.num_v());
    let (out, report) =
        fair_surface(&s, &none, 0.1, &params(10)).expect("nothing free is not an error");
    assert_eq!(
        (report.iterations, report.stop),
        (0, StopReason::NothingFree)
    );
    assert_eq!(out, s);
    let wrong = ControlMask::all_free(s.num_u() + 1, s.num_v());
    assert!(matches!(
        fair_surface(&s, &wrong, 0.1, &params(10)),
        Err(EnergyError::Core(_))
    ));
    let bad = EnergyParams {
        joint_weight: 1.0,
        ..EnergyParams::default()
    };
    assert!(matches!(
        fair_surface(&s, &mask, 0.1, &bad),
        Err(EnergyError::InvalidParameter { .. })
    ));
    // rational surfaces are faired with fixed weights (tests/rational.rs), but not with the
    // polynomial-only joint terms
    let rational = random_surface(1, 3..=3, 8, true);
    let joints = EnergyParams {
        joint_weight: 0.5,
        ..EnergyParams::default()
    };
    let rational_mask = ControlMask::with_boundary_frame(&rational, Frame::Positional);
    assert!(matches!(
        fair_surface(&rational, &rational_mask, 0.1, &joints),
        Err(EnergyError::InvalidParameter {
            name: "joint_weight",
            ..
        })
    ));
    // the trait maps our errors into the kernel's FairingFailed
    let method = LocalEnergyFairing::default();
    assert!(matches!(
        method.fair(&FairingProblem::new(&s, &mask, -1.0)),
        Err(nurbs_core::Error::FairingFailed { .. })
    ));
    let (_, report) = FairingProblem::new(&s, &mask, 0.01)
        .solve(&method)
        .expect("fairs");
    assert_eq!(report.method, "energy");
    assert!(report.energy_after <= report.energy_before && report.max_deviation <= 0.01);
    // the problem's iteration limit is the limit: 7 moves, not the method's 10,000
    let (_, limited) = FairingProblem::new(&s, &mask, 0.01)
        .with_max_iterations(7)
        .solve(&method)
        .expect("fairs");
    assert_eq!(limited.iterations, 7);
    assert!(report.iterations > 7 && limited.energy_after > report.energy_after);
}
