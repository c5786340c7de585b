//! A link over part of a side (`SideLink::range`): a trimmed face's side lies on the surface it
//! meets only up to the trim. Closed-form case: an exact rational quarter cylinder of radius r
//! whose side v = 0 is the line (r, 0, z), tangent to the plane x = r, against a plane patch that
//! ends at z = 0.6 h — the side lies on it over the first 60 % only.

use g_continuity::measure::measure_link_on;
use g_continuity::{ConnectParams, MeasureParams, SideLink, connect_slave, measure_link};
use nurbs_core::shapes::{cylinder, plane_patch};
use nurbs_core::{Continuity, Direction, Point3, Side, Vector3};

const R: f64 = 5.0;
const H: f64 = 40.0;

fn pair() -> (nurbs_core::BSplineSurface, nurbs_core::BSplineSurface) {
    // u along z (degree 1, split at quarters so that the far end has its own control points), v
    // around; the plane x = R over y ∈ [-H, H], z ∈ [0, 0.6 H]
    let cyl = cylinder(R, H)
        .unwrap()
        .refine(Direction::U, &[0.25, 0.5, 0.75])
        .unwrap();
    let plane = plane_patch(
        Point3::new(R, 0.0, 0.0),
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(0.0, 0.0, 1.0),
        (-H, H),
        (0.0, 0.6 * H),
    )
    .unwrap();
    (cyl, plane)
}

/// The exact cylinder with its axial direction (u, along z) one polynomial span of `degree`.
fn one_span_cylinder(degree: usize) -> nurbs_core::BSplineSurface {
    let c = cylinder(R, H).unwrap();
    let long = c
        .elevate_degree(Direction::U, degree - c.degree_u())
        .unwrap();
    assert_eq!(long.knots_u().spans().count(), 1);
    long
}

#[test]
fn g2_over_part_of_a_side_holds_there_and_leaves_the_rest() {
    let (cyl, plane) = pair();
    let link = SideLink {
        side: Side::V0,
        master: &plane,
        target: Continuity::G2,
        range: Some((0.0, 0.6)),
        g2_zones: [0.0; 2],
    };
    let params = ConnectParams::default();
    // before: on the plane and tangent over the part, curvature 1/R against 0
    let m = MeasureParams::default();
    let before = measure_link_on(&plane, &cyl, Side::V0, link.range, &m).unwrap();
    assert!(
        before.g0 < 1e-12 && before.g1_deg.unwrap() < 1e-9,
        "{before:?}"
    );
    assert!(before.g2_rel.unwrap() > 0.99, "{before:?}");
    let (set, report) = connect_slave(&cyl, &[link], &params).unwrap();
    assert!(report.sides[0].met, "{:?}", report.sides[0]);
    let t = params.tolerances;
    let after = link.measure(&set, &m).unwrap();
    assert!(after.g0 <= t.g0, "{after:?}");
    assert!(after.g1_deg.unwrap() <= t.g1_deg, "{after:?}");
    assert!(after.g2_rel.unwrap() <= t.g2_rel, "{after:?}");
    // past the part the boundary was not pulled onto the plane's edge: the whole side's gap is
    // still the 0.4 H it runs past the patch
    let whole = measure_link(&plane, &set, Side::V0, &m).unwrap();
    assert!((whole.g0 - 0.4 * H).abs() < 1e-9 * H, "{}", whole.g0);
    // and the far end, whose control points no basis function of the part reaches, is exactly
    // the cylinder's
    for k in 0..=8 {
        let v = set.domain_v().0 + (set.domain_v().1 - set.domain_v().0) * k as f64 / 8.0;
        let (a, b) = (cyl.point(1.0, v), set.point(1.0, v));
        assert!((a - b).norm() < 1e-12 * H, "v = {v}: {a:?} against {b:?}");
    }
}

