//! IGES files as other systems write them (IGES 5.3 §2): blank lines after the Terminate
//! record, a Terminate record whose counts disagree with the sections, a directory entry whose
//! parameter line count disagrees with the lines pointing back to it — each read as it is,
//! with a warning where a count is wrong.

use nurbs_core::shapes::cylinder;
use nurbs_io::{IgesWriteParams, read_iges, write_iges};

/// A quarter cylinder written as IGES entity 128, as lines.
fn lines() -> Vec<String> {
    let s = cylinder(5.0, 20.0).unwrap();
    write_iges(&[("CYL", &s)], &[], &IgesWriteParams::default())
        .unwrap()
        .lines()
        .map(str::to_string)
        .collect()
}

/// The file of `lines` read: its one surface is the quarter cylinder.
fn read_cylinder(lines: &[String]) -> nurbs_io::IgesFile {
    let f = read_iges((lines.join("\n") + "\n").as_bytes()).unwrap();
    let s = cylinder(5.0, 20.0).unwrap();
    assert_eq!(f.surfaces.len(), 1);
    let back = &f.surfaces[0].surface;
    assert!((back.point(0.3, 0.7) - s.point(0.3, 0.7)).norm() < 1e-9);
    f
}

#[test]
fn blank_lines_after_the_terminate_record_are_no_records() {
    let mut l = lines();
    l.extend(["".to_string(), "   ".to_string(), "\r".to_string()]);
    let f = read_cylinder(&l);
    assert!(f.warnings.is_empty(), "{:?}", f.warnings);
}

#[test]
fn a_terminate_record_that_miscounts_is_read_with_a_warning() {
    let mut l = lines();
    let t = l.len() - 1;
    assert_eq!(l[t].as_bytes()[72], b'T');
    // the Global count (columns 9–16) says 4
    l[t].replace_range(8..16, "G      4");
    let f = read_cylinder(&l);
    assert_eq!(f.warnings.len(), 1, "{:?}", f.warnings);
    assert!(f.warnings[0].contains("Terminate record says \"G      4\""));
    assert!(!f.warnings[0].contains('\n'));
}

#[test]
fn a_parameter_line_count_that_disagrees_with_the_back_pointers_is_read_with_a_warning() {
    let mut l = lines();
    let d = l.iter().position(|r| r.as_bytes()[72] == b'D').unwrap();
    // the second directory line's field 14 (columns 25–32): the parameter line count
    l[d + 1].replace_range(24..32, &format!("{:>8}", 99));
    let f = read_cylinder(&l);
    assert_eq!(f.warnings.len(), 1, "{:?}", f.warnings);
    assert!(f.warnings[0].contains("gives 99"), "{}", f.warnings[0]);
}
