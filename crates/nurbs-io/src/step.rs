//! A STEP reader (ISO 10303-21 exchange structure, the AP203/AP214/AP242 geometry of
//! ISO 10303-42): each ADVANCED_FACE (or FACE_SURFACE) becomes an exact NURBS surface over the
//! parameter box of its bounds.
//!
//! Surfaces: PLANE, CYLINDRICAL_SURFACE, CONICAL_SURFACE, SPHERICAL_SURFACE, TOROIDAL_SURFACE
//! (rational quadratic arcs in the angular directions, [NB] A7.1 / A8.1), SURFACE_OF_LINEAR_EXTRUSION
//! of a B-spline curve (exact, [`nurbs_core::shapes::extrude_curve`]), SURFACE_OF_REVOLUTION
//! of a B-spline curve, and B_SPLINE_SURFACE_WITH_KNOTS, plain or in the complex instance with
//! RATIONAL_B_SPLINE_SURFACE.
//! The parameter box of a face is that of its edges: the vertices and points along every edge
//! curve (LINE between its vertices, CIRCLE along the arc the edge runs, B-spline curves
//! sampled) are inverted on the surface — in closed form on the elementary surfaces, by
//! projection on a B-spline — and an angular range that wraps is taken as the complement of the
//! largest gap. Length unit: the SI_UNIT of the LENGTH_UNIT (METRE with its prefix) or a
//! CONVERSION_BASED_UNIT named INCH / FOOT; coordinates stay in that unit.
//!
//! # Deviation from the standard
//! Only what a face's geometry needs is read; topology beyond the face bounds, colours,
//! assemblies and placements of product instances are ignored (a file of several placed
//! solids reads each solid in its own coordinates).

use std::collections::HashMap;

use nurbs_core::{BSplineCurve, BSplineSurface, KnotVector, Point3, ProjectionParams, Vector3};

use crate::bounds::Face;

/// A boundary point whose Newton foot from the previous point's lies within this fraction of
/// the surface size is on the surface there (a face's edges lie on it to the kernel's
/// tolerance, 1e-7 of a part; the foot of a point on a surface is that point): the full search
/// from the start grid is skipped.
pub const ON_SURFACE_RELATIVE: f64 = 1e-7;

/// Points along each edge curve used for a face's parameter box.
pub const EDGE_SAMPLES: usize = 17;

/// Points along a B-spline edge between its vertices for the face's parameter box: the largest
/// parameter of the edge on its face falls between samples and is missed by about |v''| h²/8
/// (h the spacing); 257 make that (16/256)² of what 17 miss (2.6·10⁻⁵ of a lofted face's
/// domain in Open CASCADE's IGES of the same model: a 2 µm gap along its fillet).
pub const SPLINE_EDGE_SAMPLES: usize = 257;

/// Largest angle (radians) between the samples of a circular edge: 2°. An angular range whose
/// largest gap between boundary samples is at most two steps is a full turn (a face closed
/// around its axis: a ring fillet, a pipe); a face open by more than 4° keeps its opening.
pub const ARC_STEP: f64 = std::f64::consts::TAU / 180.0;

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

/// A parameter value of an entity instance.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// integer or real
    Number(f64),
    /// 'text'
    Text(String),
    /// .ENUM.
    Enum(String),
    /// #N
    Ref(u64),
    /// ( … )
    List(Vec<Value>),
    /// $ or *
    Unset,
    /// TYPE( … ) inside a parameter list
    Typed(String, Vec<Value>),
}

/// One instance: its parts (one for a simple instance, several for a complex one).
#[derive(Debug, Clone, PartialEq)]
pub struct Instance {
    /// (entity type, parameters) per part
    pub parts: Vec<(String, Vec<Value>)>,
    /// 1-based line where it starts
    pub line: usize,
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
}

/// Parses the DATA section of a Part 21 file into its instances.
pub fn parse_instances(text: &str) -> Result<HashMap<u64, Instance>, StepError> {
    let bytes = text.as_bytes();
    let Some(start) = text.find("DATA;") else {
        return Err(StepError::Syntax {
            line: 1,
            detail: "no DATA section (not an ISO 10303-21 file?)".into(),
        });
    };
    let mut p = Parser {
        b: bytes,
        i: start + 5,
        line: 1 + text[..start].matches('\n').count(),
    };
    let mut out = HashMap::new();
    loop {
        p.skip();
        if p.i >= bytes.len() {
            return Err(p.err("the DATA section has no ENDSEC"));
        }
        if bytes[p.i..].starts_with(b"ENDSEC") {
            break;
        }
        if bytes[p.i] != b'#' {
            return Err(p.err("expected an instance #N = …"));
        }
        let line = p.line;
        p.i += 1;
        let id = p.integer()?;
        p.skip();
        p.expect(b'=')?;
        p.skip();
        let mut parts = Vec::new();
        if p.peek() == Some(b'(') {
            // complex instance: ( A(..) B(..) … )
            p.i += 1;
            loop {
                p.skip();
                if p.peek() == Some(b')') {
                    p.i += 1;
                    break;
                }
                let name = p.keyword()?;
                p.skip();
                let args = p.list()?;
                parts.push((name, args));
            }
        } else {
            let name = p.keyword()?;
            p.skip();
            let args = p.list()?;
            parts.push((name, args));
        }
        p.skip();
        p.expect(b';')?;
        if parts.is_empty() {
            return Err(StepError::Syntax {
                line,
                detail: format!("instance #{id} is an empty complex instance"),
            });
        }
        if out.insert(id, Instance { parts, line }).is_some() {
            return Err(StepError::Syntax {
                line,
                detail: format!("instance #{id} is defined twice"),
            });
        }
    }
    Ok(out)
}

struct Parser<'a> {
    b: &'a [u8],
    i: usize,
    line: usize,
}

