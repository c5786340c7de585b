//! A STEP reader (ISO 10303-21 exchange structure, the AP203/AP214/AP242 geometry of
//! ISO 10303-42): each ADVANCED_FACE (or FACE_SURFACE) becomes an exact NURBS surface over the
//! parameter box of its bounds, and each surface outside a face (a GEOMETRIC_SET's) one over
//! its own bounds.
//!
//! Surfaces: PLANE, CYLINDRICAL_SURFACE, CONICAL_SURFACE, SPHERICAL_SURFACE, TOROIDAL_SURFACE
//! (rational quadratic arcs in the angular directions, \[NB\] A7.1 / A8.1), SURFACE_OF_LINEAR_EXTRUSION
//! of a B-spline curve (exact, [`nurbs_core::shapes::extrude_curve`]), SURFACE_OF_REVOLUTION
//! of a B-spline curve, and B-spline surfaces — B_SPLINE_SURFACE_WITH_KNOTS, or the
//! QUASI_UNIFORM_, UNIFORM_ and BEZIER_SURFACE forms with their knots implied — plain or in the
//! complex instance with RATIONAL_B_SPLINE_SURFACE.
//! The parameter box of a face is that of its bounds: the vertices and points along every edge
//! curve (LINE between its vertices, CIRCLE along the arc the edge runs — a whole circle for an
//! edge from a vertex to itself —, B-spline curves sampled) are inverted on the surface — in
//! closed form on the elementary surfaces, by projection on a B-spline — and, on a periodic
//! surface, unwrapped along each loop (module `domain`: loops that wind round, poles, seams). A
//! face with no edge loop is its surface's natural box. Length unit: the SI_UNIT of the
//! LENGTH_UNIT (METRE with its prefix) or a CONVERSION_BASED_UNIT named INCH / FOOT;
//! coordinates stay in that unit.
//!
//! A face or surface that cannot be read is skipped and named in [`StepFile::warnings`]; the
//! rest of the file is read.
//!
//! # Deviation from the standard
//! Only what a face's geometry needs is read; topology beyond the face bounds, colours,
//! assemblies and placements of product instances are ignored (a file of several placed
//! solids reads each solid in its own coordinates).
//!
//! Modules: `lexer` (the Part 21 instances), `entities` (access to them by number, the length
//! unit), `knots` (the implied-knot B-spline forms), `surfaces` (a face's surface and its
//! inversion), `curves` (points along the curves that bound a surface, the plane-angle unit),
//! `faces` (a face's bound loops and their parameters), `domain` (a face's parameter box),
//! `loose` (surfaces outside faces), `writer` (the AP214 writer).

mod aspects;
mod assembly;
mod curves;
mod domain;
mod entities;
mod faces;
mod knots;
mod lexer;
mod loose;
mod shell;
mod surfaces;
mod writer;

pub use lexer::{Instance, Value, parse_instances};
pub use writer::{write_step, write_step_faces, write_step_faces_within, write_step_shell};

use nurbs_core::{BSplineSurface, Point3};

use domain::face_box;
use entities::{Model, units};
use faces::{bound_loops, trim_loops};
use surfaces::surface;

/// A boundary point whose Newton foot from the previous point's lies within this fraction of
/// the surface size is on the surface there (a face's edges lie on it to the kernel's
/// tolerance, 1e-7 of a part; the foot of a point on a surface is that point): the full search
/// from the start grid is skipped.
pub(crate) const ON_SURFACE_RELATIVE: f64 = 1e-7;

/// Points along each edge curve used for a face's parameter box.
pub(crate) const EDGE_SAMPLES: usize = 17;

/// Points along a B-spline edge between its vertices for the face's parameter box: the largest
/// parameter of the edge on its face falls between samples and is missed by about |v''| h²/8
/// (h the spacing); 257 make that (16/256)² of what 17 miss (2.6·10⁻⁵ of a lofted face's
/// domain in Open CASCADE's IGES of the same model: a 2 µm gap along its fillet).
pub(crate) const SPLINE_EDGE_SAMPLES: usize = 257;

/// Largest angle (radians) between the samples of a circular edge: 2°, so that consecutive
/// boundary points of a face on a periodic surface are far less than half a turn apart and its
/// loops unwrap unambiguously (module `domain`).
pub(crate) const ARC_STEP: f64 = std::f64::consts::TAU / 180.0;

/// What is wrong with a STEP file, with the entity it concerns.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum StepError {
    /// The exchange structure itself (sections, an entity instance's syntax).
    #[error("line {line}: {detail}")]
    Syntax {
        /// 1-based line
        line: usize,
        /// what is wrong
        detail: String,
    },
    /// An entity whose parameters do not fit its type.
    #[error("#{id} {entity}: {detail}")]
    Entity {
        /// instance number
        id: u64,
        /// entity type
        entity: String,
        /// what is wrong
        detail: String,
    },
    /// Geometry rejected by the kernel.
    #[error("#{id}: {source}")]
    Geometry {
        /// instance number
        id: u64,
        /// the kernel's error
        source: nurbs_core::Error,
    },
}

