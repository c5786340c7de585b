//! The layering of docs/ARCHITECTURE.md, checked on `cargo metadata`.

use std::collections::BTreeMap;

/// Workspace crates each crate may depend on (normal and build dependencies; dev-dependencies
/// too, except on itself for features). Unknown crates must be added here deliberately.
fn allowed() -> BTreeMap<&'static str, &'static [&'static str]> {
    let methods: &[&str] = &["nurbs-core"];
    let mut m: BTreeMap<&str, &[&str]> = BTreeMap::new();
    m.insert("nurbs-core", &[]);
    for c in [
        "g-continuity",
        "fair-energy",
        "fair-krr",
        "fair-curvature",
        "nside-discrete",
        "trim-label",
        "nurbs-io",
    ] {
        m.insert(c, methods);
    }
    m.insert(
        "hier-fair",
        &[
            "nurbs-core",
            "g-continuity",
            "fair-energy",
            "fair-krr",
            "fair-curvature",
            "nside-discrete",
            "trim-label",
            "nurbs-io",
        ],
    );
    m.insert(
        "hier-fair-cli",
        &[
            "nurbs-core",
            "g-continuity",
            "fair-energy",
            "fair-krr",
            "fair-curvature",
            "nside-discrete",
            "trim-label",
            "nurbs-io",
            "hier-fair",
        ],
    );
    m.insert(
        "hier-fair-py",
        &["nurbs-core", "g-continuity", "nurbs-io", "hier-fair"],
    );
    m.insert(
        "xtask",
        &[
            "nurbs-core",
            "g-continuity",
            "fair-energy",
            "fair-krr",
            "fair-curvature",
            "nside-discrete",
            "trim-label",
            "nurbs-io",
            "hier-fair",
            "hier-fair-cli",
        ],
    );
    m
}

#[test]
fn crates_depend_only_downward() {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = std::process::Command::new(cargo)
        .args([
            "metadata",
            "--format-version",
            "1",
            "--no-deps",
            "--offline",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cargo metadata runs");
    assert!(
        out.status.success(),
        "cargo metadata failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let meta: serde_json::Value = serde_json::from_slice(&out.stdout).expect("metadata is JSON");
    let packages = meta["packages"].as_array().expect("packages");
    let names: Vec<&str> = packages.iter().filter_map(|p| p["name"].as_str()).collect();
    let rules = allowed();
    let mut violations = Vec::new();
    for p in packages {
        let name = p["name"].as_str().expect("name");
        let Some(ok) = rules.get(name) else {
            violations.push(format!(
                "{name}: not in the layering table (add it to docs/ARCHITECTURE.md and this test)"
            ));
            continue;
        };
        for d in p["dependencies"].as_array().expect("dependencies") {
            let dep = d["name"].as_str().expect("dependency name");
            if dep == name || !names.contains(&dep) {
                continue;
            }
            if !ok.contains(&dep) {
                violations.push(format!("{name} depends on {dep}"));
            }
        }
    }
    assert!(
        violations.is_empty(),
        "layering violations:\n{}",
        violations.join("\n")
    );
}

#[test]
fn library_crates_do_not_use_anyhow_or_paths() {
    // the command line and xtask alone deal with files and anyhow (house style)
    let root = xtask::root();
    for krate in std::fs::read_dir(root.join("crates")).expect("crates dir") {
        let dir = krate.expect("entry").path();
        let name = dir.file_name().expect("name").to_string_lossy().to_string();
        if name == "hier-fair-cli" {
            continue;
        }
        let manifest = std::fs::read_to_string(dir.join("Cargo.toml")).unwrap_or_default();
        let deps = manifest
            .split("[dev-dependencies]")
            .next()
            .unwrap_or_default();
        assert!(!deps.contains("anyhow"), "{name} must not depend on anyhow");
    }
}
