//! Constructed pairs with closed-form truth: measuring, G1 on a 10° kink, G2 on a G1-but-not-G2
//! join, every orientation combination, bit-identical fixed rows.

mod common;

use common::*;
use g_continuity::{MeasureParams, SetParams, measure_link, set_g1, set_g2};
use nurbs_core::testing::assert_close;
use nurbs_core::{BSplineSurface, Continuity, KnotVector, Point3, Side};

/// z = a·x² over x ∈ [x0, x1], y ∈ [0, 2] as a bicubic Bézier patch (u along x).
fn parabolic(a: f64, x0: f64, x1: f64) -> BSplineSurface {
    let (z0, z1, z2) = (x0 * x0, x0 * x1, x1 * x1);
    let cz = [z0, (z0 + 2.0 * z1) / 3.0, (2.0 * z1 + z2) / 3.0, z2];
    let k = KnotVector::bezier(3).unwrap();
    let pts = (0..4)
        .flat_map(|i| (0..4).map(move |j| (i, j)))
        .map(|(i, j)| {
            Point3::new(
                x0 + (x1 - x0) * i as f64 / 3.0,
                2.0 * j as f64 / 3.0,
                a * cz[i],
            )
        })
        .collect();
    BSplineSurface::new(k.clone(), k, pts, None).unwrap()
}

#[test]
fn measure_closed_form_kink_and_curvature() {
    // plane z = 0 and the plane through its edge x = 0 rotated by 10°: the angle is 10° everywhere
    let master = parabolic(0.0, -1.0, 0.0);
    let r = 10f64.to_radians();
    let slave = common::bicubic(4, 4, |i, j| {
        let s = i as f64 / 3.0;
        Point3::new(s * r.cos(), 2.0 * j as f64 / 3.0, s * r.sin())
    });
    let m = measure_link(&master, &slave, Side::U0, &MeasureParams::default()).unwrap();
    assert_close(m.g0, 0.0, 1e-12, "gap");
    assert_close(m.g1_deg.unwrap(), 10.0, 1e-9, "angle");
    assert_eq!(m.g2_rel, Some(0.0), "both flat");
    assert!(!m.collapsed && m.undefined_normals == 0);

    // z = 0.5 x² (x ≤ 0) against z = 2 x² (x ≥ 0): tangent, κ = 1 against 4 in the x direction
    let master = parabolic(0.5, -1.0, 0.0);
    let slave = parabolic(2.0, 0.0, 1.0);
    let m = measure_link(&master, &slave, Side::U0, &MeasureParams::default()).unwrap();
    assert_close(m.g1_deg.unwrap(), 0.0, 1e-9, "angle");
    assert_close(m.g2_abs.unwrap(), 3.0, 1e-9, "|κs − κm|");
    assert_close(m.g2_rel.unwrap(), 0.75, 1e-9, "relative");
    // orientation independence: flipping the master's normal does not change anything
    let flipped = reversed(&master, false);
    let m2 = measure_link(&flipped, &slave, Side::U0, &MeasureParams::default()).unwrap();
    assert_close(m2.g2_rel.unwrap(), 0.75, 1e-9, "relative, flipped master");
    assert_close(m2.g1_deg.unwrap(), 0.0, 1e-9, "angle, flipped master");
}

#[test]
fn collapsed_side_is_reported_not_measured() {
    let master = parabolic(0.0, -1.0, 0.0);
    // a triangle-like slave: its side u0 is the single point (0, 1, 0)
    let slave = common::bicubic(4, 4, |i, j| {
        let s = i as f64 / 3.0;
        Point3::new(-s, 1.0 + s * (2.0 * j as f64 / 3.0 - 1.0), 0.0)
    });
    let m = measure_link(&master, &slave, Side::U0, &MeasureParams::default()).unwrap();
    assert!(m.collapsed);
    assert_eq!(m.g1_deg, None);
    assert_eq!(m.g2_rel, None);
    assert!(m.g0 < 1e-12);
}

