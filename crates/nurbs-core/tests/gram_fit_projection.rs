//! Gram integrals, thin-plate energy, least-squares fitting and projection.

use nurbs_core::energy::thin_plate_energy;
use nurbs_core::fit::{FitParams, fit_curve, fit_surface};
use nurbs_core::gram::{ThinPlateGram, gram_matrix};
use nurbs_core::projection::{ProjectionParams, project_to_curve, project_to_surface};
use nurbs_core::testing::{assert_close, random_curve, random_param, random_surface, rng};
use nurbs_core::{
    ControlMask, Error, Frame, KnotVector, Point3, Side, basis::basis_function_derivative,
};
use proptest::prelude::*;

/// ∫ N_i^(a) N_j^(b) by a fine composite Simpson rule, as an independent reference.
fn simpson(kv: &KnotVector, i: usize, j: usize, a: usize, b: usize) -> f64 {
    let k = kv.knots();
    let mut total = 0.0;
    for s in kv.spans() {
        let (lo, hi) = (k[s], k[s + 1]);
        let n = 200;
        let h = (hi - lo) / n as f64;
        // evaluate just inside the span so one-sided derivatives belong to it
        let f = |t: f64| {
            let t = t.clamp(lo + 1e-12 * (hi - lo), hi - 1e-12 * (hi - lo));
            basis_function_derivative(kv, i, t, a) * basis_function_derivative(kv, j, t, b)
        };
        let mut acc = f(lo) + f(hi);
        for m in 1..n {
            acc += if m % 2 == 1 { 4.0 } else { 2.0 } * f(lo + m as f64 * h);
        }
        total += acc * h / 3.0;
    }
    total
}

#[test]
fn gram_integrals_match_quadrature_reference() {
    let kv = KnotVector::new(3, vec![0., 0., 0., 0., 0.15, 0.4, 0.4, 0.8, 1., 1., 1., 1.]).unwrap();
    for (a, b) in [(0, 0), (1, 1), (2, 2), (3, 3), (0, 2), (1, 3)] {
        let g = gram_matrix(&kv, a, b).unwrap();
        for i in 0..kv.num_basis() {
            for j in 0..kv.num_basis() {
                let reference = simpson(&kv, i, j, a, b);
                assert_close(
                    g.get(i, j),
                    reference,
                    1e-6 * (1.0 + reference.abs()),
                    &format!("G^{a}{b}[{i}][{j}]"),
                );
            }
        }
    }
    // ∫ N_i = (t_{i+p+1} − t_i)/(p+1): row sums of G^00 (Σ_j N_j = 1)
    let g = gram_matrix(&kv, 0, 0).unwrap();
    for i in 0..kv.num_basis() {
        let row: f64 = (0..kv.num_basis()).map(|j| g.get(i, j)).sum();
        assert_close(
            row,
            (kv.knots()[i + 4] - kv.knots()[i]) / 4.0,
            1e-14,
            "integral of N_i",
        );
    }
}

#[test]
fn energy_by_quadrature_equals_gram_quadratic_form() {
    for seed in 0..6 {
        let s = random_surface(seed, 2..=4, 9, false);
        let gram = ThinPlateGram::new(s.knots_u(), s.knots_v()).unwrap();
        let (nu, nv) = (s.num_u(), s.num_v());
        let mut form = 0.0;
        for i in 0..nu {
            for j in 0..nv {
                for k in 0..nu {
                    for l in 0..nv {
                        let kij = gram.stiffness((i, j), (k, l));
                        form += kij
                            * s.control_point(i, j)
                                .coords
                                .dot(&s.control_point(k, l).coords);
                    }
                }
            }
        }
        let e = thin_plate_energy(&s);
        assert_close(e, form, 1e-10 * form.abs().max(1.0), "thin-plate energy");
    }
    // a bilinear (flat) patch has zero energy
    let flat = nurbs_core::shapes::paraboloid_bicubic(&[]).unwrap();
    assert!(thin_plate_energy(&flat) > 0.0);
}

#[test]
fn fitting_reproduces_a_surface_from_its_samples() {
    for seed in 0..8 {
        let s = random_surface(seed, 1..=4, 8, false);
        let us = s.knots_u().uniform_params(4 * s.num_u());
        let vs = s.knots_v().uniform_params(4 * s.num_v());
        let params: Vec<(f64, f64)> = us
            .iter()
            .flat_map(|&u| vs.iter().map(move |&v| (u, v)))
            .collect();
        let points = s.eval_grid_points(&us, &vs);
        // start from a flattened template so the fit has to recover everything
        let mut template = s.clone();
        template
            .control_points_mut()
            .iter_mut()
            .for_each(|p| *p = Point3::origin());
        let mask = ControlMask::for_surface(&s);
        let (fitted, report) =
            fit_surface(&template, &mask, &params, &points, &FitParams::default()).unwrap();
        assert!(report.max_error < 1e-9, "seed {seed}: {report:?}");
        for (a, b) in fitted.control_points().iter().zip(s.control_points()) {
            assert!((a - b).norm() < 1e-8);
        }
        // fixed frames stay bit-identical
        let mut moved = template.clone();
        moved.control_points_mut()[0] = Point3::new(9.0, 9.0, 9.0);
        let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
        let (fitted, _) = fit_surface(
            &moved,
            &mask,
            &params,
            &points,
            &FitParams { smoothing: 1e-3 },
        )
        .unwrap();
        for side in Side::ALL {
            for (i, j) in side.row(0, s.num_u(), s.num_v()) {
                assert_eq!(fitted.control_point(i, j), moved.control_point(i, j));
            }
        }
    }
}

