//! Slaves linked on two and four sides (twists, \[SV\] §3.3) and a trimmed master (boundary along a
//! non-isoparametric curve, knot insertion).

mod common;

use common::*;
use g_continuity::{ConnectParams, MeasureParams, SideLink, connect_slave, measure_link};
use nurbs_core::testing::rng;
use nurbs_core::{BSplineSurface, Continuity, Point3, Side, Vector3};
use rand::Rng;

fn big_wavy() -> BSplineSurface {
    bicubic(16, 16, |i, j| {
        let (x, y) = (3.0 * i as f64 / 15.0, 3.0 * j as f64 / 15.0);
        Point3::new(x, y, 0.4 * (1.1 * x).sin() * (0.9 * y).cos() + 0.1 * x * y)
    })
}

const A: f64 = 1.0 / 3.0;
const B: f64 = 2.0 / 3.0;

/// Moves every control point that is not on a boundary row by up to `amount` (seeded).
fn perturb_inside(s: &BSplineSurface, seed: u64, amount: f64) -> BSplineSurface {
    let mut r = rng(seed);
    let mut out = s.clone();
    let (nu, nv) = (s.num_u(), s.num_v());
    for i in 1..nu - 1 {
        for j in 1..nv - 1 {
            let idx = out.index(i, j);
            out.control_points_mut()[idx] += Vector3::new(
                r.random_range(-amount..amount),
                r.random_range(-amount..amount),
                r.random_range(-amount..amount),
            );
        }
    }
    out
}

fn check_all(links: &[SideLink], slave: &BSplineSurface, g1: f64, g2: f64, what: &str) {
    for l in links {
        let m = measure_link(l.master, slave, l.side, &MeasureParams::default()).unwrap();
        assert!(m.g0 <= 1e-9, "{what} {}: gap {}", l.side, m.g0);
        assert!(
            m.g1_deg.unwrap() <= g1,
            "{what} {}: angle {:?}",
            l.side,
            m.g1_deg
        );
        assert!(
            m.g2_rel.unwrap() <= g2,
            "{what} {}: curvature {:?}",
            l.side,
            m.g2_rel
        );
    }
}

#[test]
fn x_node_centre_linked_on_four_sides_gets_consistent_twists() {
    let w = big_wavy();
    let left = w.extract((0.0, A), (0.0, 1.0)).unwrap();
    let right = w.extract((B, 1.0), (0.0, 1.0)).unwrap();
    let bottom = w.extract((0.0, 1.0), (0.0, A)).unwrap();
    let top = w.extract((0.0, 1.0), (B, 1.0)).unwrap();
    let centre = w.extract((A, B), (A, B)).unwrap();
    let slave = perturb_inside(&centre, 7, 0.02);
    let links = [
        SideLink {
            side: Side::U0,
            master: &left,
            target: Continuity::G2,
            range: None,
            g2_zones: [0.0; 2],
        },
        SideLink {
            side: Side::U1,
            master: &right,
            target: Continuity::G2,
            range: None,
            g2_zones: [0.0; 2],
        },
        SideLink {
            side: Side::V0,
            master: &bottom,
            target: Continuity::G2,
            range: None,
            g2_zones: [0.0; 2],
        },
        SideLink {
            side: Side::V1,
            master: &top,
            target: Continuity::G2,
            range: None,
            g2_zones: [0.0; 2],
        },
    ];
    let before = measure_link(&left, &slave, Side::U0, &MeasureParams::default()).unwrap();
    assert!(
        before.g1_deg.unwrap() > 0.5,
        "perturbation must break G1: {:?}",
        before.g1_deg
    );
    // ask for the curvature tolerance checked below (the default 2e-2 would stop the knot
    // insertion above it)
    let mut params = ConnectParams::default();
    params.tolerances.g2_rel = 5e-3;
    let (s, report) = connect_slave(&slave, &links, &params).unwrap();
    assert!(
        report.twists_averaged >= 8,
        "4 twists and 4 inner twists: {}",
        report.twists_averaged
    );
    check_all(&links, &s, 1e-2, 5e-3, "X-node");
    // moves of the order of the perturbation (0.02); the scalar-only G2 solve moved rows by 6.6
    assert!(
        report.max_control_movement <= 0.06,
        "moved {}",
        report.max_control_movement
    );
    assert!(
        report.sides.iter().all(|r| r.met),
        "{:?}",
        report
            .sides
            .iter()
            .map(|r| (r.side, r.after.g1_deg, r.after.g2_rel))
            .collect::<Vec<_>>()
    );
    // the boundary rows stay where they were (C0 was exact), bit for bit
    if report.knots_inserted == 0 {
        for side in Side::ALL {
            assert_eq!(
                row_points(&s, side, 0),
                row_points(&slave, side, 0),
                "row 0 of {side}"
            );
        }
    }
}

