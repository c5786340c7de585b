//! CAD exchange: a STEP or IGES file into a model with its hierarchy found
//! ([`crate::build_hierarchy`]: links, their targets, the roles), and a model out as STEP
//! (AP214 B-spline faces) or IGES 5.3 (entity 128, a 144 over it where it is trimmed), through
//! `nurbs-io`. The command line's `import`, `export` and `fair FILE.step` call these; so can any
//! program built on the library (it reads and writes the files, the library the text).

use std::collections::{BTreeMap, HashSet};
use std::path::Path;

use crate::build::{BuildLog, build_hierarchy};
use crate::error::{Error, Result};
use crate::model::{Model, Role};

/// A CAD file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CadFormat {
    /// ISO 10303-21 (STEP)
    Step,
    /// IGES 5.3
    Iges,
}

impl CadFormat {
    /// The format of a file that starts with `head` (its first kilobytes): `ISO-10303-21` first
    /// (after a byte-order mark and white space) is STEP; a first line of at least 73 columns
    /// with S, G or C in column 73 is IGES (fixed 80-column records, \[IGES\] §2.1).
    pub fn of_content(head: &[u8]) -> Option<Self> {
        let head = String::from_utf8_lossy(head);
        let text = head.trim_start_matches('\u{feff}').trim_start();
        if text.starts_with("ISO-10303-21") {
            return Some(Self::Step);
        }
        let first = head.lines().find(|l| !l.trim().is_empty())?;
        (first.len() >= 73 && matches!(first.as_bytes()[72], b'S' | b'G' | b'C'))
            .then_some(Self::Iges)
    }

    /// The format an output's extension names: `.step`, `.stp` or `.igs`, `.iges` (any case).
    pub fn of_extension(path: &Path) -> Option<Self> {
        let e = path.extension()?.to_str()?.to_ascii_lowercase();
        match e.as_str() {
            "step" | "stp" => Some(Self::Step),
            "igs" | "iges" => Some(Self::Iges),
            _ => None,
        }
    }
}

/// A CAD file read into a model.
#[derive(Debug, Clone)]
pub struct Imported {
    /// the model, its hierarchy found
    pub model: Model,
    /// one paragraph: what was read, skipped and found
    pub summary: String,
    /// every decision of the hierarchy finder
    pub log: BuildLog,
}

/// Reads a CAD file's bytes (STEP or IGES, known by their content: [`CadFormat::of_content`])
/// into a model with its hierarchy found. The library reads no file by path: the caller reads
/// it and names it in what it reports.
pub fn read_cad(bytes: &[u8]) -> Result<Imported> {
    match CadFormat::of_content(bytes) {
        Some(CadFormat::Step) => read_step(&String::from_utf8_lossy(bytes)),
        Some(CadFormat::Iges) => read_iges(bytes),
        None => Err(Error::Exchange {
            detail: "neither a STEP file (ISO-10303-21 first) nor an IGES file (80-column records, S or G in column 73)".into(),
        }),
    }
}

/// Reads STEP text (its faces, [`nurbs_io::read_step`]) into a model with its hierarchy found;
/// each face over its parameter box, its bounds kept as trim loops (thinned to
/// [`crate::trim::TRIM_SHARE`] of the G0 tolerance), its part where the file places it in one.
pub fn read_step(text: &str) -> Result<Imported> {
    let file = nurbs_io::read_step(text).map_err(|e| Error::Exchange {
        detail: e.to_string(),
    })?;
    if file.faces.is_empty() {
        return Err(Error::Exchange {
            detail: "the file holds no face whose surface is read".into(),
        });
    }
    let (model, log) = primaries_model(
        file.faces.iter().map(|f| ReadFace {
            name: f.name.clone(),
            suffix: f.id.to_string(),
            surface: f.surface.clone(),
            part: f.part.clone(),
            trim: f.trim.clone(),
        }),
        &file.units,
    );
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
    Ok(Imported {
        model,
        summary,
        log,
    })
}

