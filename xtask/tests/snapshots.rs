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

/// Third-party models live in `fixtures/third_party` (their licences and sources in its README).
#[test]
fn shared_model_summaries() {
    let path = xtask::root().join("fixtures/third_party/teapot.json");
    assert!(path.exists(), "{} is in the repository", path.display());
    let summary = xtask::fixture_summary(&path).expect("teapot evaluates");
    insta::assert_json_snapshot!("teapot", summary);
}

/// The framework on every fixture model: rounded per-surface and per-link results.
#[test]
fn fixture_model_pipeline() {
    let files = xtask::model_files().expect("fixtures/models is readable");
    assert!(files.len() >= 5, "the five analytic fixture models");
    for path in files {
        let name = path
            .file_stem()
            .expect("file name")
            .to_string_lossy()
            .to_string();
        let (_, report) = xtask::fair_file(&path).expect("fixture runs");
        insta::assert_json_snapshot!(format!("model_{name}"), xtask::pipeline_summary(&report));
    }
}

/// The committed fixture models are exactly what `cargo xtask fixtures` writes.
#[test]
fn fixture_models_are_up_to_date() {
    for (name, model) in xtask::fixtures::all().expect("constructions run") {
        let path = xtask::root().join(format!("fixtures/models/{name}.json"));
        let on_disk: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&path).expect("fixture exists"))
                .expect("fixture is JSON");
        assert_eq!(on_disk, model, "{name}: run `cargo xtask fixtures`");
    }
}
