//! Closed-form truth: circles, spheres, cylinders, tori and the paraboloid.

use nurbs_core::shapes::{
    circle, cylinder, paraboloid_bicubic, sphere_octant, sphere_patch, torus,
};
use nurbs_core::testing::assert_close;
use nurbs_core::{Direction, Point3, Vector3};

const TOL: f64 = 1e-12;

#[test]
fn rational_circle_has_radius_and_curvature() {
    for r in [0.5, 3.0, 120.0] {
        let c = circle(r).unwrap();
        for k in 0..=200 {
            let t = k as f64 / 200.0;
            let p = c.point(t);
            assert_close(p.coords.norm(), r, TOL * r, "radius");
            assert_close(c.curvature(t).unwrap(), 1.0 / r, TOL / r, "curvature");
        }
    }
}

/// The octant from the pole: every point on the sphere, the u = 0 side one point (the pole), no
/// normal there, and |k| = 1/r wherever the normal is defined.
#[test]
fn sphere_octant_has_its_pole_and_the_sphere_curvature() {
    let r = 1.5;
    let s = sphere_octant(r).unwrap();
    for b in 0..=10 {
        let v = b as f64 / 10.0;
        assert_close(s.point(0.0, v).z, r, TOL * r, "pole");
        assert_close(s.point(0.0, v).coords.xy().norm(), 0.0, TOL * r, "pole");
        assert!(
            s.derivatives(0.0, v).normal().is_none(),
            "no normal at the pole"
        );
        for a in 1..=10 {
            let d = s.derivatives(a as f64 / 10.0, v);
            assert_close(d.point.coords.norm(), r, TOL * r, "on sphere");
            let pc = d.principal_curvatures().unwrap();
            assert_close(pc.k1.abs(), 1.0 / r, 1e-10, "k1");
            assert_close(pc.k2.abs(), 1.0 / r, 1e-10, "k2");
        }
    }
}

#[test]
fn sphere_patch_curvatures() {
    let r = 2.5;
    let s = sphere_patch(r).unwrap();
    for a in 0..=10 {
        for b in 0..=10 {
            let d = s.derivatives(a as f64 / 10.0, b as f64 / 10.0);
            assert_close(d.point.coords.norm(), r, TOL * r, "on sphere");
            let pc = d.principal_curvatures().unwrap();
            // normal S_u × S_v of this patch points inward: curvatures are +1/r
            let outward = d.point.coords.dot(&pc.normal) > 0.0;
            let sign = if outward { -1.0 } else { 1.0 };
            assert_close(pc.k1, sign / r, 1e-10, "k1");
            assert_close(pc.k2, sign / r, 1e-10, "k2");
            assert_close(pc.gauss, 1.0 / (r * r), 1e-10, "K");
            assert_close(pc.mean.abs(), 1.0 / r, 1e-10, "|H|");
            // normal curvature in any tangent direction is the same
            let dir = d.du * 0.3 + d.dv * 0.7;
            assert_close(
                d.normal_curvature(&dir).unwrap(),
                sign / r,
                1e-10,
                "normal curvature",
            );
        }
    }
}

#[test]
fn cylinder_curvatures_and_directions() {
    let (r, h) = (4.0, 10.0);
    let s = cylinder(r, h).unwrap();
    for a in 0..=6 {
        for b in 0..=6 {
            let d = s.derivatives(a as f64 / 6.0, b as f64 / 6.0);
            let p = d.point;
            assert_close(p.x.hypot(p.y), r, TOL * r, "on cylinder");
            let pc = d.principal_curvatures().unwrap();
            let outward = Vector3::new(p.x, p.y, 0.0).dot(&pc.normal) > 0.0;
            let curved = if outward { -1.0 / r } else { 1.0 / r };
            let (kmax, kmin) = if curved > 0.0 {
                (curved, 0.0)
            } else {
                (0.0, curved)
            };
            assert_close(pc.k1, kmax, 1e-10, "k1");
            assert_close(pc.k2, kmin, 1e-10, "k2");
            assert_close(pc.gauss, 0.0, 1e-10, "K");
            // the zero-curvature direction is the axis
            let axis_dir = if curved > 0.0 { pc.dir2 } else { pc.dir1 };
            assert_close(axis_dir.z.abs(), 1.0, 1e-8, "ruling along z");
            assert_close(
                d.normal_curvature(&Vector3::z()).unwrap(),
                0.0,
                1e-10,
                "axis curvature",
            );
        }
    }
}