/// Reads an IGES file's bytes ([`nurbs_io::read_iges`]) into a model with its hierarchy found;
/// each surface over its face's box, its outer and inner boundaries kept as trim loops.
pub fn read_iges(bytes: &[u8]) -> Result<Imported> {
    let file = nurbs_io::read_iges(bytes).map_err(|e| Error::Exchange {
        detail: e.to_string(),
    })?;
    if file.surfaces.is_empty() {
        return Err(Error::Exchange {
            detail: format!(
                "the file holds no surface that is read (B-spline 128, revolution 120, tabulated cylinder 122, ruled 118, offset 140, plane 108 under a 144){}",
                if file.refused.is_empty() {
                    String::new()
                } else {
                    format!("; not read exactly: {}", file.refused.join("; "))
                }
            ),
        });
    }
    let (model, log) = primaries_model(
        file.surfaces.iter().map(|s| ReadFace {
            name: s.name.clone(),
            suffix: format!("de{}", s.de),
            surface: s.surface.clone(),
            part: None,
            trim: s.trim_loops(),
        }),
        &nurbs_io::units::iges_unit(file.unit_flag, &file.units),
    );
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
    Ok(Imported {
        model,
        summary,
        log,
    })
}

/// One face as a reader gives it.
struct ReadFace {
    name: String,
    /// what a name already taken gets appended (`_suffix`): the entity's id
    suffix: String,
    surface: nurbs_core::BSplineSurface,
    part: Option<String>,
    trim: Vec<Vec<nurbs_core::Point3>>,
}

/// A model of primaries from the faces read, in `units`, each face's trim loops thinned to
/// [`crate::trim::TRIM_SHARE`] of the G0 tolerance, with its hierarchy found.
fn primaries_model(faces: impl Iterator<Item = ReadFace>, units: &str) -> (Model, BuildLog) {
    let faces: Vec<ReadFace> = faces.collect();
    let mut model = Model::from_primaries(faces.iter().map(|f| f.surface.clone()).collect());
    model.set_units(units);
    let tol = crate::trim::TRIM_SHARE * model.tolerances.g0;
    let mut used = HashSet::new();
    for (m, f) in model.surfaces.iter_mut().zip(faces) {
        let name = if used.contains(&f.name) {
            format!("{}_{}", f.name, f.suffix)
        } else {
            f.name
        };
        used.insert(name.clone());
        m.name = name;
        m.part = f.part;
        m.trim = f
            .trim
            .iter()
            .map(|l| crate::trim::thin_loop(l, tol))
            .collect();
    }
    let log = build_hierarchy(&mut model);
    (model, log)
}

