//! The IGES reader: records, sections, global parameters, directory, parameter data, and the
//! entities 128 (rational B-spline surface), 120 (surface of revolution, with its 110 axis and
//! its 110 / 100 / 126 generatrix), 108 (plane, bounded by the outer boundary of the 144 that
//! trims it: its 142 and the 102 / 110 / 100 / 126 model-space curve), 126 (curve), 144 (trimmed
//! surface) and 124 (transformation matrix) ([IGES] §2, §4.3, §4.13, §4.16, §4.23, §4.24, §4.34, §4.21).
//! A trimmed surface's boundaries are kept as data on its surface ([`IgesSurface::trim`], the
//! outer one, and [`IgesSurface::holes`], its N2 inner ones): each 142's parameter-space curve
//! through a B-spline surface where it has one, else its model-space curve (100, 102, 110, 126)
//! on the surface.
//!
//! Control points of entity 128 are stored with the u index varying fastest, W(0,0), W(1,0), …;
//! here they go to the flat net `P[i * n_v + j]`. Weights that are all equal make a polynomial
//! surface. Coordinates are divided by the model-space scale of the Global section when it is
//! not 1 (model units → real-world units).

use std::collections::BTreeMap;

use nurbs_core::{BSplineCurve, BSplineSurface, KnotVector, Point3};

use crate::error::IgesError;
use crate::params::{Located, Param, parse_params};

/// Columns of a record, the section letter column, the data columns of the P section.
pub const RECORD_COLUMNS: usize = 80;
/// Column of the section letter (IGES 5.3 §2.1: columns 73, 0-based 72).
const LETTER_COLUMN: usize = 72;
/// Data columns of a P-section record (IGES 5.3 §2.2.4: 1–64; 65–72 hold the DE pointer).
const P_DATA_COLUMNS: usize = 64;
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
/// Points sampled along each member of a plane's boundary curve.
const BOUNDARY_SAMPLES: usize = 17;
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
}

pub(crate) struct Record<'a> {
    pub(crate) data: &'a [u8],
    pub(crate) line: usize,
}

pub(crate) struct Sections<'a> {
    pub(crate) s: Vec<Record<'a>>,
    pub(crate) g: Vec<Record<'a>>,
    pub(crate) d: Vec<Record<'a>>,
    pub(crate) p: Vec<Record<'a>>,
    pub(crate) t: Vec<Record<'a>>,
}

fn layout(line: usize, detail: impl Into<String>) -> IgesError {
    IgesError::Layout {
        line,
        detail: detail.into(),
    }
}

pub(crate) fn split_sections(bytes: &[u8]) -> Result<Sections<'_>, IgesError> {
    let mut sec = Sections {
        s: vec![],
        g: vec![],
        d: vec![],
        p: vec![],
        t: vec![],
    };
    let order = b"SGDPT";
    let mut current = 0usize;
    let mut lines: Vec<&[u8]> = bytes.split(|&b| b == b'\n').collect();
    if lines
        .last()
        .is_some_and(|l| l.is_empty() || l.iter().all(|&b| b == b'\r' || b == b' '))
    {
        lines.pop();
    }
    for (k, raw) in lines.iter().enumerate() {
        let line = k + 1;
        let rec = raw.strip_suffix(b"\r").unwrap_or(raw);
        if rec.len() <= LETTER_COLUMN {
            return Err(layout(
                line,
                format!(
                    "record has {} columns; IGES records have {RECORD_COLUMNS} with the section letter in column 73",
                    rec.len()
                ),
            ));
        }
        if rec.len() > RECORD_COLUMNS && rec[RECORD_COLUMNS..].iter().any(|&b| b != b' ') {
            return Err(layout(
                line,
                format!(
                    "record has {} columns, more than {RECORD_COLUMNS}",
                    rec.len()
                ),
            ));
        }
        let letter = rec[LETTER_COLUMN];
        let Some(pos) = order.iter().position(|&c| c == letter) else {
            let what = if matches!(letter, b'C' | b'B') {
                "compressed or binary IGES is not supported"
            } else {
                "column 73 must hold a section letter S, G, D, P or T"
            };
            return Err(layout(line, format!("{what} (found {:?})", letter as char)));
        };
        if pos < current {
            return Err(layout(
                line,
                format!(
                    "section {} after section {}",
                    letter as char, order[current] as char
                ),
            ));
        }
        current = pos;
        let seq_text = std::str::from_utf8(&rec[LETTER_COLUMN + 1..rec.len().min(RECORD_COLUMNS)])
            .unwrap_or("")
            .trim();
        let list = match letter {
            b'S' => &mut sec.s,
            b'G' => &mut sec.g,
            b'D' => &mut sec.d,
            b'P' => &mut sec.p,
            _ => &mut sec.t,
        };
        let expected = list.len() + 1;
        match seq_text.parse::<usize>() {
            Ok(n) if n == expected => {}
            _ => {
                return Err(layout(
                    line,
                    format!("sequence number {seq_text:?} in columns 74–80, expected {expected}"),
                ));
            }
        }
        list.push(Record {
            data: &rec[..LETTER_COLUMN],
            line,
        });
    }
    if sec.t.len() != 1 {
        return Err(IgesError::Structure {
            detail: format!(
                "the file must end with one Terminate record, found {} (truncated file?)",
                sec.t.len()
            ),
        });
    }
    if sec.g.is_empty() {
        return Err(IgesError::Structure {
            detail: "the Global section is missing".into(),
        });
    }
    if !sec.d.len().is_multiple_of(2) {
        return Err(layout(
            sec.d.last().map_or(0, |r| r.line),
            "the Directory section has an odd number of records (each entry is two)",
        ));
    }
    Ok(sec)
}