#[test]
fn g1_removes_a_ten_degree_kink_and_keeps_row_zero() {
    let master = wavy_master();
    let slave = kinked_slave(&master, 10.0, 0.0);
    let before = measure_link(&master, &slave, Side::U0, &MeasureParams::default()).unwrap();
    assert!(before.g1_deg.unwrap() > 5.0, "{:?}", before.g1_deg);
    let mut s = slave.clone();
    set_g1(&master, &mut s, Side::U0, &SetParams::default()).unwrap();
    let after = measure_link(&master, &s, Side::U0, &MeasureParams::default()).unwrap();
    assert!(
        after.g1_deg.unwrap() <= 1e-6,
        "G1 after: {:?}",
        after.g1_deg
    );
    assert_eq!(
        row_points(&s, Side::U0, 0),
        row_points(&slave, Side::U0, 0),
        "positional row bit-identical"
    );
}

#[test]
fn g2_on_a_g1_join_reaches_curvature_continuity_and_keeps_rows() {
    let master = wavy_master();
    let slave = kinked_slave(&master, 0.0, 0.08);
    let before = measure_link(&master, &slave, Side::U0, &MeasureParams::default()).unwrap();
    assert!(before.g1_deg.unwrap() < 1e-9);
    assert!(before.g2_rel.unwrap() > 0.1, "{:?}", before.g2_rel);
    let mut s = slave.clone();
    set_g2(&master, &mut s, Side::U0, &SetParams::default()).unwrap();
    let after = measure_link(&master, &s, Side::U0, &MeasureParams::default()).unwrap();
    assert!(
        after.g2_rel.unwrap() <= 1e-6,
        "G2 after: {:?}",
        after.g2_rel
    );
    for k in 0..2 {
        assert_eq!(
            row_points(&s, Side::U0, k),
            row_points(&slave, Side::U0, k),
            "row {k} bit-identical"
        );
    }
}

#[test]
fn fixed_directions_variant_also_sets_g2() {
    let master = wavy_master();
    let slave = kinked_slave(&master, 0.0, 0.08);
    let mut s = slave.clone();
    let params = SetParams {
        g2_method: g_continuity::G2Method::FixedDirections,
        ..SetParams::default()
    };
    set_g2(&master, &mut s, Side::U0, &params).unwrap();
    let after = measure_link(&master, &s, Side::U0, &MeasureParams::default()).unwrap();
    // one scalar per point along fixed normals cannot follow the (rational) master curvature
    // exactly: a large improvement, not exactness
    let before = measure_link(&master, &slave, Side::U0, &MeasureParams::default()).unwrap();
    assert!(
        after.g2_rel.unwrap() <= 1e-2 && after.g2_rel.unwrap() < before.g2_rel.unwrap() / 20.0,
        "G2 after: {:?}",
        after.g2_rel
    );
}

#[test]
fn every_orientation_combination_reaches_g1_and_g2() {
    let base_master = wavy_master();
    let base_slave = kinked_slave(&base_master, 10.0, 0.08);
    for mcode in 0..8u8 {
        let (master, _) = reoriented(&base_master, mcode);
        for scode in 0..8u8 {
            let (slave, side) = reoriented(&base_slave, scode);
            let (s, report) = connect_one(&master, &slave, side, Continuity::G2);
            let a = &report.sides[0].after;
            let what = format!("master code {mcode}, slave code {scode} (side {side})");
            assert!(
                report.sides[0].before.g1_deg.unwrap() > 5.0,
                "{what}: before"
            );
            assert!(a.g0 <= 1e-9, "{what}: gap {}", a.g0);
            assert!(a.g1_deg.unwrap() <= 1e-6, "{what}: angle {:?}", a.g1_deg);
            assert!(
                a.g2_rel.unwrap() <= 1e-6,
                "{what}: curvature {:?}",
                a.g2_rel
            );
            assert_eq!(
                row_points(&s, side, 0),
                row_points(&slave, side, 0),
                "{what}: row 0"
            );
        }
    }
}