#[test]
fn a_range_outside_the_side_is_clipped_to_it() {
    let (cyl, plane) = pair();
    let link = SideLink {
        side: Side::V0,
        master: &plane,
        target: Continuity::G1,
        range: Some((-3.0, 0.6)),
        g2_zones: [0.0; 2],
    };
    assert_eq!(link.domain(&cyl), (0.0, 0.6));
    let m = link.measure(&cyl, &MeasureParams::default()).unwrap();
    assert!(m.g0 < 1e-12, "{m:?}");
    assert_eq!(m.detail[0].t, 0.0);
}

/// A part that stops just short of the side's end, inside one long polynomial span (a kernel's
/// fillet of degree 11 whose side lies on its face up to the vertex blend): the row's end point
/// lies beyond the part, but its basis function carries much of the span near the part's end.
/// Held where it was, it kept the row at the cylinder's curvature there and the least-squares
/// error spread along the whole part (relative curvature 1.0 everywhere, 1.5 on a kernel's
/// fillet); moved with the rest of the row, G2 holds over the whole part.
#[test]
fn g2_over_a_part_short_of_the_end_of_one_long_span_holds_all_along_it() {
    // one span of degree 9 along the side (u, along z), as a kernel's fillet has
    let long = one_span_cylinder(9);
    // the plane reaches past the whole side; the part stops 1 % short of its end
    let plane_long = plane_patch(
        Point3::new(R, 0.0, 0.0),
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(0.0, 0.0, 1.0),
        (-H, H),
        (-0.2 * H, 1.2 * H),
    )
    .unwrap();
    let link = SideLink {
        side: Side::V0,
        master: &plane_long,
        target: Continuity::G2,
        range: Some((0.0, 0.99)),
        g2_zones: [0.0; 2],
    };
    let m = MeasureParams::default();
    let before = link.measure(&long, &m).unwrap();
    assert!(before.g2_rel.unwrap() > 0.99, "{before:?}");
    let (set, report) = connect_slave(&long, &[link], &ConnectParams::default()).unwrap();
    let t = ConnectParams::default().tolerances;
    let after = link.measure(&set, &m).unwrap();
    assert!(report.sides[0].met, "{after:?}");
    assert!(
        after.g0 <= t.g0 && after.g1_deg.unwrap() <= t.g1_deg,
        "{after:?}"
    );
    assert!(after.g2_rel.unwrap() <= t.g2_rel, "{after:?}");
}

/// A part that ends inside one long polynomial span, far from the side's end (a trimmed kernel
/// fillet of degree 13 whose face ends at 60 % of its underlying surface's side): the last two
/// basis functions reach the part only with their tails (7.8e-4 and 8.1e-3 of their integrals).
/// Decided by the part's samples, where they are that small, they move by the residual over
/// those heights (1e5 mm on the lofted block's trimmed fillet, where the master is no cylinder);
/// they stay, the rest of the row makes G2 over the part, and the underlying surface's far end,
/// past the trim, stays as it was (moved with the tails free: 0.85 here).
#[test]
fn g2_over_a_part_that_ends_inside_one_long_span_leaves_the_far_end() {
    let long = one_span_cylinder(13);
    let (_, plane) = pair();
    let link = SideLink {
        side: Side::V0,
        master: &plane,
        target: Continuity::G2,
        range: Some((0.0, 0.6)),
        g2_zones: [0.0; 2],
    };
    let (set, report) = connect_slave(&long, &[link], &ConnectParams::default()).unwrap();
    let t = ConnectParams::default().tolerances;
    let after = link.measure(&set, &MeasureParams::default()).unwrap();
    assert!(report.sides[0].met, "{after:?}");
    assert!(after.g2_rel.unwrap() <= t.g2_rel, "{after:?}");
    let (v0, v1) = long.domain_v();
    for k in 0..=16 {
        let v = v0 + (v1 - v0) * k as f64 / 16.0;
        let (a, b) = (long.point(1.0, v), set.point(1.0, v));
        assert!((a - b).norm() < 1e-9 * H, "v = {v}: {a:?} against {b:?}");
    }
}
