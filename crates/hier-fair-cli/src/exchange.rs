//! `hier-fair import FILE.igs -o MODEL.json` and `hier-fair export MODEL.json -o FILE.igs`
//! (cli-contract.md): IGES exchange through `nurbs-io`, and `hier-fair build`. An imported file
//! becomes a model whose hierarchy — links, their targets, the roles — is found from the
//! geometry ([`hier_fair::build_hierarchy`]); the user may change any of it in the JSON, and
//! `build` keeps what the model gives.

use std::collections::HashSet;
use std::path::Path;

use anyhow::{Context, Result, anyhow, bail};
use hier_fair::Model;
use nurbs_io::{IgesWriteParams, read_iges, write_iges_faces};

use crate::files::{read_text, refuse_overwrite, write_atomic};

/// Whether `path` names an IGES file (`.igs`, `.iges`, any case).
pub fn is_iges(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("igs") || e.eq_ignore_ascii_case("iges"))
}

/// Whether `path` names a STEP file (`.step`, `.stp`, any case).
pub fn is_step(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("step") || e.eq_ignore_ascii_case("stp"))
}

/// Reads a CAD file (STEP or IGES, known by its content, [`crate::kind`]) into a model with
/// its hierarchy found.
pub fn model_from_cad(input: &Path) -> Result<(Model, String, hier_fair::BuildLog)> {
    use crate::kind::FileKind;
    match crate::kind::expect("import", input, &[FileKind::Step, FileKind::Iges])? {
        FileKind::Step => model_from_step(input),
        _ => model_from_iges(input),
    }
}

/// Reads the STEP file `input` (its faces, [`nurbs_io::read_step`]) into a model with its
/// hierarchy found; returns it, the summary and the log.
pub fn model_from_step(input: &Path) -> Result<(Model, String, hier_fair::BuildLog)> {
    let text = read_text(input)?;
    let file = nurbs_io::read_step(&text).map_err(|e| anyhow!("{}: {e}", input.display()))?;
    if file.faces.is_empty() {
        bail!(
            "{}: the file holds no face whose surface is read",
            input.display()
        );
    }
    let mut model = named_primaries(
        file.faces
            .iter()
            .map(|f| (f.name.clone(), f.id.to_string(), f.surface.clone())),
    );
    model.set_units(&file.units);
    let tol = hier_fair::trim::TRIM_SHARE * model.tolerances.g0;
    for (m, f) in model.surfaces.iter_mut().zip(&file.faces) {
        m.part = f.part.clone();
        m.trim = f
            .trim
            .iter()
            .map(|l| hier_fair::trim::thin_loop(l, tol))
            .collect();
    }
    let log = hier_fair::build_hierarchy(&mut model);
    let summary = format!(
        "imported {} faces, each over its parameter box with its bounds kept as trim loops; faces of surfaces not read: {}; faces and surfaces skipped: {}; {}",
        file.faces.len(),
        counts_text(&file.skipped),
        if file.warnings.is_empty() {
            "none".to_string()
        } else {
            file.warnings.join("; ")
        },
        hierarchy_summary(&model, &log),
    );
    Ok((model, summary, log))
}

/// A model of primaries from (name, suffix, surface): a name already taken gets `_suffix`.
fn named_primaries(
    items: impl Iterator<Item = (String, String, nurbs_core::BSplineSurface)>,
) -> Model {
    let (names, surfaces): (Vec<(String, String)>, Vec<_>) =
        items.map(|(n, x, s)| ((n, x), s)).unzip();
    let mut model = Model::from_primaries(surfaces);
    let mut used = HashSet::new();
    for (m, (name, suffix)) in model.surfaces.iter_mut().zip(names) {
        let name = if used.contains(&name) {
            format!("{name}_{suffix}")
        } else {
            name
        };
        used.insert(name.clone());
        m.name = name;
    }
    model
}

