//! Loading and validating models: bad input is an error naming the link or surface at fault.

use hier_fair::{ConnectOptions, Error, Model, Role, check_model, connect};
use nurbs_core::io::SurfaceRecord;
use nurbs_core::{BSplineSurface, KnotVector, Point3};
use serde_json::{Value, json};

/// A flat bicubic patch over [x0, x0 + 1] × [0, 1] at height z.
fn patch(x0: f64, z: f64) -> BSplineSurface {
    let k = KnotVector::bezier(3).unwrap();
    let pts = (0..4)
        .flat_map(|i| (0..4).map(move |j| Point3::new(x0 + i as f64 / 3.0, j as f64 / 3.0, z)))
        .collect();
    BSplineSurface::new(k.clone(), k, pts, None).unwrap()
}

fn entry(name: &str, role: &str, s: &BSplineSurface) -> Value {
    json!({"name": name, "role": role, "surface": SurfaceRecord::from_surface(s)})
}

fn link(slave: &str, side: &str, master: &str) -> Value {
    json!({"slave": slave, "side": side, "master": master, "continuity": "G1"})
}

/// top (primary, x ∈ [0, 1]) and fillet (connecting, x ∈ [1, 2], side u0 on top's u1).
fn two(fillet_z: f64, links: Vec<Value>) -> String {
    json!({"units": "mm", "surfaces": [entry("top", "primary", &patch(0.0, 0.0)), entry("fillet", "connecting", &patch(1.0, fillet_z))], "links": links}).to_string()
}

#[test]
fn valid_model_loads_orders_and_round_trips() {
    let text = two(0.0, vec![link("fillet", "u0", "top")]);
    let m = Model::from_json(&text).unwrap();
    assert_eq!(m.surfaces.len(), 2);
    assert_eq!(m.surfaces[1].role, Role::Connecting);
    assert_eq!(m.hierarchy_order().unwrap(), vec![0, 1]);
    let again = Model::from_json(&m.to_json()).unwrap();
    assert_eq!(again, m);
    let checks = check_model(&m, &Default::default()).unwrap();
    assert_eq!(checks.len(), 1);
    assert!(checks[0].measure.g0 < 1e-12 && checks[0].measure.g1_deg.unwrap() < 1e-9);
}

#[test]
fn bare_surface_file_is_a_one_primary_model() {
    let text = nurbs_core::io::surface_to_json(&patch(0.0, 0.0));
    let m = Model::from_json(&text).unwrap();
    assert_eq!(m.surfaces.len(), 1);
    assert_eq!(m.surfaces[0].role, Role::Primary);
    assert!(m.links.is_empty());
    let (out, report) = connect(&m, &ConnectOptions::default()).unwrap();
    assert_eq!(out, m);
    assert!(report.links.is_empty());
}

#[test]
fn unknown_names_are_errors_naming_the_link() {
    let err = Model::from_json(&two(0.0, vec![link("fillet", "u0", "roof")])).unwrap_err();
    assert!(
        matches!(&err, Error::UnknownSurface { link, name } if link == "fillet.u0 -> roof" && name == "roof"),
        "{err}"
    );
    assert!(err.to_string().contains("fillet.u0 -> roof"));
    let err = Model::from_json(&two(0.0, vec![link("filet", "u0", "top")])).unwrap_err();
    assert!(
        matches!(&err, Error::UnknownSurface { name, .. } if name == "filet"),
        "{err}"
    );
    let err = Model::from_json(&two(0.0, vec![link("fillet", "w0", "top")])).unwrap_err();
    assert!(matches!(&err, Error::UnknownSide { .. }), "{err}");
    let mut bad = two(0.0, vec![]);
    bad = bad.replace("\"connecting\"", "\"fillet-ish\"");
    let err = Model::from_json(&bad).unwrap_err();
    assert!(
        matches!(&err, Error::UnknownRole { name, .. } if name == "fillet"),
        "{err}"
    );
}

