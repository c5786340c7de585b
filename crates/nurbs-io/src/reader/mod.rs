//! The IGES reader: records, sections, global parameters, directory, parameter data, and the
//! entities 128 (rational B-spline surface), 120 (surface of revolution, with its 110 axis and
//! its 110 / 100 / 126 generatrix), 108 (plane, bounded by the outer boundary of the 144 that
//! trims it: its 142 and the 102 / 110 / 100 / 126 model-space curve), 126 (curve), 144 (trimmed
//! surface), 143 (bounded surface, with its 141 boundaries: the first the outer one, each the
//! model-space curves it lists in order), 510 (a face of a manifold solid B-rep 186, read as a
//! trimmed surface: its 508 loops, each edge the part of its 504 edge's curve between its 502
//! vertices, over a 128, an exact surface, a 108 or a 190 plane surface) and 124
//! (transformation matrix) (\[IGES\] §2, §4.3, §4.13, §4.16, §4.23, §4.24, §4.33, §4.34, §4.21,
//! §4.147–§4.151).
//! A trimmed or bounded surface's boundaries are kept as data on its surface
//! ([`IgesSurface::trim`], the outer one, and [`IgesSurface::holes`], the inner ones): each
//! 142's parameter-space curve through a B-spline surface where it has one, else its
//! model-space curve (100, 102, 110, 126) on the surface; a 141's model-space curves.
//!
//! Control points of entity 128 are stored with the u index varying fastest, W(0,0), W(1,0), …;
//! here they go to the flat net `P[i * n_v + j]`. Weights that are all equal make a polynomial
//! surface. Coordinates are divided by the model-space scale of the Global section when it is
//! not 1 (model units → real-world units).
//!
//! Modules: `records` (sections, Global, directory, parameter data), `entities` (an entity's
//! parameters, transformations, curves), `surfaces` (the surface entities), `boundaries` (a
//! trimmed surface's boundaries: the face's box and its trim loops), `planes` (planes bounded
//! by their faces).

mod boundaries;
mod entities;
mod planes;
mod records;
mod seam_box;
mod surfaces;

use std::collections::BTreeMap;

use nurbs_core::{BSplineCurve, BSplineSurface, Point3};

use crate::error::IgesError;
use crate::params::Param;

use entities::{Cursor, Reader};
use planes::grow_planes;
use records::{DirEntry, Global};
pub use records::{RECORD_COLUMNS, unit_name};
pub(crate) use records::{
    check_terminate, entity_params, parse_directory, parse_global, reconcile_line_counts,
    split_sections,
};
pub use surfaces::RULED_ARC_LENGTH_RELATIVE;

/// A face's parameter box that differs from its surface's domain by at most this fraction of
/// the domain on every side is the whole surface (the boundary curve's own rounding).
const BOX_RELATIVE: f64 = 1e-9;
/// A surface boundary lies in a plane when its control row does within this fraction of the
/// model size: 1e-9 holds the round-off of exact kernel geometry written with 10–16 digits.
const IN_PLANE_RELATIVE: f64 = 1e-9;
/// A point of a face's model-space trim curve counts as on its surface within this fraction of
/// the surface size: the trim is written within the writer's tolerance (Open CASCADE: 10⁻⁷ of
/// a 100 mm part), and 10⁻⁵ leaves room for that while refusing a curve of another face.
const ON_SURFACE_RELATIVE: f64 = 1e-5;
/// Points sampled along each member of a face's boundary for its parameter box. The largest
/// parameter of a smooth boundary falls between samples and is missed by about |v''| h²/8 (h the
/// spacing): at 17 samples a lofted face of Open CASCADE's came out 2.6·10⁻⁵ of its domain short
/// of the fillet that bounds it (a 2 µm gap along the fillet's contact line); 257 samples make
/// that (16/256)² smaller, 10⁻⁷ of the domain (10 nm).
const FACE_BOX_SAMPLES: usize = 257;
/// Points sampled along each member of a plane's boundary curve before the halving by sag
/// ([`BOUNDARY_SAG_RELATIVE`]).
const BOUNDARY_SAMPLES: usize = 17;
/// A boundary's samples lie within this fraction of the curve's size of its chords (each member
/// of a boundary, its intervals halved until they do): 10⁻⁷ is 10⁻⁵ mm on a curve of 100 mm, a
/// hundredth of the 10⁻³ mm G0 tolerance a model is usually measured at, so that the loop the
/// command line thins to a share of that tolerance is the curve and not its chords; on a curve
/// of a metre it is still a tenth of it.
const BOUNDARY_SAG_RELATIVE: f64 = 1e-7;
/// Halvings of one interval at most ([`BOUNDARY_SAG_RELATIVE`]): 2¹² pieces of each of the first
/// samples' intervals, a bound of memory on a curve that no sampling follows (a member with a
/// cusp); a circle of radius 25 from 16 first chords reaches its sag within 9.
const MAX_SAG_HALVINGS: usize = 12;
/// Nesting limit of transformation matrices that reference further matrices.
const MAX_TRANSFORM_CHAIN: usize = 32;

