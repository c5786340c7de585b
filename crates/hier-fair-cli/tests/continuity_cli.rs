//! `hier-fair check` and `hier-fair connect` through the library functions and the binary
//! (exit codes, atomic outputs, never overwriting the input).

use std::process::Command;

use serde_json::{Value, json};

/// A model: a flat primary and a connecting patch on its side x = 1 with a `kink_deg` kink.
fn kinked_model(kink_deg: f64) -> String {
    let r = kink_deg.to_radians();
    let flat: Vec<Vec<[f64; 3]>> = (0..4)
        .map(|i| {
            (0..4)
                .map(|j| [i as f64 / 3.0, j as f64 / 3.0, 0.0])
                .collect()
        })
        .collect();
    let bent: Vec<Vec<[f64; 3]>> = (0..4)
        .map(|i| {
            (0..4)
                .map(|j| {
                    [
                        1.0 + r.cos() * i as f64 / 3.0,
                        j as f64 / 3.0,
                        r.sin() * i as f64 / 3.0,
                    ]
                })
                .collect()
        })
        .collect();
    json!({
        "units": "mm",
        "surfaces": [
            {"name": "top", "role": "primary", "surface": {"degree_u": 3, "degree_v": 3, "control_points": flat}},
            {"name": "fillet", "role": "connecting", "surface": {"degree_u": 3, "degree_v": 3, "control_points": bent}}
        ],
        "links": [{"slave": "fillet", "side": "u0", "master": "top", "continuity": "G1"}]
    })
    .to_string()
}

#[test]
fn check_table_json_and_presets() {
    let text = kinked_model(0.05);
    let out = hier_fair_cli::check::run(&text, "m.json", 21, false, None).unwrap();
    assert!(
        out.text.contains("fillet.u0 -> top") && !out.exceeded,
        "{}",
        out.text
    );
    let out = hier_fair_cli::check::run(&text, "m.json", 21, true, Some("class-a")).unwrap();
    assert!(out.exceeded, "0.05° exceeds class-a (0.01°)");
    let v: Value = serde_json::from_str(&out.text).unwrap();
    let l = &v["links"][0];
    for key in [
        "slave", "side", "master", "target", "samples", "g0", "g1_deg", "g2_rel", "g2_abs",
    ] {
        assert!(l.get(key).is_some(), "missing {key}");
    }
    assert_eq!(l["samples"], 21);
    assert!((l["g1_deg"].as_f64().unwrap() - 0.05).abs() < 1e-9);
    assert!(l["worst_g1"]["t"].is_number() && l["worst_g2"].get("t").is_some());
    // 0.05° is fine for the standard (0.1°) and exchange (0.5°) presets
    assert!(
        !hier_fair_cli::check::run(&text, "m.json", 21, false, Some("standard"))
            .unwrap()
            .exceeded
    );
    assert!(
        !hier_fair_cli::check::run(&text, "m.json", 21, false, Some("exchange"))
            .unwrap()
            .exceeded
    );
    assert!(hier_fair_cli::check::run(&text, "m.json", 21, false, Some("strict")).is_err());
}

