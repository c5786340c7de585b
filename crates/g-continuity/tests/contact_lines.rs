//! A contact line leaving a corner (`SetParams::contact_lines`): after the C0 rows, the side's
//! boundary is turned within its master's tangent plane to leave the corner along the line,
//! the corner and the boundary's first arm length kept, the boundary still on the master.

mod common;

use common::bicubic;
use g_continuity::{SetParams, SideLink, set_rows};
use nurbs_core::shapes::plane_patch;
use nurbs_core::{Continuity, Point3, Side, Vector3};

#[test]
fn the_boundary_leaves_its_corner_along_the_contact_line() {
    // the plane z = 0, and a flat slave on it whose side u0 runs along y from the origin
    let plane = plane_patch(
        Point3::new(-1.0, -1.0, 0.0),
        Vector3::x(),
        Vector3::y(),
        (0.0, 3.0),
        (0.0, 3.0),
    )
    .unwrap();
    let slave = bicubic(5, 5, |i, j| {
        Point3::new(i as f64 / 4.0, j as f64 / 4.0, 0.0)
    });
    let links = [SideLink {
        side: Side::U0,
        master: &plane,
        target: Continuity::G2,
        range: None,
        g2_zones: [0.0; 2],
    }];
    // a contact line 3.2° off the boundary at the corner (u0, v0), in the plane
    let a = 3.2f64.to_radians();
    let line = [a.sin(), a.cos(), 0.0];
    let mut params = SetParams::default();
    params.contact_lines[0][0] = Some(line);
    let mut set = slave.clone();
    set_rows(&mut set, &links, &params).unwrap();
    let (p0, p1) = (set.control_point(0, 0), set.control_point(0, 1));
    let arm = p1 - p0;
    let angle = arm
        .angle(&Vector3::new(line[0], line[1], line[2]))
        .to_degrees();
    assert!(angle < 1e-9, "{angle}");
    // the corner stays, the arm keeps its length, the row stays on the plane
    assert!((p0 - slave.control_point(0, 0)).norm() < 1e-15);
    let before = (slave.control_point(0, 1) - slave.control_point(0, 0)).norm();
    assert!(
        (arm.norm() - before).abs() < 1e-15,
        "{} against {before}",
        arm.norm()
    );
    for j in 0..set.num_v() {
        assert!(set.control_point(0, j)[2].abs() < 1e-15);
    }
    // the other end, without a line, is as the C0 rows left it
    let last = set.num_v() - 1;
    assert_eq!(
        set.control_point(0, last - 1),
        slave.control_point(0, last - 1)
    );
    // without the setting the boundary is not turned
    let mut plain = slave.clone();
    set_rows(&mut plain, &links, &SetParams::default()).unwrap();
    assert_eq!(plain.control_point(0, 1), slave.control_point(0, 1));
}