/// A surface read from entity 128 or 120.
#[derive(Debug, Clone, PartialEq)]
pub struct IgesSurface {
    /// directory sequence number of the entity
    pub de: usize,
    /// entity label and subscript, or `iges<de>`
    pub name: String,
    /// the geometry (transformation and scale applied)
    pub surface: BSplineSurface,
    /// whether a trimmed surface (144) uses it
    pub trimmed: bool,
    /// parameter ranges U0, U1, V0, V1 from the entity
    pub param_range: [f64; 4],
    /// the entity's own surface where `surface` is cut from it to a trimmed face's box
    pub underlying: Option<BSplineSurface>,
    /// a trimmed face's outer boundary as data: its points in order, on the surface (empty for
    /// an untrimmed surface)
    pub trim: Vec<Point3>,
    /// a trimmed face's inner boundaries (its holes) as data, each its points in order on the
    /// surface; empty where the face has none, or no outer boundary in `trim`
    pub holes: Vec<Vec<Point3>>,
}

impl IgesSurface {
    /// The face's boundary loops as the model's `trim` holds them: the outer boundary first,
    /// then the holes; none for an untrimmed surface.
    pub fn trim_loops(&self) -> Vec<Vec<Point3>> {
        if self.trim.is_empty() {
            return Vec::new();
        }
        std::iter::once(self.trim.clone())
            .chain(self.holes.iter().cloned())
            .collect()
    }
}

/// A curve read from entity 126.
#[derive(Debug, Clone, PartialEq)]
pub struct IgesCurve {
    /// directory sequence number of the entity
    pub de: usize,
    /// entity label and subscript, or `iges<de>`
    pub name: String,
    /// the geometry
    pub curve: BSplineCurve,
    /// parameter range V0, V1
    pub param_range: [f64; 2],
}

/// What a file held.
#[derive(Debug, Clone, PartialEq)]
pub struct IgesFile {
    /// Start section text
    pub start: String,
    /// unit name of the Global section (e.g. "MM")
    pub units: String,
    /// unit flag of the Global section
    pub unit_flag: i64,
    /// model-space scale of the Global section
    pub scale: f64,
    /// entity-128, 120 (revolution), 122 (tabulated cylinder) and 118 (ruled) surfaces in
    /// directory order, each plane (108) at the place of the trimmed surface (144) that bounds it
    pub surfaces: Vec<IgesSurface>,
    /// entity-126 curves in directory order
    pub curves: Vec<IgesCurve>,
    /// number of trimmed-surface entities (144)
    pub trimmed_entities: usize,
    /// entities not read, by type
    pub skipped: BTreeMap<i64, usize>,
    /// surfaces that have no exact NURBS form here, one line each (directory entry, type, why):
    /// a ruled surface (118) between rational curves of different weight functions, or of
    /// form 0 between curves of unlike speed; never approximated without a word
    pub refused: Vec<String>,
    /// what the reader tolerated, one line each (a Terminate record that miscounts)
    pub warnings: Vec<String>,
}

/// Reads an IGES file (CRLF or LF line endings).
pub fn read_iges(bytes: &[u8]) -> Result<IgesFile, IgesError> {
    let sec = split_sections(bytes)?;
    let global = parse_global(&sec.g)?;
    let (scale, unit_flag, units) = global_units(&global)?;
    let start = sec
        .s
        .iter()
        .map(|r| String::from_utf8_lossy(r.data).trim_end().to_string())
        .collect::<Vec<_>>()
        .join("\n");
    // a Terminate record whose counts disagree with the sections ([IGES] §2.2.5) is named and
    // the sections read as they are, as Open CASCADE does: the counts are redundant
    let warnings = match check_terminate(&sec) {
        Ok(()) => Vec::new(),
        Err(e) => vec![format!("{e}; the sections are read as they are")],
    };
    let mut dir = parse_directory(&sec.d)?;
    let mut warnings = warnings;
    warnings.extend(reconcile_line_counts(&mut dir, &sec.p));
    let reader = Reader {
        dir,
        p: sec.p,
        global,
    };
    let mut file = IgesFile {
        start,
        units,
        unit_flag,
        scale,
        surfaces: vec![],
        curves: vec![],
        trimmed_entities: 0,
        skipped: BTreeMap::new(),
        refused: Vec::new(),
        warnings,
    };
    let mut pending = Pending::default();
    for e in &reader.dir {
        reader.read_entity(e, scale, &mut file, &mut pending)?;
    }
    reader.cut_faces(&pending.faces, scale, &mut file)?;
    reader.trim_exact_faces(&pending.exact_faces, scale, &mut file)?;
    grow_planes(&mut file.surfaces, &pending.planes_read);
    let unbounded = reader
        .dir
        .iter()
        .filter(|e| e.entity_type == 108 && !pending.planes_read.contains(&e.seq))
        .count();
    if unbounded > 0 {
        file.skipped.insert(108, unbounded);
    }
    for s in &mut file.surfaces {
        s.trimmed = pending.trimmed_targets.contains(&s.de);
    }
    Ok(file)
}

