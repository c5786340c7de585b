//! Every run ends with a verdict a newcomer can read (cli-contract.md): `demo` (on stdout and in
//! report.md) and `connect` with before and after side by side and the tolerances, `fair` on a
//! bare surface file with one line per surface and a verdict; and the outputs and options of
//! `build`, `fair-mesh`, `label` and `fair --keep` refused where they do not apply.

use std::path::Path;
use std::process::Output;

mod common;
use common::{root, run_in};

/// The stdout of a run that succeeded.
fn ok(o: Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8(o.stdout).expect("UTF-8 output")
}

/// A run refused with one error line holding every one of `parts`, nothing at `not_written`.
fn refused(o: &Output, parts: &[&str], not_written: &Path) {
    assert_eq!(o.status.code(), Some(2), "{o:?}");
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(e.trim().lines().count(), 1, "{e}");
    for p in parts {
        assert!(e.contains(p), "{p:?} not in {e}");
    }
    assert!(!not_written.exists(), "{}", not_written.display());
}

#[test]
fn demo_shows_before_and_after_and_ends_with_a_verdict() {
    let tmp = tempfile::tempdir().unwrap();
    let text = ok(run_in(tmp.path(), &["demo", "--out", "d", "--quiet"]));
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[1].starts_with("link"), "{text}");
    for column in [
        "gap before → after",
        "angle° before → after",
        "g2 rel before → after",
        "met",
    ] {
        assert!(lines[1].contains(column), "{column}: {text}");
    }
    // the X-node comes in G1 only: each row shows the curvature jump it had and what is left
    let row = lines
        .iter()
        .find(|l| l.starts_with("corner.v0 -> fillet_s"))
        .unwrap();
    assert_eq!(row.matches(" → ").count(), 3, "{row}");
    assert!(row.contains("1.999e0 →"), "{row}");
    assert!(row.ends_with("yes"), "{row}");
    assert!(
        text.contains("model tolerances: g0 0.001 · g1 0.01° · g2 0.005"),
        "{text}"
    );
    let verdict = "verdict: 12 of 12 links met (G0 ≤ 0.001, G1 ≤ 0.01°, G2 ≤ 0.005 relative), 0 conflicts, 0 unmet; 9 of 9 surfaces within their deviation; 4 of 9 fair against their input";
    assert_eq!(lines[lines.len() - 2], verdict, "{text}");
    assert!(lines[lines.len() - 1].starts_with("wrote d/faired.json"));
    let md = std::fs::read_to_string(tmp.path().join("d/report.md")).unwrap();
    assert!(
        md.contains(&format!(
            "## Verdict\n\n{verdict}; wrote faired.json, faired.igs\n"
        )),
        "{md}"
    );
    // the report ends with that line: stdout's verdict line as printed, and what was written
    // (which stdout names on its own last line)
    assert_eq!(
        md.trim_end().lines().last(),
        Some(format!("{}; wrote faired.json, faired.igs", lines[lines.len() - 2]).as_str()),
        "{md}"
    );
}

#[test]
fn connect_shows_the_curvature_before_and_after_and_whether_each_link_is_met() {
    let tmp = tempfile::tempdir().unwrap();
    let model = root("fixtures/occt/occt_plate_boss.json");
    let text = ok(run_in(
        tmp.path(),
        &["connect", model.to_str().unwrap(), "-o", "c.json"],
    ));
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[0].contains("g2 rel bef"), "{text}");
    assert!(lines[0].ends_with("met"), "{text}");
    // the kernel's torus fillets come in G1 (relative curvature difference 1) and leave G2
    let row = lines
        .iter()
        .find(|l| l.starts_with("F02_torus.v0 -> P01_plane"))
        .unwrap();
    assert!(row.contains("1.000e0"), "{row}");
    assert!(row.ends_with("yes"), "{row}");
    assert!(text.contains("model tolerances: g0 0.001 · g1 0.01° · g2 0.005\n"));
    assert!(
        lines
            .last()
            .unwrap()
            .starts_with("verdict: 4 of 4 links met"),
        "{text}"
    );
    // a bare surface file has no links: said, not left to guess from an empty table
    let surface = root("fixtures/surfaces/hood_panel.json");
    let text = ok(run_in(
        tmp.path(),
        &[
            "connect",
            surface.to_str().unwrap(),
            "-o",
            "s.json",
            "--target",
            "G2",
        ],
    ));
    assert!(
        text.contains("has no links: nothing was set, and --target has nothing to apply to"),
        "{text}"
    );
    assert!(!text.starts_with("link"), "{text}");
}

