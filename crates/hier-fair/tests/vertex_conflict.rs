//! A corner whose two masters disagree in curvature: no surface is G2 to both there, and the
//! report names the corner with the difference, measured on the result.
//!
//! Closed form: a flat patch z = 0 over [0, 1]² whose side u0 (x = 0) lies on the plane z = 0
//! and whose side v0 (y = 0) lies on a cylinder of radius R that touches the plane along the x
//! axis. At the corner (0, 0), across v0 (along y) the cylinder curves by 1/R and the plane not
//! at all.

use hier_fair::{FairParams, Model, RoleMethods, fair_model};
use nurbs_core::io::surface_to_json;
use nurbs_core::shapes::{arc, extrude_curve, plane_patch};
use nurbs_core::{Direction, Point3, Vector3};

const R: f64 = 5.0;

fn model() -> Model {
    let ground = plane_patch(
        Point3::new(-2.0, -2.0, 0.0),
        Vector3::x(),
        Vector3::y(),
        (0.0, 4.0),
        (0.0, 4.0),
    )
    .unwrap();
    // the circle of radius R about (0, 0, R) in the y–z plane, from its lowest point both ways,
    // swept along x
    let c = arc(
        Point3::new(0.0, 0.0, R),
        -Vector3::z(),
        Vector3::y(),
        R,
        -0.5,
        0.5,
    )
    .unwrap();
    let roller = extrude_curve(&c, Vector3::x(), (-2.0, 2.0)).unwrap();
    let patch = plane_patch(
        Point3::origin(),
        Vector3::x(),
        Vector3::y(),
        (0.0, 1.0),
        (0.0, 1.0),
    )
    .unwrap()
    .elevate_degree(Direction::U, 2)
    .unwrap()
    .elevate_degree(Direction::V, 2)
    .unwrap();
    let entry = |name: &str, role: &str, s: &nurbs_core::BSplineSurface| {
        format!(
            r#"{{"name":"{name}","role":"{role}","surface":{}}}"#,
            surface_to_json(s)
        )
    };
    let json = format!(
        r#"{{"units":"mm","surfaces":[{},{},{}],"links":[
            {{"slave":"blend","side":"u0","master":"ground","continuity":"G2"}},
            {{"slave":"blend","side":"v0","master":"roller","continuity":"G2"}}],
            "tolerances":{{"deviation":1.0,"g0":0.001,"g1_deg":0.01,"g2_rel":0.005}}}}"#,
        entry("ground", "primary", &ground),
        entry("roller", "primary", &roller),
        entry("blend", "corner", &patch),
    );
    Model::from_json(&json).unwrap()
}

#[test]
fn a_vertex_conflict_between_masters_is_named_with_its_figure() {
    let m = model();
    let (out, report) =
        fair_model(&m, &RoleMethods::default(), None, &FairParams::default()).unwrap();
    let note = report
        .problems
        .iter()
        .find(|p| {
            p.link.as_deref() == Some("blend.v0 -> roller")
                && p.message.contains("no surface is G2 to both")
        })
        .unwrap_or_else(|| panic!("{:#?}", report.problems));
    assert!(
        note.message.contains("at its corner with u0"),
        "{}",
        note.message
    );
    let figure: f64 = note
        .message
        .split("across this side by ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap();
    // the figure is the two masters' difference across v0 at the result's corner
    let blend = &out.surfaces[out.find("blend").unwrap()].surface;
    let (u, v) = (blend.domain_u().0, blend.domain_v().0);
    let d = blend.derivatives(u, v);
    let params = nurbs_core::ProjectionParams::default();
    let kappa = |name: &str| {
        let s = &out.surfaces[out.find(name).unwrap()].surface;
        let f = nurbs_core::project_to_surface(s, &d.point, &params);
        s.derivatives(f.u, f.v)
            .normal_curvature(&d.dv)
            .unwrap()
            .abs()
    };
    let diff = (kappa("roller") - kappa("ground")).abs();
    assert!(
        (figure - diff).abs() <= 1e-3 * diff,
        "{figure} against {diff}: {}",
        note.message
    );
    // and that is the cylinder's curvature 1/R, the result's cross direction at the corner
    // still along y (within the angle its G1 tolerance leaves)
    assert!((figure - 1.0 / R).abs() <= 1e-3 / R, "{figure}");
}

#[test]
fn a_vertex_conflict_relaxes_g2_only_within_its_zone() {
    // the same corner: G2 to the cylinder across v0 is met along the rest of the side, and
    // relaxed within the vertex zone at the corner with u0, 1/20 of the side (the side is the
    // unit segment y = 0 before fairing; after, within the deviation of it)
    let m = model();
    let (out, report) =
        fair_model(&m, &RoleMethods::default(), None, &FairParams::default()).unwrap();
    let k = m
        .links
        .iter()
        .position(|l| l.side == nurbs_core::Side::V0)
        .unwrap();
    let link = report.links.iter().find(|l| l.link == k).unwrap();
    assert!(link.met, "{:?}", link.after);
    let after = link.after.as_ref().unwrap();
    assert!(after.g2_rel.unwrap() <= m.tolerances.g2_rel, "{after:?}");
    // (the blend's side u1 lies on the ground too: the framework links it as a shared edge, and
    // the corner of v0 with u1 is a conflict of the same kind, with a zone of its own)
    let zone = after.vertex_zones[0];
    assert!(
        (zone - hier_fair::zones::VERTEX_ZONE).abs() <= 1e-2 * hier_fair::zones::VERTEX_ZONE,
        "{zone}"
    );
    // inside it the two masters cannot both be met: the vertex figure stays far above
    assert!(after.vertex_g2_rel.unwrap() > 0.1, "{after:?}");
    // named as a conflict with its length, every zone (the one a found link makes included)
    let on_v0: Vec<&hier_fair::Problem> = report
        .problems
        .iter()
        .filter(|p| {
            p.kind == hier_fair::ProblemKind::Conflict
                && p.link.as_deref() == Some("blend.v0 -> roller")
        })
        .collect();
    let note = on_v0
        .first()
        .unwrap_or_else(|| panic!("{:#?}", report.problems));
    assert_eq!(note.amount, Some(zone));
    let named = on_v0.len();
    let zones = after.vertex_zones.iter().filter(|&&z| z > 0.0).count();
    assert_eq!(named, zones, "{:#?}", report.problems);
    assert!(
        note.message.contains("met along the rest of the side"),
        "{}",
        note.message
    );
    // `check` judges the result on the same samples
    let checks = hier_fair::check_model(&out, &g_continuity::MeasureParams::default()).unwrap();
    let c = checks.iter().find(|c| c.link == k).unwrap();
    assert!(
        c.measure.g2_rel.unwrap() <= m.tolerances.g2_rel,
        "{:?}",
        c.measure
    );
    assert_eq!(c.measure.vertex_zones[0], zone);
    // without the zone the same result misses at the corner: the zone is what makes it met
    let blend = &out.surfaces[out.find("blend").unwrap()].surface;
    let roller = &out.surfaces[out.find("roller").unwrap()].surface;
    let plain = g_continuity::measure_link(
        roller,
        blend,
        nurbs_core::Side::V0,
        &g_continuity::MeasureParams::default(),
    )
    .unwrap();
    assert!(plain.g2_rel.unwrap() > m.tolerances.g2_rel, "{plain:?}");
}