#[test]
fn torus_gauss_and_mean_everywhere() {
    let (big, small) = (5.0, 1.5);
    let s = torus(big, small).unwrap();
    for a in 0..=24 {
        for b in 0..=24 {
            let d = s.derivatives(a as f64 / 24.0, b as f64 / 24.0);
            let p = d.point;
            let rho = p.x.hypot(p.y);
            assert_close((rho - big).hypot(p.z), small, 1e-12 * big, "on torus");
            let cos_theta = (rho - big) / small;
            let k_exact = cos_theta / (small * (big + small * cos_theta));
            let h_exact =
                (big + 2.0 * small * cos_theta) / (2.0 * small * (big + small * cos_theta));
            let pc = d.principal_curvatures().unwrap();
            let tube_centre = Point3::new(big * p.x / rho, big * p.y / rho, 0.0);
            let outward = (p - tube_centre).dot(&pc.normal) > 0.0;
            assert_close(pc.gauss, k_exact, 1e-10, "K");
            assert_close(
                pc.mean,
                if outward { -h_exact } else { h_exact },
                1e-10,
                "H",
            );
            // the direction-free path gives the same values
            let cv = d.curvature_values().unwrap();
            assert_close(cv.k1, pc.k1, 1e-12, "k1 values");
            assert_close(cv.k2, pc.k2, 1e-12, "k2 values");
            assert!((cv.normal - pc.normal).norm() < 1e-15);
        }
    }
}

#[test]
fn paraboloid_bicubic_is_exact() {
    let s = paraboloid_bicubic(&[0.2, 0.45, 0.7]).unwrap();
    assert_eq!((s.degree_u(), s.degree_v()), (3, 3));
    assert!(!s.is_rational());
    for a in 0..=20 {
        for b in 0..=20 {
            let (u, v) = (a as f64 / 20.0, b as f64 / 20.0);
            let d = s.derivatives(u, v);
            let (x, y) = (2.0 * u - 1.0, 2.0 * v - 1.0);
            assert_close(d.point.x, x, 1e-13, "x");
            assert_close(d.point.y, y, 1e-13, "y");
            assert_close(d.point.z, x * x + y * y, 1e-13, "z");
            let w = 1.0 + 4.0 * x * x + 4.0 * y * y;
            let pc = d.principal_curvatures().unwrap();
            assert!(pc.normal.z > 0.0);
            assert_close(pc.gauss, 4.0 / (w * w), 1e-10, "K");
            assert_close(
                pc.mean,
                (2.0 + 4.0 * x * x + 4.0 * y * y) / w.powf(1.5),
                1e-10,
                "H",
            );
        }
    }
    // the isocurve at u = 0.5 (x = 0) is the parabola z = y²
    let iso = s.isocurve(Direction::U, 0.5).unwrap();
    for k in 0..=10 {
        let t = k as f64 / 10.0;
        let y = 2.0 * t - 1.0;
        let c = iso.point(t);
        assert_close(c.z, y * y, 1e-13, "isocurve z");
        let exact_curv = 2.0 / (1.0 + 4.0 * y * y).powf(1.5);
        assert_close(
            iso.curvature(t).unwrap(),
            exact_curv,
            1e-10,
            "parabola curvature",
        );
    }
}

