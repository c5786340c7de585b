//! A new user's walk-through, as the README leads it: the demo, then a STEP file of their own
//! imported, checked, faired and exported, and the export read back. Each command is run as a
//! user would and its output lines are checked: what it wrote, and the verdict it ends with.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn fixture(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(path)
}

/// Runs `hier-fair` in `dir` and returns its output, which must be a success.
fn run_ok(dir: &Path, args: &[&str]) -> String {
    let o: Output = Command::new(env!("CARGO_BIN_EXE_hier-fair"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("binary runs");
    assert!(
        o.status.success(),
        "hier-fair {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8(o.stdout).expect("UTF-8 output")
}

fn last_line(text: &str) -> &str {
    text.lines().last().unwrap_or("")
}

#[test]
fn the_readme_walk_through_runs_as_written() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();

    // the main job: the bundled model faired, its files written where the README says
    let demo = run_ok(dir, &["demo", "--out", "demo", "--quiet"]);
    assert!(demo.starts_with("hier-fair demo: X-node"), "{demo}");
    assert!(
        last_line(&demo).starts_with(
            "wrote demo/faired.json, demo/faired.igs, demo/report.json, demo/report.md"
        ),
        "{demo}"
    );
    for f in [
        "faired.json",
        "faired.igs",
        "report.json",
        "report.md",
        "images",
    ] {
        assert!(dir.join("demo").join(f).exists(), "demo/{f}");
    }

    // a STEP file of one's own: imported with its hierarchy found
    let step = fixture("occt_variants/plate_boss_a.step");
    let import = run_ok(dir, &["import", step.to_str().unwrap(), "-o", "m.json"]);
    assert!(import.contains("imported 10 faces"), "{import}");
    assert!(import.contains("4 links found"), "{import}");
    assert!(last_line(&import).ends_with("wrote m.json"), "{import}");

    // checked: the input is G1 only, so no G2 link is met yet
    let check = run_ok(dir, &["check", "m.json"]);
    assert_eq!(
        last_line(&check),
        "verdict: 0 of 4 links met (G0 ≤ 0.001, G1 ≤ 0.01°, G2 ≤ 0.005 relative, each up to its target)"
    );

    // faired: every link met, every surface within its deviation, the verdict names the file
    let fair = run_ok(
        dir,
        &[
            "fair", "m.json", "-o", "f.json", "--report", "r.json", "--quiet",
        ],
    );
    let verdict = last_line(&fair);
    assert!(
        verdict.starts_with("verdict: 4 of 4 links met (G0 ≤ 0.001, G1 ≤ 0.01°, G2 ≤ 0.005 relative), 0 conflicts, 0 unmet; 10 of 10 surfaces within their deviation;"),
        "{fair}"
    );
    assert!(verdict.ends_with("wrote f.json"), "{fair}");
    assert!(dir.join("r.json").exists());
    let check = run_ok(dir, &["check", "f.json"]);
    assert!(
        last_line(&check).starts_with("verdict: 4 of 4 links met"),
        "{check}"
    );

    // exported to STEP and read back: the same faces and links
    let export = run_ok(dir, &["export", "f.json", "-o", "f.step"]);
    assert!(
        export.starts_with("exported 10 surfaces (STEP AP214"),
        "{export}"
    );
    let text = std::fs::read_to_string(dir.join("f.step")).unwrap();
    assert!(text.starts_with("ISO-10303-21;"));
    let back = run_ok(dir, &["import", "f.step", "-o", "back.json"]);
    assert!(back.contains("imported 10 faces"), "{back}");
    assert!(back.contains("4 links found"), "{back}");
    let check = run_ok(dir, &["check", "back.json"]);
    assert!(
        last_line(&check).starts_with("verdict: 4 of 4 links met"),
        "{check}"
    );
}