#[test]
fn fair_on_a_bare_surface_names_the_method_once_and_ends_with_a_verdict() {
    let tmp = tempfile::tempdir().unwrap();
    let surface = root("fixtures/surfaces/hood_panel.json");
    let text = ok(run_in(
        tmp.path(),
        &["fair", surface.to_str().unwrap(), "-o", "h.json"],
    ));
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 2, "{text}");
    assert!(
        lines[0].starts_with("surface (energy): thin-plate energy 5.505985e5 -> "),
        "{text}"
    );
    assert!(lines[0].contains("(tolerance 0.02)"), "{text}");
    assert!(
        lines[1].starts_with("verdict: 1 of 1 surfaces faired (thin-plate energy 5.5060e5 -> "),
        "{text}"
    );
    assert!(
        lines[1].ends_with(
            "0 kept as they were; largest deviation 3.634e-3 (tolerance 0.02); wrote h.json"
        ),
        "{text}"
    );
    // --quiet: the verdict line alone, as on a model
    let quiet = ok(run_in(
        tmp.path(),
        &["fair", surface.to_str().unwrap(), "-o", "q.json", "--quiet"],
    ));
    assert_eq!(quiet.lines().count(), 1, "{quiet}");
    assert!(
        quiet.starts_with("verdict: 1 of 1 surfaces faired"),
        "{quiet}"
    );
}

/// `--keep` chooses the frames of a bare surface; on a model (or a CAD file) the links choose
/// them, and the option is refused rather than ignored.
#[test]
fn keep_on_a_model_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("f.json");
    for input in [
        "fixtures/models/x_node.json",
        "fixtures/occt/occt_plate_boss.step",
    ] {
        let o = run_in(
            tmp.path(),
            &[
                "fair",
                root(input).to_str().unwrap(),
                "-o",
                "f.json",
                "--keep",
                "G2",
            ],
        );
        refused(
            &o,
            &["--keep applies to a bare surface file", "leave --keep out"],
            &out,
        );
    }
}

/// `build`, `fair-mesh` and `label` take their kind of input and write their outputs in the
/// format the extension names, from a known list.
#[test]
fn build_fair_mesh_and_label_check_their_inputs_and_outputs() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let step = root("fixtures/occt/occt_plate_boss.step");
    let model = root("fixtures/occt/occt_plate_boss.json");
    let mesh = root("fixtures/third_party/neon_side.obj");
    let o = run_in(dir, &["build", model.to_str().unwrap(), "-o", "b.txt"]);
    refused(&o, &["-o b.txt", "use one of .json"], &dir.join("b.txt"));
    let o = run_in(dir, &["build", step.to_str().unwrap(), "-o", "b.json"]);
    refused(
        &o,
        &["`build` takes a model JSON", "is a STEP file", "`import`"],
        &dir.join("b.json"),
    );
    let o = run_in(dir, &["fair-mesh", mesh.to_str().unwrap(), "-o", "m.stl"]);
    refused(&o, &["-o m.stl", "use one of .obj"], &dir.join("m.stl"));
    let o = run_in(dir, &["fair-mesh", model.to_str().unwrap(), "-o", "m.obj"]);
    refused(
        &o,
        &["`fair-mesh` takes an OBJ mesh", "is a model JSON"],
        &dir.join("m.obj"),
    );
    let o = run_in(
        dir,
        &[
            "label",
            mesh.to_str().unwrap(),
            "-o",
            "l.json",
            "--svg",
            "l.png",
        ],
    );
    refused(&o, &["--svg l.png", "use one of .svg"], &dir.join("l.json"));
    let o = run_in(
        dir,
        &[
            "label",
            mesh.to_str().unwrap(),
            "-o",
            "l.json",
            "--fit",
            "f.igs",
        ],
    );
    refused(
        &o,
        &["--fit f.igs", "use one of .json"],
        &dir.join("l.json"),
    );
    let o = run_in(dir, &["label", step.to_str().unwrap(), "-o", "l.json"]);
    refused(
        &o,
        &["`label` takes an OBJ mesh", "is a STEP file"],
        &dir.join("l.json"),
    );
}

#[test]
fn a_link_met_with_a_vertex_zone_is_counted_with_the_met_ones() {
    // tests/models/vertex_conflict.json: the construction of hier-fair's tests/vertex_conflict.rs
    // — a flat corner patch linked G2 to a plane (u0) and to a cylinder of radius 5 (v0) that
    // touches the plane along its side: at their common corner the cylinder curves by 1/5 across
    // v0 and the plane not at all, so v0 is relaxed within a vertex zone there and met beyond
    let tmp = tempfile::tempdir().unwrap();
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/models/vertex_conflict.json");
    let out = tmp.path().join("out.json");
    let report = tmp.path().join("report.json");
    let text = ok(run_in(
        tmp.path(),
        &[
            "fair",
            model.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
            "--quiet",
        ],
    ));
    let verdict = text.lines().last().unwrap();
    assert!(
        verdict.starts_with("verdict: 2 of 2 links met"),
        "{verdict}"
    );
    assert!(
        verdict.contains("with G2 relaxed in a vertex zone"),
        "{verdict}"
    );
    assert!(verdict.contains(", 0 conflicts, 0 unmet"), "{verdict}");
    // the report names the zone as a conflict, with its length
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let named = r["problems"]
        .as_array()
        .unwrap()
        .iter()
        .any(|p| p["kind"] == "conflict" && p["link"] == "blend.v0 -> roller");
    assert!(named, "{}", r["problems"]);
    let zones = r["links"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["side"] == "v0")
        .map(|l| l["after"]["vertex_zones"].clone())
        .unwrap();
    assert!(zones[0].as_f64().unwrap() > 0.0, "{zones}");
}