#[test]
fn poles_have_no_normal() {
    // a sphere cap with a pole: a quarter meridian from the equator to the north pole
    use nurbs_core::{BSplineSurface, KnotVector};
    let c = std::f64::consts::FRAC_1_SQRT_2;
    let prof = [(1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
    let rot = [(1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
    let w = [1.0, c, 1.0];
    let mut pts = Vec::new();
    let mut ws = Vec::new();
    for i in 0..3 {
        for j in 0..3 {
            pts.push(Point3::new(
                prof[i].0 * rot[j].0,
                prof[i].0 * rot[j].1,
                prof[i].1,
            ));
            ws.push(w[i] * w[j]);
        }
    }
    let s = BSplineSurface::new(
        KnotVector::bezier(2).unwrap(),
        KnotVector::bezier(2).unwrap(),
        pts,
        Some(ws),
    )
    .unwrap();
    for b in 0..=10 {
        let d = s.derivatives(1.0, b as f64 / 10.0);
        assert!(d.normal().is_none(), "pole must have no normal");
        assert!(d.principal_curvatures().is_none());
        assert!(d.normal_curvature(&d.du).is_none());
        let inside = s.derivatives(0.5, b as f64 / 10.0);
        assert!(inside.principal_curvatures().is_some());
    }
}

/// Arcs of any sweep up to a full turn are exact: every point at the radius, the ends at the
/// given angles, the angle increasing along the arc.
#[test]
fn arcs_of_every_sweep_are_exact() {
    for (start, end) in [
        (0.3, 0.9),
        (-1.0, 2.0),
        (4.712_388_98, 6.1),
        (0.0, std::f64::consts::TAU),
    ] {
        let c = nurbs_core::shapes::arc(
            Point3::new(1.0, 2.0, 3.0),
            Vector3::x(),
            Vector3::y(),
            2.5,
            start,
            end,
        )
        .unwrap();
        let (t0, t1) = c.knots().domain();
        assert_eq!((t0, t1), (start, end));
        let mut last = f64::NEG_INFINITY;
        for k in 0..=200 {
            let t = t0 + (t1 - t0) * k as f64 / 200.0;
            let p = c.point(t) - Point3::new(1.0, 2.0, 3.0);
            assert!((p.norm() - 2.5).abs() < 1e-12, "{start}..{end} at {t}");
            assert!(p.z.abs() < 1e-15);
            // unwrapped angle from the start direction
            let a = start + (p.y.atan2(p.x) - start).rem_euclid(std::f64::consts::TAU);
            let a = if k == 200 && a < last {
                a + std::f64::consts::TAU
            } else {
                a
            };
            assert!(a >= last - 1e-12, "{start}..{end}: angle falls at {t}");
            last = a;
        }
        let e = c.point(t1) - Point3::new(1.0, 2.0, 3.0);
        assert!((e - Vector3::new(end.cos(), end.sin(), 0.0) * 2.5).norm() < 1e-12);
    }
    assert!(nurbs_core::shapes::unit_arc(1.0, 1.0).is_err());
    assert!(nurbs_core::shapes::unit_arc(0.0, 7.0).is_err());
}

/// A full turn written with its rounding past 2π (Open CASCADE writes 6.28320989) is a closed
/// circle: its knots run to the written end, its last point is its first bit for bit (it
/// overlapped itself by 2.5e-5 rad), and every point lies on the circle.
#[test]
fn a_turn_past_two_pi_closes_exactly() {
    let end = 6.28320989;
    let (kv, pts, w) = nurbs_core::shapes::unit_arc(0.0, end).unwrap();
    assert_eq!(kv.domain(), (0.0, end));
    assert_eq!(pts[0], pts[pts.len() - 1]);
    let points = pts.iter().map(|&(a, b)| Point3::new(a, b, 0.0)).collect();
    let c = nurbs_core::BSplineCurve::new(kv, points, Some(w)).unwrap();
    for k in 0..=400 {
        let p = c.point(end * k as f64 / 400.0);
        assert!((p.coords.norm() - 1.0).abs() < 1e-12, "{p:?}");
    }
    assert_eq!(c.point(end), c.point(0.0));
}

/// A line parallel to an oblique axis turned about it is a cylinder (every point at the
/// distance, curvatures 1/r and 0); a half circle with its ends on the axis is a sphere with two
/// poles (curvature 1/r in every direction).
#[test]
fn surfaces_of_revolution_are_exact() {
    use nurbs_core::{BSplineCurve, KnotVector};
    let origin = Point3::new(1.0, -2.0, 0.5);
    let axis = Vector3::new(1.0, 2.0, 2.0) / 3.0;
    let side = Vector3::new(2.0, -1.0, 0.0).normalize() * 4.0;
    let line = BSplineCurve::new(
        KnotVector::bezier(1).unwrap(),
        vec![origin + side, origin + side + axis * 10.0],
        None,
    )
    .unwrap();
    let cyl = nurbs_core::shapes::revolve_curve(&line, origin, axis * 3.0, 0.2, 2.9).unwrap();
    let y = axis.cross(&side.normalize());
    let sphere_profile = nurbs_core::shapes::arc(
        origin,
        side.normalize(),
        axis,
        3.0,
        -std::f64::consts::FRAC_PI_2,
        std::f64::consts::FRAC_PI_2,
    )
    .unwrap();
    let sphere =
        nurbs_core::shapes::revolve_curve(&sphere_profile, origin, axis, 0.0, 5.0).unwrap();
    for a in 0..=10 {
        for b in 0..=10 {
            let (u, v) = (a as f64 / 10.0, 0.2 + 2.7 * b as f64 / 10.0);
            let d = cyl.derivatives(u, v);
            let r = d.point - origin;
            let radial = r - axis * axis.dot(&r);
            assert!((radial.norm() - 4.0).abs() < 1e-12);
            let k = d.principal_curvatures().unwrap();
            let (lo, hi) = (k.k1.abs().min(k.k2.abs()), k.k1.abs().max(k.k2.abs()));
            assert!(lo < 1e-9 && (hi - 0.25).abs() < 1e-9, "{k:?}");
            let (u, v) = (
                -std::f64::consts::FRAC_PI_2
                    + std::f64::consts::PI * (0.05 + 0.9 * a as f64 / 10.0),
                5.0 * b as f64 / 10.0,
            );
            let d = sphere.derivatives(u, v);
            assert!(((d.point - origin).norm() - 3.0).abs() < 1e-12);
            // umbilic everywhere: H = ±1/r, K = 1/r²
            let (h, g) = (d.mean_curvature().unwrap(), d.gaussian_curvature().unwrap());
            assert!(
                (h.abs() - 1.0 / 3.0).abs() < 1e-8 && (g - 1.0 / 9.0).abs() < 1e-8,
                "{h} {g}"
            );
        }
    }
    // the start angle turns the generatrix by that much about the axis
    let p = cyl.point(0.0, 0.2);
    let want = origin + side * 0.2f64.cos() + y * 4.0 * 0.2f64.sin();
    assert!((p - want).norm() < 1e-12);
    // the sphere's profile ends lie on the axis: both rows collapse to a pole
    let n = sphere.num_v();
    for i in [0, sphere.num_u() - 1] {
        let first = sphere.control_point(i, 0);
        assert!((0..n).all(|j| (sphere.control_point(i, j) - first).norm() < 1e-12));
    }
}

/// A rational circle extruded along a slanted direction is an elliptic cylinder whose sections
/// parallel to the circle's plane are that circle moved: every point is C(u) + v d exactly, and
/// with d along the axis it is a circular cylinder (curvatures 0 and 1/r).
#[test]
fn an_extruded_circle_is_an_exact_cylinder() {
    let c = circle(2.5).unwrap();
    let (t0, t1) = c.knots().domain();
    for d in [Vector3::new(0.0, 0.0, 4.0), Vector3::new(1.0, -0.5, 3.0)] {
        let s = nurbs_core::shapes::extrude_curve(&c, d, (-1.0, 2.0)).unwrap();
        assert!(s.is_rational());
        for a in 0..=20 {
            for b in 0..=6 {
                let t = t0 + (t1 - t0) * a as f64 / 20.0;
                let v = -1.0 + 3.0 * b as f64 / 6.0;
                let want = c.point(t) + d * v;
                assert!((s.point(t, v) - want).norm() < TOL, "{d:?} {t} {v}");
                if d.x == 0.0 {
                    let k = s.derivatives(t, v).principal_curvatures().unwrap();
                    let (lo, hi) = (k.k1.abs().min(k.k2.abs()), k.k1.abs().max(k.k2.abs()));
                    assert!(lo < 1e-9 && (hi - 0.4).abs() < 1e-9, "{k:?}");
                }
            }
        }
    }
    assert!(nurbs_core::shapes::extrude_curve(&c, Vector3::zeros(), (0.0, 1.0)).is_err());
}

/// The ruling of two coaxial circular arcs of radii r₁, r₂ at heights 0 and h is the cone
/// frustum: at v the point lies at radius (1 − v) r₁ + v r₂ and height v h. A line and a cubic
/// of different knots rule exactly too (the rows are the two curves), and two rational curves
/// with different weight functions are refused.
#[test]
fn ruled_surfaces_are_exact_where_a_ruling_of_their_degree_exists() {
    use nurbs_core::shapes::{arc, ruled_surface};
    use nurbs_core::{BSplineCurve, KnotVector};
    let a = arc(Point3::origin(), Vector3::x(), Vector3::y(), 1.0, 0.0, 2.0).unwrap();
    let b = arc(
        Point3::new(0.0, 0.0, 4.0),
        Vector3::x(),
        Vector3::y(),
        3.0,
        0.0,
        2.0,
    )
    .unwrap();
    let s = ruled_surface(&a, &b).unwrap();
    for i in 0..=10 {
        for j in 0..=10 {
            let (u, v) = (i as f64 / 10.0, j as f64 / 10.0);
            let p = s.point(u, v);
            assert!((p.x.hypot(p.y) - (1.0 + 2.0 * v)).abs() < TOL, "{u} {v}");
            assert!((p.z - 4.0 * v).abs() < TOL);
        }
    }
    // a segment and a cubic on other knots: every point is the interpolation of the two curves
    let line = BSplineCurve::new(
        KnotVector::new(1, vec![2.0, 2.0, 7.0, 7.0]).unwrap(),
        vec![Point3::new(0.0, 0.0, 0.0), Point3::new(10.0, 0.0, 0.0)],
        None,
    )
    .unwrap();
    let cubic = BSplineCurve::new(
        KnotVector::new(3, vec![0.0, 0.0, 0.0, 0.0, 0.3, 1.0, 1.0, 1.0, 1.0]).unwrap(),
        vec![
            Point3::new(0.0, 5.0, 1.0),
            Point3::new(3.0, 6.0, -1.0),
            Point3::new(6.0, 4.0, 2.0),
            Point3::new(8.0, 5.0, 0.0),
            Point3::new(10.0, 5.0, 1.0),
        ],
        None,
    )
    .unwrap();
    let s = ruled_surface(&line, &cubic).unwrap();
    assert_eq!(s.degree_u(), 3);
    for i in 0..=20 {
        for j in 0..=4 {
            let (u, v) = (i as f64 / 20.0, j as f64 / 4.0);
            let want = line.point(2.0 + 5.0 * u) * (1.0 - v) + cubic.point(u).coords * v;
            assert!((s.point(u, v) - want).norm() < TOL, "{u} {v}");
        }
    }
    // a circle against a rational arc of other weights: no exact ruling of this degree
    let bent = BSplineCurve::new(
        KnotVector::bezier(2).unwrap(),
        vec![
            Point3::new(0.0, 0.0, 1.0),
            Point3::new(1.0, 1.0, 1.0),
            Point3::new(2.0, 0.0, 1.0),
        ],
        Some(vec![1.0, 3.0, 1.0]),
    )
    .unwrap();
    let other = BSplineCurve::new(
        KnotVector::bezier(2).unwrap(),
        vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(2.0, 0.0, 0.0),
        ],
        Some(vec![1.0, 0.5, 1.0]),
    )
    .unwrap();
    assert!(ruled_surface(&bent, &other).is_err());
    // proportional weights are one weight function: ruled exactly
    let scaled = BSplineCurve::new(
        KnotVector::bezier(2).unwrap(),
        vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(2.0, 0.0, 0.0),
        ],
        Some(vec![2.0, 6.0, 2.0]),
    )
    .unwrap();
    let s = ruled_surface(&bent, &scaled).unwrap();
    for i in 0..=10 {
        let u = i as f64 / 10.0;
        let want = bent.point(u) + Vector3::new(0.0, 0.0, -0.5);
        let got = s.point(u, 0.5);
        assert!((got - want).norm() < TOL, "{u}: {got:?} vs {want:?}");
    }
}

/// A curve run backwards passes the same points in the opposite order, C'(t) = C(a + b − t),
/// and reversed twice is the curve again (rational circle on a non-uniform domain).
#[test]
fn a_reversed_curve_runs_backwards() {
    let c = nurbs_core::shapes::arc(
        Point3::new(1.0, 2.0, 0.0),
        Vector3::x(),
        Vector3::y(),
        3.0,
        0.3,
        4.0,
    )
    .unwrap();
    let r = c.reversed().unwrap();
    let (a, b) = c.knots().domain();
    // a + b − k is rounded once per knot: the domain is the same to an ulp of b
    let ulp = f64::EPSILON * b.abs();
    let (ra, rb) = r.knots().domain();
    assert!((ra - a).abs() <= ulp && (rb - b).abs() <= ulp, "{ra} {rb}");
    for k in 0..=40 {
        let t = a + (b - a) * k as f64 / 40.0;
        assert!((r.point(t) - c.point(a + b - t)).norm() < TOL, "{t}");
    }
    // twice: the control points and weights come back exactly, the knots to an ulp
    let back = r.reversed().unwrap();
    assert_eq!(back.control_points(), c.control_points());
    assert_eq!(back.weights(), c.weights());
    for (x, y) in back.knots().knots().iter().zip(c.knots().knots()) {
        assert!((x - y).abs() <= 2.0 * ulp, "{x} {y}");
    }
}

/// A torus band cut across its seam (u from 3π/2 round to π/2, as a face from −90° to 90°)
/// comes back as one surface: the piece after the seam joined to the one before it, shifted by
/// the period, is the torus point for point, C⁰ at the old seam (a knot of multiplicity p).
#[test]
fn a_band_across_the_seam_of_a_closed_surface_is_one_joined_surface() {
    use nurbs_core::Direction;
    let torus = nurbs_core::shapes::torus(10.0, 3.0).unwrap();
    let ((a, b), (c, d)) = (torus.domain_u(), torus.domain_v());
    let period = b - a;
    let (start, end) = (a + 0.75 * period, a + 0.25 * period);
    let before = torus.extract((start, b), (c, d)).unwrap();
    let after = torus
        .extract((a, end), (c, d))
        .unwrap()
        .shifted(Direction::U, period)
        .unwrap();
    let band = before.joined(Direction::U, &after).unwrap();
    assert_eq!(band.domain_u(), (start, end + period));
    let p = band.degree_u();
    let at_seam = band.knots_u().knots().iter().filter(|&&k| k == b).count();
    assert_eq!(at_seam, p, "the old seam is a C0 knot");
    for k in 0..=20 {
        let u = start + (end + period - start) * k as f64 / 20.0;
        let on_torus = if u > b { u - period } else { u };
        for l in 0..=6 {
            let v = c + (d - c) * l as f64 / 6.0;
            let gap = (band.point(u, v) - torus.point(on_torus, v)).norm();
            assert!(gap < 1e-12, "u {u} v {v}: {gap}");
        }
    }
    // the same in v, through the transposes
    let band_v = before
        .transposed()
        .unwrap()
        .joined(Direction::V, &after.transposed().unwrap())
        .unwrap();
    assert_eq!(band_v.transposed().unwrap(), band);
    // pieces that do not meet are refused
    let gap = torus.extract((a, end), (c, d)).unwrap();
    assert!(before.joined(Direction::U, &gap).is_err());
    let other_degree = after.elevate_degree(Direction::U, 1).unwrap();
    assert!(before.joined(Direction::U, &other_degree).is_err());
}
