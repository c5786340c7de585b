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

/// The folder a file path lives in (`.` for a bare name).
fn folder_of(path: &Path) -> &Path {
    path.parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// The path as it will be written: its folder canonicalized (the file need not exist yet), so
/// `./r.json`, `r.json` and a symlinked folder compare equal.
fn resolved(path: &Path) -> Option<PathBuf> {
    let name = path.file_name()?;
    Some(std::fs::canonicalize(folder_of(path)).ok()?.join(name))
}

/// Validates every output before any work starts: none is an input, no two are the same
/// file, and each one's folder exists and takes a new file (probed by creating and removing a
/// temporary file there). `outputs` pairs each path with the option that names it, for the
/// message.
pub fn check_outputs(outputs: &[(&str, &Path)], inputs: &[&Path]) -> Result<()> {
    for (k, &(flag, path)) in outputs.iter().enumerate() {
        refuse_overwrite(path, inputs)?;
        let Some(name) = path.file_name() else {
            bail!("{flag} {}: not a file path", path.display());
        };
        let folder = folder_of(path);
        if !folder.is_dir() {
            bail!(
                "cannot write {flag} {}: the folder {} does not exist",
                path.display(),
                folder.display()
            );
        }
        if path.is_dir() {
            bail!("cannot write {flag} {}: it is a folder", path.display());
        }
        let here = resolved(path);
        for &(other_flag, other) in &outputs[..k] {
            if here.is_some() && resolved(other) == here {
                bail!(
                    "{other_flag} and {flag} name the same file {}: give each output its own path",
                    path.display()
                );
            }
        }
        let probe = folder.join(format!(
            ".{}.probe{}",
            name.to_string_lossy(),
            std::process::id()
        ));
        match std::fs::File::create(&probe) {
            Ok(_) => {
                let _ = std::fs::remove_file(&probe);
            }
            Err(e) => bail!("cannot write {flag} {}: {e}", path.display()),
        }
    }
    Ok(())
}

/// Validates an output folder before any work starts: an existing folder, or a new one whose
/// parent exists; never an input.
pub fn check_output_folder(flag: &str, folder: &Path, inputs: &[&Path]) -> Result<()> {
    refuse_overwrite(folder, inputs)?;
    if folder.exists() && !folder.is_dir() {
        bail!(
            "cannot write {flag} {}: it is a file, not a folder",
            folder.display()
        );
    }
    if !folder.exists() && !folder_of(folder).is_dir() {
        bail!(
            "cannot write {flag} {}: the folder {} does not exist",
            folder.display(),
            folder_of(folder).display()
        );
    }
    Ok(())
}

/// Writes `bytes` to `path` atomically: a temporary file beside it, flushed and renamed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = folder_of(path);
    let name = path
        .file_name()
        .with_context(|| format!("{} is not a file path", path.display()))?;
    let tmp = dir.join(format!(
        ".{}.tmp{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    // errors name the user's path, never the temporary file
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })()
    .with_context(|| format!("cannot write {}", path.display()));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