#[test]
fn wrong_roles_duplicates_and_cycles_are_errors() {
    // a primary is never a slave
    let err = Model::from_json(&two(0.0, vec![link("top", "u1", "fillet")])).unwrap_err();
    assert!(
        matches!(&err, Error::WrongRoles { link, .. } if link == "top.u1 -> fillet"),
        "{err}"
    );
    // a connecting surface cannot hang on a corner
    let text = json!({"surfaces": [entry("c", "corner", &patch(0.0, 0.0)), entry("f", "connecting", &patch(1.0, 0.0))], "links": [link("f", "u0", "c")]}).to_string();
    assert!(matches!(
        Model::from_json(&text).unwrap_err(),
        Error::WrongRoles { .. }
    ));
    // the same side twice
    let err = Model::from_json(&two(
        0.0,
        vec![link("fillet", "u0", "top"), link("fillet", "u0", "top")],
    ))
    .unwrap_err();
    assert!(matches!(&err, Error::DuplicateLink { .. }), "{err}");
    // two connecting surfaces hanging on each other
    let text = json!({"surfaces": [entry("a", "connecting", &patch(0.0, 0.0)), entry("b", "connecting", &patch(1.0, 0.0))], "links": [link("a", "u1", "b"), link("b", "u0", "a")]}).to_string();
    let err = Model::from_json(&text).unwrap_err();
    assert!(
        matches!(&err, Error::Cycle { surfaces } if surfaces.contains('a') && surfaces.contains('b')),
        "{err}"
    );
}

#[test]
fn corners_and_tolerances_are_validated() {
    let base: Value = serde_json::from_str(&two(0.0, vec![])).unwrap();
    let mut m = base.clone();
    m["corners"] = json!([{"name": "c5", "patches": ["top", "nowhere"]}]);
    let err = Model::from_json(&m.to_string()).unwrap_err();
    assert!(
        matches!(&err, Error::BadCorner { corner, .. } if corner == "c5"),
        "{err}"
    );
    let mut m = base.clone();
    m["tolerances"] = json!({"g0": -1.0});
    assert!(matches!(
        Model::from_json(&m.to_string()).unwrap_err(),
        Error::BadTolerance { name: "g0", .. }
    ));
    let mut m = base;
    m["tolerances"] = json!({"g1_deg": 0.05});
    let model = Model::from_json(&m.to_string()).unwrap();
    assert_eq!(model.tolerances.g1_deg, 0.05);
    assert_eq!(model.tolerances.g0, 1e-3);
    assert!(model.to_json().contains("\"g1_deg\":0.05"));
}

#[test]
fn link_that_does_not_touch_its_master_is_an_error_with_the_gap() {
    // the fillet floats 0.5 above the top: gap 0.5 > 100 × 0.001
    let m = Model::from_json(&two(0.5, vec![link("fillet", "u0", "top")])).unwrap();
    let err = check_model(&m, &Default::default()).unwrap_err();
    match &err {
        Error::LinkNotTouching { link, gap, limit } => {
            assert_eq!(link, "fillet.u0 -> top");
            assert!((gap - 0.5).abs() < 1e-9, "{gap}");
            assert!((limit - 0.1).abs() < 1e-12);
        }
        other => panic!("expected LinkNotTouching, got {other}"),
    }
    assert!(
        err.to_string().contains("fillet.u0 -> top") && err.to_string().contains("5.0"),
        "{err}"
    );
    assert!(matches!(
        connect(&m, &ConnectOptions::default()).unwrap_err(),
        Error::LinkNotTouching { .. }
    ));
    // a small gap (0.05 < 0.1) is closed by connect
    let m = Model::from_json(&two(0.05, vec![link("fillet", "u0", "top")])).unwrap();
    let (out, report) = connect(&m, &ConnectOptions::default()).unwrap();
    assert!(
        report.links[0].after.g0 < 1e-9,
        "{}",
        report.links[0].after.g0
    );
    assert_eq!(out.surfaces[0], m.surfaces[0], "the master never moves");
}

