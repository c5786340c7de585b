//! Unit tests of the one-hump section: contact lines, tangent planes, one hump, exact sweeps.

use super::*;
use nurbs_core::energy::max_deviation;
use nurbs_core::fairness::{count_extrema, cross_profile};
use nurbs_core::shapes::{arc, cylinder, revolve_curve};
use nurbs_core::{Point3, Vector3};
use std::f64::consts::{FRAC_PI_2, PI};

/// A torus fillet of tube radius 3 between the plane z = 0 and the cylinder ρ = 7 about z (the
/// inner bottom quarter of the tube centred at ρ = 10, z = 3), a quarter turn about z; u runs
/// across (the tube's arc), v around the axis.
fn torus_fillet() -> BSplineSurface {
    let section = arc(
        Point3::new(10.0, 0.0, 3.0),
        Vector3::x(),
        Vector3::z(),
        3.0,
        PI,
        1.5 * PI,
    )
    .unwrap();
    revolve_curve(&section, Point3::origin(), Vector3::z(), 0.0, FRAC_PI_2).unwrap()
}

/// The cross profile's samples (normal curvature across, at the middle of the length).
fn profile(s: &BSplineSurface, cross: Direction, at: f64) -> Vec<f64> {
    cross_profile(s, cross, at, 201)
        .into_iter()
        .map(|k| k.unwrap().abs())
        .collect()
}

#[test]
fn a_cylinder_fillet_gets_one_hump_with_its_contact_lines_and_tangent_planes_kept() {
    let r = 2.0;
    let s = cylinder(r, 1.0).unwrap();
    let f = 0.15;
    let out = one_hump_section(&s, Direction::V, (f, f), RampShape::Linear, [None, None]).unwrap();
    assert!(out.is_rational() || !s.is_rational());
    let (v0, v1) = s.domain_v();
    let (u0, u1) = s.domain_u();
    for k in 0..=10 {
        let u = u0 + (u1 - u0) * k as f64 / 10.0;
        for v in [v0, v1] {
            // the contact line, point for point
            assert!((out.point(u, v) - s.point(u, v)).norm() < 1e-12);
            // the cross tangent's direction (the tangent plane with the along tangent)
            let (a, b) = (out.derivatives(u, v).dv, s.derivatives(u, v).dv);
            assert!(a.normalize().cross(&b.normalize()).norm() < 1e-9, "{a} {b}");
            // curvature 0 across at a ramped side (a plane's)
            let k = out.derivatives(u, v).normal_curvature(&a).unwrap();
            assert!(k.abs() < 1e-6 / r, "curvature {k} at the side");
        }
    }
    // one hump, its peak a little above 1/R (about 1/(1 − f/2) with the linear ramp's deficit ¼)
    for at in [0.0, 0.5, 1.0] {
        let p = profile(&out, Direction::V, at);
        let peak = p.iter().cloned().fold(0.0, f64::max);
        assert_eq!(count_extrema(&p, 0.005 * peak), 1, "{p:?}");
        assert!(peak > 1.0 / r && peak < 1.12 / r, "peak {peak}");
    }
    // it moved, by about 0.1 ℓ for a 90° arc (ℓ the ramp's length)
    let ramp = f * FRAC_PI_2 * r;
    let d = max_deviation(&s, &out, 21);
    assert!(
        d > 0.05 * ramp && d < 0.15 * ramp,
        "deviation {d}, ramp {ramp}"
    );
}