#[test]
fn binary_check_exit_codes_and_connect_outputs() {
    let bin = env!("CARGO_BIN_EXE_hier-fair");
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("model.json");
    std::fs::write(&model, kinked_model(10.0)).unwrap();
    let status = Command::new(bin)
        .args(["check", model.to_str().unwrap(), "--fail-above", "class-a"])
        .output()
        .unwrap();
    assert_eq!(
        status.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let status = Command::new(bin)
        .args(["check", model.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(status.status.code(), Some(0));

    // connect never overwrites its input
    let status = Command::new(bin)
        .args([
            "connect",
            model.to_str().unwrap(),
            "-o",
            model.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_ne!(status.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&status.stderr).contains("refusing to overwrite"));

    let out = dir.path().join("out.json");
    let report = dir.path().join("report.json");
    let status = Command::new(bin)
        .args([
            "connect",
            model.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--target",
            "G1",
            "--report",
            report.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(
        status.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let r: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let link = &r["links"][0];
    assert!(link["before"]["g1_deg"].as_f64().unwrap() > 9.9);
    assert!(link["after"]["g1_deg"].as_f64().unwrap() <= 1e-6, "{link}");
    assert_eq!(r["surfaces"][0]["name"], "fillet");
    assert!(r["seconds_total"].is_number());
    // the written model passes the class-a check
    let status = Command::new(bin)
        .args(["check", out.to_str().unwrap(), "--fail-above", "class-a"])
        .output()
        .unwrap();
    assert_eq!(
        status.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&status.stdout)
    );
    // bad input: one line, non-zero, no panic
    std::fs::write(
        &model,
        kinked_model(10.0).replace("\"master\":\"top\"", "\"master\":\"roof\""),
    )
    .unwrap();
    let status = Command::new(bin)
        .args(["check", model.to_str().unwrap()])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&status.stderr);
    assert_eq!(status.status.code(), Some(2));
    assert!(
        err.contains("fillet.u0 -> roof") && err.lines().count() == 1 && !err.contains("panicked"),
        "{err}"
    );
}

/// `check --fairness` measures every surface: on the kernel's plate with a boss, the torus
/// fillets read their tube curvature (1/3 and 1/5 per mm) with no extremum across, the planes 0
/// with no cross lines (they are no slaves).
#[test]
fn check_fairness_reads_the_fillet_radii() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/occt/occt_plate_boss.json");
    let text = std::fs::read_to_string(&path).unwrap();
    let out = hier_fair_cli::check::run_with(&text, "m.json", 21, true, None, true).unwrap();
    let v: Value = serde_json::from_str(&out.text).unwrap();
    let list = v["fairness"].as_array().unwrap();
    assert_eq!(list.len(), 10);
    let get = |name: &str| list.iter().find(|s| s["name"] == name).unwrap();
    for (name, r) in [("F09_torus", 3.0), ("F02_torus", 5.0)] {
        let s = get(name);
        let peak = s["peak_curvature"].as_f64().unwrap();
        assert!((peak - 1.0 / r).abs() < 1e-9, "{name}: {s}");
        assert_eq!(s["cross_extrema"], json!(0), "{name}: {s}");
    }
    assert_eq!(get("P01_plane")["peak_curvature"], json!(0.0));
    assert_eq!(get("P01_plane")["cross_extrema"], Value::Null);
    // the table names every surface after the links
    let table = hier_fair_cli::check::run_with(&text, "m.json", 21, false, None, true).unwrap();
    assert!(
        table.text.contains("F09_torus") && table.text.contains("peak 1/mm"),
        "{}",
        table.text
    );
}

/// `check --json` on the kernel's lofted block carries the checker's figures (across the
/// boundary, the vertices apart) for every G2 link, next to the framework's; the table prints
/// them as one more column.
#[test]
fn check_reports_the_across_figures_of_every_g2_link() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/occt/occt_loft_block.json"
    );
    let text = std::fs::read_to_string(path).unwrap();
    let out = hier_fair_cli::check::run(&text, path, 101, true, None).unwrap();
    let v: Value = serde_json::from_str(&out.text).unwrap();
    let links = v["links"].as_array().unwrap();
    let g2: Vec<&Value> = links.iter().filter(|l| l["target"] == "G2").collect();
    assert!(!g2.is_empty());
    for l in g2 {
        let name = format!("{}.{}", l["slave"], l["side"]);
        assert!(l["g2_rel"].is_number(), "{name}: g2_rel");
        let across = l["g2_rel_across"].as_f64();
        assert!(across.is_some_and(|r| r >= 0.0), "{name}: g2_rel_across");
        assert!(l["g2_abs_across"].is_number(), "{name}: g2_abs_across");
        assert!(l["worst_g2_across"]["t"].is_number(), "{name}: worst t");
        assert!(l["g1_deg_vertex"].is_number(), "{name}: g1_deg_vertex");
        assert!(l["g2_rel_vertex"].is_number(), "{name}: g2_rel_vertex");
    }
    let table = hier_fair_cli::check::run(&text, path, 101, false, None).unwrap();
    let header = table.text.lines().next().unwrap();
    assert!(
        header.contains("g2 abs") && header.contains("g2 across"),
        "{header}"
    );
}