#[test]
fn fitting_reports_singular_systems() {
    let s = random_surface(3, 3..=3, 8, false);
    // all samples in the first half of the u domain: some control points see no data
    let params: Vec<(f64, f64)> = (0..200)
        .map(|k| (0.3 * (k % 20) as f64 / 19.0, (k / 20) as f64 / 9.0))
        .collect();
    let points: Vec<Point3> = params.iter().map(|&(u, v)| s.point(u, v)).collect();
    let err = fit_surface(
        &s,
        &ControlMask::for_surface(&s),
        &params,
        &points,
        &FitParams::default(),
    )
    .unwrap_err();
    assert!(matches!(err, Error::SingularSystem { .. }), "{err}");
    assert!(err.to_string().contains("no data point"), "{err}");
    let bad = vec![Point3::new(f64::NAN, 0.0, 0.0); params.len()];
    assert!(
        fit_surface(
            &s,
            &ControlMask::for_surface(&s),
            &params,
            &bad,
            &FitParams::default()
        )
        .is_err()
    );
}

#[test]
fn curve_fit_with_fixed_ends_and_smoothing() {
    let c = random_curve(11, 3..=3, 12, false);
    let ts = c.knots().uniform_params(80);
    let pts: Vec<Point3> = ts.iter().map(|&t| c.point(t)).collect();
    let mut free = vec![true; c.control_points().len()];
    free[0] = false;
    *free.last_mut().unwrap() = false;
    let (exact, rep) = fit_curve(&c, &free, &ts, &pts, &FitParams::default()).unwrap();
    assert!(rep.max_error < 1e-10);
    assert_eq!(exact.control_points()[0], c.control_points()[0]);
    let (smooth, rep_s) = fit_curve(&c, &free, &ts, &pts, &FitParams { smoothing: 1e-2 }).unwrap();
    assert!(rep_s.max_error > rep.max_error);
    let bend = |x: &nurbs_core::BSplineCurve| -> f64 {
        (0..=200)
            .map(|k| x.derivatives(k as f64 / 200.0, 2).d[2].norm_squared())
            .sum()
    };
    assert!(bend(&smooth) < bend(&exact));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, .. ProptestConfig::default() })]

    #[test]
    fn projection_finds_the_sampling_parameters(seed in 0u64..10_000, rational in any::<bool>()) {
        let s = random_surface(seed, 2..=4, 8, rational);
        let mut r = rng(seed);
        let params = ProjectionParams::default();
        for _ in 0..5 {
            let (u, v) = (random_param(&mut r, s.knots_u()), random_param(&mut r, s.knots_v()));
            let p = s.point(u, v);
            let proj = project_to_surface(&s, &p, &params);
            prop_assert!(proj.converged);
            prop_assert!(proj.distance < 1e-9, "distance {}", proj.distance);
            prop_assert!((proj.u - u).abs() < 1e-6 && (proj.v - v).abs() < 1e-6, "({}, {}) vs ({u}, {v})", proj.u, proj.v);
            // a point off the surface along the normal projects back to the same foot point
            if let Some(n) = s.derivatives(u, v).normal() {
                let off = p + n * 1e-3;
                let back = project_to_surface(&s, &off, &params);
                prop_assert!(back.converged);
                prop_assert!(back.distance <= 1e-3 + 1e-9);
            }
        }
        let c = random_curve(seed, 2..=5, 10, rational);
        let t = random_param(&mut r, c.knots());
        let pc = project_to_curve(&c, &c.point(t), &params);
        prop_assert!(pc.converged && pc.distance < 1e-9);
    }
}

#[test]
fn projection_survives_far_and_outside_points() {
    let s = nurbs_core::shapes::sphere_patch(1.0).unwrap();
    let params = ProjectionParams::default();
    // the centre is equidistant from every point: any foot point at distance 1 is right
    let c = project_to_surface(&s, &Point3::origin(), &params);
    assert_close(c.distance, 1.0, 1e-9, "centre distance");
    // a point far outside the patch's angular range projects to the boundary
    let p = Point3::new(-5.0, -5.0, 0.0);
    let q = project_to_surface(&s, &p, &params);
    assert!(q.converged, "{q:?}");
    let brute = {
        let us = s.knots_u().uniform_params(401);
        let vs = s.knots_v().uniform_params(401);
        s.eval_grid_points(&us, &vs)
            .iter()
            .map(|x| (x - p).norm())
            .fold(f64::INFINITY, f64::min)
    };
    assert!(
        q.distance <= brute + 1e-9,
        "{} vs brute {}",
        q.distance,
        brute
    );
}

