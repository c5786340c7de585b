//! A seam at the end of a linked side (`SetParams::seam_end_tangents`): the boundary's end
//! tangent, which the C0 fit leaves off the master's tangent plane by its slope error, is turned
//! into that plane, so the corner normal is the master's.

mod common;

use common::*;
use g_continuity::{SetParams, SideLink, set_rows};
use nurbs_core::{BSplineSurface, Continuity, Point3, ProjectionParams, Side, project_to_surface};

/// The master's unit normal at the foot point of the slave's corner (u0, v0).
fn master_normal(master: &BSplineSurface, slave: &BSplineSurface) -> nurbs_core::Vector3 {
    let p = slave.control_point(0, 0);
    let foot = project_to_surface(master, &p, &ProjectionParams::default());
    master.derivatives(foot.u, foot.v).normal().unwrap()
}

/// Angle (degrees) between the slave's normal at its corner (u0, v0) and the master's there.
fn corner_angle(master: &BSplineSurface, slave: &BSplineSurface) -> f64 {
    let (u, v) = (slave.domain_u().0, slave.domain_v().0);
    let m = slave.derivatives(u, v).normal().unwrap();
    master_normal(master, slave)
        .dot(&m)
        .abs()
        .min(1.0)
        .acos()
        .to_degrees()
}

/// Sine of the angle between the boundary's end tangent at (u0, v0) and the master's tangent
/// plane there.
fn end_tangent_tilt(master: &BSplineSurface, slave: &BSplineSurface) -> f64 {
    let t = slave.control_point(0, 1) - slave.control_point(0, 0);
    master_normal(master, slave).dot(&t).abs() / t.norm()
}

/// A slave on the u1 side of [`wavy_master`] whose boundary row has five points against the
/// master's eight: the wavy boundary is not in its spline space, so the C0 fit leaves a slope
/// error at the ends.
fn coarse_slave(master: &BSplineSurface) -> BSplineSurface {
    let fine = kinked_slave(master, 0.0, 0.0);
    // the cross leg of the fine slave's column nearest below t (of its columns 0..=7)
    let last = fine.num_v() - 1;
    bicubic(5, 5, |i, j| {
        let t = j as f64 / 4.0;
        let (u, v) = (master.domain_u().1, t * master.domain_v().1);
        let p = master.point(u, v);
        let column = (t * (last as f64 + 0.5)) as usize;
        let leg = fine.control_point(1, column) - fine.control_point(0, column);
        Point3::from(p.coords + leg * i as f64)
    })
}

#[test]
fn seam_end_tangent_takes_the_masters_normal_at_the_corner() {
    let master = wavy_master();
    let start = coarse_slave(&master);
    let links = [SideLink {
        side: Side::U0,
        master: &master,
        target: Continuity::G1,
        range: None,
        g2_zones: [0.0; 2],
    }];
    let plain = SetParams::default();
    let mut without = start.clone();
    set_rows(&mut without, &links, &plain).unwrap();
    let mut seam = SetParams::default();
    seam.seam_end_tangents[2] = true; // v0
    let mut with = start.clone();
    set_rows(&mut with, &links, &seam).unwrap();
    // the fit's slope error tilts the end tangent out of the master's plane; turned, it lies in
    // it to rounding, and the corner normal comes nearer the master's (the G1 rows, a least
    // squares fit over the side's samples, leave their own residual at the corner)
    let (t0, t1) = (
        end_tangent_tilt(&master, &without),
        end_tangent_tilt(&master, &with),
    );
    assert!(
        t0 > 1e-4,
        "the plain fit leaves the end tangent tilted: {t0}"
    );
    assert!(
        t1 < 1e-12,
        "the turned end tangent lies in the master's plane: {t1}"
    );
    let (a0, a1) = (
        corner_angle(&master, &without),
        corner_angle(&master, &with),
    );
    assert!(
        a1 < a0,
        "the corner normal comes nearer the master's: {a0}° -> {a1}°"
    );
    // the other end (v1, no seam there) keeps the tilt the fit left
    let m = with.num_v() - 1;
    let far = with.control_point(0, m - 1) - with.control_point(0, m);
    let foot = project_to_surface(&master, &with.control_point(0, m), &Default::default());
    let n = master.derivatives(foot.u, foot.v).normal().unwrap();
    assert!(n.dot(&far).abs() / far.norm() > 1e-4, "v1 end untouched");
    // the move is the slope error times the spacing: far below the boundary's size
    let moved = (with.control_point(0, 1) - without.control_point(0, 1)).norm();
    assert!(moved > 0.0 && moved < 1e-2 * master.size(), "moved {moved}");
}
