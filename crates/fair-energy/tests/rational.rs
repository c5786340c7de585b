//! The local scheme on rational surfaces with fixed weights: the assembled stiffness against the
//! quadrature energy, unit weights against the separable stiffness, and fairing of noisy and
//! exact rational cylinders (masks, weights, tolerance, deviation).

mod common;

use common::{assert_contract, with_interior_noise};
use fair_energy::{
    EnergyParams, LocalEnergyFairing, LocalStart, RationalStiffness, SeparableStiffness,
    fair_surface,
};
use nurbs_core::energy::{max_deviation, thin_plate_energy};
use nurbs_core::shapes::{cylinder, sphere_patch, torus};
use nurbs_core::testing::{assert_close, random_surface};
use nurbs_core::{BSplineSurface, ControlMask, Direction, FairingProblem, Frame};

/// Relative agreement of xᵀ K x with the quadrature energy: both sum the same Gauss points, so
/// only rounding separates them.
const SAME_RULE_REL: f64 = 1e-9;

/// Samples per direction for the sampled deviation.
const DEVIATION_SAMPLES: usize = nurbs_core::fairing::REPORT_DEVIATION_SAMPLES;

/// \[H\]'s scheme from the original net (the solved start has its own tests in
/// `tests/start.rs`).
fn params(iterations: usize) -> EnergyParams {
    EnergyParams {
        max_iterations: iterations,
        start: LocalStart::Original,
        ..EnergyParams::default()
    }
}

/// The quarter cylinder of radius 1 and height 2 with u around the axis (degree 2, weights
/// 1, √2/2, 1) and v along it, raised to degree `degree_v` in v.
fn quarter_cylinder(degree_v: usize) -> BSplineSurface {
    let s = cylinder(1.0, 2.0)
        .and_then(|s| s.transposed())
        .expect("cylinder");
    assert_eq!((s.degree_u(), s.degree_v()), (2, 1));
    s.elevate_degree(Direction::V, degree_v - 1)
        .expect("elevate v")
}

/// The quarter cylinder, bicubic with interior knots, so that it has interior control points.
fn refined_cylinder() -> BSplineSurface {
    let s = quarter_cylinder(3)
        .elevate_degree(Direction::U, 1)
        .and_then(|s| s.refine(Direction::U, &[0.2, 0.4, 0.6, 0.8]))
        .and_then(|s| {
            s.refine(
                Direction::V,
                &[1.0 / 6.0, 2.0 / 6.0, 0.5, 4.0 / 6.0, 5.0 / 6.0],
            )
        })
        .expect("refine");
    assert!(s.is_rational());
    s
}

/// Every weight of `b` has the bits of the same weight of `a`.
#[track_caller]
fn assert_weights_identical(a: &BSplineSurface, b: &BSplineSurface) {
    let (wa, wb) = (
        a.weights().expect("rational"),
        b.weights().expect("rational"),
    );
    assert_eq!(wa.len(), wb.len());
    for (k, (x, y)) in wa.iter().zip(wb).enumerate() {
        assert_eq!(x.to_bits(), y.to_bits(), "weight {k} changed: {x} -> {y}");
    }
}