/// "3×100, 2×102" of a count per kind, or "none".
fn counts_text<K: std::fmt::Display>(counts: &std::collections::BTreeMap<K, usize>) -> String {
    if counts.is_empty() {
        return "none".to_string();
    }
    counts
        .iter()
        .map(|(t, n)| format!("{n}×{t}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Reads the IGES file `input` into a model with its hierarchy found
/// ([`hier_fair::build_hierarchy`]); returns it, the summary of what was read and found, and
/// the log.
pub fn model_from_iges(input: &Path) -> Result<(Model, String, hier_fair::BuildLog)> {
    let bytes = std::fs::read(input).with_context(|| format!("cannot read {}", input.display()))?;
    let file = read_iges(&bytes).map_err(|e| anyhow!("{}: {e}", input.display()))?;
    if file.surfaces.is_empty() {
        bail!(
            "{}: the file holds no surface that is read (B-spline 128, revolution 120, tabulated cylinder 122, ruled 118, offset 140, plane 108 under a 144){}",
            input.display(),
            if file.refused.is_empty() {
                String::new()
            } else {
                format!("; not read exactly: {}", file.refused.join("; "))
            }
        );
    }
    let mut model = named_primaries(
        file.surfaces
            .iter()
            .map(|s| (s.name.clone(), format!("de{}", s.de), s.surface.clone())),
    );
    model.set_units(&nurbs_io::units::iges_unit(file.unit_flag, &file.units));
    let tol = hier_fair::trim::TRIM_SHARE * model.tolerances.g0;
    for (m, s) in model.surfaces.iter_mut().zip(&file.surfaces) {
        m.trim = s
            .trim_loops()
            .iter()
            .map(|l| hier_fair::trim::thin_loop(l, tol))
            .collect();
    }
    let log = hier_fair::build_hierarchy(&mut model);
    let trimmed = file.surfaces.iter().filter(|s| s.trimmed).count();
    let summary = format!(
        "imported {} surfaces ({} trimmed by entity 144, bounded by 143 or a face (510) of a B-rep solid: each kept over its face's box with its outer and inner boundaries kept as trim loops); {} curves (126) not imported; other entities skipped: {}; surfaces with no exact form, not imported: {}; {}{}",
        file.surfaces.len(),
        trimmed,
        file.curves.len(),
        counts_text(&file.skipped),
        if file.refused.is_empty() {
            "none".to_string()
        } else {
            file.refused.join("; ")
        },
        hierarchy_summary(&model, &log),
        file.warnings
            .iter()
            .map(|w| format!("; warning: {w}"))
            .collect::<String>(),
    );
    Ok((model, summary, log))
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

/// "N links found; roles: …" for the summaries.
fn hierarchy_summary(model: &Model, log: &hier_fair::BuildLog) -> String {
    let count = |r: hier_fair::Role| model.surfaces.iter().filter(|s| s.role == r).count();
    format!(
        "{} links found ({} in all); roles {}: {} primary, {} connecting, {} corner",
        log.links_added,
        model.links.len(),
        if log.roles_found {
            "found"
        } else {
            "kept as given"
        },
        count(hier_fair::Role::Primary),
        count(hier_fair::Role::Connecting),
        count(hier_fair::Role::Corner)
    )
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
        hierarchy_summary(&model, &log),
        output.display()
    );
    Ok(out)
}

/// `YYYYMMDD.HHNNSS` of now (UTC), as the Global section wants it.
fn iges_date_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs()) as i64;
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    // civil date from days since 1970-01-01 (H. Hinnant's algorithm)
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}{m:02}{d:02}.{:02}{:02}{:02}",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
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

/// Share of the model's G0 tolerance a STEP trim edge may lie from its loop's points when it is
/// fitted as a cubic ([`nurbs_io::write_step_faces_within`]): a half, so that two neighbouring
/// faces' edges, each fitted, still touch within G0; the points lie on the surface, so the
/// edge does too within that half. The loops were thinned to the G0 tolerance on import.
pub const EDGE_FIT_SHARE: f64 = 0.5;

/// The model as the text of the CAD file `output` names by its extension: STEP (`.step`,
/// `.stp`: AP214, each surface a B-spline face bounded by its trim loops — each edge a cubic
/// within [`EDGE_FIT_SHARE`] of the G0 tolerance of its points — or by its boundary curves
/// where it has none) or IGES (each trim loop composite curves of cubic pieces between its
/// corners, within the same share, in model and parameter space).
pub fn cad_text(model: &Model, output: &Path) -> Result<String> {
    if is_step(output) {
        let name = output
            .file_name()
            .map_or_else(|| "model.step".into(), |n| n.to_string_lossy().into_owned());
        nurbs_io::write_step_faces_within(
            &faces(model),
            written_unit(model),
            &name,
            EDGE_FIT_SHARE * model.tolerances.g0,
        )
        .map_err(|e| anyhow!("{e}"))
    } else {
        iges_text(model, output)
    }
}

/// The unit a model's coordinates are written in: its own where [`nurbs_io::units`] knows it,
/// else millimetres, as which the model was read ([`Model::mm_per_unit`]).
fn written_unit(model: &Model) -> &str {
    match model.units.as_deref() {
        Some(u) if nurbs_io::units::mm_per_unit(u).is_some() => u,
        _ => "mm",
    }
}

/// The model's surfaces as faces to write, each with its trim loops (the writers put the loops
/// on the surface that is written: a faired surface has moved by up to its deviation).
fn faces(model: &Model) -> Vec<nurbs_io::Face<'_>> {
    model
        .surfaces
        .iter()
        .map(|s| nurbs_io::Face {
            name: &s.name,
            surface: &s.surface,
            trim: &s.trim,
        })
        .collect()
}

/// The surfaces of `model` as the text of an IGES 5.3 file named `output` (entity 128, a
/// trimmed surface 144 over it where the surface has trim loops).
pub fn iges_text(model: &Model, output: &Path) -> Result<String> {
    let u = written_unit(model);
    let (unit_flag, units) = nurbs_io::units::iges_flag(u).ok_or_else(|| {
        anyhow!("the model's unit {u:?} has no IGES unit flag ([IGES] Global parameter 14): export it to STEP")
    })?;
    let params = IgesWriteParams {
        unit_flag,
        units,
        file_name: output
            .file_name()
            .map_or_else(|| "model.igs".into(), |n| n.to_string_lossy().into_owned()),
        date: iges_date_now(),
        edge_tolerance: EDGE_FIT_SHARE * model.tolerances.g0,
        ..IgesWriteParams::default()
    };
    write_iges_faces(&faces(model), &[], &params).map_err(|e| anyhow!("{e}"))
}

#[cfg(test)]
mod tests {
    #[test]
    fn dates_are_well_formed() {
        let d = super::iges_date_now();
        assert_eq!(d.len(), 15);
        assert!(d.starts_with("20") && d.as_bytes()[8] == b'.');
    }
}