#[test]
fn corner_patch_on_two_sides_with_g1_and_g2() {
    let w = big_wavy();
    let left = w.extract((0.0, A), (0.0, 1.0)).unwrap();
    let bottom = w.extract((0.0, 1.0), (0.0, A)).unwrap();
    let slave = perturb_inside(&w.extract((A, B), (A, B)).unwrap(), 11, 0.02);
    let links = [
        SideLink {
            side: Side::U0,
            master: &left,
            target: Continuity::G1,
            range: None,
            g2_zones: [0.0; 2],
        },
        SideLink {
            side: Side::V0,
            master: &bottom,
            target: Continuity::G2,
            range: None,
            g2_zones: [0.0; 2],
        },
    ];
    // ask for the curvature tolerance checked below (the default 2e-2 would stop the knot
    // insertion above it)
    let mut params = ConnectParams::default();
    params.tolerances.g2_rel = 5e-3;
    let (s, report) = connect_slave(&slave, &links, &params).unwrap();
    let m = measure_link(&left, &s, Side::U0, &MeasureParams::default()).unwrap();
    assert!(m.g1_deg.unwrap() <= 1e-2, "u0 angle {:?}", m.g1_deg);
    // the rows move by the order of the perturbation (0.02), not by the weakly determined
    // directions of the row systems (the scalar-only G2 solve moved them by 0.2)
    assert!(
        report.max_control_movement <= 0.06,
        "moved {}",
        report.max_control_movement
    );
    let m = measure_link(&bottom, &s, Side::V0, &MeasureParams::default()).unwrap();
    assert!(
        m.g1_deg.unwrap() <= 1e-2 && m.g2_rel.unwrap() <= 5e-3,
        "v0 {:?} {:?}",
        m.g1_deg,
        m.g2_rel
    );
    assert!(report.twists_averaged >= 1);
}

#[test]
fn trimmed_master_non_isoparametric_boundary_with_knot_insertion() {
    let w = big_wavy();
    // the slave's boundary follows the master curve (u, v) = (0.2 + 0.5 t, 0.3 + 0.4 t), which is
    // no isocurve: the slave row only approximates it, and the master is "trimmed" along it
    let curve = |t: f64| w.point(0.2 + 0.5 * t, 0.3 + 0.4 * t);
    let slave = bicubic(5, 6, |i, j| {
        let t = j as f64 / 5.0;
        let p = curve(t);
        // leave the curve sideways (perpendicular to it in the xy-plane) with a 15° kink upward
        let d = (curve((t + 0.01).min(1.0)) - curve((t - 0.01).max(0.0))).normalize();
        let out = Vector3::new(d.y, -d.x, 0.0).normalize() * 0.12 + Vector3::new(0.0, 0.0, 0.03);
        p + out * i as f64
    });
    let links = [SideLink {
        side: Side::U0,
        master: &w,
        target: Continuity::G2,
        range: None,
        g2_zones: [0.0; 2],
    }];
    let before = measure_link(&w, &slave, Side::U0, &MeasureParams::default()).unwrap();
    assert!(before.g1_deg.unwrap() > 1.0, "{:?}", before.g1_deg);
    eprintln!(
        "trimmed before: gap {} angle {:?} curvature {:?}",
        before.g0, before.g1_deg, before.g2_rel
    );
    let (s, report) = connect_slave(&slave, &links, &ConnectParams::default()).unwrap();
    let m = &report.sides[0].after;
    eprintln!(
        "trimmed after: gap {} angle {:?} curvature {:?}, {} knots",
        m.g0, m.g1_deg, m.g2_rel, report.knots_inserted
    );
    assert!(m.g0 <= 1e-3, "gap {}", m.g0);
    assert!(m.g1_deg.unwrap() <= 1e-2, "angle {:?}", m.g1_deg);
    assert!(m.g2_rel.unwrap() <= 5e-3, "curvature {:?}", m.g2_rel);
    assert!(
        report.knots_inserted > 0,
        "the corner needs knot insertion here"
    );
    assert_eq!(
        measure_link(&w, &s, Side::U0, &MeasureParams::default())
            .unwrap()
            .g2_rel,
        m.g2_rel
    );
}

#[test]
fn rational_slave_is_kept_exact_and_connected() {
    // a quarter cylinder (rational) of radius 2 standing on the plane z = 0: its side u0 is the
    // circle arc on z = 0 and the master is the horizontal plane around it (a G0 join, 90°)
    let cyl = nurbs_core::shapes::cylinder(2.0, 1.0).unwrap();
    let plane = bicubic(4, 4, |i, j| {
        Point3::new(
            -1.0 + 4.0 * i as f64 / 3.0,
            -1.0 + 4.0 * j as f64 / 3.0,
            0.0,
        )
    });
    let links = [SideLink {
        side: Side::U0,
        master: &plane,
        target: Continuity::G0,
        range: None,
        g2_zones: [0.0; 2],
    }];
    let (s, report) = connect_slave(&cyl, &links, &ConnectParams::default()).unwrap();
    // the weights stay: no polynomial re-approximation
    assert!(s.is_rational());
    assert!(!report.made_polynomial);
    assert!(
        report.sides[0].after.g0 <= 1e-9,
        "{}",
        report.sides[0].after.g0
    );
    // the join was exact already, so the cylinder is the same surface (to rounding)
    assert!(nurbs_core::energy::max_deviation(&cyl, &s, 21) <= 1e-12);
}