/// The model scale, unit flag and unit name of the Global section (its fields 13, 14, 15; the
/// unit name from the flag where the field is empty).
fn global_units(global: &Global) -> Result<(f64, i64, String), IgesError> {
    let text_param = |k: usize| match global.params.get(k).map(|p| &p.value) {
        Some(Param::Text(s)) => s.clone(),
        _ => String::new(),
    };
    let num_param = |k: usize, default: f64| match global.params.get(k).map(|p| &p.value) {
        Some(Param::Number(x)) => *x,
        _ => default,
    };
    // global fields 13, 14, 15 (1-based) are model scale, unit flag, unit name; params start at field 3
    let scale = num_param(10, 1.0);
    if !(scale > 0.0) {
        return Err(IgesError::Parameter {
            line: global.params.get(10).map_or(0, |p| p.line),
            detail: format!("model space scale {scale} must be > 0"),
        });
    }
    // a flag outside 1–11, or 3 ("refer to parameter 15") without a unit name this reader
    // knows, is read as the parameter's default, 1 (inches), [IGES] §2.2.4.3.14 — as other
    // readers do
    let flag = num_param(11, 1.0) as i64;
    let name = text_param(12);
    let known = crate::units::mm_per_unit(&name).is_some();
    let (unit_flag, units) = match flag {
        1..=11 if flag != 3 => {
            let units = if name.is_empty() {
                unit_name(flag).to_string()
            } else {
                name
            };
            (flag, units)
        }
        _ if known => (3, name),
        _ => (1, unit_name(1).to_string()),
    };
    Ok((scale, unit_flag, units))
}

/// A trimmed surface's (144) entry and its outer and inner boundaries (142).
type FaceBoundaries<'r> = (&'r DirEntry, &'r DirEntry, Vec<&'r DirEntry>);

