//! Input files known by their content, not their name: a STEP file renamed `.txt` is still
//! read as STEP, and a command given the wrong kind of file says what it got and what to do
//! (cli-contract.md, "Files").

use std::io::Read;
use std::path::Path;

use anyhow::{Result, bail};

/// Bytes read to tell a file's kind: the STEP header's first keyword, an IGES record (80
/// columns) and the first keys of a JSON object all lie well within them.
pub const SNIFF_BYTES: usize = 64 * 1024;

/// What an input file holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileKind {
    /// ISO 10303-21 (`ISO-10303-21;` first)
    Step,
    /// IGES 5.3: fixed 80-column records, the section letter (S, G) in column 73
    Iges,
    /// a model JSON (`surfaces` entries with a `surface`, or `links`)
    Model,
    /// a surface file: one surface, a list, `{"surfaces": [...]}` or `{"patches": [...]}`
    Surfaces,
    /// a report JSON of `fair` or `connect` (`seconds_total` or `stages`)
    Report,
    /// a Wavefront OBJ mesh (`v`, `f` records)
    Obj,
    /// the parameters `eval --params` takes: `{"params": [[u, v], ...]}`
    Params,
    /// a JSON list of vertex indices (`fair-mesh --fixed`): `[i, ...]`
    Indices,
    /// boundary segments (`label --segments`): `[[i, ...], ...]`, `{"segments": [...]}` or
    /// `label`'s own output
    Segments,
    /// anything else
    Unknown,
}

impl FileKind {
    /// The kind in words, for messages.
    pub fn name(self) -> &'static str {
        match self {
            FileKind::Step => "a STEP file",
            FileKind::Iges => "an IGES file",
            FileKind::Model => "a model JSON",
            FileKind::Surfaces => "a surface file (JSON)",
            FileKind::Report => "a report JSON",
            FileKind::Obj => "an OBJ mesh",
            FileKind::Params => "a params JSON ({\"params\": [[u, v], …]})",
            FileKind::Indices => "an index JSON (a list of vertex indices, [i, …])",
            FileKind::Segments => "a segments JSON (lists of boundary vertex indices, [[i, …], …])",
            FileKind::Unknown => "no file kind hier-fair reads",
        }
    }

    /// What to do with this kind instead, for a command that does not take it.
    fn hint(self) -> &'static str {
        match self {
            FileKind::Step | FileKind::Iges => {
                "`import` turns it into a model (`fair` reads it directly)"
            }
            FileKind::Model => "`check`, `connect`, `fair` and `export` take models",
            FileKind::Surfaces => {
                "`fair` fairs it, `eval` evaluates it, `build` finds a model's links in it"
            }
            FileKind::Report => "reports are written by `fair` and `connect`, not read",
            FileKind::Obj => "`fair-mesh` and `label` take meshes",
            FileKind::Params => "`eval --params` takes it",
            FileKind::Indices => "`fair-mesh --fixed` takes it",
            FileKind::Segments => "`label --segments` takes it",
            FileKind::Unknown => {
                "hier-fair reads STEP, IGES, model and surface JSON, and OBJ meshes"
            }
        }
    }
}

/// The kind of the file at `path`, from its first [`SNIFF_BYTES`] bytes.
pub fn sniff(path: &Path) -> Result<FileKind> {
    let mut file = std::fs::File::open(path)
        .map_err(|e| anyhow::anyhow!("cannot read {}: {e}", path.display()))?;
    let mut head = Vec::with_capacity(SNIFF_BYTES);
    file.by_ref()
        .take(SNIFF_BYTES as u64)
        .read_to_end(&mut head)
        .map_err(|e| anyhow::anyhow!("cannot read {}: {e}", path.display()))?;
    Ok(classify(&String::from_utf8_lossy(&head)))
}

/// The kind of a file that starts with `head`.
pub fn classify(head: &str) -> FileKind {
    // STEP and IGES by the library's rule ([`hier_fair::exchange::CadFormat::of_content`])
    match hier_fair::exchange::CadFormat::of_content(head.as_bytes()) {
        Some(hier_fair::exchange::CadFormat::Step) => return FileKind::Step,
        Some(hier_fair::exchange::CadFormat::Iges) => return FileKind::Iges,
        None => {}
    }
    let text = head.trim_start_matches('\u{feff}').trim_start();
    if text.starts_with('{') || text.starts_with('[') {
        return json_kind(text);
    }
    let mesh = text
        .lines()
        .map(str::trim_start)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .take(8)
        .all(|l| {
            [
                "v ", "vn ", "vt ", "f ", "o ", "g ", "s ", "l ", "mtllib ", "usemtl ",
            ]
            .iter()
            .any(|k| l.starts_with(k))
        });
    if mesh && !text.is_empty() {
        return FileKind::Obj;
    }
    FileKind::Unknown
}