/// A face or set element whose surface type is not read: counted by type in
/// [`StepFile::skipped`], not an error of the file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{kind}")]
struct UnreadSurface {
    /// the entity type of the surface
    kind: String,
}

/// A face read from a STEP file.
#[derive(Debug, Clone, PartialEq)]
pub struct StepFace {
    /// instance number of the face
    pub id: u64,
    /// the face's name, or `step<id>`
    pub name: String,
    /// the surface over the face's parameter box
    pub surface: BSplineSurface,
    /// the entity type of the face's surface
    pub kind: String,
    /// the face's bounds as data: each loop's points in order along it (the outer bound first),
    /// on the surface
    pub trim: Vec<Vec<Point3>>,
    /// the instance path of the part the face belongs to in an assembly (its usage occurrences,
    /// `LBA1/LBRACKET1`), `None` outside assemblies
    pub part: Option<String>,
}

/// What a STEP file held.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StepFile {
    /// the faces, in instance order
    pub faces: Vec<StepFace>,
    /// the length unit's name ("mm", "m", "in", …)
    pub units: String,
    /// faces whose surface type is not read, by type
    pub skipped: std::collections::BTreeMap<String, usize>,
    /// what was not read and why, one line each naming the entity (a face whose bounds or
    /// geometry cannot be read is skipped, the rest of the file read)
    pub warnings: Vec<String>,
}

/// Reads the faces of a STEP file, and the surfaces it holds outside faces (module `loose`).
/// A face that cannot be read is skipped and named in [`StepFile::warnings`]; when nothing at
/// all is read, the first such reason is the error.
pub fn read_step(text: &str) -> Result<StepFile, StepError> {
    let all = parse_instances(text)?;
    let m = Model { all: &all };
    let mut ids: Vec<u64> = all.keys().copied().collect();
    ids.sort_unstable();
    let mut file = StepFile {
        units: units(&m, &ids),
        ..StepFile::default()
    };
    let mut first_error = None;
    for &id in &ids {
        let kind = m.kind(id)?;
        if kind != "ADVANCED_FACE" && kind != "FACE_SURFACE" {
            continue;
        }
        match read_face(&m, id, kind) {
            Ok(Ok(face)) => file.faces.push(face),
            Ok(Err(unread)) => *file.skipped.entry(unread.kind).or_default() += 1,
            Err(e) => {
                file.warnings.push(format!("{kind} #{id} not read: {e}"));
                first_error.get_or_insert(e);
            }
        }
    }
    loose::read_loose(&m, &ids, &mut file, &mut first_error);
    drop_aspect_faces(&m, &ids, &mut file);
    file.faces = assembly::place(
        &m,
        &ids,
        std::mem::take(&mut file.faces),
        &mut file.warnings,
    );
    match first_error {
        Some(e) if file.faces.is_empty() => Err(e),
        _ => Ok(file),
    }
}

/// `file` without the faces only representations of shape aspects hold ([`aspects`]), named
/// in one warning.
fn drop_aspect_faces(m: &Model, ids: &[u64], file: &mut StepFile) {
    let read: std::collections::BTreeSet<u64> = file.faces.iter().map(|f| f.id).collect();
    let only = aspects::aspect_only_faces(m, ids, &read);
    if only.is_empty() {
        return;
    }
    file.faces.retain(|f| !only.contains(&f.id));
    let list: Vec<String> = only.iter().map(|id| format!("#{id}")).collect();
    file.warnings.push(format!(
        "{} faces of shape aspects (form features' geometry, SHAPE_ASPECT representations) not read as the part's: {}",
        only.len(),
        list.join(", ")
    ));
}

/// Face `id` (an ADVANCED_FACE or FACE_SURFACE, `kind`) over its parameter box, or the type of
/// its surface where that is not read.
fn read_face(m: &Model, id: u64, kind: &str) -> Result<Result<StepFace, UnreadSurface>, StepError> {
    let p = m.part(id, kind)?;
    let name = match p.first() {
        Some(Value::Text(t)) if !t.is_empty() => t.clone(),
        _ => format!("step{id}"),
    };
    let sid = m.reference(id, p.get(2))?;
    let skind = m.kind(sid)?.to_string();
    let Some(surface) = surface(m, sid)? else {
        return Ok(Err(UnreadSurface { kind: skind }));
    };
    let bounds = bound_loops(m, id, p.get(1), &surface)?;
    let same_sense = !matches!(p.get(3), Some(Value::Enum(e)) if e == "F");
    let (u, v) = face_box(&surface, &bounds, same_sense)
        .map_err(|detail| m.bad(id, format!("{detail} (surface #{sid} {skind})")))?;
    let built = surface
        .build(u, v)
        .map_err(|source| StepError::Geometry { id, source })?;
    Ok(Ok(StepFace {
        id,
        name,
        surface: built,
        kind: skind,
        trim: trim_loops(&bounds),
        part: None,
    }))
}