/// What the directory pass leaves for after every surface is read.
#[derive(Default)]
struct Pending<'r> {
    /// the directory numbers of the surfaces a 144 trims
    trimmed_targets: Vec<usize>,
    /// the planes (108) read, bounded by their faces
    planes_read: Vec<usize>,
    /// the B-spline faces (144 over a 128): its surface's directory number and boundaries
    faces: Vec<(usize, FaceBoundaries<'r>)>,
    /// faces on the exact surfaces read over their own range (120, 122, 118, 140): their trim
    /// only
    exact_faces: Vec<(usize, FaceBoundaries<'r>)>,
}

/// `read` into `file`'s surfaces, or its error named among the refused entities where the
/// entity has no exact form or cannot be approximated (an entity or geometry error); any other
/// error ends the read.
fn keep_or_refuse(
    read: Result<IgesSurface, IgesError>,
    file: &mut IgesFile,
) -> Result<(), IgesError> {
    match read {
        Ok(s) => file.surfaces.push(s),
        Err(err @ (IgesError::Entity { .. } | IgesError::Geometry { .. })) => {
            file.refused.push(err.to_string());
        }
        Err(err) => return Err(err),
    }
    Ok(())
}

impl Reader<'_> {
    /// Reads the entity `e` into `file`, or into `pending` what waits for the surfaces.
    fn read_entity<'r>(
        &'r self,
        e: &'r DirEntry,
        scale: f64,
        file: &mut IgesFile,
        pending: &mut Pending<'r>,
    ) -> Result<(), IgesError> {
        match e.entity_type {
            128 => file.surfaces.push(self.surface(e, scale)?),
            120 => file.surfaces.push(self.revolution(e, scale)?),
            // a surface with no exact form, or an offset that cannot be approximated, is named
            // and the rest of the file is read
            122 => keep_or_refuse(self.tabulated(e, scale), file)?,
            118 => keep_or_refuse(self.ruled(e, scale), file)?,
            126 => file.curves.push(self.curve(e, scale)?),
            140 => keep_or_refuse(self.offset(e, scale), file)?,
            144 | 143 | 510 => self.trimmed_surface(e, scale, file, pending)?,
            // planes are read through the trimmed surfaces and faces that bound them; a
            // manifold solid (186) and its shells (514), loops (508), edges (504) and vertices
            // (502) through its faces (510, [IGES] §4.150), each of which names its surface
            124 | 108 | 190 | 186 | 514 | 508 | 504 | 502 => {}
            other => *file.skipped.entry(other).or_default() += 1,
        }
        Ok(())
    }

    /// A trimmed surface (144), bounded surface (143) or face of a B-rep solid (510) `e`:
    /// counted, its surface marked trimmed; a plane (108, 190) under it read bounded by it, a
    /// B-spline or exact surface's face kept in `pending`.
    fn trimmed_surface<'r>(
        &'r self,
        e: &'r DirEntry,
        scale: f64,
        file: &mut IgesFile,
        pending: &mut Pending<'r>,
    ) -> Result<(), IgesError> {
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        // a bounded surface (143, [IGES] §4.33) has TYPE before its surface pointer and a list
        // of boundaries (141) after it, the first the outer one; a trimmed surface (144) its
        // N1, N2, outer and inner boundaries (142)
        if e.entity_type == 143 {
            c.int()?;
        }
        let pts = c.int()?;
        let target = self.entry(pts, e)?;
        pending.trimmed_targets.push(target.seq);
        file.trimmed_entities += 1;
        let boundaries = match e.entity_type {
            143 => self.bounded_boundaries(&mut c, e)?,
            510 => self.loop_boundaries(&mut c, e)?,
            _ => self.face_boundaries(&mut c, e)?,
        };
        if target.entity_type == 128 {
            // a B-spline face is its surface over the face's parameter box, cut once
            // every surface is read (a writer may put the 144 before its 128: Open
            // CASCADE does)
            if let (Some(outer), inner) = boundaries {
                pending.faces.push((target.seq, (e, outer, inner)));
            }
        } else if matches!(target.entity_type, 120 | 122 | 118 | 140) {
            if let (Some(outer), inner) = boundaries {
                pending.exact_faces.push((target.seq, (e, outer, inner)));
            }
        } else if matches!(target.entity_type, 108 | 190) {
            // a plane is as large as its face: bounded by the outer boundary
            if let (Some(outer), inner) = boundaries
                && !pending.planes_read.contains(&target.seq)
            {
                let mut plane = self.bounded_plane(target, outer, e, scale)?;
                plane.holes = self.plane_holes(&inner, scale)?;
                file.surfaces.push(plane);
                pending.planes_read.push(target.seq);
            }
        }
        Ok(())
    }

    /// Each B-spline face's surface cut to its box, with its outer and inner boundaries as its
    /// trim (the first face of a surface that cuts it wins).
    fn cut_faces(
        &self,
        faces: &[(usize, FaceBoundaries<'_>)],
        scale: f64,
        file: &mut IgesFile,
    ) -> Result<(), IgesError> {
        let mut boxed = Vec::new();
        for &(target, (e, boundary, ref inner)) in faces {
            let Some(k) = file.surfaces.iter().position(|s| s.de == target) else {
                continue;
            };
            if boxed.contains(&target) {
                continue;
            }
            let (cut, trim) = self.face_box(&file.surfaces[k].surface, boundary, e, scale)?;
            if trim.len() >= 3 {
                file.surfaces[k].trim = trim;
                file.surfaces[k].holes =
                    self.spline_holes(&file.surfaces[k].surface, inner, scale)?;
            }
            if let Some(cut) = cut {
                let whole = std::mem::replace(&mut file.surfaces[k].surface, cut);
                file.surfaces[k].underlying = Some(whole);
                boxed.push(target);
            }
        }
        Ok(())
    }

    /// The trim of each face on an exact surface (its first face): the outer and inner
    /// boundaries' model-space curves on the surface.
    fn trim_exact_faces(
        &self,
        faces: &[(usize, FaceBoundaries<'_>)],
        scale: f64,
        file: &mut IgesFile,
    ) -> Result<(), IgesError> {
        for &(target, (_, boundary, ref inner)) in faces {
            if let Some(k) = file.surfaces.iter().position(|s| s.de == target)
                && file.surfaces[k].trim.is_empty()
            {
                let trim = self.model_trim(&file.surfaces[k].surface, boundary, scale)?;
                if trim.len() >= 3 {
                    let surface = &file.surfaces[k].surface;
                    let mut holes = Vec::new();
                    for b in inner {
                        holes.push(self.model_trim(surface, b, scale)?);
                    }
                    holes.retain(|h| h.len() >= 3);
                    file.surfaces[k].trim = trim;
                    file.surfaces[k].holes = holes;
                }
            }
        }
        Ok(())
    }
}