#[test]
fn a_torus_fillet_stays_a_surface_of_revolution() {
    let s = torus_fillet();
    let out = one_hump_section(
        &s,
        Direction::U,
        (0.2, 0.2),
        RampShape::Linear,
        [None, None],
    )
    .unwrap();
    let (u0, u1) = out.domain_u();
    let (v0, v1) = out.domain_v();
    for k in 0..=20 {
        let u = u0 + (u1 - u0) * k as f64 / 20.0;
        let p = out.point(u, v0);
        let (rho, z) = (p.x.hypot(p.y), p.z);
        for m in 1..=8 {
            let q = out.point(u, v0 + (v1 - v0) * m as f64 / 8.0);
            assert!((q.x.hypot(q.y) - rho).abs() < 1e-9 && (q.z - z).abs() < 1e-9);
        }
    }
    // the contact circles kept: on the plane z = 0 at ρ = 10 and on the cylinder ρ = 7 at z = 3
    let (a, b) = (out.point(u0, v0), out.point(u1, v0));
    assert!(
        (a - Point3::new(7.0, 0.0, 3.0)).norm() < 1e-12
            || (a - Point3::new(10.0, 0.0, 0.0)).norm() < 1e-12
    );
    assert!((a - b).norm() > 1.0);
    let p = profile(&out, Direction::U, 0.5);
    let peak = p.iter().cloned().fold(0.0, f64::max);
    assert_eq!(count_extrema(&p, 0.005 * peak), 1, "{p:?}");
    assert!(peak < 1.35 / 3.0, "peak {peak}");
}

#[test]
fn an_unramped_end_keeps_a_curvature() {
    let r = 2.0;
    let s = cylinder(r, 1.0).unwrap();
    let out =
        one_hump_section(&s, Direction::V, (0.2, 0.0), RampShape::Flat, [None, None]).unwrap();
    let (u0, _) = s.domain_u();
    let (v0, v1) = s.domain_v();
    let at = |v: f64| {
        let d = out.derivatives(u0, v);
        d.normal_curvature(&d.dv).unwrap().abs()
    };
    assert!(at(v0) < 1e-6);
    // no ramp there: the end bends (the profile's tilt shares the turn between the ends)
    assert!(at(v1) > 0.5 / r, "end curvature {}", at(v1));
}

#[test]
fn a_wider_ramp_moves_the_section_further() {
    let s = cylinder(2.0, 1.0).unwrap();
    for shape in [RampShape::Linear, RampShape::Flat] {
        let d = |f: f64| {
            let out = one_hump_section(&s, Direction::V, (f, f), shape, [None, None]).unwrap();
            max_deviation(&s, &out, 21)
        };
        let (a, b) = (d(0.05), d(0.2));
        assert!(a < b && b < 5.0 * a && b > 3.0 * a, "{shape:?}: {a} {b}");
    }
}

#[test]
fn the_ramp_shapes_meet_their_end_conditions_and_deficits() {
    // ρ(0) = 0, ρ(1) = 1, ρ'(1) = ρ''(1) = 0; the flat one also ρ'(0) = 0, the linear one
    // ρ'(0) = 3. Central differences with h = 1e-3: truncation h²/6·|ρ'''| ≤ 1e-5 and
    // h²/12·|ρ''''| ≤ 3e-5 for these polynomials, rounding 1e-10 — far below the bound 1e-4
    let h = 1e-3;
    for shape in [RampShape::Linear, RampShape::Flat] {
        let r = |x: f64| {
            // the polynomial itself beyond [0, 1] (`at` clamps there)
            let y = 1.0 - x;
            match shape {
                RampShape::Linear => 1.0 - y * y * y,
                RampShape::Flat => x * x * x * (10.0 + x * (6.0 * x - 15.0)),
            }
        };
        for x in [0.0, 0.3, 0.7, 1.0] {
            assert!((r(x) - shape.at(x)).abs() < 1e-15, "{shape:?} at {x}");
        }
        let d1 = |x: f64| (r(x + h) - r(x - h)) / (2.0 * h);
        let d2 = |x: f64| (r(x + h) - 2.0 * r(x) + r(x - h)) / (h * h);
        assert!(shape.at(0.0).abs() < 1e-15 && (shape.at(1.0) - 1.0).abs() < 1e-15);
        assert!(d1(1.0).abs() < 1e-4 && d2(1.0).abs() < 1e-4, "{shape:?}");
        let start = match shape {
            RampShape::Linear => 3.0,
            RampShape::Flat => 0.0,
        };
        assert!(
            (d1(0.0) - start).abs() < 1e-4,
            "{shape:?}: ρ'(0) = {}",
            d1(0.0)
        );
        // the deficit ∫(1 − ρ), midpoint rule on 10 000 steps
        let n = 10_000;
        let deficit: f64 = (0..n)
            .map(|i| 1.0 - shape.at((i as f64 + 0.5) / n as f64))
            .sum::<f64>()
            / n as f64;
        let expected = match shape {
            RampShape::Linear => 0.25,
            RampShape::Flat => 0.5,
        };
        assert!((deficit - expected).abs() < 1e-8, "{shape:?}: {deficit}");
    }
}

