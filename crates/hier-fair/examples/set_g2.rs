//! G2 between a rolling-ball fillet and the two faces it joins: an exact rational quarter
//! cylinder of radius 5 is tangent (G1) to a floor and a wall but has curvature 1/5 across its
//! contact lines where the planes have 0. `connect_slave` sets G2 on both sides with a curvature
//! lead-in (\[SV\] §4.2) and reports how far the fillet moved.
//!
//!     cargo run -p hier-fair --example set_g2

use g_continuity::{ConnectParams, MeasureParams, SideLink, Tolerances, connect_slave};
use nurbs_core::shapes::{arc, extrude_curve, plane_patch};
use nurbs_core::{Continuity, Point3, Side, Vector3};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
    // floor z = 0 from x = 5 on, wall x = 0 from z = 5 up, both 10 long in y
    let floor = plane_patch(Point3::new(5.0, 0.0, 0.0), x, y, (0.0, 20.0), (0.0, 10.0))?;
    let wall = plane_patch(Point3::new(0.0, 0.0, 5.0), z, y, (0.0, 20.0), (0.0, 10.0))?;
    // the fillet: the arc about (5, 0, 5) from the floor (angle 0) to the wall, along y
    let profile = arc(
        Point3::new(5.0, 0.0, 5.0),
        -z,
        -x,
        5.0,
        0.0,
        std::f64::consts::FRAC_PI_2,
    )?;
    let fillet = extrude_curve(&profile, y * 10.0, (0.0, 1.0))?;
    let links = [
        SideLink {
            side: Side::U0,
            master: &floor,
            target: Continuity::G2,
            range: None,
            g2_zones: [0.0; 2],
        },
        SideLink {
            side: Side::U1,
            master: &wall,
            target: Continuity::G2,
            range: None,
            g2_zones: [0.0; 2],
        },
    ];
    let measure = MeasureParams::default();
    let params = ConnectParams {
        tolerances: Tolerances {
            g0: 1e-3,
            g1_deg: 1e-2,
            g2_rel: 5e-3,
        },
        lead_in: Some(g_continuity::MAX_LEAD_IN),
        ..ConnectParams::default()
    };
    let (faired, report) = connect_slave(&fillet, &links, &params)?;
    for (l, side) in links.iter().zip(&report.sides) {
        let (b, a) = (l.measure(&fillet, &measure)?, l.measure(&faired, &measure)?);
        println!(
            "{:?}: curvature difference {:.3} -> {:.1e} (relative), angle {:.1e}° -> {:.1e}°, met {}",
            l.side,
            b.g2_rel.unwrap_or(0.0),
            a.g2_rel.unwrap_or(0.0),
            b.g1_deg.unwrap_or(0.0),
            a.g1_deg.unwrap_or(0.0),
            side.met
        );
        assert!(side.met, "{:?} not met", l.side);
    }
    println!(
        "largest control-point move {:.4} (radius 5), {} knots inserted, degree {} across",
        report.max_control_movement,
        report.knots_inserted,
        faired.degree_u()
    );
    Ok(())
}