/// Concatenates the data columns of records, remembering the file line of every byte.
fn concat(records: &[Record<'_>], columns: usize) -> (Vec<u8>, Vec<usize>) {
    let mut text = Vec::with_capacity(records.len() * columns);
    let mut lines = Vec::with_capacity(records.len() * columns);
    for r in records {
        let d = &r.data[..columns.min(r.data.len())];
        text.extend_from_slice(d);
        lines.extend(std::iter::repeat_n(r.line, d.len()));
    }
    (text, lines)
}

pub(crate) struct Global {
    pdelim: u8,
    rdelim: u8,
    params: Vec<Located>,
}

pub(crate) fn parse_global(records: &[Record<'_>]) -> Result<Global, IgesError> {
    let (text, lines) = concat(records, LETTER_COLUMN);
    let first_line = records[0].line;
    let mut i = 0;
    let mut delims = [b',', b';'];
    for k in 0..2 {
        while i < text.len() && text[i] == b' ' {
            i += 1;
        }
        if text.get(i..i + 2) == Some(b"1H") || text.get(i..i + 2) == Some(b"1h") {
            delims[k] = *text
                .get(i + 2)
                .ok_or_else(|| layout(first_line, "Global section ends inside a delimiter"))?;
            i += 3;
        }
        // each of the two fields is followed by the parameter delimiter
        while i < text.len() && text[i] == b' ' {
            i += 1;
        }
        match text.get(i) {
            Some(&c) if c == delims[0] => i += 1,
            _ => {
                return Err(IgesError::Parameter {
                    line: first_line,
                    detail: "Global section: parameter and record delimiters are malformed".into(),
                });
            }
        }
    }
    let [pdelim, rdelim] = delims;
    let params = parse_params(&text[i..], &lines[i..], pdelim, rdelim)?;
    Ok(Global {
        pdelim,
        rdelim,
        params,
    })
}

#[derive(Debug, Clone, Copy)]
pub(crate) struct DirEntry {
    pub(crate) seq: usize,
    pub(crate) entity_type: i64,
    pub(crate) pointer: i64,
    transform: i64,
    pub(crate) line_count: i64,
    /// the form number (second line, field 5)
    form: i64,
    label: [u8; 8],
    subscript: i64,
}

pub(crate) fn parse_directory(records: &[Record<'_>]) -> Result<Vec<DirEntry>, IgesError> {
    let field = |r: &Record<'_>, k: usize| -> Result<i64, IgesError> {
        let raw = std::str::from_utf8(&r.data[8 * k..8 * k + 8])
            .unwrap_or("")
            .trim();
        if raw.is_empty() {
            return Ok(0);
        }
        raw.parse::<i64>().map_err(|_| {
            layout(
                r.line,
                format!("directory field {} is {raw:?}, not an integer", k + 1),
            )
        })
    };
    let mut out = Vec::with_capacity(records.len() / 2);
    for (k, pair) in records.chunks(2).enumerate() {
        let (a, b) = (&pair[0], &pair[1]);
        let entity_type = field(a, 0)?;
        if field(b, 0)? != entity_type {
            return Err(layout(
                b.line,
                format!(
                    "entity type {} differs from {entity_type} on the line before",
                    field(b, 0)?
                ),
            ));
        }
        let mut label = [b' '; 8];
        label.copy_from_slice(&b.data[56..64]);
        out.push(DirEntry {
            seq: 2 * k + 1,
            entity_type,
            pointer: field(a, 1)?,
            transform: field(a, 6)?,
            line_count: field(b, 3)?,
            form: field(b, 4)?,
            label,
            subscript: field(b, 8).unwrap_or(0),
        });
    }
    Ok(out)
}

/// Reads the parameters of one entity.
pub(crate) fn entity_params(
    e: &DirEntry,
    p: &[Record<'_>],
    g: &Global,
) -> Result<Vec<Located>, IgesError> {
    let err = |detail: String| IgesError::Entity {
        de: e.seq,
        entity_type: e.entity_type,
        detail,
    };
    if e.pointer < 1 || e.line_count < 1 || (e.pointer + e.line_count - 1) as usize > p.len() {
        return Err(err(format!(
            "parameter data pointer {} with {} lines is out of range (the P section has {} lines)",
            e.pointer,
            e.line_count,
            p.len()
        )));
    }
    let records = &p[e.pointer as usize - 1..(e.pointer + e.line_count - 1) as usize];
    for r in records {
        let back = std::str::from_utf8(&r.data[64..72])
            .unwrap_or("")
            .trim()
            .parse::<usize>()
            .ok();
        if back != Some(e.seq) {
            return Err(layout(
                r.line,
                format!(
                    "parameter line points back to directory entry {back:?}, expected {}",
                    e.seq
                ),
            ));
        }
    }
    let (text, lines) = concat(records, P_DATA_COLUMNS);
    let params = parse_params(&text, &lines, g.pdelim, g.rdelim)?;
    match params.first().map(|p| &p.value) {
        Some(Param::Number(t)) if *t as i64 == e.entity_type => Ok(params),
        other => Err(err(format!(
            "parameter data starts with {other:?}, not the entity type"
        ))),
    }
}

/// Sequential access to an entity's parameters with errors that name the entity.
struct Cursor<'a> {
    params: &'a [Located],
    next: usize,
    e: &'a DirEntry,
}

impl<'a> Cursor<'a> {
    fn err(&self, detail: String) -> IgesError {
        IgesError::Entity {
            de: self.e.seq,
            entity_type: self.e.entity_type,
            detail,
        }
    }
    fn real(&mut self) -> Result<f64, IgesError> {
        let k = self.next;
        let p = self.params.get(k).ok_or_else(|| {
            self.err(format!(
                "the data ends after {} parameters, but more are needed (count mismatch)",
                self.params.len()
            ))
        })?;
        self.next += 1;
        match &p.value {
            Param::Number(x) => Ok(*x),
            Param::Empty => Ok(0.0),
            Param::Text(_) => Err(IgesError::Parameter {
                line: p.line,
                detail: format!(
                    "parameter {k} of entity {} is a string, expected a number",
                    self.e.seq
                ),
            }),
        }
    }
    fn int(&mut self) -> Result<i64, IgesError> {
        let line = self.params.get(self.next).map_or(0, |p| p.line);
        let x = self.real()?;
        if x.fract() != 0.0 || x.abs() > 1e15 {
            return Err(IgesError::Parameter {
                line,
                detail: format!(
                    "parameter {} of entity {} is {x}, expected an integer",
                    self.next - 1,
                    self.e.seq
                ),
            });
        }
        Ok(x as i64)
    }
    fn count(&mut self, what: &str, min: i64) -> Result<usize, IgesError> {
        let n = self.int()?;
        if n < min || n > 1_000_000 {
            return Err(self.err(format!("{what} is {n}")));
        }
        Ok(n as usize)
    }
    fn reals(&mut self, n: usize) -> Result<Vec<f64>, IgesError> {
        (0..n).map(|_| self.real()).collect()
    }
}

/// An affine map x ↦ R x + t.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Affine {
    r: [[f64; 3]; 3],
    t: [f64; 3],
}

impl Affine {
    fn apply(&self, p: &Point3) -> Point3 {
        let c = |k: usize| self.r[k][0] * p.x + self.r[k][1] * p.y + self.r[k][2] * p.z + self.t[k];
        Point3::new(c(0), c(1), c(2))
    }
    fn then(&self, outer: &Affine) -> Affine {
        let mut r = [[0.0; 3]; 3];
        let mut t = [0.0; 3];
        for i in 0..3 {
            for j in 0..3 {
                r[i][j] = (0..3).map(|k| outer.r[i][k] * self.r[k][j]).sum();
            }
            t[i] = (0..3).map(|k| outer.r[i][k] * self.t[k]).sum::<f64>() + outer.t[i];
        }
        Affine { r, t }
    }
}

struct Reader<'a> {
    dir: Vec<DirEntry>,
    p: Vec<Record<'a>>,
    global: Global,
}

