//! `hier-fair fair --split-poles`: a corner patch with a pole comes out as three quads named
//! after it, the report says so (cli-contract.md, `pole_splits`), and a model without such a
//! patch says in a warning that the option had nothing to apply to.

mod common;
use common::{root, run_in};

#[test]
fn a_pole_corner_comes_out_as_three_named_quads() {
    let dir = tempfile::tempdir().unwrap();
    let model = hier_fair::synthetic::sphere_corner(5.0, 0).unwrap();
    std::fs::write(dir.path().join("in.json"), model.to_json()).unwrap();
    let o = run_in(
        dir.path(),
        &[
            "fair",
            "in.json",
            "-o",
            "out.json",
            "--report",
            "r.json",
            "--quiet",
            "--split-poles",
        ],
    );
    // 0, or 1 where a link is left unmet (cli-contract.md): never bad input
    assert!(
        matches!(o.status.code(), Some(0 | 1)),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let out =
        hier_fair::Model::from_json(&std::fs::read_to_string(dir.path().join("out.json")).unwrap())
            .unwrap();
    let names: Vec<&str> = out.surfaces.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(
        names,
        ["cyl_z", "cyl_y", "cyl_x", "pole.q0", "pole.q1", "pole.q2"]
    );
    assert_eq!(out.corners.len(), 1);
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("r.json")).unwrap()).unwrap();
    let split = &report["pole_splits"][0];
    assert_eq!(split["surface"], "pole");
    assert_eq!(split["split"], true);
    assert!(split["fit_error"].as_f64().unwrap() <= 1e-4);
    // the quads' links to the cylinders and to each other are met, or the report names why
    // not: the last quad of the ring would meet its four links only with a curvature spike
    // (3.5× its input's), which the framework does not take
    let problems = report["problems"].as_array().unwrap();
    let links = report["links"].as_array().unwrap();
    let met = links.iter().filter(|l| l["met"] == true).count();
    assert!(met >= 5, "{met} of {}", links.len());
    for l in links.iter().filter(|l| l["met"] != true) {
        assert!(
            problems.iter().any(|p| {
                // a quad's link reads slave "pole", side "q2.v0"; its problems "pole.q2"
                let quad = format!(
                    "{}.{}",
                    l["slave"].as_str().unwrap(),
                    l["side"].as_str().unwrap()
                );
                quad.starts_with(p["surface"].as_str().unwrap())
                    && p["message"].as_str().unwrap().contains("curvature spike")
            }),
            "{l}"
        );
    }
}

#[test]
fn split_poles_on_a_model_without_a_pole_warns() {
    let dir = tempfile::tempdir().unwrap();
    let input = root("fixtures/models/x_node.json");
    let o = run_in(
        dir.path(),
        &[
            "fair",
            input.to_str().unwrap(),
            "-o",
            "out.json",
            "--quiet",
            "--split-poles",
        ],
    );
    assert!(o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("warning: --split-poles has nothing to apply to"),
        "{err}"
    );
    assert!(!dir.path().join("r.json").exists());
}

/// A sphere corner with its pole, faired with `--keep-faired`: its faired result peaks at 2.7×
/// its input's curvature beside the pole (by default its continuity setting is kept instead,
/// at 1.16×), and the verdict points to `--split-poles`.
#[test]
fn a_spiked_pole_corner_is_pointed_to_the_option() {
    let dir = tempfile::tempdir().unwrap();
    let model = hier_fair::synthetic::sphere_corner(5.0, 0).unwrap();
    std::fs::write(dir.path().join("in.json"), model.to_json()).unwrap();
    let o = run_in(
        dir.path(),
        &["fair", "in.json", "-o", "out.json", "--keep-faired"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8_lossy(&o.stdout);
    let hint = out
        .lines()
        .find(|l| l.starts_with("hint:"))
        .unwrap_or_else(|| panic!("no hint in {out}"));
    assert!(
        hint.contains("(pole)") && hint.contains("--split-poles"),
        "{hint}"
    );
}