impl Parser<'_> {
    fn err(&self, detail: &str) -> StepError {
        StepError::Syntax {
            line: self.line,
            detail: detail.to_string(),
        }
    }
    fn peek(&self) -> Option<u8> {
        self.b.get(self.i).copied()
    }
    /// Skips white space and /* comments */.
    fn skip(&mut self) {
        while let Some(c) = self.peek() {
            if c == b'\n' {
                self.line += 1;
                self.i += 1;
            } else if c.is_ascii_whitespace() {
                self.i += 1;
            } else if self.b[self.i..].starts_with(b"/*") {
                match self.b[self.i + 2..].windows(2).position(|w| w == b"*/") {
                    Some(k) => {
                        self.line += self.b[self.i..self.i + k + 4]
                            .iter()
                            .filter(|&&c| c == b'\n')
                            .count();
                        self.i += k + 4;
                    }
                    None => self.i = self.b.len(),
                }
            } else {
                break;
            }
        }
    }
    fn expect(&mut self, c: u8) -> Result<(), StepError> {
        if self.peek() == Some(c) {
            self.i += 1;
            Ok(())
        } else {
            Err(self.err(&format!("expected '{}'", c as char)))
        }
    }
    fn integer(&mut self) -> Result<u64, StepError> {
        let s = self.i;
        while self.peek().is_some_and(|c| c.is_ascii_digit()) {
            self.i += 1;
        }
        std::str::from_utf8(&self.b[s..self.i])
            .ok()
            .and_then(|t| t.parse().ok())
            .ok_or_else(|| self.err("expected an instance number"))
    }
    fn keyword(&mut self) -> Result<String, StepError> {
        let s = self.i;
        while self
            .peek()
            .is_some_and(|c| c.is_ascii_alphanumeric() || c == b'_' || c == b'!')
        {
            self.i += 1;
        }
        if s == self.i {
            return Err(self.err("expected an entity name"));
        }
        Ok(String::from_utf8_lossy(&self.b[s..self.i]).to_uppercase())
    }
    /// ( value, value, … )
    fn list(&mut self) -> Result<Vec<Value>, StepError> {
        self.expect(b'(')?;
        let mut out = Vec::new();
        loop {
            self.skip();
            if self.peek() == Some(b')') {
                self.i += 1;
                return Ok(out);
            }
            out.push(self.value()?);
            self.skip();
            match self.peek() {
                Some(b',') => self.i += 1,
                Some(b')') => {}
                _ => return Err(self.err("expected ',' or ')' in a parameter list")),
            }
        }
    }
    fn value(&mut self) -> Result<Value, StepError> {
        match self.peek() {
            Some(b'(') => Ok(Value::List(self.list()?)),
            Some(b'#') => {
                self.i += 1;
                Ok(Value::Ref(self.integer()?))
            }
            Some(b'$') | Some(b'*') => {
                self.i += 1;
                Ok(Value::Unset)
            }
            Some(b'\'') => {
                self.i += 1;
                let mut s = Vec::new();
                loop {
                    match self.peek() {
                        None => return Err(self.err("a string does not end")),
                        Some(b'\'') if self.b.get(self.i + 1) == Some(&b'\'') => {
                            s.push(b'\'');
                            self.i += 2;
                        }
                        Some(b'\'') => {
                            self.i += 1;
                            break;
                        }
                        Some(c) => {
                            if c == b'\n' {
                                self.line += 1;
                            }
                            s.push(c);
                            self.i += 1;
                        }
                    }
                }
                Ok(Value::Text(String::from_utf8_lossy(&s).into_owned()))
            }
            Some(b'.')
                if self
                    .b
                    .get(self.i + 1)
                    .is_some_and(|c| c.is_ascii_alphabetic()) =>
            {
                self.i += 1;
                let s = self.i;
                while self.peek().is_some_and(|c| c != b'.') {
                    self.i += 1;
                }
                let e = String::from_utf8_lossy(&self.b[s..self.i]).to_uppercase();
                self.expect(b'.')?;
                Ok(Value::Enum(e))
            }
            Some(c) if c.is_ascii_digit() || c == b'-' || c == b'+' || c == b'.' => {
                let s = self.i;
                while self
                    .peek()
                    .is_some_and(|c| c.is_ascii_digit() || b"+-.eE".contains(&c))
                {
                    self.i += 1;
                }
                std::str::from_utf8(&self.b[s..self.i])
                    .ok()
                    .and_then(|t| t.parse::<f64>().ok())
                    .filter(|x| x.is_finite())
                    .map(Value::Number)
                    .ok_or_else(|| self.err("a malformed number"))
            }
            Some(c) if c.is_ascii_alphabetic() => {
                let name = self.keyword()?;
                self.skip();
                Ok(Value::Typed(name, self.list()?))
            }
            _ => Err(self.err("an unexpected character in a parameter list")),
        }
    }
}

/// Access to the instances with errors that name them.
struct Model<'a> {
    all: &'a HashMap<u64, Instance>,
}

type R<T> = Result<T, StepError>;

impl<'a> Model<'a> {
    fn get(&self, id: u64) -> R<&'a Instance> {
        self.all.get(&id).ok_or_else(|| StepError::Entity {
            id,
            entity: "?".into(),
            detail: "is referenced but not defined".into(),
        })
    }
    /// The parameters of the part `name` of instance `id`.
    fn part(&self, id: u64, name: &str) -> R<&'a [Value]> {
        let inst = self.get(id)?;
        inst.parts
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
            .ok_or_else(|| StepError::Entity {
                id,
                entity: inst.parts.first().map_or_else(String::new, |p| p.0.clone()),
                detail: format!("expected {name}"),
            })
    }
    fn kind(&self, id: u64) -> R<&'a str> {
        Ok(self.get(id)?.parts.first().map_or("", |p| p.0.as_str()))
    }
    fn bad(&self, id: u64, detail: impl Into<String>) -> StepError {
        StepError::Entity {
            id,
            entity: self.kind(id).unwrap_or("?").to_string(),
            detail: detail.into(),
        }
    }
    fn num(&self, id: u64, v: Option<&Value>) -> R<f64> {
        match v {
            Some(Value::Number(x)) => Ok(*x),
            Some(Value::Typed(_, inner)) => self.num(id, inner.first()),
            _ => Err(self.bad(id, "expected a number")),
        }
    }
    fn reference(&self, id: u64, v: Option<&Value>) -> R<u64> {
        match v {
            Some(Value::Ref(r)) => Ok(*r),
            _ => Err(self.bad(id, "expected a reference")),
        }
    }
    fn list<'v>(&self, id: u64, v: Option<&'v Value>) -> R<&'v [Value]> {
        match v {
            Some(Value::List(l)) => Ok(l),
            _ => Err(self.bad(id, "expected a list")),
        }
    }
    fn numbers(&self, id: u64, v: Option<&Value>) -> R<Vec<f64>> {
        self.list(id, v)?
            .iter()
            .map(|x| self.num(id, Some(x)))
            .collect()
    }
    fn point(&self, id: u64) -> R<Point3> {
        let c = self.numbers(id, self.part(id, "CARTESIAN_POINT")?.get(1))?;
        Ok(Point3::new(
            c.first().copied().unwrap_or(0.0),
            c.get(1).copied().unwrap_or(0.0),
            c.get(2).copied().unwrap_or(0.0),
        ))
    }
    fn direction(&self, id: u64) -> R<Vector3> {
        let c = self.numbers(id, self.part(id, "DIRECTION")?.get(1))?;
        Vector3::new(
            c.first().copied().unwrap_or(0.0),
            c.get(1).copied().unwrap_or(0.0),
            c.get(2).copied().unwrap_or(0.0),
        )
        .try_normalize(0.0)
        .ok_or_else(|| self.bad(id, "a zero direction"))
    }
    /// AXIS2_PLACEMENT_3D: origin and the right-handed frame (x, y, z).
    fn placement(&self, id: u64) -> R<(Point3, Vector3, Vector3, Vector3)> {
        let p = self.part(id, "AXIS2_PLACEMENT_3D")?;
        let o = self.point(self.reference(id, p.get(1))?)?;
        let z = match p.get(2) {
            Some(Value::Ref(r)) => self.direction(*r)?,
            _ => Vector3::z(),
        };
        let x0 = match p.get(3) {
            Some(Value::Ref(r)) => self.direction(*r)?,
            _ => {
                if z.x.abs() < 0.9 {
                    Vector3::x()
                } else {
                    Vector3::y()
                }
            }
        };
        let x = (x0 - z * z.dot(&x0))
            .try_normalize(0.0)
            .ok_or_else(|| self.bad(id, "the reference direction is along the axis"))?;
        Ok((o, x, z.cross(&x), z))
    }
}