/// "3×100, 2×102" of a count per kind, or "none".
fn counts_text<K: std::fmt::Display>(counts: &BTreeMap<K, usize>) -> String {
    if counts.is_empty() {
        return "none".to_string();
    }
    counts
        .iter()
        .map(|(t, n)| format!("{n}×{t}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// "N links found (M in all); roles …: P primary, C connecting, K corner", for summaries.
pub fn hierarchy_summary(model: &Model, log: &BuildLog) -> String {
    let count = |r: Role| model.surfaces.iter().filter(|s| s.role == r).count();
    format!(
        "{} links found ({} in all); roles {}: {} primary, {} connecting, {} corner",
        log.links_added,
        model.links.len(),
        if log.roles_found {
            "found"
        } else {
            "kept as given"
        },
        count(Role::Primary),
        count(Role::Connecting),
        count(Role::Corner)
    )
}

/// Share of the model's G0 tolerance a written trim edge may lie from its loop's points when it
/// is fitted as a cubic ([`nurbs_io::write_step_faces_within`], the IGES writer's
/// `edge_tolerance`): a half, so that two neighbouring faces' edges, each fitted, still touch
/// within G0; the points lie on the surface, so the edge does too within that half. The loops
/// were thinned to the G0 tolerance on import.
pub const EDGE_FIT_SHARE: f64 = 0.5;

/// The model as the text of a CAD file in `format`, named `file_name` in its header: STEP
/// (AP214, each surface a B-spline face bounded by its trim loops — each edge a cubic within
/// [`EDGE_FIT_SHARE`] of the G0 tolerance of its points — or by its boundary curves where it
/// has none; faces that meet within the G0 tolerance share their vertices and edges, a shell
/// per connected set of faces of one part, closed where every edge is used twice:
/// [`nurbs_io::write_step_shell`]) or IGES (each trim loop composite curves of cubic pieces
/// between its corners, within the same share, in model and parameter space; dated now).
pub fn cad_text(model: &Model, format: CadFormat, file_name: &str) -> Result<String> {
    match format {
        CadFormat::Step => nurbs_io::write_step_shell(
            &faces(model),
            written_unit(model),
            file_name,
            EDGE_FIT_SHARE * model.tolerances.g0,
            model.tolerances.g0,
            &parts(model),
        )
        .map_err(|e| Error::Exchange {
            detail: e.to_string(),
        }),
        CadFormat::Iges => iges_text(model, file_name, &iges_date_now()),
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

/// Each surface's part of an assembly, numbered in order of first appearance (surfaces of no
/// part are one part): the STEP writer joins faces into shells within a part only.
fn parts(model: &Model) -> Vec<usize> {
    let mut names: Vec<Option<&str>> = Vec::new();
    model
        .surfaces
        .iter()
        .map(|s| {
            let p = s.part.as_deref();
            names.iter().position(|&n| n == p).unwrap_or_else(|| {
                names.push(p);
                names.len() - 1
            })
        })
        .collect()
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

/// The surfaces of `model` as the text of an IGES 5.3 file named `file_name`, dated `date`
/// (`YYYYMMDD.HHNNSS`): entity 128, a trimmed surface 144 over it where it has trim loops.
pub fn iges_text(model: &Model, file_name: &str, date: &str) -> Result<String> {
    let u = written_unit(model);
    let (unit_flag, units) = nurbs_io::units::iges_flag(u).ok_or_else(|| Error::Exchange {
        detail: format!(
            "the model's unit {u:?} has no IGES unit flag ([IGES] Global parameter 14): export it to STEP"
        ),
    })?;
    let params = nurbs_io::IgesWriteParams {
        unit_flag,
        units,
        file_name: file_name.to_string(),
        date: date.to_string(),
        edge_tolerance: EDGE_FIT_SHARE * model.tolerances.g0,
        ..nurbs_io::IgesWriteParams::default()
    };
    nurbs_io::write_iges_faces(&faces(model), &[], &params).map_err(|e| Error::Exchange {
        detail: e.to_string(),
    })
}

/// `YYYYMMDD.HHNNSS` of now (UTC), as the IGES Global section wants it.
pub fn iges_date_now() -> String {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_are_well_formed() {
        let d = iges_date_now();
        assert_eq!(d.len(), 15);
        assert!(d.starts_with("20") && d.as_bytes()[8] == b'.');
    }

    #[test]
    fn formats_are_known_by_content_and_extension() {
        assert_eq!(
            CadFormat::of_content(b"\xef\xbb\xbf ISO-10303-21;\nHEADER;"),
            Some(CadFormat::Step)
        );
        let iges = format!("{:72}S      1\n", "a start record");
        assert_eq!(
            CadFormat::of_content(iges.as_bytes()),
            Some(CadFormat::Iges)
        );
        assert_eq!(CadFormat::of_content(b"{\"surfaces\": []}"), None);
        assert_eq!(
            CadFormat::of_extension(Path::new("a/B.STP")),
            Some(CadFormat::Step)
        );
        assert_eq!(
            CadFormat::of_extension(Path::new("b.Iges")),
            Some(CadFormat::Iges)
        );
        assert_eq!(CadFormat::of_extension(Path::new("c.json")), None);
    }
}