#[test]
fn deviation_per_surface_and_per_role_with_its_precedence() {
    let mut fillet = entry("fillet", "connecting", &patch(1.0, 0.0));
    fillet["deviation"] = json!(0.3);
    let text = json!({
        "surfaces": [entry("top", "primary", &patch(0.0, 0.0)), fillet, entry("corner", "corner", &patch(2.0, 0.0))],
        "links": [link("fillet", "u0", "top")],
        "tolerances": {"deviation": {"primary": 0.02, "corner": 0.4}}
    })
    .to_string();
    let m = Model::from_json(&text).unwrap();
    let none = [None; 3];
    // the surface's own value wins, then the role's, then the global default
    assert_eq!(m.deviation_of(0, &none, None), 0.02);
    assert_eq!(m.deviation_of(1, &none, None), 0.3);
    assert_eq!(m.deviation_of(2, &none, None), 0.4);
    // the command line's role value wins over the file's role value, never over the surface's
    let cli = [Some(0.07), Some(0.9), None];
    assert_eq!(m.deviation_of(0, &cli, None), 0.07);
    assert_eq!(m.deviation_of(1, &cli, None), 0.3);
    // --tolerance only where neither the surface nor its role gives one
    let plain = Model::from_json(&two(0.0, vec![link("fillet", "u0", "top")])).unwrap();
    assert_eq!(plain.deviation_of(1, &none, Some(0.11)), 0.11);
    assert_eq!(plain.deviation_of(1, &none, None), 0.05);
    // written back as given
    let again = Model::from_json(&m.to_json()).unwrap();
    assert_eq!(again, m);
    assert!(m.to_json().contains("\"corner\":0.4"));
}

#[test]
fn bad_deviations_are_named() {
    let mut fillet = entry("fillet", "connecting", &patch(1.0, 0.0));
    fillet["deviation"] = json!(-1.0);
    let text = json!({"surfaces": [entry("top", "primary", &patch(0.0, 0.0)), fillet]}).to_string();
    let e = Model::from_json(&text).unwrap_err().to_string();
    assert!(e.contains("deviation") && e.contains("-1"), "{e}");
    let text = json!({
        "surfaces": [entry("top", "primary", &patch(0.0, 0.0))],
        "tolerances": {"deviation": {"connecting": 0.0}}
    })
    .to_string();
    let e = Model::from_json(&text).unwrap_err().to_string();
    assert!(e.contains("connecting deviation"), "{e}");
}

/// A trim loop of fewer than three points, with a non-finite coordinate, with fewer than three
/// distinct points or with a point far outside its surface is one line naming the surface and
/// the loop.
#[test]
fn a_bad_trim_loop_is_an_error_naming_the_surface() {
    let s = patch(0.0, 0.0);
    let mut p = entry("p", "primary", &s);
    p["trim"] = json!([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]]);
    let text = json!({"surfaces": [p], "links": []}).to_string();
    let e = Model::from_json(&text).unwrap_err().to_string();
    assert!(e.contains("surface p: trim loop 0"), "{e}");
    let mut p = entry("p", "primary", &s);
    p["trim"] = json!([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]]]);
    let text = json!({"surfaces": [p], "links": []}).to_string();
    let m = Model::from_json(&text).unwrap();
    assert_eq!(m.surfaces[0].trim[0].len(), 3);
    let back = Model::from_json(&m.to_json()).unwrap();
    assert_eq!(back.surfaces[0].trim, m.surfaces[0].trim);
    // one point repeated, and a loop of another part (far outside the surface's box)
    for (bad, says) in [
        (
            json!([[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]]),
            "distinct",
        ),
        (
            json!([[[0.0, 0.0, 0.0], [1e6, 0.0, 0.0], [1.0, 1.0, 0.0]]]),
            "outside the surface",
        ),
    ] {
        let mut p = entry("p", "primary", &s);
        p["trim"] = bad;
        let text = json!({"surfaces": [p], "links": []}).to_string();
        let e = Model::from_json(&text).unwrap_err().to_string();
        assert!(
            e.contains("surface p: trim loop 0") && e.contains(says),
            "{e}"
        );
    }
}