/// An elementary or B-spline surface with its closed-form parametrization.
enum Surface {
    Plane(Point3, Vector3, Vector3),
    /// origin, x, y, z, radius, semi-angle (0 for a cylinder)
    Cone(Point3, Vector3, Vector3, Vector3, f64, f64),
    /// origin, x, y, z, radius
    Sphere(Point3, Vector3, Vector3, Vector3, f64),
    /// origin, x, y, z, major, minor
    Torus(Point3, Vector3, Vector3, Vector3, f64, f64),
    Spline(BSplineSurface),
    /// a generatrix turned about the axis through the point with the unit direction; the
    /// generatrix's radial direction at its middle is angle 0 (it lies in a half-plane through
    /// the axis, as every surface of revolution a kernel writes)
    Revolution(BSplineCurve, Point3, Vector3, Vector3),
    /// a curve moved along a vector (magnitude included): S(u, v) = C(u) + v V; with the curve
    /// projected along V onto the plane through the origin perpendicular to it (the same
    /// weights: a linear map of the net), which inverts a point
    Extrusion(BSplineCurve, Vector3, BSplineCurve),
}

impl Surface {
    /// Parameters (u, v) of a point on the surface, u the angle where there is one.
    fn invert(&self, p: &Point3) -> (f64, f64) {
        match self {
            Surface::Plane(o, x, y) => ((p - o).dot(x), (p - o).dot(y)),
            Surface::Cone(o, x, y, z, _, _) => {
                let d = p - o;
                (d.dot(y).atan2(d.dot(x)), d.dot(z))
            }
            Surface::Sphere(o, x, y, z, _) => {
                let d = p - o;
                let (a, b) = (d.dot(x), d.dot(y));
                (b.atan2(a), d.dot(z).atan2(a.hypot(b)))
            }
            Surface::Torus(o, x, y, z, major, _) => {
                let d = p - o;
                let (a, b) = (d.dot(x), d.dot(y));
                (b.atan2(a), d.dot(z).atan2(a.hypot(b) - major))
            }
            Surface::Spline(s) => {
                let f = nurbs_core::project_to_surface(s, p, &ProjectionParams::default());
                (f.u, f.v)
            }
            Surface::Extrusion(c, vector, flat) => {
                // the foot on the projected curve gives u; v is the offset along V from C(u)
                let unit = vector.normalize();
                let q = p - unit * unit.dot(&p.coords);
                let u = nurbs_core::project_to_curve(flat, &q, &ProjectionParams::default()).t;
                (u, (p - c.point(u)).dot(vector) / vector.norm_squared())
            }
            Surface::Revolution(c, o, z, x) => {
                let d = p - o;
                let y = z.cross(x);
                let u = d.dot(&y).atan2(d.dot(x));
                // turned back into the generatrix's half-plane, the point lies on it
                let h = z * d.dot(z);
                let back = o + h + x * (d - h).norm();
                (
                    u,
                    nurbs_core::project_to_curve(c, &back, &ProjectionParams::default()).t,
                )
            }
        }
    }
    fn angular(&self) -> (bool, bool) {
        match self {
            Surface::Plane(..) | Surface::Spline(_) | Surface::Extrusion(..) => (false, false),
            Surface::Revolution(..) => (true, false),
            Surface::Cone(..) => (true, false),
            // a sphere's latitude never wraps (−π/2 … π/2)
            Surface::Sphere(..) => (true, false),
            Surface::Torus(..) => (true, true),
        }
    }
    /// The NURBS surface over [u0, u1] × [v0, v1].
    fn build(&self, u: (f64, f64), v: (f64, f64)) -> nurbs_core::Result<BSplineSurface> {
        use nurbs_core::shapes::{arc, revolve_curve};
        let line = |a: Point3, b: Point3| {
            BSplineCurve::new(
                KnotVector::new(1, vec![v.0, v.0, v.1, v.1])?,
                vec![a, b],
                None,
            )
        };
        match self {
            Surface::Plane(o, x, y) => nurbs_core::shapes::plane_patch(*o, *x, *y, u, v),
            Surface::Cone(o, x, _, z, r, semi) => {
                let at = |h: f64| o + x * (r + h * semi.tan()) + z * h;
                let profile = line(at(v.0), at(v.1))?;
                // u the angle about z: the profile turned from u0 to u1; the result runs
                // (profile, angle), transposed to (angle, height)
                Ok(revolve_curve(&profile, *o, *z, u.0, u.1)?.transposed()?)
            }
            Surface::Sphere(o, x, _, z, r) => {
                let profile = arc(*o, *x, *z, *r, v.0, v.1)?;
                Ok(revolve_curve(&profile, *o, *z, u.0, u.1)?.transposed()?)
            }
            Surface::Torus(o, x, _, z, major, minor) => {
                let profile = arc(o + x * *major, *x, *z, *minor, v.0, v.1)?;
                Ok(revolve_curve(&profile, *o, *z, u.0, u.1)?.transposed()?)
            }
            Surface::Spline(s) => s.extract(u, v),
            Surface::Revolution(c, o, z, _) => {
                let part = c.extract(v.0, v.1)?;
                Ok(revolve_curve(&part, *o, *z, u.0, u.1)?.transposed()?)
            }
            Surface::Extrusion(c, vector, _) => {
                nurbs_core::shapes::extrude_curve(&c.extract(u.0, u.1)?, *vector, v)
            }
        }
    }
}

/// The range of angles `a` (radians) as an interval: the complement of the largest gap on the
/// circle, from its end to its start + 2π; a full turn where the points are all around.
fn angle_range(a: &[f64]) -> (f64, f64) {
    let mut s: Vec<f64> = a
        .iter()
        .map(|x| x.rem_euclid(std::f64::consts::TAU))
        .collect();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    let mut best = (s[0] + std::f64::consts::TAU - s[n - 1], n - 1);
    for k in 0..n - 1 {
        let gap = s[k + 1] - s[k];
        if gap > best.0 {
            best = (gap, k);
        }
    }
    // no gap wider than two arc samples: the face goes all around
    if best.0 <= 2.0 * ARC_STEP {
        return (0.0, std::f64::consts::TAU);
    }
    let start = s[(best.1 + 1) % n];
    let end = s[best.1];
    let end = if end <= start {
        end + std::f64::consts::TAU
    } else {
        end
    };
    (start, end)
}

