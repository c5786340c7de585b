//! What the tests of the kernel models share: the list of `fixtures/occt/index.json` and the
//! loader.

use hier_fair::Model;

/// The kernel models, as the directory's `index.json` lists them (one list for every test and
/// `cargo xtask regress`).
pub fn models() -> Vec<String> {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/occt/index.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let index: Vec<serde_json::Value> = serde_json::from_str(&text).unwrap();
    let names: Vec<String> = index
        .iter()
        .map(|m| m["name"].as_str().expect("a name per model").to_string())
        .collect();
    assert!(names.len() >= 6, "{names:?}");
    names
}

pub fn model(name: &str) -> Option<Model> {
    // the models are part of the repository: a missing one is a failure, never a skip
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/occt")
        .join(format!("{name}.json"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    Some(Model::from_json(&text).unwrap())
}
