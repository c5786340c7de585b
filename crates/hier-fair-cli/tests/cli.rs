//! The command line as users run it: exit codes, one-line errors, JSON fields.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_hier-fair"))
}

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/surfaces")
        .join(name)
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

fn write(dir: &tempfile::TempDir, name: &str, text: &str) -> String {
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p.to_string_lossy().to_string()
}

#[test]
fn eval_grid_json_fields_and_signs() {
    let o = run(&[
        "eval",
        fixture("sphere_patch_r50.json").to_str().unwrap(),
        "--grid",
        "3,4",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let results = v["results"].as_array().unwrap();
    assert_eq!(results.len(), 12);
    // u varies slowest, both ends included
    assert_eq!(results[0]["u"], 0.0);
    assert_eq!(results[3]["v"], 1.0);
    assert_eq!(results[4]["u"], 0.5);
    for r in results {
        for key in ["point", "du", "dv", "duu", "duv", "dvv", "normal"] {
            assert_eq!(r[key].as_array().unwrap().len(), 3, "{key}");
        }
        let p: Vec<f64> = r["point"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let n: Vec<f64> = r["normal"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let outward = p[0] * n[0] + p[1] * n[1] + p[2] * n[2] > 0.0;
        let (k1, k2) = (r["k1"].as_f64().unwrap(), r["k2"].as_f64().unwrap());
        assert!(k1 >= k2);
        let expected = if outward { -1.0 / 50.0 } else { 1.0 / 50.0 };
        assert!(
            (k1 - expected).abs() < 1e-10 && (k2 - expected).abs() < 1e-10,
            "{k1} {k2} vs {expected}"
        );
        assert!((r["mean"].as_f64().unwrap() - expected).abs() < 1e-10);
        assert!((r["gauss"].as_f64().unwrap() - 1.0 / 2500.0).abs() < 1e-12);
    }
}

#[test]
fn eval_params_and_summary() {
    let dir = tempfile::tempdir().unwrap();
    let params = write(
        &dir,
        "p.json",
        r#"{"params": [[0, 0], [0.5, 0.25], [1, 1]]}"#,
    );
    let surface = fixture("hood_panel.json");
    let o = run(&[
        "eval",
        surface.to_str().unwrap(),
        "--params",
        &params,
        "--summary",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["count"], 3);
    assert!(v["seconds"].as_f64().unwrap() >= 0.0);
    // corners of a clamped surface are corner control points: (0,0,0) + (100,60,z) + middle
    let full = run(&["eval", surface.to_str().unwrap(), "--params", &params]);
    let r: serde_json::Value = serde_json::from_slice(&full.stdout).unwrap();
    let sum: f64 = r["results"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|x| {
            x["point"]
                .as_array()
                .unwrap()
                .iter()
                .map(|c| c.as_f64().unwrap())
        })
        .sum();
    assert!((sum - v["checksum"].as_f64().unwrap()).abs() < 1e-9);
    assert_eq!(r["results"][0]["point"], serde_json::json!([0.0, 0.0, 0.0]));
}

#[test]
fn poles_give_null_normals() {
    let dir = tempfile::tempdir().unwrap();
    // a biquadratic with the u = 0 row collapsed to one point
    let text = r#"{"degree_u": 2, "degree_v": 2, "control_points": [
        [[0,0,1],[0,0,1],[0,0,1]], [[1,-1,0],[1,0,0],[1,1,0]], [[2,-1,0],[2,0,0],[2,1,0]]]}"#;
    let s = write(&dir, "cone.json", text);
    let o = run(&["eval", &s, "--grid", "2,2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["results"][0]["normal"].is_null());
    assert!(v["results"][0]["k1"].is_null());
    assert!(!v["results"][3]["normal"].is_null());
}

#[test]
fn bad_input_is_one_line_and_non_zero() {
    let dir = tempfile::tempdir().unwrap();
    let good = fixture("hood_panel.json");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![
                "eval".into(),
                dir.path().join("missing.json").to_string_lossy().into(),
                "--grid".into(),
                "2,2".into(),
            ],
            "cannot read",
        ),
        (
            vec![
                "eval".into(),
                write(&dir, "bad.json", "{not json"),
                "--grid".into(),
                "2,2".into(),
            ],
            "malformed JSON",
        ),
        (
            vec![
                "eval".into(),
                write(
                    &dir,
                    "knots.json",
                    r#"{"degree_u":1,"degree_v":1,"knots_u":[0,0,1,0.5],"control_points":[[[0,0,0],[0,1,0]],[[1,0,0],[1,1,0]]]}"#,
                ),
                "--grid".into(),
                "2,2".into(),
            ],
            "knots_u",
        ),
        (
            vec![
                "eval".into(),
                write(
                    &dir,
                    "w.json",
                    r#"{"degree_u":1,"degree_v":1,"control_points":[[[0,0,0],[0,1,0]],[[1,0,0],[1,1,0]]],"weights":[[1,1],[0,1]]}"#,
                ),
                "--grid".into(),
                "2,2".into(),
            ],
            "weight [1][0] is 0",
        ),
        (
            vec![
                "eval".into(),
                write(
                    &dir,
                    "shape.json",
                    r#"{"degree_u":2,"degree_v":1,"control_points":[[[0,0,0],[0,1,0]],[[1,0,0],[1,1,0]]]}"#,
                ),
                "--grid".into(),
                "2,2".into(),
            ],
            "Bézier patch of degree 2",
        ),
        (
            vec![
                "eval".into(),
                good.to_string_lossy().into(),
                "--grid".into(),
                "0,3".into(),
            ],
            "--grid expects",
        ),
        (
            vec![
                "eval".into(),
                good.to_string_lossy().into(),
                "--params".into(),
                write(&dir, "p.json", r#"{"params": [[0.5, 2.0]]}"#),
            ],
            "params[0] v",
        ),
        (
            vec![
                "eval".into(),
                good.to_string_lossy().into(),
                "--params".into(),
                write(&dir, "q.json", r#"{"par": []}"#),
            ],
            "malformed params",
        ),
    ];
    for (args, expected) in cases {
        let o = bin().args(&args).output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = stderr(&o);
        assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
        assert!(
            err.contains(expected),
            "{args:?}: {err} should mention {expected}"
        );
        assert!(!err.contains("panicked"));
    }
}

#[test]
fn demo_fairs_the_bundled_x_node_and_writes_everything_atomically() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = run(&["demo", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("corner.u0 -> fillet_w"), "{text}");
    assert!(text.contains("surfaces faired in"), "{text}");
    for f in [
        "faired.json",
        "faired.igs",
        "model.json",
        "report.json",
        "report.md",
        "images/zebra_before.png",
        "images/zebra_after.png",
        "images/mean_curvature_before.png",
        "images/mean_curvature_after.png",
        "images/curvature_corner_u0_on_fillet_w.png",
        "images/corner_corner_zebra_before.png",
        "images/corner_corner_zebra_after.png",
        "images/corner_corner_mean_curvature_before.png",
        "images/corner_corner_mean_curvature_after.png",
    ] {
        assert!(out.join(f).exists(), "{f} missing");
    }
    // the corner view is zoomed on the corner: it fills the middle of the picture (the
    // background is light grey, 236/238/242), and the whole-model view is another picture
    let zoomed = image::open(out.join("images/corner_corner_zebra_after.png"))
        .unwrap()
        .to_rgb8();
    let (w, h) = zoomed.dimensions();
    let covered = (w / 3..2 * w / 3)
        .flat_map(|x| (h / 3..2 * h / 3).map(move |y| (x, y)))
        .filter(|&(x, y)| zoomed.get_pixel(x, y).0 != [236, 238, 242])
        .count();
    assert_eq!(
        covered as u32,
        (w / 3) * (h / 3),
        "the middle third is the model"
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["surfaces"].as_array().unwrap().len(), 9);
    assert_eq!(report["links"].as_array().unwrap().len(), 12);
    for key in ["seconds_total", "surfaces", "links"] {
        assert!(report.get(key).is_some(), "{key}");
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("## Links") && md.contains("## Surfaces"));
    let leftovers: Vec<_> = [out.clone(), out.join("images")]
        .iter()
        .flat_map(|d| std::fs::read_dir(d).unwrap())
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains(".tmp"))
        .collect();
    assert!(leftovers.is_empty());
}

fn model_fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/models")
        .join(name)
}

fn one_line_error(o: &Output) -> String {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.starts_with("error:") && err.lines().count() == 1,
        "{err}"
    );
    err
}

/// A grid beyond the bound (or whose count overflows) is one line naming the bound, not a
/// panic or an allocation abort; a listing beyond its bound points to `--summary`.
#[test]
fn eval_grids_beyond_their_bounds_are_one_line_errors() {
    let hood = fixture("hood_panel.json");
    let hood = hood.to_str().unwrap();
    for grid in ["18446744073709551615,2", "100000,100001"] {
        let o = run(&["eval", hood, "--grid", grid, "--summary"]);
        assert!(one_line_error(&o).contains("100000000"), "{grid}");
    }
    let o = run(&["eval", hood, "--grid", "3000,3000"]);
    assert!(one_line_error(&o).contains("--summary"));
    // the summary streams: a grid of 10⁸ is allowed (here 10⁶, the same code path)
    let o = run(&["eval", hood, "--grid", "1000,1000", "--summary"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["count"], 1_000_000);
}

/// The streamed summary sums the same points as the full listing.
#[test]
fn eval_summary_checksum_is_the_sum_of_the_listed_points() {
    let sphere = fixture("sphere_patch_r50.json");
    let sphere = sphere.to_str().unwrap();
    let full = run(&["eval", sphere, "--grid", "70,90"]);
    let summary = run(&["eval", sphere, "--grid", "70,90", "--summary"]);
    let full: serde_json::Value = serde_json::from_slice(&full.stdout).unwrap();
    let summary: serde_json::Value = serde_json::from_slice(&summary.stdout).unwrap();
    let sum: f64 = full["results"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|r| r["point"].as_array().unwrap().clone())
        .map(|x| x.as_f64().unwrap())
        .sum();
    let checksum = summary["checksum"].as_f64().unwrap();
    assert_eq!(summary["count"], 6300);
    assert!(
        (sum - checksum).abs() <= 1e-9 * sum.abs(),
        "{sum} {checksum}"
    );
}

/// Two outputs naming one file (in any spelling) are refused before any work, and nothing is
/// written; so is an output whose folder does not exist, found before `-o` is written.
#[test]
fn outputs_are_validated_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let model = model_fixture("fillet_freeform.json");
    let model = model.to_str().unwrap();
    let x = dir.path().join("x.json");
    let x_again = dir.path().join(".").join("x.json");
    let o = run(&[
        "connect",
        model,
        "-o",
        x.to_str().unwrap(),
        "--report",
        x_again.to_str().unwrap(),
    ]);
    assert!(one_line_error(&o).contains("same file"));
    assert!(!x.exists());
    let y = dir.path().join("y.json");
    let missing = dir.path().join("no-such-folder").join("r.json");
    let o = run(&[
        "fair",
        model,
        "-o",
        y.to_str().unwrap(),
        "--report",
        missing.to_str().unwrap(),
    ]);
    assert!(one_line_error(&o).contains("does not exist"));
    assert!(!y.exists(), "-o was written although --report could not be");
    let o = run(&[
        "fair",
        model,
        "-o",
        y.to_str().unwrap(),
        "--images",
        missing.to_str().unwrap(),
    ]);
    one_line_error(&o);
    assert!(!y.exists());
}

/// An error while writing names the user's path, never the temporary file beside it.
#[test]
fn write_errors_name_the_users_path() {
    let model = model_fixture("fillet_freeform.json");
    let o = run(&[
        "fair",
        model.to_str().unwrap(),
        "-o",
        "/proc/hier-fair-test.json",
    ]);
    let err = one_line_error(&o);
    assert!(
        err.contains("/proc/hier-fair-test.json") && !err.contains(".tmp"),
        "{err}"
    );
}

/// Readers bound weights, coordinates and nets (nurbs_core::io): one line naming the bound,
/// each cause said once.
#[test]
fn readers_bound_weight_ratios_coordinates_and_nets() {
    let dir = tempfile::tempdir().unwrap();
    let model: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(model_fixture("fillet_freeform.json")).unwrap(),
    )
    .unwrap();
    type Edit = Box<dyn Fn(&mut serde_json::Value)>;
    let cases: [(&str, Edit, &str); 3] = [
        (
            "weight.json",
            Box::new(|m| {
                let s = &mut m["surfaces"][2]["surface"];
                let (nu, nv) = (
                    s["control_points"].as_array().unwrap().len(),
                    s["control_points"][0].as_array().unwrap().len(),
                );
                let mut w = vec![vec![1.0; nv]; nu];
                w[1][1] = 1e7;
                s["weights"] = serde_json::json!(w);
            }),
            "ratio of the largest weight",
        ),
        (
            "far.json",
            Box::new(|m| m["surfaces"][1]["surface"]["control_points"][0][0][2] = 1e308.into()),
            "beyond the bound of 1e9",
        ),
        (
            "degree.json",
            Box::new(|m| m["surfaces"][1]["surface"]["degree_u"] = 0.into()),
            "degree must be at least 1",
        ),
    ];
    for (name, edit, expected) in cases {
        let mut m = model.clone();
        edit(&mut m);
        let path = write(&dir, name, &m.to_string());
        let out = dir.path().join(format!("out-{name}"));
        let o = run(&["fair", &path, "-o", out.to_str().unwrap()]);
        let err = one_line_error(&o);
        assert_eq!(err.matches(expected).count(), 1, "{name}: {err}");
        assert!(!out.exists());
    }
}

/// `--iterations` is the limit of the iterative methods (0, 5 and 100000 give three different
/// results) and a one-line error for the direct solves, never silently ignored.
#[test]
fn iterations_set_the_limit_or_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let model = model_fixture("fillet_freeform.json");
    let model = model.to_str().unwrap();
    let mut outputs = Vec::new();
    for n in ["0", "5", "100000"] {
        let out = dir.path().join(format!("it{n}.json"));
        let o = run(&[
            "fair",
            model,
            "-o",
            out.to_str().unwrap(),
            "--iterations",
            n,
            "--quiet",
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        outputs.push(std::fs::read_to_string(&out).unwrap());
    }
    assert!(outputs[0] != outputs[1] && outputs[1] != outputs[2]);
    for method in ["curvature", "greiner"] {
        let out = dir.path().join(format!("{method}.json"));
        let o = run(&[
            "fair",
            model,
            "-o",
            out.to_str().unwrap(),
            "--method",
            method,
            "--iterations",
            "5",
        ]);
        assert!(one_line_error(&o).contains("direct solve"), "{method}");
        assert!(!out.exists());
    }
}

/// `connect --target` above every link's own continuity says that it caps.
#[test]
fn connect_target_says_it_caps() {
    let dir = tempfile::tempdir().unwrap();
    let mut m: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(model_fixture("fillet_freeform.json")).unwrap(),
    )
    .unwrap();
    for l in m["links"].as_array_mut().unwrap() {
        l["continuity"] = "G1".into();
    }
    let path = write(&dir, "g1.json", &m.to_string());
    let out = dir.path().join("out.json");
    let o = run(&[
        "connect",
        &path,
        "-o",
        out.to_str().unwrap(),
        "--target",
        "G2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("is a cap") && text.contains("G1"), "{text}");
}

/// A model-level JSON error names the field's place in the model and its line.
#[test]
fn model_json_errors_name_the_place() {
    let dir = tempfile::tempdir().unwrap();
    let mut m: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(model_fixture("fillet_freeform.json")).unwrap(),
    )
    .unwrap();
    m["surfaces"][1]["surface"]["control_points"][0][0] = serde_json::json!([1.0, 2.0]);
    let path = write(&dir, "bad.json", &serde_json::to_string_pretty(&m).unwrap());
    let out = dir.path().join("out.json");
    let o = run(&["fair", &path, "-o", out.to_str().unwrap()]);
    let err = one_line_error(&o);
    assert!(
        err.contains("surfaces[1].surface.control_points[0][0]") && err.contains("line"),
        "{err}"
    );
}

/// `check` measures a link that does not touch its master and reports its gap (the table says
/// so, the JSON has `"touches": false`); `--fail-above` then exits 1, as for any link beyond it.
#[test]
fn check_reports_a_link_that_does_not_touch() {
    let dir = tempfile::tempdir().unwrap();
    let mut m: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(model_fixture("fillet_freeform.json")).unwrap(),
    )
    .unwrap();
    for row in m["surfaces"][2]["surface"]["control_points"]
        .as_array_mut()
        .unwrap()
    {
        for p in row.as_array_mut().unwrap() {
            p[2] = (p[2].as_f64().unwrap() + 5.0).into();
        }
    }
    let path = write(&dir, "apart.json", &m.to_string());
    let o = run(&["check", &path]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("DOES NOT TOUCH"));
    let o = run(&["check", &path, "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let link = &v["links"][0];
    assert_eq!(link["touches"], false);
    assert!(link["g0"].as_f64().unwrap() > 4.9);
    let o = run(&["check", &path, "--fail-above", "class-a"]);
    assert_eq!(o.status.code(), Some(1));
}

/// `fair` on a model ends with one verdict line: the links met against the model's tolerances,
/// conflicts and unmet links counted, the surfaces within their deviation and the fair ones,
/// and the file written; the fairness line names every surface that is not fair.
#[test]
fn fair_ends_with_a_verdict_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.json");
    let model = model_fixture("x_node.json");
    let o = run(&[
        "fair",
        model.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--no-verify",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    let last = text.lines().last().unwrap();
    let expected = format!(
        "verdict: 12 of 12 links met (G0 ≤ 0.001, G1 ≤ 0.01°, G2 ≤ 0.005 relative), 0 conflicts, 0 unmet; 9 of 9 surfaces within their deviation; 4 of 9 fair against their input; wrote {}",
        out.display()
    );
    assert_eq!(last, expected, "{text}");
    assert!(
        text.contains("fairness: 4 of 9 surfaces fair against their input; not: fillet_s"),
        "{text}"
    );
    // --quiet: the verdict line alone
    let quiet = dir.path().join("q.json");
    let o = run(&[
        "fair",
        model.to_str().unwrap(),
        "-o",
        quiet.to_str().unwrap(),
        "--no-verify",
        "--quiet",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(text.lines().count(), 1, "{text}");
    assert!(text.starts_with("verdict: 12 of 12 links met"), "{text}");
}
