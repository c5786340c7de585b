//! Helpers shared by the command-line tests: a repository path, and the binary run in a folder.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `path` under the repository root.
pub fn root(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

/// `hier-fair ARGS` run in `dir`.
pub fn run_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hier-fair"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("binary runs")
}