#[test]
fn the_linear_ramp_moves_the_section_about_half_as_far_as_the_flat_one() {
    // the deviation follows the ramp's deficit (module docs): ¼ against ½
    let s = cylinder(2.0, 1.0).unwrap();
    let d = |shape: RampShape| {
        let out = one_hump_section(&s, Direction::V, (0.15, 0.15), shape, [None, None]).unwrap();
        max_deviation(&s, &out, 21)
    };
    let (linear, flat) = (d(RampShape::Linear), d(RampShape::Flat));
    assert!(
        linear > 0.4 * flat && linear < 0.6 * flat,
        "linear {linear}, flat {flat}"
    );
}

#[test]
fn a_flat_ramp_leaves_the_contact_line_with_less_curvature_than_a_linear_one() {
    // at 2 % of the section from the contact line, inside a ramp of 20 %: the flat ramp's
    // curvature grows as x³ there, the linear one's as x
    let r = 2.0;
    let s = cylinder(r, 1.0).unwrap();
    let near = |shape: RampShape| {
        let out = one_hump_section(&s, Direction::V, (0.2, 0.2), shape, [None, None]).unwrap();
        let (u0, _) = out.domain_u();
        let (v0, v1) = out.domain_v();
        let d = out.derivatives(u0, v0 + 0.02 * (v1 - v0));
        d.normal_curvature(&d.dv).unwrap().abs()
    };
    let (linear, flat) = (near(RampShape::Linear), near(RampShape::Flat));
    assert!(linear > 0.15 / r && linear < 0.5 / r, "linear {linear}");
    assert!(flat < 0.1 * linear, "flat {flat}, linear {linear}");
}

#[test]
fn weights_that_are_no_product_keep_both_contact_curves() {
    let s = cylinder(2.0, 1.0).unwrap();
    let mut w = s.weights().unwrap().to_vec();
    // the far contact row's weights doubled on one column: a NURBS fillet's kind of weights
    let last = s.num_v() - 1;
    w[last] *= 2.0;
    let odd = BSplineSurface::new(
        s.knots_u().clone(),
        s.knots_v().clone(),
        s.control_points().to_vec(),
        Some(w),
    )
    .unwrap();
    let out = one_hump_section(
        &odd,
        Direction::V,
        (0.1, 0.1),
        RampShape::Linear,
        [None, None],
    )
    .unwrap();
    let (u0, u1) = odd.domain_u();
    let (v0, v1) = odd.domain_v();
    for k in 0..=10 {
        let u = u0 + (u1 - u0) * k as f64 / 10.0;
        for v in [v0, v1] {
            assert!(
                (out.point(u, v) - odd.point(u, v)).norm() < 1e-12,
                "{u} {v} {}",
                (out.point(u, v) - odd.point(u, v)).norm()
            );
        }
    }
}

/// A polynomial fillet whose section changes along it: cubic Bézier arcs across (u), a 90° arc
/// of radius 2 at v = 0 and a 60° arc of radius 3 at v = 1, both leaving the plane z = 0 along
/// +x, joined linearly along (v).
fn changing_fillet() -> BSplineSurface {
    changing_fillet_along(KnotVector::new(1, vec![0.0, 0.0, 1.0, 1.0]).unwrap())
}

