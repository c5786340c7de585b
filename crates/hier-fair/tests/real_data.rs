//! Real data from `fixtures/third_party/` (their licences and sources in its README): the car
//! shell after `connect --target G1`, and the Utah teapot with perturbed rows restored to G1/G2.

use g_continuity::{ConnectParams, MeasureParams, SideLink, connect_slave, measure_link};
use hier_fair::{ConnectOptions, Model, check_model, connect};
use nurbs_core::BSplineSurface;
use nurbs_core::{Continuity, Side, Vector3};

fn data(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/third_party")
        .join(name);
    std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{} is in the repository: {e}", path.display()))
}

#[test]
fn car_shell_connect_g1_meets_class_a_on_every_link() {
    let text = data("car_shell1.model.json");
    let model = Model::from_json(&text).unwrap();
    assert_eq!(model.links.len(), 9);
    let before = check_model(&model, &MeasureParams::default()).unwrap();
    let options = ConnectOptions {
        target: Some(Continuity::G1),
        ..ConnectOptions::default()
    };
    let (out, report) = connect(&model, &options).unwrap();
    for (b, l) in before.iter().zip(&report.links) {
        eprintln!(
            "{:28} before gap {:.3e} angle {:.4}°  after gap {:.3e} angle {:.5}° at {:?}",
            l.label,
            b.measure.g0,
            b.measure.g1_deg.unwrap_or(f64::NAN),
            l.after.g0,
            l.after.g1_deg.unwrap_or(f64::NAN),
            l.after.worst_g1_t
        );
    }
    for s in &report.surfaces {
        eprintln!(
            "{:8} moved {:.3e} (deviation {:.3e}), {} knots, {} twists, {:.2}s",
            s.name,
            s.max_control_movement,
            s.max_deviation,
            s.knots_inserted,
            s.twists_averaged,
            s.seconds
        );
    }
    for l in &report.links {
        assert!(l.after.g0 <= 1e-3, "{}: gap {}", l.label, l.after.g0);
        assert!(
            l.after.g1_deg.unwrap() <= 1e-2,
            "{}: angle {:?}",
            l.label,
            l.after.g1_deg
        );
    }
    // masters (primaries) never move
    for (a, b) in model.surfaces.iter().zip(&out.surfaces) {
        if a.role == hier_fair::Role::Primary {
            assert_eq!(a.surface, b.surface, "{} moved", a.name);
        }
    }
    assert!(report.surfaces.iter().any(|s| s.max_control_movement > 0.0));
}

/// The sides of `b` whose boundary row equals that of `side` of `a` (either direction).
fn shared_side(a: &BSplineSurface, side: Side, b: &BSplineSurface) -> Option<Side> {
    let row = |s: &BSplineSurface, side: Side| -> Vec<nurbs_core::Point3> {
        side.row(0, s.num_u(), s.num_v())
            .into_iter()
            .map(|(i, j)| s.control_point(i, j))
            .collect()
    };
    let ra = row(a, side);
    let spread = ra.iter().map(|p| (p - ra[0]).norm()).fold(0.0, f64::max);
    if spread < 1e-9 {
        return None; // collapsed side (pole)
    }
    Side::ALL.into_iter().find(|&sb| {
        let mut rb = row(b, sb);
        let same = |x: &[nurbs_core::Point3], y: &[nurbs_core::Point3]| {
            x.len() == y.len() && x.iter().zip(y).all(|(p, q)| (p - q).norm() < 1e-9)
        };
        if same(&ra, &rb) {
            return true;
        }
        rb.reverse();
        same(&ra, &rb)
    })
}

