//! `hier-fair import` / `export`: IGES in and out through the command line.

use std::path::Path;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_hier-fair"))
}

#[test]
fn export_then_import_keeps_geometry_and_names() {
    let dir = tempfile::tempdir().unwrap();
    let fixture =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/surfaces/sphere_patch_r50.json");
    let igs = dir.path().join("out.igs");
    let o = bin()
        .args([
            "export",
            fixture.to_str().unwrap(),
            "-o",
            igs.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    nurbs_io::check_structure(&std::fs::read(&igs).unwrap()).unwrap();
    let model = dir.path().join("model.json");
    let o = bin()
        .args([
            "import",
            igs.to_str().unwrap(),
            "-o",
            model.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let back = hier_fair::Model::from_json(&std::fs::read_to_string(&model).unwrap()).unwrap();
    let original =
        nurbs_core::io::surfaces_from_json(&std::fs::read_to_string(&fixture).unwrap()).unwrap();
    assert_eq!(back.surfaces.len(), 1);
    assert_eq!(back.surfaces[0].name, "surface");
    assert_eq!(back.surfaces[0].surface, original[0]);
    assert!(back.links.is_empty());
    // the input is never overwritten
    let o = bin()
        .args(["import", igs.to_str().unwrap(), "-o", igs.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("refusing to overwrite"));
}

#[test]
fn impeller_imports_as_primaries() {
    let igs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/impeller.igs");
    if !igs.exists() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("impeller.json");
    let o = bin()
        .args([
            "import",
            igs.to_str().unwrap(),
            "-o",
            model.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("imported 247 surfaces"));
    let m = hier_fair::Model::from_json(&std::fs::read_to_string(&model).unwrap()).unwrap();
    assert_eq!(m.surfaces.len(), 247);
    assert_eq!(m.units.as_deref(), Some("mm"));
}

#[test]
fn bad_iges_is_one_line_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.igs");
    std::fs::write(&bad, "not an iges file\n").unwrap();
    let o = bin()
        .args([
            "import",
            bad.to_str().unwrap(),
            "-o",
            dir.path().join("m.json").to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.trim_end().lines().count(), 1);
    assert!(err.contains("line 1"), "{err}");
    assert!(!dir.path().join("m.json").exists());
}