/// Reads the faces of a STEP file.
pub fn read_step(text: &str) -> Result<StepFile, StepError> {
    let all = parse_instances(text)?;
    let m = Model { all: &all };
    let mut ids: Vec<u64> = all.keys().copied().collect();
    ids.sort_unstable();
    let mut file = StepFile {
        units: units(&m, &ids),
        ..StepFile::default()
    };
    for &id in &ids {
        let kind = m.kind(id)?;
        if kind != "ADVANCED_FACE" && kind != "FACE_SURFACE" {
            continue;
        }
        let p = m.part(id, kind)?;
        let name = match p.first() {
            Some(Value::Text(t)) if !t.is_empty() => t.clone(),
            _ => format!("step{id}"),
        };
        let sid = m.reference(id, p.get(2))?;
        let skind = m.kind(sid)?.to_string();
        let Some(surface) = surface(&m, sid)? else {
            *file.skipped.entry(skind).or_default() += 1;
            continue;
        };
        let (trim, params) = boundary_params(&m, id, p.get(1), &surface)?;
        if params.is_empty() {
            return Err(m.bad(id, "the face has no bounds"));
        }
        let (ua, va) = surface.angular();
        let range = |xs: Vec<f64>, angular: bool| {
            if angular {
                angle_range(&xs)
            } else {
                xs.iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                        (a.min(x), b.max(x))
                    })
            }
        };
        let u = range(params.iter().map(|p| p.0).collect(), ua);
        let v = range(params.iter().map(|p| p.1).collect(), va);
        let built = surface
            .build(u, v)
            .map_err(|source| StepError::Geometry { id, source })?;
        file.faces.push(StepFace {
            id,
            name,
            surface: built,
            kind: skind,
            trim,
        });
    }
    Ok(file)
}

/// A face's bound loops (points in order) and the parameters of their points on its surface.
type Bounds = (Vec<Vec<Point3>>, Vec<(f64, f64)>);

/// The bounds of face `id` (its `bounds` list) as loops of points in order, the outer bound
/// first (a loop of fewer than three points, a vertex loop at a pole, is no trim loop), and the
/// parameters of all those points on `surface`: a B-spline's projector builds its grid of start
/// points once per face, not once per point.
fn boundary_params(m: &Model, id: u64, bounds: Option<&Value>, surface: &Surface) -> R<Bounds> {
    // the face's boundary points, inverted on the surface (a B-spline's projector builds its
    // grid of start points once per face, not once per point)
    let mut params = Vec::new();
    let mut projector = match surface {
        Surface::Spline(s) => Some(nurbs_core::SurfaceProjector::new(
            s,
            ProjectionParams::default(),
        )),
        _ => None,
    };
    // consecutive boundary points are close: Newton from the previous foot first, the full
    // search from the grid only where that does not land on the surface
    let on_surface = match surface {
        Surface::Spline(s) => ON_SURFACE_RELATIVE * s.size(),
        _ => 0.0,
    };
    let mut previous: Option<(f64, f64)> = None;
    let mut loops: Vec<Vec<Point3>> = Vec::new();
    for b in m.list(id, bounds)? {
        let Value::Ref(bid) = b else { continue };
        let bound = m.get(*bid)?;
        let fb = &bound.parts[0].1;
        let loop_id = m.reference(*bid, fb.get(1))?;
        let points = loop_points(m, loop_id)?;
        if bound.parts[0].0 == "FACE_OUTER_BOUND" {
            loops.insert(0, points.clone());
        } else {
            loops.push(points.clone());
        }
        for pt in points {
            params.push(match projector.as_mut() {
                Some(pr) => {
                    let warm = previous
                        .map(|start| pr.project_from(&pt, start))
                        .filter(|f| f.converged && f.distance <= on_surface);
                    let f = warm.unwrap_or_else(|| pr.project(&pt));
                    previous = Some((f.u, f.v));
                    (f.u, f.v)
                }
                None => surface.invert(&pt),
            });
        }
    }
    loops.retain(|l| l.len() >= 3);
    Ok((loops, params))
}

/// The surface of instance `sid`, `None` for a type that is not read.
fn surface(m: &Model, sid: u64) -> R<Option<Surface>> {
    let kind = m.kind(sid)?;
    let inst = m.get(sid)?;
    Ok(Some(match kind {
        "PLANE" => {
            let (o, x, y, _) = m.placement(m.reference(sid, m.part(sid, kind)?.get(1))?)?;
            Surface::Plane(o, x, y)
        }
        "CYLINDRICAL_SURFACE" | "CONICAL_SURFACE" | "SPHERICAL_SURFACE" | "TOROIDAL_SURFACE" => {
            let p = m.part(sid, kind)?;
            let (o, x, y, z) = m.placement(m.reference(sid, p.get(1))?)?;
            let a = m.num(sid, p.get(2))?;
            match kind {
                "CYLINDRICAL_SURFACE" => Surface::Cone(o, x, y, z, a, 0.0),
                "CONICAL_SURFACE" => {
                    // the semi-angle in the file's plane-angle unit: radians, or degrees when
                    // it is above π/2 (no cone opens that wide)
                    let semi = m.num(sid, p.get(3))?;
                    let semi = if semi.abs() > std::f64::consts::FRAC_PI_2 {
                        semi.to_radians()
                    } else {
                        semi
                    };
                    Surface::Cone(o, x, y, z, a, semi)
                }
                "SPHERICAL_SURFACE" => Surface::Sphere(o, x, y, z, a),
                _ => Surface::Torus(o, x, y, z, a, m.num(sid, p.get(3))?),
            }
        }
        "SURFACE_OF_REVOLUTION" => {
            let p = m.part(sid, kind)?;
            let cid = m.reference(sid, p.get(1))?;
            let curve = match m.kind(cid)? {
                _ if m
                    .get(cid)?
                    .parts
                    .iter()
                    .any(|(k, _)| k == "B_SPLINE_CURVE_WITH_KNOTS") =>
                {
                    spline_curve(m, cid)?
                }
                _ => return Ok(None),
            };
            let aid = m.reference(sid, p.get(2))?;
            let a = m.part(aid, "AXIS1_PLACEMENT")?;
            let o = m.point(m.reference(aid, a.get(1))?)?;
            let z = match a.get(2) {
                Some(Value::Ref(r)) => m.direction(*r)?,
                _ => Vector3::z(),
            };
            let (t0, t1) = curve.knots().domain();
            let mid = curve.point(0.5 * (t0 + t1)) - o;
            let x = (mid - z * z.dot(&mid))
                .try_normalize(0.0)
                .ok_or_else(|| m.bad(sid, "the generatrix lies on the axis"))?;
            Surface::Revolution(curve, o, z, x)
        }
        "SURFACE_OF_LINEAR_EXTRUSION" => {
            // (name, swept curve, extrusion axis: a VECTOR of a direction and a magnitude)
            let p = m.part(sid, kind)?;
            let cid = m.reference(sid, p.get(1))?;
            if !m
                .get(cid)?
                .parts
                .iter()
                .any(|(k, _)| k == "B_SPLINE_CURVE_WITH_KNOTS")
            {
                return Ok(None);
            }
            let curve = spline_curve(m, cid)?;
            let vid = m.reference(sid, p.get(2))?;
            let v = m.part(vid, "VECTOR")?;
            let dir = m.direction(m.reference(vid, v.get(1))?)?;
            let vector = dir * m.num(vid, v.get(2))?;
            if !(vector.norm() > 0.0) {
                return Err(m.bad(sid, "the extrusion vector has zero length"));
            }
            let unit = vector.normalize();
            let flat_points = curve
                .control_points()
                .iter()
                .map(|q| q - unit * unit.dot(&q.coords))
                .collect();
            let flat = BSplineCurve::new(
                curve.knots().clone(),
                flat_points,
                curve.weights().map(<[f64]>::to_vec),
            )
            .map_err(|source| StepError::Geometry { id: sid, source })?;
            Surface::Extrusion(curve, vector, flat)
        }
        _ if inst
            .parts
            .iter()
            .any(|(n, _)| n == "B_SPLINE_SURFACE_WITH_KNOTS") =>
        {
            Surface::Spline(spline_surface(m, sid)?)
        }
        _ => return Ok(None),
    }))
}

