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