#[test]
fn rational_quadratic_form_equals_the_quadrature_energy() {
    let mut surfaces = vec![quarter_cylinder(1), quarter_cylinder(3), refined_cylinder()];
    surfaces.extend((0..6).map(|seed| random_surface(seed, 2..=4, 10, true)));
    for (n, s) in surfaces.iter().enumerate() {
        assert!(s.is_rational());
        let k = RationalStiffness::thin_plate(s);
        let e = thin_plate_energy(s);
        assert!(e > 0.0, "surface {n} bends");
        assert_close(
            k.energy(s.control_points()),
            e,
            SAME_RULE_REL * e,
            &format!("surface {n}: x^T K x vs quadrature"),
        );
        // K is stored with both halves: they must agree exactly
        let (nu, nv) = (k.num_u(), k.num_v());
        let (p, q) = k.stencil();
        for i in 0..nu {
            for j in 0..nv {
                for a in i.saturating_sub(p)..(i + p + 1).min(nu) {
                    for b in j.saturating_sub(q)..(j + q + 1).min(nv) {
                        assert_eq!(
                            k.entry((i, j), (a, b)).to_bits(),
                            k.entry((a, b), (i, j)).to_bits(),
                            "surface {n}: K not symmetric at ({i}, {j}), ({a}, {b})"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn rational_quadrature_is_converged_on_exact_shapes() {
    // the default rule (RATIONAL_EXTRA_POINTS more per direction) against a much finer one on
    // conic surfaces, whose weights vary as in practice (measured: ≤ 8e-7 relative, the sphere
    // patch; random weights in [0.5, 2] from point to point are off by up to 1 %, see the
    // `rational` module's # Tolerance)
    let surfaces = [
        quarter_cylinder(1),
        refined_cylinder(),
        sphere_patch(1.0).expect("sphere"),
        torus(3.0, 1.0).expect("torus"),
    ];
    for (n, s) in surfaces.iter().enumerate() {
        let coarse = RationalStiffness::thin_plate(s).energy(s.control_points());
        let fine =
            RationalStiffness::thin_plate_with_extra_points(s, 12).energy(s.control_points());
        assert_close(coarse, fine, 1e-6 * fine, &format!("surface {n}"));
    }
}

#[test]
fn unit_weights_give_the_separable_stiffness() {
    for seed in 0..6 {
        let s = random_surface(seed, 2..=5, 12, false);
        let ones = vec![1.0; s.control_points().len()];
        let w = BSplineSurface::new(
            s.knots_u().clone(),
            s.knots_v().clone(),
            s.control_points().to_vec(),
            Some(ones),
        )
        .expect("surface");
        // explicit unit weights are kept: this surface takes the rational path
        assert!(w.is_rational());
        let rational = RationalStiffness::thin_plate(&w);
        let separable = SeparableStiffness::thin_plate(s.knots_u(), s.knots_v()).expect("K");
        let e = separable.energy(s.control_points());
        assert_close(
            rational.energy(w.control_points()),
            e,
            1e-9 * e,
            &format!("seed {seed}: energies"),
        );
        let (nu, nv) = (s.num_u(), s.num_v());
        let (p, q) = rational.stencil();
        assert_eq!(separable.stencil(), (p, q));
        let scale = (0..nu * nv)
            .map(|r| separable.entry((r / nv, r % nv), (r / nv, r % nv)))
            .fold(0.0, f64::max);
        for r in 0..nu * nv {
            let (i, j) = (r / nv, r % nv);
            for a in i.saturating_sub(p)..(i + p + 1).min(nu) {
                for b in j.saturating_sub(q)..(j + q + 1).min(nv) {
                    assert_close(
                        rational.entry((i, j), (a, b)),
                        separable.entry((i, j), (a, b)),
                        1e-11 * scale,
                        &format!("seed {seed}: K at ({i}, {j}), ({a}, {b})"),
                    );
                }
            }
        }
        // and the fairing of both agrees up to rounding
        let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
        let (a, ra) = fair_surface(&s, &mask, 0.01, &params(500)).expect("fairs");
        let (b, rb) = fair_surface(&w, &mask, 0.01, &params(500)).expect("fairs");
        assert_eq!(ra.iterations, rb.iterations, "seed {seed}");
        assert_close(
            ra.energy_after,
            rb.energy_after,
            1e-9 * ra.energy_before,
            "energy",
        );
        let apart = nurbs_core::max_displacement(a.control_points(), b.control_points());
        assert!(apart <= 1e-9, "seed {seed}: results {apart} apart");
    }
}

#[test]
fn one_free_rational_point_reaches_the_closed_form_optimum() {
    // with every other point fixed and a large ε, ∂E/∂d_r of the quadrature energy must vanish
    for seed in 30..34 {
        let s = random_surface(seed, 2..=4, 9, true);
        let mut mask = ControlMask::all_fixed(s.num_u(), s.num_v());
        let (i, j) = (s.num_u() / 2, s.num_v() / 2);
        mask.set_free(i, j, true);
        let (out, report) = fair_surface(&s, &mask, 1e3, &params(5)).expect("fairs");
        assert_eq!(
            report.iterations, 1,
            "seed {seed}: one move reaches the optimum"
        );
        let h = 1e-3;
        let scale = thin_plate_energy(&out).max(1.0);
        for c in 0..3 {
            let (mut plus, mut minus) = (out.clone(), out.clone());
            let r = out.index(i, j);
            plus.control_points_mut()[r][c] += h;
            minus.control_points_mut()[r][c] -= h;
            let slope = (thin_plate_energy(&plus) - thin_plate_energy(&minus)) / (2.0 * h);
            assert!(
                slope.abs() <= 1e-6 * scale,
                "seed {seed}: dE/dd[{c}] = {slope}"
            );
        }
        assert!(thin_plate_energy(&out) < thin_plate_energy(&s));
    }
}

#[test]
fn noisy_rational_cylinder_is_faired_within_tolerance() {
    let exact = refined_cylinder();
    let eps = 0.02;
    for seed in [1, 2, 3] {
        let noisy = with_interior_noise(&exact, seed, 0.01);
        let mask = ControlMask::with_boundary_frame(&noisy, Frame::Positional);
        let (out, report) = fair_surface(&noisy, &mask, eps, &params(5000)).expect("fairs");
        assert_contract(&noisy, &out, &mask, eps);
        assert_weights_identical(&noisy, &out);
        assert!(report.max_control_move <= eps);
        let (e_exact, e_noisy, e_out) = (
            thin_plate_energy(&exact),
            thin_plate_energy(&noisy),
            thin_plate_energy(&out),
        );
        assert_close(
            report.energy_before,
            e_noisy,
            1e-9 * e_noisy,
            "energy before",
        );
        assert_close(
            report.energy_after,
            e_out,
            1e-9 * e_noisy,
            "tracked energy after",
        );
        assert!(
            e_out - e_exact <= 0.5 * (e_noisy - e_exact),
            "seed {seed}: energy {e_noisy} -> {e_out}, exact cylinder {e_exact}"
        );
        let deviation = max_deviation(&noisy, &out, DEVIATION_SAMPLES);
        assert!(
            deviation <= eps,
            "seed {seed}: deviation {deviation} > {eps}"
        );
    }
    // the same through the framework's trait
    let noisy = with_interior_noise(&exact, 4, 0.01);
    let mask = ControlMask::with_boundary_frame(&noisy, Frame::Positional);
    let (out, report) = FairingProblem::new(&noisy, &mask, eps)
        .solve(&LocalEnergyFairing::default())
        .expect("fairs");
    assert_weights_identical(&noisy, &out);
    assert!(report.energy_after < report.energy_before);
    assert!(report.max_deviation <= eps);
}

#[test]
fn exact_rational_cylinder_with_fixed_frames_gains_no_energy() {
    let s = refined_cylinder();
    let e = thin_plate_energy(&s);
    let eps = 0.01;
    for frame in [Frame::Positional, Frame::Tangential, Frame::Curvature] {
        let mask = ControlMask::with_boundary_frame(&s, frame);
        assert!(mask.free_count() > 0, "{frame:?} leaves points free");
        let (out, report) = fair_surface(&s, &mask, eps, &params(3000)).expect("fairs");
        assert_contract(&s, &out, &mask, eps);
        assert_weights_identical(&s, &out);
        let e_out = thin_plate_energy(&out);
        assert!(
            e_out <= e * (1.0 + 1e-12),
            "{frame:?}: energy {e} -> {e_out} ({report:?})"
        );
        assert!(max_deviation(&s, &out, DEVIATION_SAMPLES) <= eps);
    }
}