impl Reader<'_> {
    fn entry(&self, pointer: i64, from: &DirEntry) -> Result<&DirEntry, IgesError> {
        if pointer < 1 || pointer % 2 == 0 || (pointer as usize).div_ceil(2) > self.dir.len() {
            return Err(IgesError::Entity {
                de: from.seq,
                entity_type: from.entity_type,
                detail: format!("pointer {pointer} does not name a directory entry"),
            });
        }
        Ok(&self.dir[(pointer as usize - 1) / 2])
    }

    /// The composite transformation of an entity (identity when it has none).
    fn transform(&self, e: &DirEntry) -> Result<Option<Affine>, IgesError> {
        let mut total: Option<Affine> = None;
        let mut pointer = e.transform;
        let mut depth = 0;
        while pointer != 0 {
            depth += 1;
            if depth > MAX_TRANSFORM_CHAIN {
                return Err(IgesError::Entity {
                    de: e.seq,
                    entity_type: e.entity_type,
                    detail: "transformation matrices form a cycle".into(),
                });
            }
            let m = self.entry(pointer, e)?;
            if m.entity_type != 124 {
                return Err(IgesError::Entity {
                    de: e.seq,
                    entity_type: e.entity_type,
                    detail: format!(
                        "transformation pointer {pointer} names entity type {}",
                        m.entity_type
                    ),
                });
            }
            let params = entity_params(m, &self.p, &self.global)?;
            let mut c = Cursor {
                params: &params,
                next: 1,
                e: m,
            };
            let v = c.reals(12)?;
            let a = Affine {
                r: [[v[0], v[1], v[2]], [v[4], v[5], v[6]], [v[8], v[9], v[10]]],
                t: [v[3], v[7], v[11]],
            };
            total = Some(match total {
                None => a,
                Some(inner) => inner.then(&a),
            });
            pointer = m.transform;
        }
        Ok(total)
    }

    fn name(e: &DirEntry) -> String {
        let label = String::from_utf8_lossy(&e.label).trim().to_string();
        match (label.is_empty(), e.subscript) {
            (true, _) => format!("iges{}", e.seq),
            (false, 0) => label,
            (false, s) => format!("{label}_{s}"),
        }
    }

    fn geometry_err(e: &DirEntry) -> impl Fn(nurbs_core::Error) -> IgesError + '_ {
        move |source| IgesError::Geometry {
            de: e.seq,
            entity_type: e.entity_type,
            source,
        }
    }

    fn points(&self, e: &DirEntry, coords: &[f64], scale: f64) -> Result<Vec<Point3>, IgesError> {
        let affine = self.transform(e)?;
        Ok(coords
            .chunks(3)
            .map(|c| {
                let p = Point3::new(c[0], c[1], c[2]);
                let p = affine.map_or(p, |a| a.apply(&p));
                if scale != 1.0 {
                    Point3::from(p.coords / scale)
                } else {
                    p
                }
            })
            .collect())
    }

    fn surface(&self, e: &DirEntry, scale: f64) -> Result<IgesSurface, IgesError> {
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let k1 = c.count("K1 (upper index of the u control points)", 1)?;
        let k2 = c.count("K2 (upper index of the v control points)", 1)?;
        let m1 = c.count("M1 (u degree)", 1)?;
        let m2 = c.count("M2 (v degree)", 1)?;
        let _props = c.reals(5)?;
        let (nu, nv) = (k1 + 1, k2 + 1);
        let ku = c.reals(k1 + m1 + 2)?;
        let kv = c.reals(k2 + m2 + 2)?;
        let w = c.reals(nu * nv)?;
        let coords = c.reals(3 * nu * nv)?;
        let range = c.reals(4)?;
        let pts = self.points(e, &coords, scale)?;
        let mut points = vec![Point3::origin(); nu * nv];
        let mut weights = vec![1.0; nu * nv];
        for j in 0..nv {
            for i in 0..nu {
                points[i * nv + j] = pts[i + nu * j];
                weights[i * nv + j] = w[i + nu * j];
            }
        }
        let polynomial = weights.iter().all(|&x| x == weights[0]) && weights[0] > 0.0;
        let g = Self::geometry_err(e);
        let knots_u = KnotVector::new(m1, ku).map_err(|x| g(x.context("u knots")))?;
        let knots_v = KnotVector::new(m2, kv).map_err(|x| g(x.context("v knots")))?;
        let surface =
            BSplineSurface::new(knots_u, knots_v, points, (!polynomial).then_some(weights))
                .map_err(&g)?;
        Ok(IgesSurface {
            de: e.seq,
            name: Self::name(e),
            surface,
            trimmed: false,
            param_range: [range[0], range[1], range[2], range[3]],
            underlying: None,
            trim: Vec::new(),
            holes: Vec::new(),
        })
    }

    /// A curve entity as an exact NURBS curve: 110 (line segment, degree 1), 100 (circular arc,
    /// rational quadratic, [IGES] §4.3: centre, start and end in the plane z = ZT of its
    /// definition space, counterclockwise; start = end is a full circle) or 126. The entity's
    /// transformation applies to the control points, which is exact for a rational curve.
    fn any_curve(&self, e: &DirEntry, scale: f64) -> Result<BSplineCurve, IgesError> {
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let g = Self::geometry_err(e);
        match e.entity_type {
            110 => {
                let ends = c.reals(6)?;
                let pts = self.points(e, &ends, scale)?;
                BSplineCurve::new(nurbs_core::KnotVector::bezier(1).map_err(&g)?, pts, None)
                    .map_err(&g)
            }
            100 => {
                let v = c.reals(7)?;
                let (zt, centre) = (v[0], (v[1], v[2]));
                let (a, b) = (
                    (v[3] - centre.0, v[4] - centre.1),
                    (v[5] - centre.0, v[6] - centre.1),
                );
                let r = a.0.hypot(a.1);
                let start = a.1.atan2(a.0);
                let mut end = b.1.atan2(b.0);
                while end <= start + 1e-12 {
                    end += std::f64::consts::TAU;
                }
                let arc = nurbs_core::shapes::arc(
                    Point3::new(centre.0, centre.1, zt),
                    nurbs_core::Vector3::x(),
                    nurbs_core::Vector3::y(),
                    r,
                    start,
                    end,
                )
                .map_err(&g)?;
                let coords: Vec<f64> = arc
                    .control_points()
                    .iter()
                    .flat_map(|p| [p.x, p.y, p.z])
                    .collect();
                let pts = self.points(e, &coords, scale)?;
                BSplineCurve::new(arc.knots().clone(), pts, arc.weights().map(<[f64]>::to_vec))
                    .map_err(&g)
            }
            126 => Ok(self.curve(e, scale)?.curve),
            other => Err(IgesError::Entity {
                de: e.seq,
                entity_type: other,
                detail:
                    "a curve of this type is not read (lines 110, arcs 100 and B-splines 126 are)"
                        .to_string(),
            }),
        }
    }

    /// Entity 120, the surface of revolution ([IGES] §4.16): the generatrix C turned about the
    /// axis line L from the start angle SA to the terminate angle TA, right-handed about L's
    /// direction (start point to end point), as an exact rational surface
    /// ([`nurbs_core::shapes::revolve_curve`]): u along C, v around the axis.
    fn revolution(&self, e: &DirEntry, scale: f64) -> Result<IgesSurface, IgesError> {
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let axis = self.entry(c.int()?, e)?;
        let generatrix = self.entry(c.int()?, e)?;
        let (sa, ta) = (c.real()?, c.real()?);
        if axis.entity_type != 110 {
            return Err(IgesError::Entity {
                de: e.seq,
                entity_type: e.entity_type,
                detail: format!(
                    "the axis is entity {}, expected a line (110)",
                    axis.entity_type
                ),
            });
        }
        // the axis and the generatrix are in the 120's definition space: the surface is built
        // there, then the 120's own transformation and the model scale apply to its net
        let line = self.any_curve(axis, 1.0)?;
        let (o, d) = (
            line.control_points()[0],
            line.control_points()[1] - line.control_points()[0],
        );
        let curve = self.any_curve(generatrix, 1.0)?;
        let g = Self::geometry_err(e);
        let local = nurbs_core::shapes::revolve_curve(&curve, o, d, sa, ta).map_err(&g)?;
        let (t0, t1) = curve.knots().domain();
        self.placed(e, local, scale, [t0, t1, sa, ta])
    }

    /// A surface built in an entity's definition space, moved into model space by the entity's
    /// own transformation and the model scale (exact: an affine map of a rational net).
    fn placed(
        &self,
        e: &DirEntry,
        local: BSplineSurface,
        scale: f64,
        param_range: [f64; 4],
    ) -> Result<IgesSurface, IgesError> {
        let coords: Vec<f64> = local
            .control_points()
            .iter()
            .flat_map(|p| [p.x, p.y, p.z])
            .collect();
        let points = self.points(e, &coords, scale)?;
        let surface = BSplineSurface::new(
            local.knots_u().clone(),
            local.knots_v().clone(),
            points,
            local.weights().map(<[f64]>::to_vec),
        )
        .map_err(Self::geometry_err(e))?;
        Ok(IgesSurface {
            de: e.seq,
            name: Self::name(e),
            surface,
            trimmed: false,
            param_range,
            underlying: None,
            trim: Vec::new(),
            holes: Vec::new(),
        })
    }

    /// Entity 122, the tabulated cylinder ([IGES] §4.19): the directrix C (110, 100 or 126)
    /// moved along the line from its start point C(t0) to the terminate point L,
    /// S(u, v) = C(u) + v (L − C(t0)), v ∈ [0, 1], exactly
    /// ([`nurbs_core::shapes::extrude_curve`]); u keeps the directrix's parameter.
    fn tabulated(&self, e: &DirEntry, scale: f64) -> Result<IgesSurface, IgesError> {
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let directrix = self.entry(c.int()?, e)?;
        let l = c.reals(3)?;
        let curve = self.any_curve(directrix, 1.0)?;
        let (t0, t1) = curve.knots().domain();
        let d = Point3::new(l[0], l[1], l[2]) - curve.point(t0);
        let local = nurbs_core::shapes::extrude_curve(&curve, d, (0.0, 1.0))
            .map_err(Self::geometry_err(e))?;
        self.placed(e, local, scale, [t0, t1, 0.0, 1.0])
    }

    /// Entity 118, the ruled surface ([IGES] §4.14) between two curves (110, 100 or 126),
    /// S(u, v) = (1 − v) C₁(u) + v C₂(u), DIRFLG 1 joining the first end of C₁ to the last of
    /// C₂, exactly ([`nurbs_core::shapes::ruled_surface`]). Form 1 (equal relative parameter)
    /// is that surface. Form 0 rules points of equal relative arc length: it is read when the
    /// two curves' relative arc lengths agree at their relative parameters within
    /// [`RULED_ARC_LENGTH_RELATIVE`] (lines, arcs of the same sweep, one curve a scaled copy
    /// of the other), and refused otherwise rather than approximated.
    fn ruled(&self, e: &DirEntry, scale: f64) -> Result<IgesSurface, IgesError> {
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let first = self.entry(c.int()?, e)?;
        let second = self.entry(c.int()?, e)?;
        let reversed = c.int()? == 1;
        let a = self.any_curve(first, 1.0)?;
        let mut b = self.any_curve(second, 1.0)?;
        if reversed {
            b = b.reversed().map_err(Self::geometry_err(e))?;
        }
        if e.form == 0 {
            let (fa, fb) = (relative_arc_lengths(&a), relative_arc_lengths(&b));
            let off = fa
                .iter()
                .zip(&fb)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            if off > RULED_ARC_LENGTH_RELATIVE {
                return Err(IgesError::Entity {
                    de: e.seq,
                    entity_type: e.entity_type,
                    detail: format!(
                        "form 0 rules points of equal arc length, and the two curves' relative arc lengths differ by up to {off:.3e} at equal parameters: not read exactly"
                    ),
                });
            }
        }
        let local = nurbs_core::shapes::ruled_surface(&a, &b).map_err(Self::geometry_err(e))?;
        self.placed(e, local, scale, [0.0, 1.0, 0.0, 1.0])
    }

    /// Points along a model-space boundary curve: a composite (102) of lines, arcs and
    /// B-splines, each sampled at [`BOUNDARY_SAMPLES`] points; every transformation from the
    /// member up to `e` applied, not the model scale.
    fn boundary_points(&self, e: &DirEntry, depth: usize) -> Result<Vec<Point3>, IgesError> {
        self.boundary_samples(e, depth, BOUNDARY_SAMPLES)
    }

    /// [`Self::boundary_points`] with `samples` points per member.
    fn boundary_samples(
        &self,
        e: &DirEntry,
        depth: usize,
        samples: usize,
    ) -> Result<Vec<Point3>, IgesError> {
        if depth > MAX_TRANSFORM_CHAIN {
            return Err(IgesError::Entity {
                de: e.seq,
                entity_type: e.entity_type,
                detail: "composite curves nest too deep (a cycle?)".into(),
            });
        }
        let local = match e.entity_type {
            102 => {
                let params = entity_params(e, &self.p, &self.global)?;
                let mut c = Cursor {
                    params: &params,
                    next: 1,
                    e,
                };
                let n = c.count("N (number of curves of the composite)", 0)?;
                let mut out = Vec::new();
                for _ in 0..n {
                    let member = self.entry(c.int()?, e)?;
                    out.extend(self.boundary_samples(member, depth + 1, samples)?);
                }
                // the members carry their own transformations; the composite's applies on top
                return Ok(match self.transform(e)? {
                    Some(a) => out.iter().map(|p| a.apply(p)).collect(),
                    None => out,
                });
            }
            _ => self.any_curve(e, 1.0)?,
        };
        let (t0, t1) = local.knots().domain();
        Ok((0..samples)
            .map(|k| local.point(t0 + (t1 - t0) * k as f64 / (samples - 1) as f64))
            .collect())
    }

    /// The pointers of a curve on a surface (142, [IGES] §4.32): to its parameter-space curve
    /// and to its model-space curve (0 where absent).
    fn curve_on_surface(&self, e: &DirEntry) -> Result<(i64, i64), IgesError> {
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let (_crtn, _surface) = (c.int()?, c.int()?);
        Ok((c.int()?, c.int()?))
    }

    /// `surface` cut to the parameter box of the outer boundary `boundary` (142) of the trimmed
    /// surface `face`: the box of its parameter-space curve, or where the 142 has none, of its
    /// model-space curve projected onto the surface; clamped to the surface's domain (`None`
    /// where the 142 has neither curve, or the box is the whole domain to [`BOX_RELATIVE`]). A
    /// kernel trims a face on its underlying surface, which may run far beyond it (a fillet past
    /// the faces it ends on); the face's box is the surface the face uses, as the kernel's own
    /// UV bounds give it. The curves are sampled densely ([`FACE_BOX_SAMPLES`]): a box short of
    /// the trim leaves the fillet that bounds the face off its master.
    fn face_box(
        &self,
        surface: &BSplineSurface,
        boundary: &DirEntry,
        face: &DirEntry,
        scale: f64,
    ) -> Result<(Option<BSplineSurface>, Vec<Point3>), IgesError> {
        let (parametric, model) = self.curve_on_surface(boundary)?;
        if parametric == 0 && model == 0 {
            return Ok((None, Vec::new()));
        }
        // the boundary's points on the surface, in order (the face's trim as data)
        let mut trim: Vec<Point3> = Vec::new();
        let (du, dv) = (surface.domain_u(), surface.domain_v());
        let mut b = [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        if parametric != 0 {
            let curve = self.entry(parametric, boundary)?;
            for p in &self.boundary_samples(curve, 0, FACE_BOX_SAMPLES)? {
                b = [b[0].min(p.x), b[1].max(p.x), b[2].min(p.y), b[3].max(p.y)];
                if p.x.is_finite() && p.y.is_finite() {
                    let (u, v) = (p.x.clamp(du.0, du.1), p.y.clamp(dv.0, dv.1));
                    trim.push(surface.point(u, v));
                }
            }
        }
        if parametric == 0 {
            for (u, v) in self.model_space_feet(surface, model, boundary, scale)? {
                b = [b[0].min(u), b[1].max(u), b[2].min(v), b[3].max(v)];
                trim.push(surface.point(u, v));
            }
        }
        if !b.iter().all(|x| x.is_finite()) {
            return Ok((None, trim));
        }
        let (u0, u1) = (b[0].max(du.0), b[1].min(du.1));
        let (v0, v1) = (b[2].max(dv.0), b[3].min(dv.1));
        if !(u1 > u0 && v1 > v0) {
            return Err(IgesError::Entity {
                de: face.seq,
                entity_type: face.entity_type,
                detail: format!(
                    "the outer boundary's parameter box [{}, {}] × [{}, {}] misses the surface's domain",
                    b[0], b[1], b[2], b[3]
                ),
            });
        }
        let tiny = |a: f64, b: f64, d: (f64, f64)| (a - b).abs() <= BOX_RELATIVE * (d.1 - d.0);
        if tiny(u0, du.0, du) && tiny(u1, du.1, du) && tiny(v0, dv.0, dv) && tiny(v1, dv.1, dv) {
            return Ok((None, trim));
        }
        let cut = surface
            .extract((u0, u1), (v0, v1))
            .map_err(Self::geometry_err(face))?;
        Ok((Some(cut), trim))
    }

    /// The feet on `surface` (parameters, in order) of the samples of the model-space curve
    /// `model` of the boundary (142) `boundary`: a point of the trim lies on the surface, so one
    /// that projects farther than the rounding of the file is no point of this face (a broken
    /// curve) and is left out. Consecutive samples are close: each starts from the last one's
    /// parameters, and from the sampled starts where that does not land on the surface.
    fn model_space_feet(
        &self,
        surface: &BSplineSurface,
        model: i64,
        boundary: &DirEntry,
        scale: f64,
    ) -> Result<Vec<(f64, f64)>, IgesError> {
        let curve = self.entry(model, boundary)?;
        let mut pts = self.boundary_samples(curve, 0, FACE_BOX_SAMPLES)?;
        if let Some(a) = self.transform(boundary)? {
            pts = pts.iter().map(|p| a.apply(p)).collect();
        }
        let near = ON_SURFACE_RELATIVE * surface.size();
        let mut projector =
            nurbs_core::SurfaceProjector::new(surface, nurbs_core::ProjectionParams::default());
        let mut last: Option<(f64, f64)> = None;
        let mut feet = Vec::new();
        for p in &pts {
            let p = Point3::from(p.coords / scale);
            let mut pr = match last {
                Some(uv) => projector.project_from(&p, uv),
                None => projector.project(&p),
            };
            if pr.distance > near {
                pr = projector.project(&p);
            }
            if pr.distance <= near {
                feet.push((pr.u, pr.v));
                last = Some((pr.u, pr.v));
            } else {
                last = None;
            }
        }
        Ok(feet)
    }

    /// The outer boundary (142) `boundary` of a face on `surface` (an exact surface read over
    /// its own range: a revolution, a tabulated cylinder, a ruled surface) as points on it, from
    /// the boundary's model-space curve; empty where the boundary has none.
    fn model_trim(
        &self,
        surface: &BSplineSurface,
        boundary: &DirEntry,
        scale: f64,
    ) -> Result<Vec<Point3>, IgesError> {
        let (_, model) = self.curve_on_surface(boundary)?;
        if model == 0 {
            return Ok(Vec::new());
        }
        Ok(self
            .model_space_feet(surface, model, boundary, scale)?
            .into_iter()
            .map(|(u, v)| surface.point(u, v))
            .collect())
    }

    /// An offset surface ([IGES], entity 140): S(u, v) + d N(u, v) over the base surface's
    /// domain, N its unit normal, turned to the side of the offset indicator (NX, NY, NZ) where
    /// that is given. An offset is not a NURBS surface in general, so it is approximated: a
    /// polynomial B-spline of degree max(3, the base's) on the base's breakpoints, fitted by least
    /// squares to the exact offset and refined (every span halved) until it lies within
    /// [`crate::offset::OFFSET_TOLERANCE_RELATIVE`] of the base's size at points between the fitted ones, up to
    /// [`crate::offset::OFFSET_MAX_NET`] control points per direction; otherwise, or where the base's normal
    /// is undefined, the entity is refused with the error reached.
    fn offset(&self, e: &DirEntry, scale: f64) -> Result<IgesSurface, IgesError> {
        let err = |detail: String| IgesError::Entity {
            de: e.seq,
            entity_type: e.entity_type,
            detail,
        };
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let indicator = c.reals(4)?;
        let base_de = c.int()?;
        if self.transform(e)?.is_some() {
            return Err(err(
                "an offset surface with its own transformation is not read".into(),
            ));
        }
        let base_entry = self.entry(base_de, e)?;
        let base = match base_entry.entity_type {
            128 => self.surface(base_entry, scale)?,
            120 => self.revolution(base_entry, scale)?,
            122 => self.tabulated(base_entry, scale)?,
            118 => self.ruled(base_entry, scale)?,
            other => return Err(err(format!("the offset of entity {other} is not read"))),
        }
        .surface;
        let mut d = indicator[3] / scale;
        let (du, dv) = (base.domain_u(), base.domain_v());
        let mid = base.derivatives(0.5 * (du.0 + du.1), 0.5 * (dv.0 + dv.1));
        let side = nurbs_core::Vector3::new(indicator[0], indicator[1], indicator[2]);
        if let Some(n) = mid.normal()
            && n.dot(&side) < 0.0
        {
            d = -d;
        }
        let surface = crate::offset::approximate_offset(&base, d).map_err(err)?;
        Ok(IgesSurface {
            de: e.seq,
            name: Self::name(e),
            surface,
            trimmed: false,
            param_range: [du.0, du.1, dv.0, dv.1],
            underlying: None,
            trim: Vec::new(),
            holes: Vec::new(),
        })
    }

    /// A plane (108) under a trimmed surface (144) whose outer boundary (142, its model-space
    /// curve) bounds it ([IGES] §4.12, §4.32): the bilinear 2 × 2 patch over the smallest
    /// rectangle in the plane that holds the boundary, its sides along one of the boundary's
    /// chords (the minimum-area rectangle of a polygon has a side along one of its edges: exact
    /// for a face bounded by lines, tight for one bounded by arcs), u and v by length.
    fn bounded_plane(
        &self,
        plane: &DirEntry,
        boundary: &DirEntry,
        face: &DirEntry,
        scale: f64,
    ) -> Result<IgesSurface, IgesError> {
        let err = |detail: String| IgesError::Entity {
            de: face.seq,
            entity_type: face.entity_type,
            detail,
        };
        let params = entity_params(plane, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e: plane,
        };
        let abcd = c.reals(4)?;
        let mut n = nurbs_core::Vector3::new(abcd[0], abcd[1], abcd[2]);
        let len = n.norm();
        if !(len > 0.0) {
            return Err(err("the plane's normal (A, B, C) is zero".into()));
        }
        n /= len;
        let mut origin = Point3::from(n * (abcd[3] / len));
        if let Some(a) = self.transform(plane)? {
            let tip = a.apply(&(origin + n));
            origin = a.apply(&origin);
            n = (tip - origin)
                .try_normalize(0.0)
                .ok_or_else(|| err("the plane's transformation is singular".into()))?;
        }
        let (_, model_curve) = self.curve_on_surface(boundary)?;
        if model_curve == 0 {
            return Err(err("the plane's boundary has no model-space curve".into()));
        }
        let curve = self.entry(model_curve, boundary)?;
        let mut pts = self.boundary_points(curve, 0)?;
        if let Some(a) = self.transform(boundary)? {
            pts = pts.iter().map(|p| a.apply(p)).collect();
        }
        if pts.len() < 3 {
            return Err(err("the plane's boundary has fewer than 3 points".into()));
        }
        // a frame in the plane: any unit x ⟂ n, then y = n × x
        let helper = if n.x.abs() < 0.9 {
            nurbs_core::Vector3::x()
        } else {
            nurbs_core::Vector3::y()
        };
        let e1 = n.cross(&helper).normalize();
        let e2 = n.cross(&e1);
        let flat: Vec<(f64, f64)> = pts
            .iter()
            .map(|p| {
                let d = p - origin;
                (d.dot(&e1), d.dot(&e2))
            })
            .collect();
        let mut best: Option<(f64, f64, [f64; 4])> = None;
        for w in flat.windows(2) {
            let (dx, dy) = (w[1].0 - w[0].0, w[1].1 - w[0].1);
            let l = dx.hypot(dy);
            if !(l > 0.0) {
                continue;
            }
            let (cx, cy) = (dx / l, dy / l);
            let mut b = [
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ];
            for &(x, y) in &flat {
                let (a, c) = (x * cx + y * cy, -x * cy + y * cx);
                b = [b[0].min(a), b[1].max(a), b[2].min(c), b[3].max(c)];
            }
            let area = (b[1] - b[0]) * (b[3] - b[2]);
            if best.is_none_or(|(ar, _, _)| area < ar) {
                best = Some((area, cy.atan2(cx), b));
            }
        }
        let Some((_, angle, b)) = best else {
            return Err(err("the plane's boundary is a single point".into()));
        };
        let (x, y) = (
            e1 * angle.cos() + e2 * angle.sin(),
            -e1 * angle.sin() + e2 * angle.cos(),
        );
        let corner = origin + x * b[0] + y * b[2];
        let (lu, lv) = ((b[1] - b[0]) / scale, (b[3] - b[2]) / scale);
        let surface = nurbs_core::shapes::plane_patch(
            Point3::from(corner.coords / scale),
            x,
            y,
            (0.0, lu),
            (0.0, lv),
        )
        .map_err(Self::geometry_err(face))?;
        Ok(IgesSurface {
            de: plane.seq,
            name: Self::name(plane),
            surface,
            trimmed: true,
            param_range: [0.0, lu, 0.0, lv],
            underlying: None,
            trim: pts.iter().map(|p| Point3::from(p.coords / scale)).collect(),
            holes: Vec::new(),
        })
    }

    /// The boundaries of a trimmed surface (144, [IGES] §4.34) after its surface pointer: N1
    /// (whether the outer boundary is the domain's), N2 (the number of inner boundaries), the
    /// outer boundary's 142 (`None` where PTO is 0) and the N2 inner boundaries' 142s.
    fn face_boundaries<'r>(
        &'r self,
        c: &mut Cursor<'_>,
        e: &DirEntry,
    ) -> Result<(Option<&'r DirEntry>, Vec<&'r DirEntry>), IgesError> {
        let _n1 = c.int()?;
        let n2 = c.int()?;
        let outer = c.int()?;
        let outer = if outer == 0 {
            None
        } else {
            Some(self.entry(outer, e)?)
        };
        let mut inner = Vec::new();
        for _ in 0..n2.max(0) {
            inner.push(self.entry(c.int()?, e)?);
        }
        Ok((outer, inner))
    }

    /// The inner boundaries (142s) `inner` of a face on the B-spline surface `surface` as
    /// points on it in order, as [`Self::face_box`] takes the outer one: the parameter-space
    /// curve through the surface where the 142 has one, else the model-space curve's feet on
    /// the surface; sampled at [`FACE_BOX_SAMPLES`] points per member. A boundary with fewer
    /// than 3 points on the surface is left out.
    fn spline_holes(
        &self,
        surface: &BSplineSurface,
        inner: &[&DirEntry],
        scale: f64,
    ) -> Result<Vec<Vec<Point3>>, IgesError> {
        let (du, dv) = (surface.domain_u(), surface.domain_v());
        let mut holes = Vec::new();
        for &boundary in inner {
            let (parametric, model) = self.curve_on_surface(boundary)?;
            let hole: Vec<Point3> = if parametric != 0 {
                let curve = self.entry(parametric, boundary)?;
                self.boundary_samples(curve, 0, FACE_BOX_SAMPLES)?
                    .iter()
                    .filter(|p| p.x.is_finite() && p.y.is_finite())
                    .map(|p| surface.point(p.x.clamp(du.0, du.1), p.y.clamp(dv.0, dv.1)))
                    .collect()
            } else if model != 0 {
                self.model_space_feet(surface, model, boundary, scale)?
                    .into_iter()
                    .map(|(u, v)| surface.point(u, v))
                    .collect()
            } else {
                Vec::new()
            };
            if hole.len() >= 3 {
                holes.push(hole);
            }
        }
        Ok(holes)
    }

    /// The inner boundaries (142s) `inner` of a face on a plane (108) as points in order: the
    /// samples of each model-space curve ([`FACE_BOX_SAMPLES`] per member, the 142's
    /// transformation and the model scale applied), which lie in the plane. A boundary without
    /// a model-space curve, or with fewer than 3 points, is left out: a 108 defines no
    /// parameter space its parameter-space curve could be mapped through.
    fn plane_holes(&self, inner: &[&DirEntry], scale: f64) -> Result<Vec<Vec<Point3>>, IgesError> {
        let mut holes = Vec::new();
        for &boundary in inner {
            let (_, model) = self.curve_on_surface(boundary)?;
            if model == 0 {
                continue;
            }
            let curve = self.entry(model, boundary)?;
            let mut pts = self.boundary_samples(curve, 0, FACE_BOX_SAMPLES)?;
            if let Some(a) = self.transform(boundary)? {
                pts = pts.iter().map(|p| a.apply(p)).collect();
            }
            if pts.len() >= 3 {
                holes.push(pts.iter().map(|p| Point3::from(p.coords / scale)).collect());
            }
        }
        Ok(holes)
    }

    fn curve(&self, e: &DirEntry, scale: f64) -> Result<IgesCurve, IgesError> {
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let k = c.count("K (upper index of the control points)", 1)?;
        let m = c.count("M (degree)", 1)?;
        let _props = c.reals(4)?;
        let knots = c.reals(k + m + 2)?;
        let w = c.reals(k + 1)?;
        let coords = c.reals(3 * (k + 1))?;
        let range = c.reals(2)?;
        let points = self.points(e, &coords, scale)?;
        let polynomial = w.iter().all(|&x| x == w[0]) && w[0] > 0.0;
        let g = Self::geometry_err(e);
        let kv = KnotVector::new(m, knots).map_err(|x| g(x.context("knots")))?;
        let curve = BSplineCurve::new(kv, points, (!polynomial).then_some(w)).map_err(&g)?;
        Ok(IgesCurve {
            de: e.seq,
            name: Self::name(e),
            curve,
            param_range: [range[0], range[1]],
        })
    }
}