#[test]
fn teapot_perturbed_rows_restored_to_g1_and_g2() {
    let text = data("teapot.json");
    let patches = nurbs_core::io::surfaces_from_json(&text).unwrap();
    // an upper-body patch and every body patch sharing one of its edges
    let a = 4;
    let mut links_of: Vec<(Side, usize)> = Vec::new();
    for side in Side::ALL {
        if let Some(b) = (0..12)
            .filter(|&b| b != a)
            .find(|&b| shared_side(&patches[a], side, &patches[b]).is_some())
        {
            links_of.push((side, b));
        }
    }
    assert!(
        links_of.len() >= 3,
        "patch {a} shares edges with {links_of:?}"
    );
    let (g2_side, _) = links_of[0];
    let original = &patches[a];
    for &(side, b) in &links_of {
        let m = measure_link(&patches[b], original, side, &MeasureParams::default()).unwrap();
        assert!(
            m.g0 < 1e-9 && m.g1_deg.unwrap() < 1e-4,
            "the teapot is G1: {side} {:?}",
            m.g1_deg
        );
    }
    // perturb the second and third rows of side g2_side (interior points only: the boundary rows
    // of the neighbouring sides stay, their twists do not)
    let mut perturbed = original.clone();
    let (nu, nv) = (perturbed.num_u(), perturbed.num_v());
    for k in 1..=2 {
        let row = g2_side.row(k, nu, nv);
        for (e, &(i, j)) in row.iter().enumerate() {
            if e == 0 || e + 1 == row.len() {
                continue;
            }
            let idx = perturbed.index(i, j);
            perturbed.control_points_mut()[idx] +=
                Vector3::new(0.03 * k as f64, -0.02, 0.04 * e as f64);
        }
    }
    let before = measure_link(
        &patches[links_of[0].1],
        &perturbed,
        g2_side,
        &MeasureParams::default(),
    )
    .unwrap();
    assert!(
        before.g1_deg.unwrap() > 0.5,
        "perturbation breaks G1: {:?}",
        before.g1_deg
    );
    // (a) G1 to every neighbour: the twists between the sides are averaged
    let links: Vec<SideLink> = links_of
        .iter()
        .map(|&(side, b)| SideLink {
            side,
            master: &patches[b],
            target: Continuity::G1,
            range: None,
            g2_zones: [0.0; 2],
        })
        .collect();
    let (restored, report) = connect_slave(&perturbed, &links, &ConnectParams::default()).unwrap();
    for r in &report.sides {
        eprintln!(
            "teapot G1 {}: before angle {:?} after gap {:.2e} angle {:?}; knots {}",
            r.side, r.before.g1_deg, r.after.g0, r.after.g1_deg, report.knots_inserted
        );
    }
    for r in &report.sides {
        assert!(r.after.g0 <= 1e-6, "{}: gap {}", r.side, r.after.g0);
        assert!(
            r.after.g1_deg.unwrap() <= 1e-2,
            "{}: angle {:?}",
            r.side,
            r.after.g1_deg
        );
    }
    assert!(nurbs_core::energy::max_deviation(original, &restored, 21) < 0.2);
    // (b) G2 to the neighbour of the perturbed side. The curvature across a side at its corners
    // is fixed by the neighbouring sides' boundary rows, so only this side is linked here.
    let master = &patches[links_of[0].1];
    let links = [SideLink {
        side: g2_side,
        master,
        target: Continuity::G2,
        range: None,
        g2_zones: [0.0; 2],
    }];
    let (restored, report) = connect_slave(&perturbed, &links, &ConnectParams::default()).unwrap();
    let r = &report.sides[0];
    let orig = measure_link(master, original, g2_side, &MeasureParams::default()).unwrap();
    eprintln!(
        "teapot G2 {}: original g2 {:?}, perturbed {:?}, after gap {:.2e} angle {:?} g2 {:?}; knots {}",
        r.side,
        orig.g2_rel,
        r.before.g2_rel,
        r.after.g0,
        r.after.g1_deg,
        r.after.g2_rel,
        report.knots_inserted
    );
    assert!(
        r.after.g0 <= 1e-6 && r.after.g1_deg.unwrap() <= 1e-2,
        "{:?}",
        r.after.g1_deg
    );
    assert!(
        r.after.g2_rel.unwrap() <= 5e-3,
        "curvature {:?}",
        r.after.g2_rel
    );
    // the original join is not G2 (g2_rel ≈ 1), so the shape must change near the side, but
    // only by a fraction of the teapot's size (~6)
    let deviation = nurbs_core::energy::max_deviation(original, &restored, 21);
    eprintln!("teapot G2 deviation from the original {deviation:.3}");
    assert!(deviation < 1.0, "{deviation}");
}

/// Issue 9 acceptance: `fair` on the car shell (all links G1) meets 0.01° on every link with the
/// deviation within the model's tolerance (the default 0.05: the file gives none).
#[test]
fn car_shell_fair_meets_g1_on_every_link_within_the_tolerance() {
    let text = data("car_shell1.model.json");
    let model = Model::from_json(&text).unwrap();
    let (out, report) = hier_fair::fair_model(
        &model,
        &hier_fair::RoleMethods::default(),
        None,
        &hier_fair::FairParams::default(),
    )
    .unwrap();
    for l in &report.links {
        let after = l.after.as_ref().expect("measured");
        eprintln!(
            "{:24} gap {:.2e} angle {:.5}°",
            l.label,
            after.g0,
            after.g1_deg.unwrap_or(f64::NAN)
        );
        assert!(l.met, "{}: {after:?}", l.label);
        assert!(after.g1_deg.unwrap() <= 1e-2, "{}", l.label);
        assert!(after.g0 <= 1e-3, "{}", l.label);
    }
    for s in &report.surfaces {
        assert!(
            s.max_deviation <= report.tolerance,
            "{}: deviation {} above {}",
            s.name,
            s.max_deviation,
            report.tolerance
        );
    }
    // primaries move only by their own fairing, within the tolerance; slaves stay linked
    assert_eq!(out.surfaces.len(), model.surfaces.len());
    assert!(report.problems.is_empty(), "{:?}", report.problems);
}
