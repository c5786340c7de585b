//! Regression snapshots of the pipeline over `fixtures/` (review changes with
//! `cargo insta review` or accept them with `cargo xtask snapshots --update`).

#[test]
fn fixture_surface_summaries() {
    let files = xtask::fixture_files().expect("fixtures are readable");
    assert!(
        !files.is_empty(),
        "fixtures/surfaces holds the regression inputs"
    );
    for path in files {
        let name = path
            .file_stem()
            .expect("file name")
            .to_string_lossy()
            .to_string();
        let summary = xtask::fixture_summary(&path).expect("fixture evaluates");
        insta::assert_json_snapshot!(format!("surface_{name}"), summary);
    }
}

/// Third-party models are read in place from `../shared/data` (never copied here); the test is
/// skipped where that folder is absent.
#[test]
fn shared_model_summaries() {
    let path = xtask::root().join("../shared/data/teapot.json");
    if !path.exists() {
        eprintln!(
            "{} not found: skipping the teapot regression",
            path.display()
        );
        return;
    }
    let summary = xtask::fixture_summary(&path).expect("teapot evaluates");
    insta::assert_json_snapshot!("teapot", summary);
}
