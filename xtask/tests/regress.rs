//! `cargo xtask regress` inside the test run (so `.ci/run` runs it without a second build): the
//! framework on every fixture model and on the third-party models of `fixtures/third_party`. The table is printed (`--nocapture` shows it); the test fails only when a
//! model cannot be run at all — reaching the targets is judged by the snapshots and the
//! framework tests.

#[test]
fn regression_table_runs_every_model() {
    let external = xtask::root().join("fixtures/third_party");
    let (table, ok) = xtask::regress_table(&external).expect("regression models are readable");
    println!("{table}");
    assert!(ok, "{table}");
    assert!(table.lines().count() >= 6, "{table}");
}

/// The foreign-file table over `fixtures/foreign/` (CAD files written by other systems): every
/// file imports and runs, a line per file and a totals line.
#[test]
fn foreign_table_runs_every_fixture_file() {
    let dir = xtask::root().join("fixtures/foreign");
    let files = xtask::cad_files(std::slice::from_ref(&dir)).unwrap();
    assert!(files.len() >= 10, "{files:?}");
    let (table, ok) = xtask::foreign_table(&[dir]).expect("the folder is readable");
    println!("{table}");
    assert!(ok, "{table}");
    assert_eq!(table.lines().count(), files.len() + 2, "{table}");
    let total = table.lines().last().unwrap();
    assert!(
        total.starts_with("all: ") && total.contains("links met"),
        "{total}"
    );
}
