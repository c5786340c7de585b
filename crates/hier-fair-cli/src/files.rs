//! File handling of the command line: reading inputs with errors that name the path, and atomic
//! writes (temporary file in the same folder + rename) that never overwrite an input.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

/// Reads a text file, naming the path on failure.
pub fn read_text(path: &Path) -> Result<String> {
    std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))
}

/// Parses a surface file, naming the path on failure.
pub fn read_surfaces(path: &Path) -> Result<Vec<nurbs_core::BSplineSurface>> {
    let text = read_text(path)?;
    nurbs_core::io::surfaces_from_json(&text)
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}

/// Fails when `output` is the same file as one of `inputs`.
pub fn refuse_overwrite(output: &Path, inputs: &[&Path]) -> Result<()> {
    let canon = |p: &Path| -> Option<PathBuf> { std::fs::canonicalize(p).ok() };
    if let Some(out) = canon(output) {
        for input in inputs {
            if canon(input).as_deref() == Some(out.as_path()) {
                bail!("refusing to overwrite the input {}", input.display());
            }
        }
    }
    Ok(())
}

/// Writes `bytes` to `path` atomically: a temporary file beside it, flushed and renamed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .with_context(|| format!("{} is not a file path", path.display()))?;
    let tmp = dir.join(format!(
        ".{}.tmp{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| -> Result<()> {
        let mut f = std::fs::File::create(&tmp)
            .with_context(|| format!("cannot create {}", tmp.display()))?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path).with_context(|| format!("cannot write {}", path.display()))?;
        Ok(())
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
