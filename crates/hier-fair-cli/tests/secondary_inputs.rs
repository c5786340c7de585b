//! The files options name are known by their content too (cli-contract.md, "Files"):
//! `eval --params`, `fair-mesh --fixed` and `label --segments` given a STEP, IGES, model JSON,
//! OBJ or report JSON say in one line what they got and what the option expects (exit code 2,
//! never a parser's "missing field"); and options that do not apply to the input are said in a
//! `warning:` line (`check --samples`, `--fail-above` on a file without links; `fair`'s link
//! options on a model without links, `--tolerance` and `--tolerance-role` that no surface takes).

use std::path::{Path, PathBuf};
use std::process::Output;

mod common;
use common::{root, run_in};

/// A run refused with exit code 2 and one error line holding every one of `parts`, no parser
/// message, nothing at `not_written`.
fn refused(o: &Output, parts: &[&str], not_written: &Path) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert_eq!(e.trim().lines().count(), 1, "{e}");
    for p in parts {
        assert!(e.contains(p), "{p:?} not in {e}");
    }
    for parser in [
        "missing field",
        "expected value",
        "invalid type",
        "malformed",
    ] {
        assert!(!e.contains(parser), "{parser:?} in {e}");
    }
    assert!(!not_written.exists(), "{}", not_written.display());
}

/// Files of every kind an option might be given by mistake, each with how the message names
/// it: STEP, IGES, model JSON, OBJ, report JSON, and the other options' own kinds.
fn wrong_files(dir: &Path) -> Vec<(PathBuf, &'static str)> {
    let report = dir.join("report.json");
    std::fs::write(
        &report,
        r#"{"seconds_total": 1.5, "surfaces": [], "links": []}"#,
    )
    .unwrap();
    let params = dir.join("params.json");
    std::fs::write(&params, r#"{"params": [[0.5, 0.5]]}"#).unwrap();
    let indices = dir.join("fixed.json");
    std::fs::write(&indices, "[0, 1, 2]\n").unwrap();
    let segments = dir.join("segments.json");
    std::fs::write(&segments, "[[0, 1, 2], [2, 3, 0]]\n").unwrap();
    vec![
        (root("fixtures/occt/occt_plate_boss.step"), "is a STEP file"),
        (root("fixtures/foreign/UKI60998.igs"), "is an IGES file"),
        (
            root("fixtures/occt/occt_plate_boss.json"),
            "is a model JSON",
        ),
        (root("fixtures/third_party/neon_side.obj"), "is an OBJ mesh"),
        (report, "is a report JSON"),
        (params, "is a params JSON"),
        (indices, "is an index JSON"),
        (segments, "is a segments JSON"),
    ]
}

#[test]
fn eval_params_names_what_it_got() {
    let tmp = tempfile::tempdir().unwrap();
    let surface = root("fixtures/surfaces/hood_panel.json");
    for (file, got) in wrong_files(tmp.path()) {
        let o = run_in(
            tmp.path(),
            &[
                "eval",
                surface.to_str().unwrap(),
                "--params",
                file.to_str().unwrap(),
            ],
        );
        if got == "is a params JSON" {
            // the right kind is evaluated
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            assert!(String::from_utf8_lossy(&o.stdout).starts_with("{\"results\":[{\"u\":0.5"));
            continue;
        }
        let expects = "`eval --params` takes a params JSON ({\"params\": [[u, v], …]})";
        refused(&o, &[expects, got], &tmp.path().join("none"));
        assert!(o.stdout.is_empty());
    }
}

#[test]
fn fair_mesh_fixed_names_what_it_got() {
    let tmp = tempfile::tempdir().unwrap();
    let mesh = root("fixtures/third_party/neon_side.obj");
    let out = tmp.path().join("m.obj");
    for (file, got) in wrong_files(tmp.path()) {
        let args = [
            "fair-mesh",
            mesh.to_str().unwrap(),
            "-o",
            "m.obj",
            "--fixed",
            file.to_str().unwrap(),
        ];
        let o = run_in(tmp.path(), &args);
        if got == "is an index JSON" {
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            assert!(out.exists());
            std::fs::remove_file(&out).unwrap();
            continue;
        }
        refused(&o, &["`fair-mesh --fixed` takes an index JSON", got], &out);
    }
}

#[test]
fn label_segments_names_what_it_got() {
    let tmp = tempfile::tempdir().unwrap();
    let mesh = root("fixtures/third_party/neon_side.obj");
    let out = tmp.path().join("l.json");
    for (file, got) in wrong_files(tmp.path()) {
        if got == "is a segments JSON" {
            // the right kind reaches the labeler (these indices are not on the mesh's
            // boundary: its own message, not the kind's)
            continue;
        }
        let args = [
            "label",
            mesh.to_str().unwrap(),
            "--segments",
            file.to_str().unwrap(),
            "-o",
            "l.json",
        ];
        let o = run_in(tmp.path(), &args);
        refused(&o, &["`label --segments` takes a segments JSON", got], &out);
    }
    // label's own output is a segments JSON: it labels the mesh again with those segments
    let first = run_in(
        tmp.path(),
        &["label", mesh.to_str().unwrap(), "-o", "first.json"],
    );
    assert!(first.status.success(), "{first:?}");
    let again = run_in(
        tmp.path(),
        &[
            "label",
            mesh.to_str().unwrap(),
            "--segments",
            "first.json",
            "-o",
            "l.json",
        ],
    );
    assert!(
        again.status.success(),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    assert!(out.exists());
}

#[test]
fn check_options_on_a_file_without_links_are_warnings() {
    let tmp = tempfile::tempdir().unwrap();
    let surface = root("fixtures/surfaces/hood_panel.json");
    let o = run_in(
        tmp.path(),
        &["check", surface.to_str().unwrap(), "--samples", "51"],
    );
    assert!(o.status.success(), "{o:?}");
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(
        e.starts_with("warning: --samples 51 applies to a model's links;")
            && e.contains("has no links: nothing was sampled"),
        "{e}"
    );
    // --fail-above with neither links nor C0 knot lines to judge
    let o = run_in(
        tmp.path(),
        &[
            "check",
            surface.to_str().unwrap(),
            "--fail-above",
            "standard",
        ],
    );
    assert!(o.status.success(), "{o:?}");
    assert_eq!(
        String::from_utf8_lossy(&o.stderr).trim_end(),
        format!(
            "warning: --fail-above standard has nothing to judge: {} has no links and no surface with C0 knot lines",
            surface.display()
        )
    );
    // without the option, or on a model with links, no warning
    let o = run_in(tmp.path(), &["check", surface.to_str().unwrap()]);
    assert!(o.status.success() && o.stderr.is_empty(), "{o:?}");
    let model = root("fixtures/occt/occt_plate_boss.json");
    let o = run_in(
        tmp.path(),
        &[
            "check",
            model.to_str().unwrap(),
            "--samples",
            "21",
            "--fail-above",
            "exchange",
        ],
    );
    assert!(o.status.success() && o.stderr.is_empty(), "{o:?}");
}

/// A model of the hood panel alone (no links), with `extra` fields on its surface entry.
fn hood_model(dir: &Path, name: &str, extra: serde_json::Value) {
    let surface: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root("fixtures/surfaces/hood_panel.json")).unwrap(),
    )
    .unwrap();
    let mut entry = serde_json::json!({"name": "hood", "role": "primary", "surface": surface});
    for (k, v) in extra.as_object().unwrap() {
        entry[k] = v.clone();
    }
    let model = serde_json::json!({"surfaces": [entry], "links": []});
    std::fs::write(dir.join(name), model.to_string()).unwrap();
}

