//! Workspace automation shared by the `xtask` binary and its tests.
//!
//! The regression pipeline runs over every `fixtures/**/*.json` surface file and produces a
//! rounded summary per surface; `tests/snapshots.rs` keeps those summaries as insta snapshots,
//! so any change of the kernel's numbers shows up as a reviewable diff.

pub mod fixtures;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use serde_json::Value;

/// Significant digits kept in snapshots: enough to catch real changes, few enough that
/// round-off differences between machines do not.
pub const SNAPSHOT_DIGITS: i32 = 8;

/// The workspace root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace")
        .to_path_buf()
}

/// All fixture surface files, sorted.
pub fn fixture_files() -> Result<Vec<PathBuf>> {
    let dir = root().join("fixtures/surfaces");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .with_context(|| format!("cannot read {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    Ok(files)
}

/// Rounds every number in a JSON value to [`SNAPSHOT_DIGITS`] significant digits.
pub fn round_json(v: &Value) -> Value {
    match v {
        Value::Number(n) => match n.as_f64() {
            Some(x) if x != 0.0 && x.is_finite() && !n.is_i64() && !n.is_u64() => {
                let digits = SNAPSHOT_DIGITS - 1 - x.abs().log10().floor() as i32;
                let scale = 10f64.powi(digits);
                let r = (x * scale).round() / scale;
                serde_json::Number::from_f64(if r == 0.0 { 0.0 } else { r })
                    .map_or(Value::Null, Value::Number)
            }
            _ => v.clone(),
        },
        Value::Array(a) => Value::Array(a.iter().map(round_json).collect()),
        Value::Object(o) => {
            Value::Object(o.iter().map(|(k, x)| (k.clone(), round_json(x))).collect())
        }
        other => other.clone(),
    }
}

/// The rounded summary of every surface of one fixture file.
pub fn fixture_summary(path: &Path) -> Result<Value> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let surfaces = nurbs_core::io::surfaces_from_json(&text)
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let list: Vec<Value> = surfaces
        .iter()
        .map(|s| serde_json::to_value(hier_fair_cli::summary::summarize(s)))
        .collect::<Result<_, _>>()?;
    Ok(round_json(&Value::Array(list)))
}

/// Significant digits of the pipeline snapshots: fairing runs thousands of floating-point
/// steps, so fewer digits than the kernel snapshots.
pub const PIPELINE_DIGITS: i32 = 4;

/// Continuity values below this are reported as 0 in snapshots (round-off, not geometry).
pub const SNAPSHOT_FLOOR: f64 = 1e-8;

fn round_to(x: f64, digits: i32) -> Value {
    if !x.is_finite() {
        return Value::Null;
    }
    if x.abs() < SNAPSHOT_FLOOR {
        return serde_json::json!(0.0);
    }
    let d = digits - 1 - x.abs().log10().floor() as i32;
    let scale = 10f64.powi(d);
    serde_json::json!((x * scale).round() / scale)
}

/// All fixture model files (`fixtures/models/*.json`), sorted.
pub fn model_files() -> Result<Vec<PathBuf>> {
    let dir = root().join("fixtures/models");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .with_context(|| format!("cannot read {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    Ok(files)
}

/// Runs the framework (default methods and parameters) on a model file.
pub fn fair_file(path: &Path) -> Result<(hier_fair::Model, hier_fair::FairModelReport)> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let model = hier_fair::Model::from_json(&text)
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let (_, report) = hier_fair::fair_model(
        &model,
        &hier_fair::RoleMethods::default(),
        None,
        &hier_fair::FairParams::default(),
    )
    .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    Ok((model, report))
}

/// The rounded summary of a run that the pipeline snapshots keep: per surface energy before
/// and after, deviation, knots inserted; per link the continuity after; the problems.
pub fn pipeline_summary(report: &hier_fair::FairModelReport) -> Value {
    let r = |x: f64| round_to(x, PIPELINE_DIGITS);
    let surfaces: Vec<Value> = report
        .surfaces
        .iter()
        .map(|s| {
            serde_json::json!({
                "name": s.name,
                "energy_before": r(s.energy_before),
                "energy_after": r(s.energy_after),
                "max_deviation": r(s.max_deviation),
                "knots_inserted": s.knots_inserted,
            })
        })
        .collect();
    let links: Vec<Value> = report
        .links
        .iter()
        .map(|l| {
            let a = l.after.as_ref();
            serde_json::json!({
                "link": l.label,
                "target": format!("{:?}", l.target),
                "met": l.met,
                "g0": a.map(|m| r(m.g0)),
                "g1_deg": a.and_then(|m| m.g1_deg).map(r),
                "g2_rel": a.and_then(|m| m.g2_rel).map(r),
            })
        })
        .collect();
    let problems: Vec<String> = report
        .problems
        .iter()
        .map(|p| {
            format!(
                "{} {} {}",
                p.kind.name(),
                p.surface,
                p.link.clone().unwrap_or_default()
            )
        })
        .collect();
    serde_json::json!({"surfaces": surfaces, "links": links, "problems": problems})
}

/// One line of the external regression table.
pub fn regress_line(name: &str, report: &hier_fair::FairModelReport) -> String {
    let worst = |f: &dyn Fn(&g_continuity::LinkMeasure) -> Option<f64>| {
        report
            .links
            .iter()
            .filter_map(|l| l.after.as_ref().and_then(f))
            .fold(0.0, f64::max)
    };
    let met = report.links.iter().filter(|l| l.met).count();
    let dev = report
        .surfaces
        .iter()
        .map(|s| s.max_deviation)
        .fold(0.0, f64::max);
    let (eb, ea) = report.surfaces.iter().fold((0.0, 0.0), |(a, b), s| {
        (a + s.energy_before, b + s.energy_after)
    });
    // shared edges no link covers (hier_fair::edges) that leave worse, of all of them
    let edges_worse = report.edges.iter().filter(|e| e.worse).count();
    // the largest normal jump across a C0 knot line inside a surface of the result
    // (nurbs_core::creases): a kernel's arcs joined by double knots stay as smooth as they came
    let crease = report
        .surfaces
        .iter()
        .map(|s| s.crease_deg.1)
        .fold(0.0, f64::max);
    format!(
        "{:<28} {:>4} {:>4}/{:<4} {:>10.3e} {:>10.3e} {:>10.3e} {:>10.3e} {:>+8.1}% {:>8.3} {:>4} {:>5}/{:<5} {:>9.2e}",
        name,
        report.surfaces.len(),
        met,
        report.links.len(),
        worst(&|m| Some(m.g0)),
        worst(&|m| m.g1_deg),
        worst(&|m| m.g2_rel),
        dev,
        if eb > 0.0 {
            100.0 * (ea / eb - 1.0)
        } else {
            0.0
        },
        report.seconds_total,
        report.problems.len(),
        edges_worse,
        report.edges.len(),
        crease
    )
}

/// Header of [`regress_line`].
pub const REGRESS_HEADER: &str = "model                        surf  met/links        gap     angle°   curv.rel  deviation   energy  seconds probl edges worse/all  crease°";

/// The models made by Open CASCADE for this project, in the order of `fixtures/occt/index.json`
/// (see the directory's README): the one list the tests and the regression run share.
pub fn occt_models() -> Result<Vec<String>> {
    let path = root().join("fixtures/occt/index.json");
    let text = std::fs::read_to_string(&path).with_context(|| path.display().to_string())?;
    let index: Vec<serde_json::Value> =
        serde_json::from_str(&text).with_context(|| path.display().to_string())?;
    index
        .iter()
        .map(|m| {
            m["name"]
                .as_str()
                .map(str::to_string)
                .with_context(|| format!("{}: a model without a name", path.display()))
        })
        .collect()
}

/// The fixture models, the third-party models of `external` (car_shell1.model.json,
/// submarine_body.model.json, teapot.json; each skipped with a note when absent) and the six
/// kernel models of `fixtures/occt/`.
pub fn regress_paths(external: &Path) -> Result<(Vec<PathBuf>, Vec<String>)> {
    let mut paths = model_files()?;
    let mut notes = Vec::new();
    for name in [
        "car_shell1.model.json",
        "submarine_body.model.json",
        "teapot.json",
    ] {
        let p = external.join(name);
        if p.exists() {
            paths.push(p);
        } else {
            notes.push(format!("{} not found: skipped", p.display()));
        }
    }
    // the kernel models are the project's own and live in the repository: never skipped
    for name in occt_models()? {
        paths.push(root().join("fixtures/occt").join(format!("{name}.json")));
    }
    Ok((paths, notes))
}

/// The file name of `path` (empty where it has none), for a table's first column.
fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default()
}

/// The STEP and IGES files of the folders `dirs` (by extension, in name order within each).
pub fn cad_files(dirs: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for dir in dirs {
        let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
            .with_context(|| format!("cannot read {}", dir.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| hier_fair::exchange::CadFormat::of_extension(p).is_some())
            .collect();
        files.sort();
        out.extend(files);
    }
    Ok(out)
}

/// Header of [`foreign_line`].
pub const FOREIGN_HEADER: &str = "file                             faces  met/links  conflicts unmet  worse/edges  within  seconds";

/// One line of the foreign-file table: what `fair FILE` (the default tolerances, by content)
/// gives — links met, named conflicts, unmet links, shared edges left worse than they came,
/// surfaces within their deviation, the run's seconds.
pub fn foreign_line(name: &str, report: &hier_fair::FairModelReport) -> String {
    let met = report.links.iter().filter(|l| l.met).count();
    let conflicts = report
        .problems
        .iter()
        .filter(|p| p.kind == hier_fair::ProblemKind::Conflict)
        .filter_map(|p| p.link.as_deref())
        .collect::<std::collections::BTreeSet<_>>()
        .len();
    let within = report
        .surfaces
        .iter()
        .filter(|s| s.max_deviation <= s.tolerance)
        .count();
    format!(
        "{:<32} {:>5} {:>4}/{:<5} {:>9} {:>5} {:>5}/{:<6} {:>4}/{:<3} {:>7.2}",
        name,
        report.surfaces.len(),
        met,
        report.links.len(),
        conflicts,
        report.links.len() - met,
        report.edges.iter().filter(|e| e.worse).count(),
        report.edges.len(),
        within,
        report.surfaces.len(),
        report.seconds_total
    )
}

/// Imports every STEP and IGES file of `dirs` (hier-fair's exchange, the format by content) and
/// fairs it with the defaults, without the verification re-run; returns one table (a line per
/// file, a last line of totals) and whether every file could be read and run. A file that does
/// not import is a line naming why.
pub fn foreign_table(dirs: &[PathBuf]) -> Result<(String, bool)> {
    let mut out = format!("{FOREIGN_HEADER}\n");
    let (mut ok, mut met, mut links, mut worse, mut seconds) = (true, 0, 0, 0, 0.0);
    for path in cad_files(dirs)? {
        let name = file_name(&path);
        let run = std::fs::read(&path)
            .with_context(|| format!("cannot read {}", path.display()))
            .and_then(|bytes| Ok(hier_fair::exchange::read_cad(&bytes)?.model))
            .and_then(|model| {
                let params = hier_fair::FairParams {
                    verify_unmet: false,
                    ..hier_fair::FairParams::default()
                };
                Ok(hier_fair::fair_model(
                    &model,
                    &hier_fair::RoleMethods::default(),
                    None,
                    &params,
                )?
                .1)
            });
        match run {
            Ok(report) => {
                met += report.links.iter().filter(|l| l.met).count();
                links += report.links.len();
                worse += report.edges.iter().filter(|e| e.worse).count();
                seconds += report.seconds_total;
                out.push_str(&foreign_line(&name, &report));
                out.push('\n');
            }
            Err(e) => {
                ok = false;
                out.push_str(&format!("{name:<32} error: {e:#}\n"));
            }
        }
    }
    out.push_str(&format!(
        "all: {met} of {links} links met, {worse} shared edges worse than they came, {seconds:.1} s\n"
    ));
    Ok((out, ok))
}

/// Runs the framework on every regression model and returns one table (a line per model, its
/// problems indented below) and whether every model could be run.
pub fn regress_table(external: &Path) -> Result<(String, bool)> {
    let (paths, notes) = regress_paths(external)?;
    let mut out = String::new();
    for n in notes {
        out.push_str(&n);
        out.push('\n');
    }
    out.push_str(REGRESS_HEADER);
    out.push('\n');
    let mut ok = true;
    for path in paths {
        let name = file_name(&path);
        match fair_file(&path) {
            Ok((_, report)) => {
                out.push_str(&regress_line(&name, &report));
                out.push('\n');
                for p in &report.problems {
                    out.push_str(&format!(
                        "    {} {}: {}\n",
                        p.kind.name(),
                        p.surface,
                        p.message
                    ));
                }
            }
            Err(e) => {
                ok = false;
                out.push_str(&format!("{name:<28} error: {e:#}\n"));
            }
        }
    }
    Ok((out, ok))
}
