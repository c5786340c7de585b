//! Regression snapshots of the pipeline over `fixtures/` (review changes with
//! `cargo insta review` or accept them with `cargo xtask snapshots --update`).

#[test]
fn fixture_surface_summaries() {
    let files = xtask::fixture_files().expect("fixtures are readable");
    assert!(!files.is_empty(), "fixtures/surfaces holds the regression inputs");
    for path in files {
        let name = path.file_stem().expect("file name").to_string_lossy().to_string();
        let summary = xtask::fixture_summary(&path).expect("fixture evaluates");
        insta::assert_json_snapshot!(format!("surface_{name}"), summary);
    }
}