/// The knot vector of STEP's distinct knots and their multiplicities.
fn expand_knots(mults: &[f64], values: &[f64]) -> Vec<f64> {
    values
        .iter()
        .zip(mults)
        .flat_map(|(&k, &n)| std::iter::repeat_n(k, n.max(0.0) as usize))
        .collect()
}

/// B_SPLINE_SURFACE_WITH_KNOTS, simple or in a complex instance with B_SPLINE_SURFACE and
/// RATIONAL_B_SPLINE_SURFACE. Control points are listed row by row, u the outer index, as the
/// crate's flat net P[i · n_v + j].
fn spline_surface(m: &Model, sid: u64) -> R<BSplineSurface> {
    let inst = m.get(sid)?;
    let (base, knots) = if inst.parts.len() == 1 {
        // simple instance: name, du, dv, points, form, closed u, closed v, self-intersect,
        // mults u, mults v, knots u, knots v, spec
        let p = &inst.parts[0].1;
        if p.len() < 13 {
            return Err(m.bad(sid, format!("{} parameters, expected 13", p.len())));
        }
        // name, du, dv, points, form, u closed, v closed, self-intersect, then the knots
        (&p[1..], &p[8..])
    } else {
        (
            m.part(sid, "B_SPLINE_SURFACE")?,
            m.part(sid, "B_SPLINE_SURFACE_WITH_KNOTS")?,
        )
    };
    let (du, dv) = (
        m.num(sid, base.first())? as usize,
        m.num(sid, base.get(1))? as usize,
    );
    let rows = m.list(sid, base.get(2))?;
    let mut points = Vec::new();
    let mut nv = 0;
    for row in rows {
        let r = m.list(sid, Some(row))?;
        nv = r.len();
        for x in r {
            points.push(m.point(m.reference(sid, Some(x))?)?);
        }
    }
    let (mu, mv) = (
        m.numbers(sid, knots.first())?,
        m.numbers(sid, knots.get(1))?,
    );
    let (ku, kv) = (m.numbers(sid, knots.get(2))?, m.numbers(sid, knots.get(3))?);
    let weights = match inst
        .parts
        .iter()
        .find(|(n, _)| n == "RATIONAL_B_SPLINE_SURFACE")
    {
        Some((_, w)) => {
            let mut out = Vec::new();
            for row in m.list(sid, w.first())? {
                out.extend(m.numbers(sid, Some(row))?);
            }
            Some(out)
        }
        None => None,
    };
    let g = |source| StepError::Geometry { id: sid, source };
    if nv == 0 || points.len() != rows.len() * nv {
        return Err(m.bad(sid, "the control point rows differ in length"));
    }
    BSplineSurface::new(
        KnotVector::new(du, expand_knots(&mu, &ku)).map_err(g)?,
        KnotVector::new(dv, expand_knots(&mv, &kv)).map_err(g)?,
        points,
        weights,
    )
    .map_err(g)
}

/// Points of an EDGE_LOOP (or POLY_LOOP, VERTEX_LOOP) in order along it: each oriented edge
/// from its start to its end with points along its curve, every joint once.
fn loop_points(m: &Model, lid: u64) -> R<Vec<Point3>> {
    let kind = m.kind(lid)?;
    let p = m.part(lid, kind)?;
    let mut out: Vec<Point3> = Vec::new();
    match kind {
        "EDGE_LOOP" => {
            for oe in m.list(lid, p.get(1))? {
                let oe = m.reference(lid, Some(oe))?;
                let o = m.part(oe, "ORIENTED_EDGE")?;
                let edge = m.reference(oe, o.get(3))?;
                let mut path = edge_points(m, edge)?;
                if matches!(o.get(4), Some(Value::Enum(e)) if e == "F") {
                    path.reverse();
                }
                // the joint of two edges once
                for q in path {
                    if out.last() != Some(&q) {
                        out.push(q);
                    }
                }
            }
            if out.len() > 1 && out.first() == out.last() {
                out.pop();
            }
        }
        "POLY_LOOP" => {
            for x in m.list(lid, p.get(1))? {
                out.push(m.point(m.reference(lid, Some(x))?)?);
            }
        }
        "VERTEX_LOOP" => out.push(vertex(m, m.reference(lid, p.get(1))?)?),
        _ => return Err(m.bad(lid, "not a loop of edges")),
    }
    Ok(out)
}

fn vertex(m: &Model, vid: u64) -> R<Point3> {
    m.point(m.reference(vid, m.part(vid, "VERTEX_POINT")?.get(1))?)
}