#[test]
fn rational_slave_moves_its_rows_with_the_rational_basis() {
    // the quarter cylinder tilted off the plane (z += 0.01·(1 + x)): C0 must bring its boundary
    // circle down onto z = 0. The control moves that do it exactly, δ_j = −0.01·(1 + x_j), are
    // found in one solve only through the rational row basis w_j M_j / W; the polynomial basis
    // M_j fits another combination and leaves a gap after the C0 passes
    let mut cyl = nurbs_core::shapes::cylinder(2.0, 1.0).unwrap();
    for p in cyl.control_points_mut() {
        p.z += 0.01 * (1.0 + p.x);
    }
    let plane = bicubic(4, 4, |i, j| {
        Point3::new(
            -3.0 + 6.0 * i as f64 / 3.0,
            -3.0 + 6.0 * j as f64 / 3.0,
            0.0,
        )
    });
    let links = [SideLink {
        side: Side::U0,
        master: &plane,
        target: Continuity::G0,
        range: None,
        g2_zones: [0.0; 2],
    }];
    let params = ConnectParams::default();
    let (s, report) = connect_slave(&cyl, &links, &params).unwrap();
    assert!(s.is_rational());
    // the preparation may raise the arc's degree (exact: the weight function stays), the
    // continuity steps never change a weight
    let (prepared, _) = g_continuity::prepare_slave(&cyl, &links, &params).unwrap();
    assert!(nurbs_core::energy::max_deviation(&cyl, &prepared, 21) <= 1e-12);
    assert_eq!(s.weights(), prepared.weights(), "weights are never changed");
    assert!(
        report.sides[0].after.g0 <= 1e-12,
        "{}",
        report.sides[0].after.g0
    );
    // the arc stays an arc of radius 2 about the z axis
    let (a, b) = Side::U0.along_domain(&s);
    for k in 0..=20 {
        let t = a + (b - a) * k as f64 / 20.0;
        let (u, v) = Side::U0.params(&s, t);
        let p = s.point(u, v);
        assert!(
            (p.x.hypot(p.y) - 2.0).abs() < 1e-12 && p.z.abs() < 1e-12,
            "{p:?}"
        );
    }
}

#[test]
fn a_normal_turned_over_along_the_join_shows_as_180_degrees() {
    // master: the plane z = 0; slave: a patch in that plane, x = u across the side u0 and
    // y = f(v) = 4v − 3v² along it. Its normal (0, 0, sign f′) turns over where f′ = 4 − 6v < 0
    // (v > 2/3): there the surface folds back onto itself, and a measure that folds the angle
    // into [0°, 90°] reports 0° everywhere
    let plane = bicubic(4, 4, |i, j| {
        Point3::new(
            -1.0 + 4.0 * i as f64 / 3.0,
            -1.0 + 4.0 * j as f64 / 3.0,
            0.0,
        )
    });
    let ys = [0.0, 2.0, 1.0];
    let pts: Vec<Point3> = (0..2)
        .flat_map(|i| ys.iter().map(move |&y| Point3::new(0.5 * i as f64, y, 0.0)))
        .collect();
    let slave = BSplineSurface::new(
        nurbs_core::KnotVector::bezier(1).unwrap(),
        nurbs_core::KnotVector::bezier(2).unwrap(),
        pts,
        None,
    )
    .unwrap();
    let m = measure_link(&plane, &slave, Side::U0, &MeasureParams::default()).unwrap();
    assert!(m.g0 < 1e-12);
    assert!(m.g1_deg.unwrap() > 179.0, "{:?}", m.g1_deg);
    let flipped = m
        .detail
        .iter()
        .filter(|s| s.angle_deg.unwrap_or(0.0) > 179.0);
    // every sample beyond v = 2/3 (and none before) is turned over
    assert!(flipped.clone().all(|s| s.t > 2.0 / 3.0 - 1e-9));
    let count = flipped.count();
    let expected = m.detail.iter().filter(|s| s.t > 2.0 / 3.0 + 1e-9).count();
    assert!(
        count >= expected,
        "{count} flipped, {expected} beyond v = 2/3"
    );
    let first = &m.detail[5];
    assert!(first.angle_deg.unwrap() < 1e-9, "{:?}", first.angle_deg);
}