/// The kind of a JSON text from the keys it starts with (a prefix: the text may be cut).
fn json_kind(text: &str) -> FileKind {
    let has = |key: &str| text.contains(&format!("\"{key}\""));
    if has("seconds_total") || has("stages") || has("energy_before") {
        FileKind::Report
    } else if has("links") || has("role") || has("surface") {
        FileKind::Model
    } else if has("degree_u") || has("patches") {
        FileKind::Surfaces
    } else if has("params") {
        FileKind::Params
    } else if has("segments") || has("vertices") {
        FileKind::Segments
    } else {
        list_kind(text)
    }
}

/// The kind of a JSON list of numbers (`[i, ...]`: indices) or of lists of numbers (`[[i, ...],
/// ...]`: segments); anything else (an empty list, a list of strings) names no kind.
fn list_kind(text: &str) -> FileKind {
    let number = |t: &str| t.starts_with(|c: char| c.is_ascii_digit() || c == '-');
    let Some(inner) = text.strip_prefix('[').map(str::trim_start) else {
        return FileKind::Unknown;
    };
    match inner.strip_prefix('[').map(str::trim_start) {
        Some(first) if number(first) => FileKind::Segments,
        None if number(inner) => FileKind::Indices,
        _ => FileKind::Unknown,
    }
}

/// Refuses `path` unless its kind is one of `takes`, saying what it is and what to do:
/// "`check` takes a model JSON; X is a STEP file: `import` turns it into a model (…)". A file
/// whose content names no kind (empty, truncated, malformed) is taken as its extension says
/// where that is a kind the command takes, so that its reader names the fault (the line, the
/// field) instead of this module guessing.
pub fn expect(command: &str, path: &Path, takes: &[FileKind]) -> Result<FileKind> {
    let kind = match sniff(path)? {
        FileKind::Unknown => by_extension(path, takes).unwrap_or(FileKind::Unknown),
        k => k,
    };
    if takes.contains(&kind) {
        return Ok(kind);
    }
    let wanted: Vec<&str> = takes.iter().map(|k| k.name()).collect();
    bail!(
        "`{command}` takes {}; {} is {}: {}",
        wanted.join(" or "),
        path.display(),
        kind.name(),
        kind.hint()
    )
}

/// Refuses the file an option names (`eval --params`, `fair-mesh --fixed`, `label --segments`;
/// `option` is the command and the option) unless it holds `kind`, saying what it got and what
/// the option expects, before its reader can answer with a parser's message ("missing field").
pub fn expect_option(option: &str, path: Option<&Path>, kind: FileKind) -> Result<()> {
    match path {
        Some(p) => expect(option, p, &[kind]).map(|_| ()),
        None => Ok(()),
    }
}

/// The kind of `takes` that the extension of `path` names (`.json`: the first JSON kind).
fn by_extension(path: &Path, takes: &[FileKind]) -> Option<FileKind> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    let named: &[FileKind] = match ext.as_str() {
        "step" | "stp" => &[FileKind::Step],
        "igs" | "iges" => &[FileKind::Iges],
        "json" => &[
            FileKind::Model,
            FileKind::Surfaces,
            FileKind::Params,
            FileKind::Indices,
            FileKind::Segments,
        ],
        "obj" => &[FileKind::Obj],
        _ => &[],
    };
    takes.iter().copied().find(|k| named.contains(k))
}

/// Extensions of the CAD files hier-fair writes (STEP, IGES).
pub(crate) const CAD_OUTPUTS: &[&str] = &["step", "stp", "igs", "iges"];

/// Extensions a model or report is written to.
pub(crate) const JSON_OUTPUTS: &[&str] = &["json"];

/// Extensions `fair` writes a model to: JSON, or the CAD file the extension names.
pub(crate) const MODEL_OUTPUTS: &[&str] = &["json", "step", "stp", "igs", "iges"];

/// Extensions a mesh is written to (`fair-mesh -o`).
pub(crate) const MESH_OUTPUTS: &[&str] = &["obj"];

/// Extensions the HTML quality report is written to (`--html`).
pub(crate) const HTML_OUTPUTS: &[&str] = &["html", "htm"];

