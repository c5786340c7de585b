//! `hier-fair import` on files other CAD systems wrote (`fixtures/foreign/`): every file
//! imports, and what is skipped or tolerated is named in the one-paragraph summary.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `fixtures/foreign/NAME`.
fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/foreign")
        .join(name)
}

/// `hier-fair import INPUT -o DIR/out.json`.
fn import(input: &Path, dir: &tempfile::TempDir) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hier-fair"))
        .arg("import")
        .arg(input)
        .arg("-o")
        .arg(dir.path().join("out.json"))
        .output()
        .expect("binary runs")
}

/// The summary of a successful import.
fn summary(o: &Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).to_string()
}

#[test]
fn foreign_fixtures_import_and_say_what_they_tolerate() {
    let tmp = tempfile::tempdir().unwrap();
    let s = summary(&import(&fixture("pr1sy.stp"), &tmp));
    assert!(s.starts_with("imported 11 faces"), "{s}");
    assert!(s.contains("faces and surfaces skipped: none"), "{s}");
    std::fs::remove_file(tmp.path().join("out.json")).unwrap();
    let s = summary(&import(&fixture("bad_header.igs"), &tmp));
    assert!(s.contains("warning: line 58: Terminate record says"), "{s}");
}

/// A file with one face that cannot be read: the rest imports, the face named with why.
#[test]
fn a_face_that_cannot_be_read_is_named_in_the_summary() {
    let tmp = tempfile::tempdir().unwrap();
    let text = "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;
#1 = CARTESIAN_POINT('',(0.,0.,0.));
#2 = CARTESIAN_POINT('',(10.,0.,0.));
#3 = CARTESIAN_POINT('',(0.,10.,0.));
#4 = AXIS2_PLACEMENT_3D('',#1,$,$);
#5 = PLANE('',#4);
#6 = POLY_LOOP('',(#1,#2,#3));
#7 = FACE_OUTER_BOUND('',#6,.T.);
#8 = ADVANCED_FACE('good',(#7),#5,.T.);
#90 = B_SPLINE_SURFACE_WITH_KNOTS('',1,1);
#91 = ADVANCED_FACE('short',(),#90,.T.);
ENDSEC;
END-ISO-10303-21;
";
    let input = tmp.path().join("one_bad.step");
    std::fs::write(&input, text).unwrap();
    let s = summary(&import(&input, &tmp));
    assert!(s.starts_with("imported 1 faces"), "{s}");
    assert!(
        s.contains(
            "ADVANCED_FACE #91 not read: #90 B_SPLINE_SURFACE_WITH_KNOTS: 3 parameters, expected 13"
        ),
        "{s}"
    );
}
