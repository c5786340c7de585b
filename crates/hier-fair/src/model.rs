//! The model of `model-format.md`: named surfaces with roles, continuity links, corner groups and
//! tolerances; loading, validation and the hierarchy order (\[SV\] §1.1, §3.2).
//!
//! Roles rank primary (0) > connecting (1) > corner (2). A link's master must not be below its
//! slave, and a primary is never a slave (primaries are independent, \[SV\] §1.1). Links between
//! surfaces of the same rank (e.g. the quadrilaterals of one corner group, \[SV\] §3.4) are
//! allowed as long as the links form no cycle. The hierarchy order processes every surface after
//! all its masters, primaries first, ties broken by file order.
//!
//! A bare surface file (one surface, a list, `{"surfaces": [...]}` of plain surface records) is a
//! model of primaries named `surface` (or `surface0`, `surface1`, …) with no links.

use nurbs_core::io::SurfaceRecord;
use nurbs_core::{BSplineSurface, Continuity, Point3, Side};
use serde::{Deserialize, Serialize};

use crate::error::{DeviationError, Error, Result};

/// The place of a surface in the hierarchy.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Role {
    /// independent, large, keeps design intent
    Primary,
    /// fillets and other connecting surfaces
    Connecting,
    /// corner patches
    Corner,
}

impl Role {
    /// The model-format name.
    pub fn name(self) -> &'static str {
        match self {
            Role::Primary => "primary",
            Role::Connecting => "connecting",
            Role::Corner => "corner",
        }
    }
    /// Parses a model-format name.
    pub fn parse(s: &str) -> Option<Role> {
        [Role::Primary, Role::Connecting, Role::Corner]
            .into_iter()
            .find(|r| r.name() == s)
    }
    /// 0 for primaries, 1 for connecting surfaces, 2 for corners.
    pub fn rank(self) -> usize {
        self as usize
    }
}

/// A named surface of a model.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelSurface {
    /// unique name
    pub name: String,
    /// role in the hierarchy
    pub role: Role,
    /// the geometry
    pub surface: BSplineSurface,
    /// this surface's own deviation tolerance (model units), when the file gives one; it wins
    /// over the role's and the model's ([`Model::deviation_of`])
    pub deviation: Option<f64>,
    /// the face's trim as data: its boundary loops (outer first) as points on the surface in
    /// order, where the surface is a trimmed face's box (imported from STEP or IGES); empty:
    /// the whole surface is the face. Fairing keeps it as it is.
    pub trim: Vec<Vec<Point3>>,
    /// the part of an assembly the surface belongs to (its instance path, model-format.md);
    /// `build` links surfaces of one part only. `None`: no assembly.
    pub part: Option<String>,
}

/// A continuity link: the slave's side lies on the master.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Link {
    /// index of the slave surface
    pub slave: usize,
    /// the slave's side
    pub side: Side,
    /// index of the master surface
    pub master: usize,
    /// target continuity
    pub continuity: Continuity,
}

/// An n-sided corner patch given as its quadrilaterals, in cyclic order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CornerGroup {
    /// the group's name
    pub name: String,
    /// indices of the patches
    pub patches: Vec<usize>,
}

/// Model tolerances. Defaults: the values of the model-format example (deviation 0.05 mm, g0
/// 0.001 mm, g1 0.01°, g2 0.005 — Class-A practice); a model in another unit takes the lengths
/// in its unit ([`Model::set_units`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelTolerances {
    /// largest distance of a faired surface from its original (model units)
    pub deviation: f64,
    /// per role (primary, connecting, corner, by [`Role::rank`]) where the file gives an object
    /// `{"primary": mm, "connecting": mm, "corner": mm}`: \[SV\] §1.1, primaries keep the design
    /// intent, connecting surfaces and corners may deviate more
    pub role_deviation: [Option<f64>; 3],
    /// largest gap (model units)
    pub g0: f64,
    /// largest normal angle (degrees)
    pub g1_deg: f64,
    /// largest relative normal-curvature difference
    pub g2_rel: f64,
}

impl ModelTolerances {
    /// The continuity tolerances (gap, angle, curvature) as g-continuity takes them.
    pub fn continuity(&self) -> g_continuity::Tolerances {
        g_continuity::Tolerances {
            g0: self.g0,
            g1_deg: self.g1_deg,
            g2_rel: self.g2_rel,
        }
    }
}