/// The stderr lines of a `fair` run that succeeded and wrote its output.
fn fair_warnings(dir: &Path, args: &[&str]) -> Vec<String> {
    let mut all = vec!["fair"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["-o", "f.json", "--quiet"]);
    let _ = std::fs::remove_file(dir.join("f.json"));
    let o = run_in(dir, &all);
    assert!(o.status.success(), "{o:?}");
    assert!(dir.join("f.json").exists());
    assert_eq!(String::from_utf8_lossy(&o.stdout).lines().count(), 1);
    String::from_utf8_lossy(&o.stderr)
        .lines()
        .map(str::to_string)
        .collect()
}

#[test]
fn fair_options_a_model_gives_nothing_to_are_warnings() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    hood_model(dir, "m.json", serde_json::json!({}));
    hood_model(dir, "own.json", serde_json::json!({"deviation": 0.05}));
    // the link options on a model without links
    assert_eq!(
        fair_warnings(dir, &["m.json", "--target", "G2"]),
        [
            "warning: --target G2 has nothing to apply to: m.json has no links (`build` finds a model's links from its geometry)"
        ]
    );
    let e = fair_warnings(
        dir,
        &[
            "m.json",
            "--no-verify",
            "--keep-faired",
            "--tolerance-role",
            "corner=0.1",
        ],
    );
    assert_eq!(e.len(), 2, "{e:?}");
    assert!(
        e[0].starts_with(
            "warning: --no-verify, --keep-faired have nothing to apply to: m.json has no links"
        ),
        "{e:?}"
    );
    // a role no surface has, and --tolerance where every surface has its own deviation
    assert_eq!(
        e[1],
        "warning: --tolerance-role corner=… applies to no surface: m.json has no corner surface without its own deviation"
    );
    let e = fair_warnings(dir, &["own.json", "--tolerance", "0.1"]);
    assert_eq!(e.len(), 1, "{e:?}");
    assert!(
        e[0].starts_with(
            "warning: --tolerance applies to no surface of own.json: each has its own deviation"
        ),
        "{e:?}"
    );
    // options that apply are not warned about
    assert!(fair_warnings(dir, &["m.json", "--tolerance", "0.1"]).is_empty());
    let x_node = root("fixtures/models/x_node.json");
    let e = fair_warnings(
        dir,
        &[
            x_node.to_str().unwrap(),
            "--target",
            "G1",
            "--tolerance-role",
            "corner=0.2",
        ],
    );
    assert!(e.is_empty(), "{e:?}");
}
