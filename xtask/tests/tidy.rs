//! House rules checked on the sources (as rust-analyzer's tidy test does):
//! - every Rust file opens with `//!` module docs;
//! - no comment points outside the repository (a reader of a crate cannot open a tracker entry
//!   or the specification folder; comments cite `docs/references.md` keys instead);
//! - every top-level constant or static in a crate's `src` has a doc line (where its value
//!   comes from);
//! - no file of a crate's `src` over [`MAX_FILE_LINES`] lines and no function outside tests
//!   over [`MAX_FN_LINES`] lines, except those listed in `tidy_allowed.txt`: the list only
//!   shrinks — a listed item that is back within the bound must leave it.

use std::path::{Path, PathBuf};

/// Longest source file, in lines.
const MAX_FILE_LINES: usize = 700;

/// Longest function outside tests, in lines (signature and closing brace included): one
/// screen, readable in one sitting.
const MAX_FN_LINES: usize = 80;

/// Phrases that point outside the repository, lower case.
const OUTSIDE: [&str; 5] = [
    "the issue",
    "issue #",
    "the seed",
    "seeds/",
    "developers.md",
];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            if p.file_name().is_some_and(|n| n == "target" || n == "fuzz") {
                continue;
            }
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The workspace's Rust files, relative to the root.
fn sources() -> Vec<(String, String)> {
    let root = root();
    let mut files = Vec::new();
    rust_files(&root.join("crates"), &mut files);
    rust_files(&root.join("xtask"), &mut files);
    files
        .into_iter()
        .map(|p| {
            let rel = p
                .strip_prefix(&root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            (rel, std::fs::read_to_string(&p).unwrap())
        })
        .collect()
}

/// Whether `path` is library or binary source (not a test, bench or example).
fn is_src(path: &str) -> bool {
    path.split('/').any(|c| c == "src")
}

#[test]
fn every_file_opens_with_module_docs() {
    let missing: Vec<String> = sources()
        .into_iter()
        .filter(|(_, text)| {
            !text
                .lines()
                .find(|l| !l.trim().is_empty())
                .is_some_and(|l| l.starts_with("//!"))
        })
        .map(|(p, _)| p)
        .collect();
    assert!(missing.is_empty(), "no `//!` docs: {missing:#?}");
}

#[test]
fn no_comment_points_outside_the_repository() {
    let mut found = Vec::new();
    for (path, text) in sources() {
        if path == "xtask/tests/tidy.rs" {
            continue;
        }
        for (k, line) in text.lines().enumerate() {
            let Some(at) = line.find("//") else {
                continue;
            };
            let comment = line[at..].to_lowercase();
            if OUTSIDE.iter().any(|w| comment.contains(w)) {
                found.push(format!("{path}:{}: {}", k + 1, line.trim()));
            }
        }
    }
    assert!(found.is_empty(), "comments pointing outside: {found:#?}");
}

#[test]
fn every_top_level_constant_is_documented() {
    let mut found = Vec::new();
    for (path, text) in sources().into_iter().filter(|(p, _)| is_src(p)) {
        let lines: Vec<&str> = text.lines().collect();
        for (k, line) in lines.iter().enumerate() {
            let decl = line
                .strip_prefix("pub(crate) ")
                .or_else(|| line.strip_prefix("pub "))
                .unwrap_or(line);
            if !(decl.starts_with("const ") || decl.starts_with("static ")) {
                continue;
            }
            let doc = lines[..k]
                .iter()
                .rev()
                .find(|l| !l.starts_with("#["))
                .is_some_and(|l| l.starts_with("///"));
            if !doc {
                found.push(format!("{path}:{}: {line}", k + 1));
            }
        }
    }
    assert!(found.is_empty(), "constants without a doc line: {found:#?}");
}

/// The functions of `text` outside its test module, as (name, first line, length).
fn functions(text: &str) -> Vec<(String, usize, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let end = lines
        .iter()
        .position(|l| *l == "#[cfg(test)]")
        .unwrap_or(lines.len());
    let mut out = Vec::new();
    for k in 0..end {
        let line = lines[k];
        let indent = line.len() - line.trim_start().len();
        let mut rest = line.trim_start();
        for prefix in [
            "pub(crate) ",
            "pub(super) ",
            "pub ",
            "const ",
            "async ",
            "unsafe ",
        ] {
            rest = rest.strip_prefix(prefix).unwrap_or(rest);
        }
        let Some(sig) = rest.strip_prefix("fn ") else {
            continue;
        };
        if line.trim_end().ends_with(';') {
            continue;
        }
        let name: String = sig
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let close = format!("{}}}", " ".repeat(indent));
        if let Some(j) = (k..end).find(|&j| lines[j] == close) {
            out.push((name, k + 1, j - k + 1));
        }
    }
    out
}

#[test]
fn files_and_functions_stay_short() {
    let allowed_text =
        std::fs::read_to_string(root().join("xtask/tests/tidy_allowed.txt")).unwrap();
    let allowed: Vec<&str> = allowed_text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .collect();
    let mut long = Vec::new();
    for (path, text) in sources().into_iter().filter(|(p, _)| is_src(p)) {
        let n = text.lines().count();
        if n > MAX_FILE_LINES {
            long.push(path.clone());
        }
        for (name, _, len) in functions(&text) {
            if len > MAX_FN_LINES {
                long.push(format!("{path}::{name}"));
            }
        }
    }
    let new: Vec<&String> = long
        .iter()
        .filter(|l| !allowed.contains(&l.as_str()))
        .collect();
    let fixed: Vec<&&str> = allowed
        .iter()
        .filter(|a| !long.iter().any(|l| l == *a))
        .collect();
    assert!(
        new.is_empty(),
        "over {MAX_FILE_LINES} lines (file) or {MAX_FN_LINES} (function): {new:#?}"
    );
    assert!(
        fixed.is_empty(),
        "within the bounds now, remove from xtask/tests/tidy_allowed.txt: {fixed:#?}"
    );
}