impl Default for ModelTolerances {
    fn default() -> Self {
        Self {
            deviation: 0.05,
            role_deviation: [None; 3],
            g0: 1e-3,
            g1_deg: 1e-2,
            g2_rel: 5e-3,
        }
    }
}

/// A hierarchy of surfaces with continuity links.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    /// length unit, e.g. "mm" (free text)
    pub units: Option<String>,
    /// the surfaces
    pub surfaces: Vec<ModelSurface>,
    /// the links
    pub links: Vec<Link>,
    /// corner groups
    pub corners: Vec<CornerGroup>,
    /// tolerances
    pub tolerances: ModelTolerances,
    /// whether the tolerances were given in the file (written back only then)
    tolerances_given: [bool; 4],
}

#[derive(Debug, Serialize, Deserialize)]
struct ModelRecord {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    units: Option<String>,
    surfaces: Vec<SurfaceEntry>,
    #[serde(default)]
    links: Vec<LinkRecord>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    corners: Vec<CornerRecord>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    tolerances: Option<TolerancesRecord>,
}

#[derive(Debug, Serialize, Deserialize)]
struct SurfaceEntry {
    name: String,
    role: String,
    surface: SurfaceRecord,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    deviation: Option<f64>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    trim: Vec<Vec<[f64; 3]>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    part: Option<String>,
}

/// `tolerances.deviation`: one length for every surface, or one per role.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
#[serde(untagged, try_from = "serde_json::Value")]
enum DeviationRecord {
    All(f64),
    Roles(RoleDeviations),
}

impl TryFrom<serde_json::Value> for DeviationRecord {
    type Error = DeviationError;

    /// A number, or an object of the three roles, with an error that says which was expected
    /// (serde's untagged enums only say that no variant matched).
    fn try_from(v: serde_json::Value) -> std::result::Result<Self, DeviationError> {
        match v {
            serde_json::Value::Number(n) => n
                .as_f64()
                .map(DeviationRecord::All)
                .ok_or(DeviationError::NotALength(n)),
            serde_json::Value::Object(_) => serde_json::from_value(v)
                .map(DeviationRecord::Roles)
                .map_err(DeviationError::Roles),
            other => Err(DeviationError::Other(other)),
        }
    }
}

#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct RoleDeviations {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    primary: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    connecting: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    corner: Option<f64>,
}

#[derive(Debug, Serialize, Deserialize)]
struct LinkRecord {
    slave: String,
    side: String,
    master: String,
    continuity: String,
}

#[derive(Debug, Serialize, Deserialize)]
struct CornerRecord {
    name: String,
    patches: Vec<String>,
}

#[derive(Debug, Default, Serialize, Deserialize)]
struct TolerancesRecord {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    deviation: Option<DeviationRecord>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    g0: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    g1_deg: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    g2_rel: Option<f64>,
}

fn continuity_name(c: Continuity) -> &'static str {
    match c {
        Continuity::G0 => "G0",
        Continuity::G1 => "G1",
        Continuity::G2 => "G2",
    }
}

/// Parses "G0", "G1", "G2" (case-insensitive).
pub fn parse_continuity(s: &str) -> Option<Continuity> {
    match s.to_ascii_uppercase().as_str() {
        "G0" | "C0" => Some(Continuity::G0),
        "G1" => Some(Continuity::G1),
        "G2" => Some(Continuity::G2),
        _ => None,
    }
}

/// The surfaces of a model record, validated (names unique, roles known, deviations positive).
fn surfaces_of(entries: Vec<SurfaceEntry>) -> Result<Vec<ModelSurface>> {
    let mut surfaces: Vec<ModelSurface> = Vec::with_capacity(entries.len());
    for entry in entries {
        if surfaces.iter().any(|s| s.name == entry.name) {
            return Err(Error::DuplicateName { name: entry.name });
        }
        let role = Role::parse(&entry.role).ok_or_else(|| Error::UnknownRole {
            name: entry.name.clone(),
            role: entry.role.clone(),
        })?;
        let surface = entry
            .surface
            .to_surface()
            .map_err(|source| Error::Surface {
                name: entry.name.clone(),
                source,
            })?;
        if let Some(d) = entry.deviation.filter(|d| !(d.is_finite() && *d > 0.0)) {
            return Err(Error::BadTolerance {
                name: "surface deviation",
                value: d,
            });
        }
        let trim = crate::trim::checked_loops(&entry.name, &entry.trim, &surface)?;
        surfaces.push(ModelSurface {
            name: entry.name,
            role,
            surface,
            deviation: entry.deviation,
            trim,
            part: entry.part,
        });
    }
    Ok(surfaces)
}