/// [`changing_fillet`] with the knot vector `along` in v (its control rows blend the two end
/// arcs linearly at their Greville fractions, so every v degree gives the same surface).
fn changing_fillet_along(along: KnotVector) -> BSplineSurface {
    let bezier_arc = |y: f64, r: f64, theta: f64| {
        let h = 4.0 / 3.0 * (theta / 4.0).tan() * r;
        let end = Point3::new(r * theta.sin(), y, r - r * theta.cos());
        let back = Vector3::new(theta.cos(), 0.0, theta.sin()) * h;
        [
            Point3::new(0.0, y, 0.0),
            Point3::new(h, y, 0.0),
            end - back,
            end,
        ]
    };
    let (a, b) = (
        bezier_arc(0.0, 2.0, FRAC_PI_2),
        bezier_arc(4.0, 3.0, PI / 3.0),
    );
    let fractions = along.greville_fractions();
    let points: Vec<Point3> = (0..4)
        .flat_map(|i| {
            fractions
                .iter()
                .map(move |&t| a[i] + (b[i] - a[i]) * t)
                .collect::<Vec<_>>()
        })
        .collect();
    BSplineSurface::new(
        KnotVector::new(3, vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0]).unwrap(),
        along,
        points,
        None,
    )
    .unwrap()
}

/// A Greville abscissa is a knot average, which can round past the domain's end: at
/// x = 0.8626903632435095, (x + x + x) / 3 < x. The sections are read at the abscissae
/// clamped to the domain, so such a surface is sectioned like any other.
#[test]
fn greville_abscissae_rounded_past_the_domain_are_read_at_its_end() {
    let x = 0.862_690_363_243_509_5;
    let along = KnotVector::new(3, vec![x, x, x, x, 2.0, 2.0, 2.0, 2.0]).unwrap();
    assert!(along.greville()[0] < x, "the rounding this test needs");
    let s = changing_fillet_along(along);
    let out = one_hump_section_by_sections(
        &s,
        Direction::U,
        (0.1, 0.1),
        RampShape::Linear,
        [None, None],
    )
    .unwrap();
    for u in [0.0, 1.0] {
        assert!((out.point(u, x) - s.point(u, x)).norm() < 1e-9);
    }
}

#[test]
fn a_section_that_changes_along_the_fillet_is_followed_section_by_section() {
    // the deviation of a ramp f on an arc of radius R is about 0.15 f R with the linear ramp
    // (module docs); the middle
    // section carried through every column's frame (`one_hump_section`) keeps the middle
    // section's shape in every column, and is not one hump at the ends (three extrema at v = 1)
    let s = changing_fillet();
    let f = 0.1;
    let out =
        one_hump_section_by_sections(&s, Direction::U, (f, f), RampShape::Linear, [None, None])
            .unwrap();
    let d = max_deviation(&s, &out, 21);
    assert!(d < 0.4 * f * 3.0, "deviation {d}");
    // the contact curves kept
    let (v0, v1) = s.domain_v();
    for k in 0..=10 {
        let v = v0 + (v1 - v0) * k as f64 / 10.0;
        for u in [0.0, 1.0] {
            assert!((out.point(u, v) - s.point(u, v)).norm() < 1e-9, "{u} {v}");
        }
    }
    // and one hump across at both ends and in the middle, counted above the input's own
    // wave (a cubic Bézier quarter circle's curvature varies by 1.6 % along it)
    for at in [0.0, 0.5, 1.0] {
        let p = profile(&out, Direction::U, at);
        let peak = p.iter().cloned().fold(0.0, f64::max);
        assert_eq!(count_extrema(&p, 0.02 * peak), 1, "at {at}: {p:?}");
    }
}

