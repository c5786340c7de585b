//! House rules checked on the sources (as rust-analyzer's tidy test does):
//! - every Rust file opens with `//!` module docs;
//! - no comment points outside the repository (a reader of a crate cannot open a tracker entry
//!   or the specification folder; comments cite `docs/references.md` keys instead);
//! - every top-level constant or static in a crate's `src` has a doc line (where its value
//!   comes from);
//! - no file of a crate's `src` over [`MAX_FILE_LINES`] lines and no function outside tests
//!   over [`MAX_FN_LINES`] lines, except those listed in `tidy_allowed.txt`: the list only
//!   shrinks — a listed item that is back within the bound must leave it;
//! - no fixture's name in a comment of a crate's `src` (figures measured on a fixture go stale
//!   there; they belong in docs/benchmarks.md, and a comment names the kind of model);
//! - no import circle between the top-level modules of any crate (`crate::m` and `super::m`
//!   paths in code outside tests): a module reads only modules below it, so a newcomer can
//!   read the house bottom-up.

use std::collections::{BTreeMap, BTreeSet};
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

/// The identifiers that follow `prefix` in `code` (lower case: modules, not re-exported types).
fn paths_after<'a>(code: &'a str, prefix: &str) -> impl Iterator<Item = &'a str> {
    code.match_indices(prefix).filter_map(move |(i, _)| {
        let before = code[..i].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            return None;
        }
        let rest = &code[i + prefix.len()..];
        let end = rest
            .find(|c: char| !(c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_'))
            .unwrap_or(rest.len());
        (end > 0).then(|| &rest[..end])
    })
}

/// The top-level module of a file under a crate's `src` (`""` for the crate root), and the
/// modules its code outside tests and comments names: `crate::m`, and `super::m` from a
/// top-level file (`super::super::m` from one folder down).
fn module_imports(rel_in_src: &str, text: &str) -> (String, BTreeSet<String>) {
    let mut parts: Vec<&str> = rel_in_src.trim_end_matches(".rs").split('/').collect();
    if parts
        .last()
        .is_some_and(|p| matches!(*p, "mod" | "lib" | "main"))
    {
        parts.pop();
    }
    let code: String = text
        .split("#[cfg(test)]")
        .next()
        .unwrap_or("")
        .lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n");
    let mut deps: BTreeSet<String> = paths_after(&code, "crate::").map(str::to_string).collect();
    let up = match parts.len() {
        1 => Some("super::"),
        2 => Some("super::super::"),
        _ => None,
    };
    if let Some(up) = up {
        deps.extend(paths_after(&code, up).map(str::to_string));
    }
    let top = parts.first().copied().unwrap_or("").to_string();
    deps.remove(&top);
    (top, deps)
}

/// A circle in `graph` as the path of modules around it, if there is one.
fn find_circle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        path: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(node.to_string(), 1);
        path.push(node.to_string());
        for next in graph.get(node).into_iter().flatten() {
            match state.get(next.as_str()).copied().unwrap_or(0) {
                0 if graph.contains_key(next) => {
                    if let Some(c) = visit(next, graph, state, path) {
                        return Some(c);
                    }
                }
                1 => {
                    let from = path.iter().position(|p| p == next).unwrap_or(0);
                    let mut circle = path[from..].to_vec();
                    circle.push(next.clone());
                    return Some(circle);
                }
                _ => {}
            }
        }
        path.pop();
        state.insert(node.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for node in graph.keys() {
        if state.get(node).copied().unwrap_or(0) == 0
            && let Some(c) = visit(node, graph, &mut state, &mut Vec::new())
        {
            return Some(c);
        }
    }
    None
}

/// The import graph of every crate's top-level modules, by crate `src` folder.
fn import_graphs() -> BTreeMap<String, BTreeMap<String, BTreeSet<String>>> {
    let mut graphs: BTreeMap<String, BTreeMap<String, BTreeSet<String>>> = BTreeMap::new();
    for (path, text) in sources() {
        let Some((krate, rel)) = path.split_once("/src/") else {
            continue;
        };
        let (top, deps) = module_imports(rel, &text);
        if top.is_empty() {
            continue;
        }
        graphs
            .entry(krate.to_string())
            .or_default()
            .entry(top)
            .or_default()
            .extend(deps);
    }
    graphs
}