/// The links of a model record, by surface index (`find`: a name's index).
fn links_of(records: &[LinkRecord], find: &dyn Fn(&str) -> Option<usize>) -> Result<Vec<Link>> {
    let mut links: Vec<Link> = Vec::with_capacity(records.len());
    for l in records {
        let label = format!("{}.{} -> {}", l.slave, l.side, l.master);
        let slave = find(&l.slave).ok_or_else(|| Error::UnknownSurface {
            link: label.clone(),
            name: l.slave.clone(),
        })?;
        let master = find(&l.master).ok_or_else(|| Error::UnknownSurface {
            link: label.clone(),
            name: l.master.clone(),
        })?;
        let side = Side::parse(&l.side).ok_or_else(|| Error::UnknownSide {
            link: label.clone(),
            side: l.side.clone(),
        })?;
        let continuity =
            parse_continuity(&l.continuity).ok_or_else(|| Error::UnknownContinuity {
                link: label.clone(),
                continuity: l.continuity.clone(),
            })?;
        links.push(Link {
            slave,
            side,
            master,
            continuity,
        });
    }
    Ok(links)
}

/// The corner groups of a model record, by surface index (`find`: a name's index).
fn corners_of(
    records: Vec<CornerRecord>,
    find: &dyn Fn(&str) -> Option<usize>,
) -> Result<Vec<CornerGroup>> {
    let mut corners = Vec::with_capacity(records.len());
    for c in records {
        let mut patches = Vec::with_capacity(c.patches.len());
        for p in &c.patches {
            let k = find(p).ok_or_else(|| Error::BadCorner {
                corner: c.name.clone(),
                detail: format!("no surface is named {p:?}"),
            })?;
            if patches.contains(&k) {
                return Err(Error::BadCorner {
                    corner: c.name.clone(),
                    detail: format!("{p} is listed twice"),
                });
            }
            patches.push(k);
        }
        if patches.len() < 2 {
            return Err(Error::BadCorner {
                corner: c.name,
                detail: format!("{} patches; a corner group needs at least 2", patches.len()),
            });
        }
        corners.push(CornerGroup {
            name: c.name,
            patches,
        });
    }
    Ok(corners)
}

/// True when the JSON value looks like a model (surfaces with names and roles).
fn is_model(value: &serde_json::Value) -> bool {
    value
        .get("surfaces")
        .and_then(|s| s.as_array())
        .is_some_and(|list| list.first().is_some_and(|e| e.get("surface").is_some()))
}

impl Model {
    /// A model of primaries without links (what a bare surface file means).
    pub fn from_primaries(surfaces: Vec<BSplineSurface>) -> Self {
        let single = surfaces.len() == 1;
        let surfaces = surfaces
            .into_iter()
            .enumerate()
            .map(|(k, surface)| ModelSurface {
                name: if single {
                    "surface".into()
                } else {
                    format!("surface{k}")
                },
                role: Role::Primary,
                surface,
                deviation: None,
                trim: Vec::new(),
                part: None,
            })
            .collect();
        Self {
            units: None,
            surfaces,
            links: Vec::new(),
            corners: Vec::new(),
            tolerances: ModelTolerances::default(),
            tolerances_given: [false; 4],
        }
    }

    /// Parses and validates a model, or a bare surface file as a model of primaries.
    pub fn from_json(text: &str) -> Result<Self> {
        let value: serde_json::Value = serde_json::from_str(text).map_err(|e| Error::Format {
            detail: format!("malformed JSON: {e}"),
        })?;
        if !is_model(&value) {
            return Ok(Self::from_primaries(nurbs_core::io::surfaces_from_json(
                text,
            )?));
        }
        // parsed from the text again, through serde_path_to_error: a field's error names its
        // place in the model (`surfaces[1].surface.control_points[0][0]`) and its line
        drop(value);
        let mut de = serde_json::Deserializer::from_str(text);
        let record: ModelRecord =
            serde_path_to_error::deserialize(&mut de).map_err(|e| Error::Format {
                detail: format!("model: {}: {}", e.path(), e.inner()),
            })?;
        Self::from_record(record)
    }