/// Largest difference of relative arc length at equal relative parameters for which a form-0
/// ruled surface (118) is read as the parametric ruling: 1e-9, a thousandth of the kernel's
/// model-size tolerance, so that the points it joins are the same to far below any tolerance.
pub const RULED_ARC_LENGTH_RELATIVE: f64 = 1e-9;

/// Samples of [`relative_arc_lengths`]: 64 spans, each integrated by a 5-point Gauss rule.
const ARC_LENGTH_SPANS: usize = 64;

/// Arc length from the start at the relative parameters k / [`ARC_LENGTH_SPANS`], divided by
/// the whole length (Gauss–Legendre on each piece, [AS] 25.4.29).
fn relative_arc_lengths(c: &BSplineCurve) -> Vec<f64> {
    let rule = nurbs_core::quadrature::GaussLegendre::new(5);
    let (t0, t1) = c.knots().domain();
    let at = |k: usize| t0 + (t1 - t0) * k as f64 / ARC_LENGTH_SPANS as f64;
    let mut acc = vec![0.0];
    for k in 0..ARC_LENGTH_SPANS {
        let piece: f64 = rule
            .on(at(k), at(k + 1))
            .map(|(t, w)| w * c.derivatives(t, 1).d[1].norm())
            .sum();
        acc.push(acc[k] + piece);
    }
    let total = acc[ARC_LENGTH_SPANS].max(f64::MIN_POSITIVE);
    acc.iter().map(|x| x / total).collect()
}