/// An EDGE_CURVE's points in order from its start vertex to its end vertex, along its geometry.
fn edge_points(m: &Model, eid: u64) -> R<Vec<Point3>> {
    let p = m.part(eid, "EDGE_CURVE")?;
    let (a, b) = (
        vertex(m, m.reference(eid, p.get(1))?)?,
        vertex(m, m.reference(eid, p.get(2))?)?,
    );
    let same = !matches!(p.get(4), Some(Value::Enum(e)) if e == "F");
    let mut cid = m.reference(eid, p.get(3))?;
    // a SURFACE_CURVE / SEAM_CURVE carries its 3D curve first
    for _ in 0..4 {
        let k = m.kind(cid)?;
        if k == "SURFACE_CURVE" || k == "SEAM_CURVE" || k == "INTERSECTION_CURVE" {
            cid = m.reference(cid, m.part(cid, k)?.get(1))?;
        } else {
            break;
        }
    }
    let mut out = vec![a];
    let kind = m.kind(cid)?;
    let n = EDGE_SAMPLES;
    match kind {
        "CIRCLE" | "ELLIPSE" => {
            let c = m.part(cid, kind)?;
            let (o, x, y, _) = m.placement(m.reference(cid, c.get(1))?)?;
            let r1 = m.num(cid, c.get(2))?;
            let r2 = if kind == "ELLIPSE" {
                m.num(cid, c.get(3))?
            } else {
                r1
            };
            let angle = |p: &Point3| {
                let d = p - o;
                (d.dot(&y) / r2).atan2(d.dot(&x) / r1)
            };
            // the curve runs counterclockwise; the edge from a to b along it, or against it
            let (s, e) = if same { (a, b) } else { (b, a) };
            let t0 = angle(&s);
            let mut t1 = angle(&e);
            while t1 <= t0 + 1e-12 {
                t1 += std::f64::consts::TAU;
            }
            let n = n.max(((t1 - t0) / ARC_STEP).ceil() as usize + 1);
            let mut between: Vec<Point3> = (1..n - 1)
                .map(|k| {
                    let t = t0 + (t1 - t0) * k as f64 / (n - 1) as f64;
                    o + x * (r1 * t.cos()) + y * (r2 * t.sin())
                })
                .collect();
            if !same {
                between.reverse();
            }
            out.extend(between);
        }
        "LINE" | "POLYLINE" => {}
        _ if m
            .get(cid)?
            .parts
            .iter()
            .any(|(k, _)| k == "B_SPLINE_CURVE_WITH_KNOTS") =>
        {
            let c = spline_curve(m, cid)?;
            // the points of the curve between the vertices, found on it by projection: an edge
            // uses part of its curve, and a sample past a vertex widens the face's box (the
            // nearest of 69 samples put a fillet's box 0.3 mm past its end)
            let params = ProjectionParams::default();
            let ta = nurbs_core::project_to_curve(&c, &a, &params).t;
            let tb = nurbs_core::project_to_curve(&c, &b, &params).t;
            let k = SPLINE_EDGE_SAMPLES;
            out.extend((1..k - 1).map(|i| c.point(ta + (tb - ta) * i as f64 / (k - 1) as f64)));
        }
        _ => {}
    }
    out.push(b);
    Ok(out)
}

/// B_SPLINE_CURVE_WITH_KNOTS, simple or in a complex instance with RATIONAL_B_SPLINE_CURVE.
fn spline_curve(m: &Model, cid: u64) -> R<BSplineCurve> {
    let inst = m.get(cid)?;
    let (base, knots) = if inst.parts.len() == 1 {
        let p = &inst.parts[0].1;
        if p.len() < 9 {
            return Err(m.bad(cid, format!("{} parameters, expected 9", p.len())));
        }
        // name, degree, points, form, closed, self-intersect, then the knots
        (&p[1..], &p[6..])
    } else {
        (
            m.part(cid, "B_SPLINE_CURVE")?,
            m.part(cid, "B_SPLINE_CURVE_WITH_KNOTS")?,
        )
    };
    let d = m.num(cid, base.first())? as usize;
    let points = m
        .list(cid, base.get(1))?
        .iter()
        .map(|x| m.point(m.reference(cid, Some(x))?))
        .collect::<R<Vec<_>>>()?;
    let (mults, values) = (
        m.numbers(cid, knots.first())?,
        m.numbers(cid, knots.get(1))?,
    );
    let kv = expand_knots(&mults, &values);
    let weights = match inst
        .parts
        .iter()
        .find(|(n, _)| n == "RATIONAL_B_SPLINE_CURVE")
    {
        Some((_, w)) => Some(m.numbers(cid, w.first())?),
        None => None,
    };
    let g = |source| StepError::Geometry { id: cid, source };
    BSplineCurve::new(KnotVector::new(d, kv).map_err(g)?, points, weights).map_err(g)
}

/// The length unit's name: the LENGTH_UNIT of the GLOBAL_UNIT_ASSIGNED_CONTEXT, else the first
/// LENGTH_UNIT instance (a conversion-based unit refers to an SI one, which must not win).
fn units(m: &Model, ids: &[u64]) -> String {
    let assigned: Vec<u64> = ids
        .iter()
        .filter_map(|&id| {
            let inst = m.get(id).ok()?;
            let (_, p) = inst
                .parts
                .iter()
                .find(|(n, _)| n == "GLOBAL_UNIT_ASSIGNED_CONTEXT")?;
            match p.first() {
                Some(Value::List(l)) => Some(
                    l.iter()
                        .filter_map(|v| match v {
                            Value::Ref(r) => Some(*r),
                            _ => None,
                        })
                        .collect::<Vec<_>>(),
                ),
                _ => None,
            }
        })
        .flatten()
        .collect();
    let order: Vec<u64> = assigned.iter().chain(ids).copied().collect();
    for &id in &order {
        let Ok(inst) = m.get(id) else { continue };
        if !inst.parts.iter().any(|(n, _)| n == "LENGTH_UNIT") {
            continue;
        }
        if let Some((_, p)) = inst.parts.iter().find(|(n, _)| n == "SI_UNIT") {
            let prefix = match p.first() {
                Some(Value::Enum(e)) => e.as_str(),
                _ => "",
            };
            return match prefix {
                "MILLI" => "mm",
                "CENTI" => "cm",
                "MICRO" => "um",
                "KILO" => "km",
                _ => "m",
            }
            .to_string();
        }
        if let Some((_, p)) = inst
            .parts
            .iter()
            .find(|(n, _)| n == "CONVERSION_BASED_UNIT")
            && let Some(Value::Text(t)) = p.first()
        {
            return match t.to_uppercase().as_str() {
                "INCH" => "in".to_string(),
                "FOOT" => "ft".to_string(),
                other => other.to_lowercase(),
            };
        }
    }
    "mm".to_string()
}

/// Writes named surfaces as an AP214 STEP file, each a face bounded by its parameter box: as
/// [`write_step_faces`] with no trim.
pub fn write_step(
    surfaces: &[(&str, &BSplineSurface)],
    units: &str,
    name: &str,
) -> Result<String, nurbs_core::Error> {
    let faces: Vec<Face<'_>> = surfaces
        .iter()
        .map(|(label, s)| Face::untrimmed(label, s))
        .collect();
    write_step_faces(&faces, units, name)
}

