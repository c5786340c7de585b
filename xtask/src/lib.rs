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