#[test]
fn warm_projection_onto_an_exact_sphere_ends_at_the_radial_foot() {
    // the foot of a point off an exact (rational) sphere is its radial projection; from a start
    // near it Newton ends at the minimum of its quadratic model once the next step would move
    // the point by less than the point tolerance, and that point is the foot within it
    let r = 2.0;
    let s = nurbs_core::shapes::sphere_octant(r).unwrap();
    let params = ProjectionParams::default();
    let eps = params.point_tolerance * s.size();
    let mut projector = nurbs_core::SurfaceProjector::new(&s, params);
    for (k, (u, v)) in [(0.3, 0.4), (0.5, 0.5), (0.7, 0.2)].into_iter().enumerate() {
        let (u, v) = (
            s.domain_u().0 + u * (s.domain_u().1 - s.domain_u().0),
            s.domain_v().0 + v * (s.domain_v().1 - s.domain_v().0),
        );
        let on = s.point(u, v);
        for off in [0.0, 0.3, -0.5] {
            let p = Point3::from(on.coords * ((r + off) / r));
            let start = (u + 1e-3 * (k as f64 + 1.0), v - 1e-3);
            let f = projector.project_from(&p, start);
            assert!(f.converged, "{f:?}");
            let radial = Point3::from(p.coords * (r / p.coords.norm()));
            assert!(
                (f.point - radial).norm() <= 10.0 * eps,
                "foot {:?} vs radial {radial:?}: {:.3e} apart (eps {eps:.1e})",
                f.point,
                (f.point - radial).norm()
            );
            assert_close(f.distance, off.abs(), 10.0 * eps, "distance");
        }
    }
}

/// A point on a sphere corner beside its pole projects onto itself: the corner of radius 5 of
/// Open CASCADE's box (occt_box12_r5.igs, entity 661, as read: its first u row collapsed to the
/// pole (115, 5, 0)), and a point of its trim on the boundary meridian 0.19 from the pole. The
/// three nearest start samples are the pole row's, one point where the tangent along the row
/// vanishes; Newton stayed there and reported the pole, 0.19 away.
#[test]
// the knots are the file's roundings of 2π and 5π/2, not the constants
#[allow(clippy::approx_constant)]
fn a_point_beside_a_pole_is_found_on_the_sphere_not_at_the_pole() {
    use std::f64::consts::FRAC_PI_2;
    let ku = KnotVector::new(2, vec![-FRAC_PI_2, -FRAC_PI_2, -FRAC_PI_2, 0.0, 0.0, 0.0]).unwrap();
    let (va, vb) = (6.283185307, 7.853981634);
    let kv = KnotVector::new(2, vec![va, va, va, vb, vb, vb]).unwrap();
    let rows = [
        [[115.0, 5.0, 0.0], [115.0, 5.0, 0.0], [115.0, 5.0, 0.0]],
        [
            [120.0, 5.0000000008979315, 8.881784197001252e-16],
            [
                120.00000000089793,
                -1.275859418115033e-10,
                8.881784197001252e-16,
            ],
            [114.99999999987241, 0.0, 8.881784197001252e-16],
        ],
        [
            [120.0, 5.0000000008979315, 5.0],
            [120.00000000089793, -1.275859418115033e-10, 5.0],
            [114.99999999987241, 0.0, 5.0],
        ],
    ];
    let points: Vec<Point3> = rows.iter().flatten().map(|p| Point3::from(*p)).collect();
    let (c, h) = (std::f64::consts::FRAC_1_SQRT_2, 0.7071067811140325);
    let weights = vec![1.0, h, 1.0, c, 0.4999999999487241, c, 1.0, h, 1.0];
    let s = nurbs_core::BSplineSurface::new(ku, kv, points, Some(weights)).unwrap();
    let p = Point3::new(115.19133227615964, 5.000000000000001, 0.0036621451207314902);
    let f = nurbs_core::project_to_surface(&s, &p, &ProjectionParams::default());
    assert!(
        f.distance <= 1e-9,
        "{:.3e} off at ({}, {})",
        f.distance,
        f.u,
        f.v
    );
    let mut projector = nurbs_core::SurfaceProjector::new(&s, ProjectionParams::default());
    let (u0, u1) = s.domain_u();
    for fu in [0.002, 0.01, 0.027] {
        for fv in [0.0, 0.5, 1.0] {
            let q = s.point(u0 + fu * (u1 - u0), va + fv * (vb - va));
            let f = projector.project(&q);
            assert!(
                f.distance <= 1e-9,
                "at ({fu}, {fv}): {:.3e} off",
                f.distance
            );
        }
    }
}