#[test]
fn no_import_circle_between_modules() {
    let graphs = import_graphs();
    assert!(graphs.len() >= 10, "crates found: {:?}", graphs.keys());
    for (krate, graph) in &graphs {
        if let Some(circle) = find_circle(graph) {
            panic!("{krate}/src: import circle {}", circle.join(" -> "));
        }
    }
}

#[test]
fn the_circle_scan_sees_crate_and_super_paths() {
    let (top, deps) = module_imports(
        "framework/job.rs",
        "//! docs name crate::zones\nuse crate::edges::X;\nuse super::super::check::Y;\n\
         let n = subcrate::other;\n#[cfg(test)]\nuse crate::build;",
    );
    assert_eq!(top, "framework");
    assert_eq!(
        deps.into_iter().collect::<Vec<_>>(),
        vec!["check".to_string(), "edges".to_string()]
    );
    let graph: BTreeMap<String, BTreeSet<String>> = [
        ("a", vec!["b"]),
        ("b", vec!["c"]),
        ("c", vec!["a"]),
        ("d", vec![]),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v.into_iter().map(str::to_string).collect()))
    .collect();
    assert_eq!(
        find_circle(&graph),
        Some(
            vec!["a", "b", "c", "a"]
                .into_iter()
                .map(str::to_string)
                .collect()
        )
    );
    let mut acyclic = graph;
    acyclic.get_mut("c").unwrap().clear();
    assert_eq!(find_circle(&acyclic), None);
}

/// The names only the fixture folder defines: the stems of its model, surface and CAD files
/// (without the `occt_` prefix) that hold an underscore or a digit — common words such as a
/// teapot are no fixture's name in a comment.
fn fixture_names() -> BTreeSet<String> {
    fn walk(dir: &Path, out: &mut BTreeSet<String>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.filter_map(|e| e.ok()) {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
                continue;
            }
            let name = p.file_name().unwrap_or_default().to_string_lossy();
            let Some((stem, ext)) = name.split_once('.') else {
                continue;
            };
            let ext = ext.rsplit('.').next().unwrap_or("").to_ascii_lowercase();
            if !matches!(
                ext.as_str(),
                "json" | "step" | "stp" | "igs" | "iges" | "obj"
            ) {
                continue;
            }
            let stem = stem
                .strip_prefix("occt_")
                .unwrap_or(stem)
                .to_ascii_lowercase();
            if stem.contains('_') || stem.chars().any(|c| c.is_ascii_digit()) {
                out.insert(stem);
            }
        }
    }
    let mut out = BTreeSet::new();
    walk(&root().join("fixtures"), &mut out);
    out
}

/// Whether `name` occurs in `line` as a whole word (not inside a longer identifier).
fn names_word(line: &str, name: &str) -> bool {
    let word = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_');
    line.match_indices(name).any(|(i, _)| {
        !word(line[..i].chars().next_back()) && !word(line[i + name.len()..].chars().next())
    })
}

#[test]
fn no_fixture_name_in_a_source_comment() {
    let names = fixture_names();
    assert!(names.contains("box12_r5"), "fixture names: {names:?}");
    let mut found = Vec::new();
    // xtask's own sources are the fixtures' tooling and name them by design
    let crates = sources()
        .into_iter()
        .filter(|(p, _)| is_src(p) && p.starts_with("crates/"));
    for (path, text) in crates {
        let mut in_code = false;
        for (n, line) in text.lines().enumerate() {
            let t = line.trim_start();
            if !t.starts_with("//") {
                continue;
            }
            let body = t
                .trim_start_matches('/')
                .trim_start_matches('!')
                .trim_start();
            if body.starts_with("```") {
                in_code = !in_code;
                continue;
            }
            // a doc example names the file it loads, as a reader runs it
            if in_code || body.starts_with(">>>") {
                continue;
            }
            let lower = line.to_ascii_lowercase();
            for name in names.iter().filter(|name| names_word(&lower, name)) {
                found.push(format!("{path}:{}: {name}", n + 1));
            }
        }
    }
    assert!(
        found.is_empty(),
        "fixture names in comments:\n{}",
        found.join("\n")
    );
}
