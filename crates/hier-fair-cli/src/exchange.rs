//! `hier-fair import FILE.igs -o MODEL.json` and `hier-fair export MODEL.json -o FILE.igs`
//! (cli-contract.md), and `hier-fair build`: the files, their kinds and the messages around the
//! library's exchange ([`hier_fair::exchange`]). An imported file becomes a model whose
//! hierarchy — links, their targets, the roles — is found from the geometry
//! ([`hier_fair::build_hierarchy`]); the user may change any of it in the JSON, and `build`
//! keeps what the model gives.

use std::path::Path;

use anyhow::{Context, Result, anyhow};
use hier_fair::Model;
use hier_fair::exchange::CadFormat;

use crate::files::{read_text, refuse_overwrite, write_atomic};

/// Whether `path` names an IGES file (`.igs`, `.iges`, any case).
pub fn is_iges(path: &Path) -> bool {
    CadFormat::of_extension(path) == Some(CadFormat::Iges)
}

/// Whether `path` names a STEP file (`.step`, `.stp`, any case).
pub fn is_step(path: &Path) -> bool {
    CadFormat::of_extension(path) == Some(CadFormat::Step)
}

/// Reads a CAD file (STEP or IGES, known by its content, [`crate::kind`]) into a model with
/// its hierarchy found ([`hier_fair::exchange`]).
pub fn model_from_cad(input: &Path) -> Result<(Model, String, hier_fair::BuildLog)> {
    use crate::kind::FileKind;
    let imported = match crate::kind::expect("import", input, &[FileKind::Step, FileKind::Iges])? {
        FileKind::Step => hier_fair::exchange::read_step(&read_text(input)?),
        _ => {
            let bytes =
                std::fs::read(input).with_context(|| format!("cannot read {}", input.display()))?;
            hier_fair::exchange::read_iges(&bytes)
        }
    }
    .map_err(|e| anyhow!("{}: {e}", input.display()))?;
    Ok((imported.model, imported.summary, imported.log))
}

/// Reads `input` (STEP or IGES, by the extension) and writes the model JSON to `output`;
/// returns a one-paragraph summary
/// (the hierarchy's log first with `explain`).
pub fn import(input: &Path, output: &Path, explain: bool) -> Result<String> {
    refuse_overwrite(output, &[input])?;
    let (model, summary, log) = model_from_cad(input)?;
    write_atomic(output, model.to_json().as_bytes())?;
    let mut out = if explain {
        log.lines.join("\n") + "\n"
    } else {
        String::new()
    };
    out += &format!("{summary}; wrote {}", output.display());
    Ok(out)
}

/// `hier-fair build`: reads the model `input`, finds its hierarchy (keeping its links, and its
/// roles when it gives any) and writes the model to `output`; returns the summary (the log
/// first with `explain`).
pub fn build(input: &Path, output: &Path, explain: bool) -> Result<String> {
    refuse_overwrite(output, &[input])?;
    let text = read_text(input)?;
    let mut model = Model::from_json(&text).map_err(|e| anyhow!("{}: {e}", input.display()))?;
    let log = hier_fair::build_hierarchy(&mut model);
    write_atomic(output, model.to_json().as_bytes())?;
    let mut out = if explain {
        log.lines.join("\n") + "\n"
    } else {
        String::new()
    };
    out += &format!(
        "{}; wrote {}",
        hier_fair::exchange::hierarchy_summary(&model, &log),
        output.display()
    );
    Ok(out)
}

/// Reads the model `input` and writes its surfaces as IGES to `output`; returns a summary line.
pub fn export(input: &Path, output: &Path) -> Result<String> {
    refuse_overwrite(output, &[input])?;
    crate::kind::expect(
        "export",
        input,
        &[
            crate::kind::FileKind::Model,
            crate::kind::FileKind::Surfaces,
        ],
    )?;
    crate::kind::expect_extension("-o", output, crate::kind::CAD_OUTPUTS)?;
    let model =
        Model::from_json(&read_text(input)?).map_err(|e| anyhow!("{}: {e}", input.display()))?;
    let text = cad_text(&model, output).map_err(|e| anyhow!("{}: {e}", input.display()))?;
    write_atomic(output, text.as_bytes())?;
    let trimmed = model.surfaces.iter().filter(|s| !s.trim.is_empty()).count();
    Ok(format!(
        "exported {} surfaces ({}; {trimmed} bounded by their trim loops) to {}",
        model.surfaces.len(),
        if is_step(output) {
            "STEP AP214 B-spline faces"
        } else {
            "IGES entity 128, trimmed surfaces 144 over them"
        },
        output.display()
    ))
}

/// The model as the text of the CAD file `output` names by its extension (STEP `.step`,
/// `.stp`; IGES otherwise), named after the output in its header
/// ([`hier_fair::exchange::cad_text`]).
pub fn cad_text(model: &Model, output: &Path) -> Result<String> {
    let (format, fallback) = if is_step(output) {
        (CadFormat::Step, "model.step")
    } else {
        (CadFormat::Iges, "model.igs")
    };
    let name = output
        .file_name()
        .map_or_else(|| fallback.into(), |n| n.to_string_lossy().into_owned());
    hier_fair::exchange::cad_text(model, format, &name).map_err(|e| anyhow!("{e}"))
}