/// A ramp rises from its master's curvature across ([`Section::with_contacts`]): a cylinder
/// fillet of radius 2 whose start side lies on a cylinder of radius 10 with its circle in the
/// section's plane, tangent at the contact line and turning the same way, takes +1/10 there
/// (Meusnier: the plane holds the normal); its end, with no master given, stays at 0. The new
/// section meets both at its contact lines, and its curvature across is one hump from 1/10.
#[test]
fn a_ramp_rises_from_its_masters_curvature_across() {
    let r = 2.0;
    let s = cylinder(r, 1.0).unwrap();
    // the master: the cylinder of radius 10 through the fillet's start line (r, 0, z), its
    // axis at (r − 10, 0)
    let mut master = cylinder(10.0, 1.0).unwrap();
    for p in master.control_points_mut() {
        p.x += r - 10.0;
    }
    let section = profile::Section::read(&s, Direction::V)
        .unwrap()
        .with_contacts([Some(&master), None]);
    assert!(
        (section.contact_curvatures().0 - 0.1).abs() < 1e-9,
        "{:?}",
        section.contact_curvatures()
    );
    assert_eq!(section.contact_curvatures().1, 0.0);
    let f = 0.15;
    let out = one_hump_section(
        &s,
        Direction::V,
        (f, f),
        RampShape::Linear,
        [Some(&master), None],
    )
    .unwrap();
    let (v0, v1) = s.domain_v();
    let (u0, u1) = s.domain_u();
    for k in 0..=10 {
        let u = u0 + (u1 - u0) * k as f64 / 10.0;
        let (start, end) = (out.derivatives(u, v0), out.derivatives(u, v1));
        let k0 = start.normal_curvature(&start.dv).unwrap().abs();
        let k1 = end.normal_curvature(&end.dv).unwrap().abs();
        // the least-squares quintic meets the profile's start to a percent; the flat end exactly
        assert!(
            (k0 - 0.1).abs() < 1e-3,
            "curvature {k0} at the master's side"
        );
        assert!(k1 < 1e-6 / r, "curvature {k1} at the flat side");
    }
    for at in [0.0, 0.5, 1.0] {
        let p = profile(&out, Direction::V, at);
        let peak = p.iter().cloned().fold(0.0, f64::max);
        assert_eq!(count_extrema(&p, 0.005 * peak), 1, "{p:?}");
        assert!(p[0] > 0.099 && p[0] < 0.101, "{}", p[0]);
    }
}

/// The largest relative spread of `p` over its middle 40 % (the plateau between the ramps).
fn plateau_ripple(p: &[f64]) -> f64 {
    let n = p.len();
    let mid = &p[3 * n / 10..=7 * n / 10];
    let lo = mid.iter().cloned().fold(f64::MAX, f64::min);
    let hi = mid.iter().cloned().fold(0.0, f64::max);
    (hi - lo) / hi
}

#[test]
fn the_plateau_stays_within_the_comb_hysteresis_at_every_ramp_width_and_shape() {
    // the ramps' spans (RAMP_SPANS) keep the plateau of a 90° arc within half the 0.5 % at
    // which a comb's extrema count: three spans leave 0.6 % with the flat ramp at a quarter, two
    // extrema more
    let r = 2.0;
    let s = cylinder(r, 1.0).unwrap();
    for shape in [RampShape::Linear, RampShape::Flat] {
        for f in [1.0 / 64.0, 1.0 / 16.0, 0.125, 0.2, MAX_RAMP] {
            let out = one_hump_section(&s, Direction::V, (f, f), shape, [None, None]).unwrap();
            let p = profile(&out, Direction::V, 0.5);
            let peak = p.iter().cloned().fold(0.0, f64::max);
            assert_eq!(
                count_extrema(&p, 0.005 * peak),
                1,
                "{shape:?} at {f}: {p:?}"
            );
            let ripple = plateau_ripple(&p);
            assert!(ripple < 0.0025, "{shape:?} at {f}: plateau ripple {ripple}");
        }
    }
}