/// Reads an IGES file (CRLF or LF line endings).
pub fn read_iges(bytes: &[u8]) -> Result<IgesFile, IgesError> {
    let sec = split_sections(bytes)?;
    let global = parse_global(&sec.g)?;
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
    let unit_flag = num_param(11, 1.0) as i64;
    let mut units = text_param(12);
    if units.is_empty() {
        units = unit_name(unit_flag).to_string();
    }
    let start = sec
        .s
        .iter()
        .map(|r| String::from_utf8_lossy(r.data).trim_end().to_string())
        .collect::<Vec<_>>()
        .join("\n");
    check_terminate(&sec)?;
    let dir = parse_directory(&sec.d)?;
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
    };
    let mut trimmed_targets = Vec::new();
    let mut planes_read = Vec::new();
    let mut boxed = Vec::new();
    // the B-spline faces (144 over a 128): the entry, its surface's directory number, the
    // outer and inner boundaries
    let mut faces = Vec::new();
    // faces on the exact surfaces read over their own range (120, 122, 118): their trim only
    let mut exact_faces = Vec::new();
    for e in &reader.dir {
        match e.entity_type {
            128 => file.surfaces.push(reader.surface(e, scale)?),
            120 => file.surfaces.push(reader.revolution(e, scale)?),
            122 | 118 => {
                let read = if e.entity_type == 122 {
                    reader.tabulated(e, scale)
                } else {
                    reader.ruled(e, scale)
                };
                match read {
                    Ok(s) => file.surfaces.push(s),
                    // a surface with no exact form is named, the rest of the file is read
                    Err(err @ (IgesError::Entity { .. } | IgesError::Geometry { .. })) => {
                        file.refused.push(err.to_string());
                    }
                    Err(err) => return Err(err),
                }
            }
            126 => file.curves.push(reader.curve(e, scale)?),
            140 => match reader.offset(e, scale) {
                Ok(s) => file.surfaces.push(s),
                // an offset that cannot be read or approximated is named, the rest is read
                Err(err @ (IgesError::Entity { .. } | IgesError::Geometry { .. })) => {
                    file.refused.push(err.to_string());
                }
                Err(err) => return Err(err),
            },
            144 => {
                let params = entity_params(e, &reader.p, &reader.global)?;
                let mut c = Cursor {
                    params: &params,
                    next: 1,
                    e,
                };
                let pts = c.int()?;
                let target = reader.entry(pts, e)?;
                trimmed_targets.push(target.seq);
                file.trimmed_entities += 1;
                if target.entity_type == 128 {
                    // a B-spline face is its surface over the face's parameter box, cut once
                    // every surface is read (a writer may put the 144 before its 128: Open
                    // CASCADE does)
                    if let (Some(outer), inner) = reader.face_boundaries(&mut c, e)? {
                        faces.push((e, target.seq, outer, inner));
                    }
                } else if matches!(target.entity_type, 120 | 122 | 118 | 140) {
                    if let (Some(outer), inner) = reader.face_boundaries(&mut c, e)? {
                        exact_faces.push((target.seq, outer, inner));
                    }
                } else if target.entity_type == 108 {
                    // a plane is as large as its face: bounded by the outer boundary
                    if let (Some(outer), inner) = reader.face_boundaries(&mut c, e)?
                        && !planes_read.contains(&target.seq)
                    {
                        let mut plane = reader.bounded_plane(target, outer, e, scale)?;
                        plane.holes = reader.plane_holes(&inner, scale)?;
                        file.surfaces.push(plane);
                        planes_read.push(target.seq);
                    }
                }
            }
            // planes are read through the trimmed surfaces that bound them
            124 | 108 => {}
            other => *file.skipped.entry(other).or_default() += 1,
        }
    }
    for (e, target, boundary, inner) in faces {
        let Some(k) = file.surfaces.iter().position(|s| s.de == target) else {
            continue;
        };
        if boxed.contains(&target) {
            continue;
        }
        let (cut, trim) = reader.face_box(&file.surfaces[k].surface, boundary, e, scale)?;
        if trim.len() >= 3 {
            file.surfaces[k].trim = trim;
            file.surfaces[k].holes =
                reader.spline_holes(&file.surfaces[k].surface, &inner, scale)?;
        }
        if let Some(cut) = cut {
            let whole = std::mem::replace(&mut file.surfaces[k].surface, cut);
            file.surfaces[k].underlying = Some(whole);
            boxed.push(target);
        }
    }
    for (target, boundary, inner) in exact_faces {
        if let Some(k) = file.surfaces.iter().position(|s| s.de == target)
            && file.surfaces[k].trim.is_empty()
        {
            let trim = reader.model_trim(&file.surfaces[k].surface, boundary, scale)?;
            if trim.len() >= 3 {
                let surface = &file.surfaces[k].surface;
                let mut holes = Vec::new();
                for b in &inner {
                    holes.push(reader.model_trim(surface, b, scale)?);
                }
                holes.retain(|h| h.len() >= 3);
                file.surfaces[k].trim = trim;
                file.surfaces[k].holes = holes;
            }
        }
    }
    grow_planes(&mut file.surfaces, &planes_read);
    let unbounded = reader
        .dir
        .iter()
        .filter(|e| e.entity_type == 108 && !planes_read.contains(&e.seq))
        .count();
    if unbounded > 0 {
        file.skipped.insert(108, unbounded);
    }
    for s in &mut file.surfaces {
        s.trimmed = trimmed_targets.contains(&s.de);
    }
    Ok(file)
}

