//! CAD exchange from the library (`hier_fair::exchange`): a kernel model's STEP and IGES files
//! read with their hierarchy, the model written back and read again, and files that are not CAD
//! named in one error.

use std::path::Path;

use hier_fair::exchange::{CadFormat, Imported, cad_text, read_cad, read_iges, read_step};

fn fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/occt")
        .join(name)
}

fn import_cad(path: &Path) -> hier_fair::Result<Imported> {
    read_cad(&std::fs::read(path).unwrap())
}

/// box12_r5 from STEP and from IGES: 26 faces, the 48 links of its model JSON, the same roles.
#[test]
fn a_kernel_model_comes_in_from_step_and_iges_with_its_hierarchy() {
    let json = hier_fair::Model::from_json(
        &std::fs::read_to_string(fixture("occt_box12_r5.json")).unwrap(),
    )
    .unwrap();
    for file in ["occt_box12_r5.step", "occt_box12_r5.igs"] {
        let imported = import_cad(&fixture(file)).unwrap();
        let m = &imported.model;
        assert_eq!(m.surfaces.len(), json.surfaces.len(), "{file}");
        assert_eq!(m.links.len(), json.links.len(), "{file}");
        for role in [
            hier_fair::Role::Primary,
            hier_fair::Role::Connecting,
            hier_fair::Role::Corner,
        ] {
            let count = |m: &hier_fair::Model| m.surfaces.iter().filter(|s| s.role == role).count();
            assert_eq!(count(m), count(&json), "{file}: {role:?}");
        }
        assert!(
            imported.summary.contains("48 links found"),
            "{}",
            imported.summary
        );
    }
}

/// The model written as STEP and as IGES reads back with its faces and links.
#[test]
fn a_model_written_as_step_or_iges_reads_back() {
    let m = import_cad(&fixture("occt_plate_boss.step")).unwrap().model;
    let step = cad_text(&m, CadFormat::Step, "plate_boss.step").unwrap();
    let back = read_step(&step).unwrap().model;
    assert_eq!(back.surfaces.len(), m.surfaces.len());
    assert_eq!(back.links.len(), m.links.len());
    let iges = cad_text(&m, CadFormat::Iges, "plate_boss.igs").unwrap();
    let back = read_iges(iges.as_bytes()).unwrap().model;
    assert_eq!(back.surfaces.len(), m.surfaces.len());
    assert_eq!(back.links.len(), m.links.len());
}

/// A model JSON and a STEP file without faces are errors that say what they got.
#[test]
fn what_is_not_cad_is_named() {
    let e = import_cad(&fixture("occt_box12_r5.json"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("neither a STEP file"), "{e}");
    let empty = "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\nENDSEC;\nEND-ISO-10303-21;\n";
    let e = read_step(empty).unwrap_err().to_string();
    assert!(e.contains("no face"), "{e}");
}

/// A solid's faces written as STEP are one closed shell again: box12_r5's 26 faces, as its
/// STEP file has them, share their 48 edges (each one EDGE_CURVE used by two faces), and the
/// file reads back with every face and link.
#[test]
fn a_solids_faces_are_written_as_one_closed_shell() {
    let m = import_cad(&fixture("occt_box12_r5.step")).unwrap().model;
    let step = cad_text(&m, CadFormat::Step, "box.step").unwrap();
    let count = |kind: &str| {
        step.lines()
            .filter(|l| l.contains(&format!("= {kind}(")))
            .count()
    };
    assert_eq!(count("CLOSED_SHELL"), 1);
    assert_eq!(count("OPEN_SHELL"), 0);
    assert_eq!(count("EDGE_CURVE"), 48);
    assert_eq!(count("ORIENTED_EDGE"), 96);
    let back = read_step(&step).unwrap().model;
    assert_eq!(back.surfaces.len(), m.surfaces.len());
    assert_eq!(back.links.len(), m.links.len());
}