/// Writes faces as an AP214 STEP file: each face (ADVANCED_FACE) of its
/// B_SPLINE_SURFACE_WITH_KNOTS (the complex rational instance where it has weights), bounded by
/// its trim loops where it has them — the outer loop a FACE_OUTER_BOUND, the others FACE_BOUNDs,
/// each EDGE_LOOP of ORIENTED_EDGEs of EDGE_CURVEs between VERTEX_POINTs, every edge a degree-1
/// B_SPLINE_CURVE_WITH_KNOTS through its points on the surface ([`crate::bounds::face_bounds`]:
/// the points moved to their feet on the surface, split at the loop's corners, a seam one edge
/// used both ways) — and otherwise by its four boundary curves (exact isocurves, a collapsed side
/// a vertex loop), the faces in one open shell of a SHELL_BASED_SURFACE_MODEL, with the product
/// structure a CAD system needs to open it. `units` is the length unit ("mm", "m", "in", …);
/// `name` the file's name in the header.
pub fn write_step_faces(
    faces: &[Face<'_>],
    units: &str,
    name: &str,
) -> Result<String, nurbs_core::Error> {
    use std::fmt::Write as _;
    let mut w = StepWriter::default();
    let mut ids = Vec::new();
    for f in faces {
        ids.push(w.face(f)?);
    }
    let shell = w.add(format!("OPEN_SHELL('',({}))", refs(&ids)));
    let model = w.add(format!("SHELL_BASED_SURFACE_MODEL('',(#{shell}))"));
    let unit = match units {
        "m" => "( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT($,.METRE.) )".to_string(),
        "cm" => "( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.CENTI.,.METRE.) )".to_string(),
        "um" => "( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MICRO.,.METRE.) )".to_string(),
        "km" => "( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.KILO.,.METRE.) )".to_string(),
        _ => "( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) )".to_string(),
    };
    let inch = matches!(units, "in" | "ft");
    let length = if inch {
        let mm = w.add("( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) )".into());
        let factor = if units == "in" { 25.4 } else { 304.8 };
        let measure = w.add(format!(
            "LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE({factor}),#{mm})"
        ));
        let dims = w.add("DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.)".into());
        w.add(format!(
            "( CONVERSION_BASED_UNIT('{}',#{measure}) LENGTH_UNIT() NAMED_UNIT(#{dims}) )",
            if units == "in" { "INCH" } else { "FOOT" }
        ))
    } else {
        w.add(unit)
    };
    let angle = w.add("( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) )".into());
    let solid = w.add("( NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT() )".into());
    let uncertainty = w.add(format!(
        "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#{length},'distance_accuracy_value','confusion accuracy')"
    ));
    let context = w.add(format!(
        "( GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#{uncertainty})) GLOBAL_UNIT_ASSIGNED_CONTEXT((#{length},#{angle},#{solid})) REPRESENTATION_CONTEXT('Context #1','3D Context with UNIT and UNCERTAINTY') )"
    ));
    let origin = w.add("CARTESIAN_POINT('',(0.,0.,0.))".into());
    let z = w.add("DIRECTION('',(0.,0.,1.))".into());
    let x = w.add("DIRECTION('',(1.,0.,0.))".into());
    let axes = w.add(format!("AXIS2_PLACEMENT_3D('',#{origin},#{z},#{x})"));
    let rep = w.add(format!(
        "MANIFOLD_SURFACE_SHAPE_REPRESENTATION('',(#{axes},#{model}),#{context})"
    ));
    let app =
        w.add("APPLICATION_CONTEXT('core data for automotive mechanical design processes')".into());
    w.add(format!(
        "APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000,#{app})"
    ));
    let pctx = w.add(format!("PRODUCT_CONTEXT('',#{app},'mechanical')"));
    let product = w.add(format!("PRODUCT('{0}','{0}','',(#{pctx}))", escape(name)));
    let formation = w.add(format!("PRODUCT_DEFINITION_FORMATION('','',#{product})"));
    let dctx = w.add(format!(
        "PRODUCT_DEFINITION_CONTEXT('part definition',#{app},'design')"
    ));
    let def = w.add(format!(
        "PRODUCT_DEFINITION('design','',#{formation},#{dctx})"
    ));
    let shape = w.add(format!("PRODUCT_DEFINITION_SHAPE('','',#{def})"));
    w.add(format!("SHAPE_DEFINITION_REPRESENTATION(#{shape},#{rep})"));
    let mut out = String::new();
    let _ = write!(
        out,
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('hier-fair model'),'2;1');\nFILE_NAME('{}','',(''),(''),'hier-fair','hier-fair','');\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN {{ 1 0 10303 214 1 1 1 1 }}'));\nENDSEC;\nDATA;\n",
        escape(name)
    );
    for (k, line) in w.lines.iter().enumerate() {
        let _ = writeln!(out, "#{} = {line};", k + 1);
    }
    out.push_str("ENDSEC;\nEND-ISO-10303-21;\n");
    Ok(out)
}

#[derive(Default)]
struct StepWriter {
    lines: Vec<String>,
}

fn refs(ids: &[usize]) -> String {
    ids.iter()
        .map(|i| format!("#{i}"))
        .collect::<Vec<_>>()
        .join(",")
}

fn escape(s: &str) -> String {
    s.replace('\'', "''")
}

/// A real as STEP writes it: always with a decimal point, round-trip exact.
fn real(x: f64) -> String {
    let s = format!("{x:?}");
    if s.contains('.') || s.contains('e') || s.contains("inf") || s.contains("NaN") {
        s.replace('e', "E")
    } else {
        format!("{s}.")
    }
}