    fn from_record(record: ModelRecord) -> Result<Self> {
        let surfaces = surfaces_of(record.surfaces)?;
        if surfaces.is_empty() {
            return Err(Error::Format {
                detail: "the model has no surfaces".into(),
            });
        }
        let find = |name: &str| surfaces.iter().position(|s| s.name == name);
        let links = links_of(&record.links, &find)?;
        let corners = corners_of(record.corners, &find)?;
        let t = record.tolerances.unwrap_or_default();
        let d = ModelTolerances::default();
        let (all, roles) = match t.deviation {
            None => (None, RoleDeviations::default()),
            Some(DeviationRecord::All(x)) => (Some(x), RoleDeviations::default()),
            Some(DeviationRecord::Roles(r)) => (None, r),
        };
        let tolerances = ModelTolerances {
            deviation: all.unwrap_or(d.deviation),
            role_deviation: [roles.primary, roles.connecting, roles.corner],
            g0: t.g0.unwrap_or(d.g0),
            g1_deg: t.g1_deg.unwrap_or(d.g1_deg),
            g2_rel: t.g2_rel.unwrap_or(d.g2_rel),
        };
        let model = Self {
            units: record.units,
            surfaces,
            links,
            corners,
            tolerances,
            tolerances_given: [
                all.is_some(),
                t.g0.is_some(),
                t.g1_deg.is_some(),
                t.g2_rel.is_some(),
            ],
        };
        let mut model = model;
        model.default_lengths_in_units();
        model.validate()?;
        Ok(model)
    }

    /// Millimetres per model unit ([`nurbs_io::units::mm_per_unit`] of [`Model::units`]); 1 where
    /// the unit is not given or not known (the model is then read as millimetres).
    pub fn mm_per_unit(&self) -> f64 {
        self.units
            .as_deref()
            .and_then(nurbs_io::units::mm_per_unit)
            .unwrap_or(1.0)
    }

    /// Sets the model's unit ([`nurbs_io::units`] text); the length tolerances the model was not
    /// given (deviation, G0 gap) become the defaults, which are millimetres, in that unit.
    pub fn set_units(&mut self, units: &str) {
        self.units = Some(units.to_string());
        self.default_lengths_in_units();
    }

    /// The deviation and G0 tolerances the model was not given: [`ModelTolerances::default`]'s
    /// millimetres in the model's unit (a metre model's default deviation 0.05 mm is 5e-5).
    fn default_lengths_in_units(&mut self) {
        let d = ModelTolerances::default();
        let scale = 1.0 / self.mm_per_unit();
        if !self.tolerances_given[0] {
            self.tolerances.deviation = d.deviation * scale;
        }
        if !self.tolerances_given[1] {
            self.tolerances.g0 = d.g0 * scale;
        }
    }

    /// The model as JSON (model-format.md); the tolerances are written as given.
    pub fn to_json(&self) -> String {
        let t = &self.tolerances;
        let g = self.tolerances_given;
        let roles = t.role_deviation;
        let deviation = if roles.iter().any(Option::is_some) {
            Some(DeviationRecord::Roles(RoleDeviations {
                primary: roles[0],
                connecting: roles[1],
                corner: roles[2],
            }))
        } else {
            g[0].then_some(DeviationRecord::All(t.deviation))
        };
        let tolerances = (deviation.is_some() || g.iter().any(|&x| x)).then(|| TolerancesRecord {
            deviation,
            g0: g[1].then_some(t.g0),
            g1_deg: g[2].then_some(t.g1_deg),
            g2_rel: g[3].then_some(t.g2_rel),
        });
        let record = ModelRecord {
            units: self.units.clone(),
            surfaces: self
                .surfaces
                .iter()
                .map(|s| SurfaceEntry {
                    name: s.name.clone(),
                    role: s.role.name().into(),
                    surface: SurfaceRecord::from_surface(&s.surface),
                    deviation: s.deviation,
                    trim: s
                        .trim
                        .iter()
                        .map(|l| l.iter().map(|p| [p.x, p.y, p.z]).collect())
                        .collect(),
                    part: s.part.clone(),
                })
                .collect(),
            links: self
                .links
                .iter()
                .map(|l| LinkRecord {
                    slave: self.surfaces[l.slave].name.clone(),
                    side: l.side.name().into(),
                    master: self.surfaces[l.master].name.clone(),
                    continuity: continuity_name(l.continuity).into(),
                })
                .collect(),
            corners: self
                .corners
                .iter()
                .map(|c| CornerRecord {
                    name: c.name.clone(),
                    patches: c
                        .patches
                        .iter()
                        .map(|&k| self.surfaces[k].name.clone())
                        .collect(),
                })
                .collect(),
            tolerances,
        };
        serde_json::to_string(&record).expect("a model always serializes")
    }