/// Extensions a drawing is written to (`label --svg`).
pub(crate) const SVG_OUTPUTS: &[&str] = &["svg"];

/// Whether `path` holds a CAD file (STEP or IGES) by its content.
pub fn is_cad(path: &Path) -> Result<bool> {
    Ok(matches!(sniff(path)?, FileKind::Step | FileKind::Iges))
}

/// Whether `fair`'s input is a CAD file (STEP, IGES) rather than JSON, known by its content;
/// an input of another kind, or a report not named `.json`, is refused.
pub fn fair_input_is_cad(input: &Path, report: Option<&Path>) -> Result<bool> {
    use crate::kind::FileKind;
    let kind = crate::kind::expect(
        "fair",
        input,
        &[
            FileKind::Model,
            FileKind::Surfaces,
            FileKind::Step,
            FileKind::Iges,
        ],
    )?;
    if let Some(r) = report {
        crate::kind::expect_extension("--report", r, crate::kind::JSON_OUTPUTS)?;
    }
    Ok(matches!(kind, FileKind::Step | FileKind::Iges))
}

/// Refuses the first of the model options `given` on the bare surface file `input`: an option
/// that does not apply is an error, never silently ignored.
pub fn refuse_model_options(input: &Path, given: &[(&str, bool)]) -> Result<()> {
    if let Some((flag, _)) = given.iter().find(|(_, g)| *g) {
        bail!(
            "{flag} applies to a model; {} is a surface file (each surface faired alone, its boundaries kept): leave {flag} out, or give a model",
            input.display()
        );
    }
    Ok(())
}

/// Checks `fair` on a model (`cad`: a STEP or IGES file, imported as one) before any work: the
/// output is a model or CAD file by its extension, and the bare-surface option `--keep`
/// (`keep_given`) is refused — the model's links choose the frames kept, and an option that does
/// not apply is an error, never silently ignored.
pub fn expect_model_run(input: &Path, output: &Path, cad: bool, keep_given: bool) -> Result<()> {
    expect_extension("-o", output, MODEL_OUTPUTS)?;
    if keep_given {
        bail!(
            "--keep applies to a bare surface file; {} is {} (its links choose the frames kept): leave --keep out",
            input.display(),
            if cad {
                "a STEP or IGES file, imported as a model"
            } else {
                "a model"
            }
        );
    }
    Ok(())
}

/// Refuses an output whose extension is not one of `allowed` (lower case, without the dot),
/// naming the list: an output is written in the format its extension names.
pub fn expect_extension(flag: &str, path: &Path, allowed: &[&str]) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if ext.as_deref().is_some_and(|e| allowed.contains(&e)) {
        return Ok(());
    }
    let list: Vec<String> = allowed.iter().map(|e| format!(".{e}")).collect();
    bail!(
        "{flag} {}: the output is written in the format its extension names; use one of {}",
        path.display(),
        list.join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_are_told_by_content() {
        assert_eq!(classify("ISO-10303-21;\nHEADER;\n"), FileKind::Step);
        let iges = format!("{:<72}S      1\n", "a start line");
        assert_eq!(classify(&iges), FileKind::Iges);
        assert_eq!(
            classify(
                r#"{"surfaces": [{"name": "a", "role": "primary", "surface": {}}], "links": []}"#
            ),
            FileKind::Model
        );
        assert_eq!(
            classify(r#"{"degree_u": 3, "degree_v": 3, "knots_u": []}"#),
            FileKind::Surfaces
        );
        assert_eq!(classify(r#"[{"degree_u": 1}]"#), FileKind::Surfaces);
        assert_eq!(
            classify(r#"{"seconds_total": 1.0, "surfaces": []}"#),
            FileKind::Report
        );
        assert_eq!(
            classify("# mesh\nv 0 0 0\nv 1 0 0\nf 1 2 3\n"),
            FileKind::Obj
        );
        assert_eq!(classify(r#"{"params": [[0.5, 0.5]]}"#), FileKind::Params);
        assert_eq!(classify("[0, 4, 17]\n"), FileKind::Indices);
        assert_eq!(classify("[[0, 1, 2], [2, 3]]"), FileKind::Segments);
        assert_eq!(
            classify(r#"{"segments": [{"vertices": [0, 1], "label": "south"}]}"#),
            FileKind::Segments
        );
        assert_eq!(classify("[]"), FileKind::Unknown);
        assert_eq!(classify("hello"), FileKind::Unknown);
        assert_eq!(classify(""), FileKind::Unknown);
    }
}
