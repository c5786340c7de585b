//! `hier-fair label`: the contract's JSON, the SVG and the fitted surface, on a synthetic
//! rectangle region and on the Neon side panel of `fixtures/third_party`.

use std::process::Command;

fn run(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_hier-fair"))
        .args(args)
        .output()
        .expect("binary runs")
}

/// A gently curved 30×20 grid region of 60 × 40 mm as OBJ text.
fn rectangle_obj() -> String {
    let (nx, ny) = (30, 20);
    let mut s = String::new();
    for i in 0..=nx {
        for j in 0..=ny {
            let (x, y) = (2.0 * i as f64, 2.0 * j as f64);
            s.push_str(&format!("v {x} {y} {}\n", 0.002 * x * x + 0.001 * y * y));
        }
    }
    let id = |i: usize, j: usize| i * (ny + 1) + j + 1;
    for i in 0..nx {
        for j in 0..ny {
            s.push_str(&format!(
                "f {} {} {}\n",
                id(i, j),
                id(i + 1, j),
                id(i + 1, j + 1)
            ));
            s.push_str(&format!(
                "f {} {} {}\n",
                id(i, j),
                id(i + 1, j + 1),
                id(i, j + 1)
            ));
        }
    }
    s
}

#[test]
fn a_rectangle_gets_four_labels_and_a_close_fit() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("rect.obj");
    std::fs::write(&obj, rectangle_obj()).unwrap();
    let labels = dir.path().join("labels.json");
    let svg = dir.path().join("labels.svg");
    let fit = dir.path().join("fit.json");
    let o = run(&[
        "label",
        obj.to_str().unwrap(),
        "-o",
        labels.to_str().unwrap(),
        "--svg",
        svg.to_str().unwrap(),
        "--fit",
        fit.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&labels).unwrap()).unwrap();
    assert_eq!(v["configuration"]["labels"], 4);
    assert_eq!(v["configuration"]["corners"], 4);
    let names: Vec<&str> = v["segments"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["label"].as_str().unwrap())
        .collect();
    for side in ["south", "east", "north", "west"] {
        assert!(names.contains(&side), "{names:?}");
    }
    for c in v["corners"].as_array().unwrap() {
        assert!(c["between"].as_array().unwrap().len() == 2);
        assert!(["real", "virtual", "none"].contains(&c["kind"].as_str().unwrap()));
    }
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
    let surface = nurbs_core::io::surfaces_from_json(&std::fs::read_to_string(&fit).unwrap())
        .unwrap()
        .remove(0);
    // the fit reproduces the quadratic height field closely
    let (a, b) = surface.domain_u();
    let p = surface.point(0.5 * (a + b), 0.5 * (a + b));
    let z = 0.002 * p.x * p.x + 0.001 * p.y * p.y;
    assert!((p.z - z).abs() < 1e-3, "{p:?} vs z {z}");
}

#[test]
fn bad_regions_get_one_line_errors() {
    let dir = tempfile::tempdir().unwrap();
    // a closed tetrahedron: no boundary
    let obj = dir.path().join("closed.obj");
    std::fs::write(
        &obj,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n",
    )
    .unwrap();
    let out = dir.path().join("l.json");
    let o = run(&["label", obj.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.starts_with("error:") && err.lines().count() == 1,
        "{err}"
    );
    assert!(!out.exists());
}

#[test]
fn the_neon_panel_is_labeled_and_fitted() {
    let neon = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/third_party/neon_side.obj");
    assert!(neon.exists(), "{} is in the repository", neon.display());
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("l.json");
    let fit = dir.path().join("f.json");
    let o = run(&[
        "label",
        neon.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--fit",
        fit.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("% of the size"), "{text}");
}

/// `-o` and `--svg` naming one file is refused before any work: one output never silently
/// replaces another.
#[test]
fn label_outputs_naming_one_file_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("rect.obj");
    std::fs::write(&obj, rectangle_obj()).unwrap();
    let out = dir.path().join("l.json");
    let o = run(&[
        "label",
        obj.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--svg",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("same file") && err.lines().count() == 1,
        "{err}"
    );
    assert!(!out.exists());
}