/// Grows each plane read from a 108 (by directory number in `planes`) to hold every boundary of
/// another surface that lies in it and reaches its rectangle: a kernel's surfaces run past the
/// face they bound (a fillet beyond the plane's corner, into the vertex blend), and a side that
/// lies on the plane must project onto it. A boundary lies in the plane when its whole control
/// row does (convex hull) within [`IN_PLANE_RELATIVE`] of the model size.
fn grow_planes(surfaces: &mut [IgesSurface], planes: &[usize]) {
    let size = surfaces
        .iter()
        .map(|s| s.surface.size())
        .fold(0.0, f64::max);
    let tol = IN_PLANE_RELATIVE * size;
    for k in 0..surfaces.len() {
        if !planes.contains(&surfaces[k].de) {
            continue;
        }
        let s = &surfaces[k].surface;
        let cp = s.control_points();
        let (o, px, py) = (cp[0], cp[2], cp[1]);
        let (lx, ly) = ((px - o).norm(), (py - o).norm());
        let (x, y) = ((px - o) / lx, (py - o) / ly);
        let n = x.cross(&y);
        let mut b = [0.0, lx, 0.0, ly];
        let inside = |p: &Point3, b: &[f64; 4]| {
            let d = p - o;
            let (a, c) = (d.dot(&x), d.dot(&y));
            a >= b[0] - tol && a <= b[1] + tol && c >= b[2] - tol && c <= b[3] + tol
        };
        let mut grown = b;
        for (j, other) in surfaces.iter().enumerate() {
            if j == k {
                continue;
            }
            let g = &other.surface;
            for side in [
                nurbs_core::Side::U0,
                nurbs_core::Side::U1,
                nurbs_core::Side::V0,
                nurbs_core::Side::V1,
            ] {
                let row: Vec<Point3> = side
                    .row(0, g.num_u(), g.num_v())
                    .into_iter()
                    .map(|(i, j)| g.control_point(i, j))
                    .collect();
                let flat = row.iter().all(|p| n.dot(&(p - o)).abs() <= tol);
                if !flat || !row.iter().any(|p| inside(p, &b)) {
                    continue;
                }
                for p in &row {
                    let d = p - o;
                    let (a, c) = (d.dot(&x), d.dot(&y));
                    grown = [
                        grown[0].min(a),
                        grown[1].max(a),
                        grown[2].min(c),
                        grown[3].max(c),
                    ];
                }
            }
        }
        if grown == b {
            continue;
        }
        b = grown;
        let (lu, lv) = (b[1] - b[0], b[3] - b[2]);
        let corner = o + x * b[0] + y * b[2];
        if let Ok(plane) = nurbs_core::shapes::plane_patch(corner, x, y, (0.0, lu), (0.0, lv)) {
            surfaces[k].surface = plane;
            surfaces[k].param_range = [0.0, lu, 0.0, lv];
        }
    }
}

pub(crate) fn check_terminate(sec: &Sections<'_>) -> Result<(), IgesError> {
    let t = &sec.t[0];
    let expected = [
        (b'S', sec.s.len()),
        (b'G', sec.g.len()),
        (b'D', sec.d.len()),
        (b'P', sec.p.len()),
    ];
    for (k, (letter, count)) in expected.iter().enumerate() {
        let field = &t.data[8 * k..8 * k + 8];
        let n = std::str::from_utf8(&field[1..])
            .ok()
            .and_then(|s| s.trim().parse::<usize>().ok());
        if field[0] != *letter || n != Some(*count) {
            return Err(layout(
                t.line,
                format!(
                    "Terminate record says {:?} but the {} section has {count} records",
                    String::from_utf8_lossy(field),
                    *letter as char
                ),
            ));
        }
    }
    Ok(())
}

/// The unit name of an IGES unit flag.
pub fn unit_name(flag: i64) -> &'static str {
    match flag {
        1 => "IN",
        2 => "MM",
        4 => "FT",
        5 => "MI",
        6 => "M",
        7 => "KM",
        8 => "MIL",
        9 => "UM",
        10 => "CM",
        11 => "UIN",
        _ => "unknown",
    }
}