impl StepWriter {
    fn add(&mut self, line: String) -> usize {
        self.lines.push(line);
        self.lines.len()
    }
    fn point(&mut self, p: &Point3) -> usize {
        self.add(format!(
            "CARTESIAN_POINT('',({},{},{}))",
            real(p.x),
            real(p.y),
            real(p.z)
        ))
    }
    fn knots(kv: &KnotVector) -> (String, String) {
        let mut values: Vec<f64> = Vec::new();
        let mut mults: Vec<usize> = Vec::new();
        for &k in kv.knots() {
            if values.last() == Some(&k) {
                *mults.last_mut().expect("a value has a count") += 1;
            } else {
                values.push(k);
                mults.push(1);
            }
        }
        (
            mults
                .iter()
                .map(|m| m.to_string())
                .collect::<Vec<_>>()
                .join(","),
            values
                .iter()
                .map(|&v| real(v))
                .collect::<Vec<_>>()
                .join(","),
        )
    }
    fn curve(&mut self, c: &BSplineCurve) -> usize {
        let pts: Vec<usize> = c.control_points().iter().map(|p| self.point(p)).collect();
        let (m, k) = Self::knots(c.knots());
        let d = c.knots().degree();
        match c.weights() {
            None => self.add(format!(
                "B_SPLINE_CURVE_WITH_KNOTS('',{d},({}),.UNSPECIFIED.,.F.,.F.,({m}),({k}),.UNSPECIFIED.)",
                refs(&pts)
            )),
            Some(w) => self.add(format!(
                "( BOUNDED_CURVE() B_SPLINE_CURVE({d},({}),.UNSPECIFIED.,.F.,.F.) B_SPLINE_CURVE_WITH_KNOTS(({m}),({k}),.UNSPECIFIED.) CURVE() GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_CURVE(({})) REPRESENTATION_ITEM('') )",
                refs(&pts),
                w.iter().map(|&x| real(x)).collect::<Vec<_>>().join(",")
            )),
        }
    }
    /// The face of `f`: its surface, bounded by its trim loops or else by its parameter box.
    fn face(&mut self, f: &Face<'_>) -> Result<usize, nurbs_core::Error> {
        let surface = self.surface(f.surface);
        let bounds = crate::bounds::face_bounds(f.surface, f.trim);
        let bounds = if bounds.loops.is_empty() {
            vec![self.box_bound(f.surface)?]
        } else {
            self.trim_bounds(&bounds)?
        };
        Ok(self.add(format!(
            "ADVANCED_FACE('{}',({}),#{surface},.T.)",
            escape(f.name),
            refs(&bounds)
        )))
    }

    /// The surface entity of `s`.
    fn surface(&mut self, s: &BSplineSurface) -> usize {
        let (nu, nv) = (s.num_u(), s.num_v());
        let mut rows = Vec::new();
        for i in 0..nu {
            let row: Vec<usize> = (0..nv)
                .map(|j| self.point(&s.control_point(i, j)))
                .collect();
            rows.push(format!("({})", refs(&row)));
        }
        let (mu, ku) = Self::knots(s.knots_u());
        let (mv, kv) = Self::knots(s.knots_v());
        let (du, dv) = (s.degree_u(), s.degree_v());
        match s.weights() {
            None => self.add(format!(
                "B_SPLINE_SURFACE_WITH_KNOTS('',{du},{dv},({}),.UNSPECIFIED.,.F.,.F.,.F.,({mu}),({mv}),({ku}),({kv}),.UNSPECIFIED.)",
                rows.join(",")
            )),
            Some(w) => {
                let wrows: Vec<String> = (0..nu)
                    .map(|i| {
                        format!(
                            "({})",
                            (0..nv)
                                .map(|j| real(w[i * nv + j]))
                                .collect::<Vec<_>>()
                                .join(",")
                        )
                    })
                    .collect();
                self.add(format!(
                    "( BOUNDED_SURFACE() B_SPLINE_SURFACE({du},{dv},({}),.UNSPECIFIED.,.F.,.F.,.F.) B_SPLINE_SURFACE_WITH_KNOTS(({mu}),({mv}),({ku}),({kv}),.UNSPECIFIED.) GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_SURFACE(({})) REPRESENTATION_ITEM('') SURFACE() )",
                    rows.join(","),
                    wrows.join(",")
                ))
            }
        }
    }

    /// The outer bound of `s`'s parameter box: its four boundary curves.
    fn box_bound(&mut self, s: &BSplineSurface) -> Result<usize, nurbs_core::Error> {
        // the boundary: u0 (v increasing), v1 (u increasing), u1 (v decreasing), v0 (u
        // decreasing): a loop around the face, the corners its vertices
        let (u0, u1) = s.domain_u();
        let (v0, v1) = s.domain_v();
        let corners = [
            s.point(u0, v0),
            s.point(u0, v1),
            s.point(u1, v1),
            s.point(u1, v0),
        ];
        let vids: Vec<usize> = corners
            .iter()
            .map(|p| {
                let pt = self.point(p);
                self.add(format!("VERTEX_POINT('',#{pt})"))
            })
            .collect();
        let sides = [
            (nurbs_core::Direction::U, u0, 0, 1, true),
            (nurbs_core::Direction::V, v1, 1, 2, true),
            (nurbs_core::Direction::U, u1, 3, 2, false),
            (nurbs_core::Direction::V, v0, 0, 3, false),
        ];
        let mut edges = Vec::new();
        for (dir, t, a, b, forward) in sides {
            let c = s.isocurve(dir, t)?;
            if (corners[a] - corners[b]).norm() <= 1e-12 * s.size().max(1.0)
                && c.control_points()
                    .iter()
                    .all(|p| (p - corners[a]).norm() <= 1e-12 * s.size().max(1.0))
            {
                continue; // a side collapsed to a point (a pole): no edge
            }
            let cid = self.curve(&c);
            let e = self.add(format!(
                "EDGE_CURVE('',#{},#{},#{cid},.T.)",
                vids[a], vids[b]
            ));
            edges.push(self.add(format!(
                "ORIENTED_EDGE('',*,*,#{e},{})",
                if forward { ".T." } else { ".F." }
            )));
        }
        let lp = self.add(format!("EDGE_LOOP('',({}))", refs(&edges)));
        Ok(self.add(format!("FACE_OUTER_BOUND('',#{lp},.T.)")))
    }

    /// The bounds of a face's trim loops: each edge a degree-1 B-spline curve through its points
    /// (chord-length parameters on [0, 1]), each vertex once, the outer loop a FACE_OUTER_BOUND.
    fn trim_bounds(
        &mut self,
        b: &crate::bounds::FaceBounds,
    ) -> Result<Vec<usize>, nurbs_core::Error> {
        let vertices: Vec<usize> = b
            .vertices
            .iter()
            .map(|p| {
                let pt = self.point(p);
                self.add(format!("VERTEX_POINT('',#{pt})"))
            })
            .collect();
        let mut edges = Vec::new();
        for e in &b.edges {
            let cid = self.curve(&crate::bounds::polyline(&e.points)?);
            edges.push(self.add(format!(
                "EDGE_CURVE('',#{},#{},#{cid},.T.)",
                vertices[e.start], vertices[e.end]
            )));
        }
        let mut out = Vec::new();
        for l in &b.loops {
            let oriented: Vec<usize> = l
                .edges
                .iter()
                .map(|&(k, forward)| {
                    self.add(format!(
                        "ORIENTED_EDGE('',*,*,#{},{})",
                        edges[k],
                        if forward { ".T." } else { ".F." }
                    ))
                })
                .collect();
            let lp = self.add(format!("EDGE_LOOP('',({}))", refs(&oriented)));
            let kind = if l.outer {
                "FACE_OUTER_BOUND"
            } else {
                "FACE_BOUND"
            };
            out.push(self.add(format!("{kind}('',#{lp},.T.)")));
        }
        Ok(out)
    }
}