    /// "slave.side -> master", the name of link `k` in messages and reports.
    pub fn link_label(&self, k: usize) -> String {
        let l = &self.links[k];
        format!(
            "{}.{} -> {}",
            self.surfaces[l.slave].name, l.side, self.surfaces[l.master].name
        )
    }

    /// The deviation tolerance of surface `k` (model units): its own `deviation`, else its
    /// role's in `role` (e.g. from the command line), else its role's in the file, else
    /// `global` (e.g. `--tolerance`), else the model's `tolerances.deviation`.
    pub fn deviation_of(&self, k: usize, role: &[Option<f64>; 3], global: Option<f64>) -> f64 {
        let s = &self.surfaces[k];
        let r = s.role.rank();
        s.deviation
            .or(role[r])
            .or(self.tolerances.role_deviation[r])
            .or(global)
            .unwrap_or(self.tolerances.deviation)
    }

    /// Index of the surface named `name`.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.surfaces.iter().position(|s| s.name == name)
    }

    /// Checks roles, duplicate links, tolerances and cycles (everything but geometry).
    pub fn validate(&self) -> Result<()> {
        let t = &self.tolerances;
        for (name, value) in [
            ("primary deviation", t.role_deviation[0].unwrap_or(1.0)),
            ("connecting deviation", t.role_deviation[1].unwrap_or(1.0)),
            ("corner deviation", t.role_deviation[2].unwrap_or(1.0)),
            ("deviation", t.deviation),
            ("g0", t.g0),
            ("g1_deg", t.g1_deg),
            ("g2_rel", t.g2_rel),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(Error::BadTolerance { name, value });
            }
        }
        for (k, l) in self.links.iter().enumerate() {
            if l.slave >= self.surfaces.len() || l.master >= self.surfaces.len() {
                return Err(Error::Format {
                    detail: format!("link {k} refers to a surface index out of range"),
                });
            }
            let (sr, mr) = (self.surfaces[l.slave].role, self.surfaces[l.master].role);
            if sr == Role::Primary || mr.rank() > sr.rank() {
                return Err(Error::WrongRoles {
                    link: self.link_label(k),
                    slave_role: sr.name(),
                    master_role: mr.name(),
                });
            }
            if self.links[..k]
                .iter()
                .any(|o| o.slave == l.slave && o.side == l.side)
            {
                return Err(Error::DuplicateLink {
                    link: self.link_label(k),
                    slave: self.surfaces[l.slave].name.clone(),
                    side: l.side.name().into(),
                });
            }
        }
        self.hierarchy_order().map(|_| ())
    }

    /// Surface indices so that every master comes before its slaves; primaries first, then by
    /// rank and file order. Errors on a cycle, naming it.
    pub fn hierarchy_order(&self) -> Result<Vec<usize>> {
        let n = self.surfaces.len();
        let mut pending: Vec<usize> = vec![0; n];
        for l in &self.links {
            pending[l.slave] += 1;
        }
        let mut done = vec![false; n];
        let mut order = Vec::with_capacity(n);
        while order.len() < n {
            let next = (0..n)
                .filter(|&k| !done[k] && pending[k] == 0)
                .min_by_key(|&k| (self.surfaces[k].role.rank(), k));
            let Some(k) = next else {
                return Err(Error::Cycle {
                    surfaces: self.describe_cycle(&done),
                });
            };
            done[k] = true;
            order.push(k);
            for l in self.links.iter().filter(|l| l.master == k) {
                pending[l.slave] -= 1;
            }
        }
        Ok(order)
    }

    /// Follows master links among the unfinished surfaces until one repeats.
    fn describe_cycle(&self, done: &[bool]) -> String {
        let start = (0..self.surfaces.len()).find(|&k| !done[k]).unwrap_or(0);
        let mut path = vec![start];
        let mut cur = start;
        while let Some(l) = self
            .links
            .iter()
            .find(|l| l.slave == cur && !done[l.master])
        {
            cur = l.master;
            if let Some(pos) = path.iter().position(|&p| p == cur) {
                path.drain(..pos);
                path.push(cur);
                break;
            }
            path.push(cur);
        }
        path.iter()
            .map(|&k| self.surfaces[k].name.as_str())
            .collect::<Vec<_>>()
            .join(" -> ")
    }

    /// Indices of the links whose slave is surface `k`.
    pub fn links_of_slave(&self, k: usize) -> Vec<usize> {
        (0..self.links.len())
            .filter(|&i| self.links[i].slave == k)
            .collect()
    }
}
