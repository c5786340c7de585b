//! The HTML quality report (`fair --html`, `check --html`, the demo's `report.html`): its data
//! against `report.json` and `check --json`, no external request, and the page rendered in
//! headless Chromium — the 3D view drawn (not blank) and no error logged.
//!
//! The browser test needs Chromium (`chromium`, `chromium-browser` or `google-chrome` on the
//! path; `.ci/run` installs it). Where it cannot be installed, `.ci/run` sets
//! `HIER_FAIR_NO_BROWSER` to the reason and that one test says so and returns; without the
//! variable a missing browser fails the test.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{root, run_in};
use serde_json::Value;

/// The data embedded in a report page (the `hf-data` script element).
fn embedded(page: &str) -> Value {
    let start = page
        .find(r#"<script type="application/json" id="hf-data">"#)
        .expect("data element");
    let rest = &page[start..];
    let open = rest.find('>').expect("tag end") + 1;
    let close = rest.find("</script>").expect("element end");
    serde_json::from_str(&rest[open..close].replace("<\\/", "</")).expect("data parses")
}

/// The report page `fair --html` writes for the X-node, with its `report.json`.
fn faired_x_node(dir: &Path) -> (String, Value) {
    let model = root("fixtures/models/x_node.json");
    let out = run_in(
        dir,
        &[
            "fair",
            model.to_str().expect("utf-8"),
            "-o",
            "faired.json",
            "--report",
            "report.json",
            "--html",
            "report.html",
            "--quiet",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let page = std::fs::read_to_string(dir.join("report.html")).expect("page written");
    let report = std::fs::read_to_string(dir.join("report.json")).expect("report written");
    (page, serde_json::from_str(&report).expect("report parses"))
}

/// No URL a browser would load: the page is read offline.
fn assert_offline(page: &str) {
    for scheme in ["http://", "https://", "//cdn", "src=\"//"] {
        assert!(!page.contains(scheme), "the page holds {scheme}");
    }
}

#[test]
fn fair_report_page_holds_report_json_and_every_surface() {
    let dir = tempfile::tempdir().expect("temp dir");
    let (page, report) = faired_x_node(dir.path());
    assert_offline(&page);
    let data = embedded(&page);
    // the tables' values are report.json's, unchanged
    assert_eq!(data["report"], report);
    assert_eq!(data["kind"], "fair");
    let model = hier_fair::Model::from_json(
        &std::fs::read_to_string(root("fixtures/models/x_node.json")).expect("model"),
    )
    .expect("parses");
    let surfaces = data["surfaces"].as_array().expect("surfaces");
    assert_eq!(surfaces.len(), model.surfaces.len());
    for (s, m) in surfaces.iter().zip(&model.surfaces) {
        assert_eq!(s["name"], m.name.as_str());
        assert!(
            s["before"]["grid"]["points"].is_string()
                && s["after"]["grid"]["deviation"].is_string()
        );
    }
    let links = data["links"].as_array().expect("links");
    assert_eq!(
        links.len(),
        report["links"].as_array().expect("links").len()
    );
    for (l, r) in links.iter().zip(report["links"].as_array().expect("links")) {
        let label = format!(
            "{}.{} -> {}",
            r["slave"].as_str().unwrap(),
            r["side"].as_str().unwrap(),
            r["master"].as_str().unwrap()
        );
        assert_eq!(l["label"], label.as_str());
        assert!(l["comb_after"]["slave"].is_string(), "{label} has its comb");
    }
}

#[test]
fn check_report_page_holds_check_json() {
    let dir = tempfile::tempdir().expect("temp dir");
    let model = root("fixtures/occt/occt_pipe_tee.json");
    let model = model.to_str().expect("utf-8");
    let out = run_in(dir.path(), &["check", model, "--html", "check.html"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json = run_in(dir.path(), &["check", model, "--json"]);
    let checks: Value = serde_json::from_slice(&json.stdout).expect("check --json parses");
    let page = std::fs::read_to_string(dir.path().join("check.html")).expect("written");
    assert_offline(&page);
    let data = embedded(&page);
    assert_eq!(data["kind"], "check");
    assert_eq!(data["checks"]["links"], checks["links"]);
    // never the input
    let again = run_in(dir.path(), &["check", model, "--html", model]);
    assert!(!again.status.success());
}

#[test]
fn a_bare_surface_file_gets_its_page() {
    let dir = tempfile::tempdir().expect("temp dir");
    let input = root("fixtures/surfaces/hood_panel.json");
    let out = run_in(
        dir.path(),
        &[
            "fair",
            input.to_str().expect("utf-8"),
            "-o",
            "out.json",
            "--report",
            "r.json",
            "--html",
            "p.html",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let page = std::fs::read_to_string(dir.path().join("p.html")).expect("page");
    assert_offline(&page);
    let data = embedded(&page);
    let report: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("r.json")).expect("report"))
            .expect("parses");
    assert_eq!(data["report"], report);
    assert_eq!(data["surfaces"].as_array().map(Vec::len), Some(1));
    assert!(data["surfaces"][0]["after"]["grid"]["deviation"].is_string());
    // a page that is not .html is refused before anything is written
    let wrong = run_in(
        dir.path(),
        &[
            "fair",
            input.to_str().expect("utf-8"),
            "-o",
            "o2.json",
            "--html",
            "p.json",
        ],
    );
    assert!(!wrong.status.success() && !dir.path().join("o2.json").exists());
}

/// The browser on this machine, `None` where there is none.
fn chromium() -> Option<PathBuf> {
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find_map(|name| {
            std::env::var_os("PATH").and_then(|paths| {
                std::env::split_paths(&paths)
                    .map(|p| p.join(name))
                    .find(|p| p.is_file())
            })
        })
}

/// Chromium headless with software WebGL, a 1400 × 1000 window, 8 s of virtual time.
fn browser(exe: &Path, extra: &[&str], page: &str) -> std::process::Output {
    Command::new(exe)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-dev-shm-usage",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--window-size=1400,1000",
            "--virtual-time-budget=8000",
        ])
        .args(extra)
        .arg(format!("file://{page}"))
        .output()
        .expect("the browser runs")
}

/// Renders `page` (with `view`, the part after `#` that chooses a view: a picked link or
/// surface, a shading): the page's own account (drawn pixels, errors) from its DOM, and a
/// screenshot that is not blank.
fn assert_renders(exe: &Path, page: &Path, view: &str) {
    let url = format!("{}#{view}", page.display());
    let dom = browser(exe, &["--dump-dom"], &url);
    let dom = String::from_utf8_lossy(&dom.stdout);
    let body = dom
        .split("<body")
        .nth(1)
        .and_then(|b| b.split('>').next())
        .unwrap_or_default()
        .to_string();
    assert!(
        body.contains(r#"data-rendered="yes""#),
        "{}: not rendered: <body{body}>",
        page.display()
    );
    assert!(
        !body.contains("data-errors"),
        "{}: the page logged errors: {}",
        page.display(),
        dom.split("hf-errors").nth(1).unwrap_or_default()
    );
    let drawn: usize = body
        .split(r#"data-drawn-pixels=""#)
        .nth(1)
        .and_then(|s| s.split('"').next())
        .and_then(|s| s.parse().ok())
        .expect("drawn pixels");
    // the 3D view is about 960 × 640 at this window size; a model fills far more than 5 % of it
    assert!(
        drawn > 30_000,
        "{}: only {drawn} pixels drawn",
        page.display()
    );
    let shot = page.with_extension("png");
    let out = browser(exe, &[&format!("--screenshot={}", shot.display())], &url);
    assert!(
        shot.is_file(),
        "no screenshot: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let img = image::open(&shot).expect("screenshot decodes").to_rgb8();
    let mut colours = std::collections::HashSet::new();
    for p in img.pixels() {
        colours.insert(p.0);
    }
    // a blank page has a handful of colours; shading, stripes and text have thousands
    assert!(
        colours.len() > 500,
        "{}: screenshot nearly blank ({} colours)",
        page.display(),
        colours.len()
    );
}

#[test]
fn report_pages_render_in_headless_chromium() {
    let Some(exe) = chromium() else {
        if let Ok(reason) = std::env::var("HIER_FAIR_NO_BROWSER") {
            eprintln!("SKIPPED: no Chromium to render the HTML report: {reason}");
            return;
        }
        panic!(
            "no Chromium on the path (install it: apt-get install chromium), or set HIER_FAIR_NO_BROWSER to why it cannot be installed"
        );
    };
    let dir = tempfile::tempdir().expect("temp dir");
    faired_x_node(dir.path());
    assert_renders(&exe, &dir.path().join("report.html"), "");
    // a link picked, zoomed on, with knot lines, nets and an iso-line comb: select() and the
    // focus run, and the curvature map with its colour bar
    let view = "link=3&mode=mean&knots=1&net=1&iso=u";
    assert_renders(&exe, &dir.path().join("report.html"), view);
    let model = root("fixtures/occt/occt_box12_r5.json");
    let out = run_in(
        dir.path(),
        &[
            "check",
            model.to_str().expect("utf-8"),
            "--html",
            "box.html",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_renders(
        &exe,
        &dir.path().join("box.html"),
        "surface=C25_sphere&mode=gauss",
    );
}
