//! Access to a file's instances by number, with errors that name the instance: the parts of a
//! complex instance, numbers, references, lists, points, directions and placements
//! (AXIS2_PLACEMENT_3D), and the file's length unit.

use std::collections::HashMap;

use nurbs_core::{Point3, Vector3};

use super::StepError;
use super::lexer::{Instance, Value};

/// Access to the instances with errors that name them.
pub(super) struct Model<'a> {
    pub(super) all: &'a HashMap<u64, Instance>,
}

/// A result with a STEP error.
pub(super) type R<T> = Result<T, StepError>;

impl<'a> Model<'a> {
    /// Instance `id`.
    pub(super) fn get(&self, id: u64) -> R<&'a Instance> {
        self.all.get(&id).ok_or_else(|| StepError::Entity {
            id,
            entity: "?".into(),
            detail: "is referenced but not defined".into(),
        })
    }
    /// The parameters of the part `name` of instance `id`.
    pub(super) fn part(&self, id: u64, name: &str) -> R<&'a [Value]> {
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
    /// The entity type of instance `id` (its first part's).
    pub(super) fn kind(&self, id: u64) -> R<&'a str> {
        Ok(self.get(id)?.parts.first().map_or("", |p| p.0.as_str()))
    }
    /// An error of instance `id`.
    pub(super) fn bad(&self, id: u64, detail: impl Into<String>) -> StepError {
        StepError::Entity {
            id,
            entity: self.kind(id).unwrap_or("?").to_string(),
            detail: detail.into(),
        }
    }
    /// A number parameter of instance `id` (also inside a typed value).
    pub(super) fn num(&self, id: u64, v: Option<&Value>) -> R<f64> {
        match v {
            Some(Value::Number(x)) => Ok(*x),
            Some(Value::Typed(_, inner)) => self.num(id, inner.first()),
            _ => Err(self.bad(id, "expected a number")),
        }
    }
    /// A reference parameter of instance `id`.
    pub(super) fn reference(&self, id: u64, v: Option<&Value>) -> R<u64> {
        match v {
            Some(Value::Ref(r)) => Ok(*r),
            _ => Err(self.bad(id, "expected a reference")),
        }
    }
    /// A list parameter of instance `id`.
    pub(super) fn list<'v>(&self, id: u64, v: Option<&'v Value>) -> R<&'v [Value]> {
        match v {
            Some(Value::List(l)) => Ok(l),
            _ => Err(self.bad(id, "expected a list")),
        }
    }
    /// A list of numbers of instance `id`.
    pub(super) fn numbers(&self, id: u64, v: Option<&Value>) -> R<Vec<f64>> {
        self.list(id, v)?
            .iter()
            .map(|x| self.num(id, Some(x)))
            .collect()
    }
    /// The CARTESIAN_POINT `id` (missing coordinates 0).
    pub(super) fn point(&self, id: u64) -> R<Point3> {
        let c = self.numbers(id, self.part(id, "CARTESIAN_POINT")?.get(1))?;
        Ok(Point3::new(
            c.first().copied().unwrap_or(0.0),
            c.get(1).copied().unwrap_or(0.0),
            c.get(2).copied().unwrap_or(0.0),
        ))
    }
    /// The DIRECTION `id`, normalized.
    pub(super) fn direction(&self, id: u64) -> R<Vector3> {
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
    pub(super) fn placement(&self, id: u64) -> R<(Point3, Vector3, Vector3, Vector3)> {
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

/// The length unit as [`crate::units`] text: the LENGTH_UNIT of the GLOBAL_UNIT_ASSIGNED_CONTEXT,
/// else the first LENGTH_UNIT instance (a conversion-based unit refers to an SI one, which must
/// not win); a conversion-based unit by the size its LENGTH_MEASURE_WITH_UNIT gives it (\[ISO41\]:
/// 'INCH' as 25.4 mm is "in", 'UNKNOWN' as 10 mm "cm", 12.5 mm "12.5 mm"), by its name where
/// that size cannot be read.
pub(super) fn units(m: &Model, ids: &[u64]) -> String {
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
        if let Some(mm) = unit_mm(m, id, 0) {
            return crate::units::unit_text(mm);
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

/// Conversion-based units defined by one another, at most this deep (a cycle in a corrupt file
/// ends here).
const MAX_UNIT_NESTING: usize = 4;

/// Millimetres per the length unit `id`: an SI_UNIT (metre with its prefix, \[ISO41\]) or a
/// CONVERSION_BASED_UNIT, its LENGTH_MEASURE_WITH_UNIT's value times its unit's size.
fn unit_mm(m: &Model, id: u64, depth: usize) -> Option<f64> {
    let inst = m.get(id).ok()?;
    if let Some((_, p)) = inst.parts.iter().find(|(n, _)| n == "SI_UNIT") {
        if !matches!(p.get(1), Some(Value::Enum(e)) if e == "METRE") {
            return None;
        }
        let prefix = match p.first() {
            Some(Value::Enum(e)) => e.as_str(),
            _ => "",
        };
        // every si_prefix of [ISO41], in millimetres
        return Some(match prefix {
            "" => 1e3,
            "EXA" => 1e21,
            "PETA" => 1e18,
            "TERA" => 1e15,
            "GIGA" => 1e12,
            "MEGA" => 1e9,
            "KILO" => 1e6,
            "HECTO" => 1e5,
            "DECA" => 1e4,
            "DECI" => 1e2,
            "CENTI" => 1e1,
            "MILLI" => 1.0,
            "MICRO" => 1e-3,
            "NANO" => 1e-6,
            "PICO" => 1e-9,
            "FEMTO" => 1e-12,
            "ATTO" => 1e-15,
            _ => return None,
        });
    }
    if depth >= MAX_UNIT_NESTING {
        return None;
    }
    let (_, p) = inst
        .parts
        .iter()
        .find(|(n, _)| n == "CONVERSION_BASED_UNIT")?;
    let Some(Value::Ref(measure)) = p.get(1) else {
        return None;
    };
    let mu = m.get(*measure).ok()?;
    let (_, q) = mu.parts.first()?;
    let value = m.num(*measure, q.first()).ok()?;
    let Some(Value::Ref(base)) = q.get(1) else {
        return None;
    };
    let mm = value * unit_mm(m, *base, depth + 1)?;
    (mm.is_finite() && mm > 0.0).then_some(mm)
}
