//! Surfaces that are not faces of a shell (\[ISO42\] geometry_schema and geometric_model_schema):
//! the elements of a GEOMETRIC_SET and the items of a shape representation that are surfaces —
//! a B-spline surface in any form, an elementary surface, a RECTANGULAR_TRIMMED_SURFACE (its
//! parameter box) or a CURVE_BOUNDED_SURFACE (the box of its boundary curves, kept as trim
//! loops). A surface that a face lies on is read once, as that face. Faces of a
//! SHELL_BASED_SURFACE_MODEL's OPEN_SHELL or CLOSED_SHELL are read as faces.

use std::collections::BTreeSet;

use super::curves::{angle_unit, curve_points};
use super::domain::{ParamBox, face_box};
use super::entities::{Model, R};
use super::faces::{BoundLoop, Inverter};
use super::lexer::Value;
use super::surfaces::{Surface, surface};
use super::{StepError, StepFace, StepFile, UnreadSurface};

/// Reads into `file` the surfaces of the file that no face lies on (module doc); what cannot be
/// read is named in its warnings, the first such error kept in `first_error`.
pub(super) fn read_loose(
    m: &Model,
    ids: &[u64],
    file: &mut StepFile,
    first_error: &mut Option<StepError>,
) {
    let mut used = BTreeSet::new();
    let mut roots = BTreeSet::new();
    for &id in ids {
        let Ok(inst) = m.get(id) else { continue };
        for (kind, p) in &inst.parts {
            let list = |k: usize| match p.get(k) {
                Some(Value::List(l)) => l.as_slice(),
                _ => &[],
            };
            let refs = |l: &[Value]| {
                l.iter()
                    .filter_map(|v| match v {
                        Value::Ref(r) => Some(*r),
                        _ => None,
                    })
                    .collect::<Vec<_>>()
            };
            match kind.as_str() {
                "ADVANCED_FACE" | "FACE_SURFACE" => {
                    if let Some(Value::Ref(s)) = p.get(2) {
                        used.insert(*s);
                    }
                }
                "GEOMETRIC_SET" | "GEOMETRIC_CURVE_SET" => roots.extend(refs(list(1))),
                // a shape representation's items (a pcurve's DEFINITIONAL_REPRESENTATION holds
                // 2D curves, no surface)
                k if k.ends_with("SHAPE_REPRESENTATION") && inst.parts.len() == 1 => {
                    roots.extend(refs(list(1)));
                }
                _ => {}
            }
        }
    }
    let angle = angle_unit(m, ids);
    for id in roots {
        if used.contains(&id) {
            continue;
        }
        match loose_surface(m, id, angle, &used, &mut file.warnings) {
            Ok(Some(Ok(face))) => file.faces.push(face),
            Ok(Some(Err(unread))) => *file.skipped.entry(unread.kind).or_default() += 1,
            Ok(None) => {}
            Err(e) => {
                let kind = m.kind(id).unwrap_or("?");
                file.warnings.push(format!("{kind} #{id} not read: {e}"));
                first_error.get_or_insert(e);
            }
        }
    }
}

/// Set element `id` as a face over its box: `None` when it is no surface (a curve, a point) or
/// lies under a face, `Some(Err(unread))` for a surface type that is not read; a boundary that is
/// not read is said in `warnings`.
fn loose_surface(
    m: &Model,
    id: u64,
    angle: f64,
    used: &BTreeSet<u64>,
    warnings: &mut Vec<String>,
) -> R<Option<Result<StepFace, UnreadSurface>>> {
    let inst = m.get(id)?;
    let kind = m.kind(id)?.to_string();
    let named = inst
        .parts
        .iter()
        .find(|(k, _)| inst.parts.len() == 1 || k == "REPRESENTATION_ITEM")
        .and_then(|(_, p)| match p.first() {
            Some(Value::Text(t)) if !t.is_empty() => Some(t.clone()),
            _ => None,
        });
    let name = named.unwrap_or_else(|| format!("step{id}"));
    let (basis, bounds): (u64, Bounds) = match kind.as_str() {
        "CURVE_BOUNDED_SURFACE" => {
            let p = m.part(id, &kind)?;
            let implicit_outer = matches!(p.get(3), Some(Value::Enum(e)) if e == "T");
            let basis = m.reference(id, p.get(1))?;
            let curves = m.list(id, p.get(2))?.to_vec();
            (basis, Bounds::Curves(curves, implicit_outer))
        }
        "RECTANGULAR_TRIMMED_SURFACE" => {
            let p = m.part(id, &kind)?;
            let n = |k: usize| m.num(id, p.get(k));
            let basis = m.reference(id, p.get(1))?;
            (basis, Bounds::Box([n(2)?, n(3)?], [n(4)?, n(5)?]))
        }
        _ => (id, Bounds::Natural),
    };
    if basis != id && used.contains(&basis) {
        return Ok(None);
    }
    let Some(s) = surface(m, basis)? else {
        let bkind = m.kind(basis)?;
        let is_surface =
            bkind.ends_with("SURFACE") || inst.parts.iter().any(|(k, _)| k == "SURFACE");
        return Ok(is_surface.then(|| {
            Err(UnreadSurface {
                kind: bkind.to_string(),
            })
        }));
    };
    let ((u, v), trim) = bounded_box(m, id, &kind, bounds, &s, angle, warnings)?;
    let built = s
        .build(u, v)
        .map_err(|source| StepError::Geometry { id, source })?;
    Ok(Some(Ok(StepFace {
        id,
        name,
        surface: built,
        kind: m.kind(basis)?.to_string(),
        trim,
        part: None,
    })))
}

/// The parameter box of set element `id` (`kind`) on its surface `s` from its `bounds`, with
/// its boundary as trim loops; a boundary that is not read is said in `warnings`.
fn bounded_box(
    m: &Model,
    id: u64,
    kind: &str,
    bounds: Bounds,
    s: &Surface,
    angle: f64,
    warnings: &mut Vec<String>,
) -> R<(ParamBox, Vec<Vec<nurbs_core::Point3>>)> {
    Ok(match bounds {
        Bounds::Natural => (
            face_box(s, &[], true).map_err(|e| m.bad(id, e.to_string()))?,
            Vec::new(),
        ),
        Bounds::Box(u, v) => (rectangular_box(s, u, v, angle), Vec::new()),
        Bounds::Curves(curves, implicit) => match boundary_loops(m, id, &curves, s, angle) {
            Ok(loops) => {
                let outer: &[BoundLoop] = if implicit { &[] } else { &loops };
                let uv = face_box(s, outer, true).map_err(|e| m.bad(id, e.to_string()))?;
                let trim = loops
                    .into_iter()
                    .map(|l| l.points)
                    .filter(|l| l.len() >= 3)
                    .collect();
                (uv, trim)
            }
            // a boundary of curves that are not read (a pcurve alone): the surface over its
            // natural box where it has one, and said so
            Err(e) => {
                let uv = face_box(s, &[], true)
                    .map_err(|d| m.bad(id, format!("{d}, and its boundary is not read: {e}")))?;
                warnings.push(format!(
                    "{kind} #{id}: its boundary is not read ({e}); read over its surface's whole parameter box, untrimmed"
                ));
                (uv, Vec::new())
            }
        },
    })
}

/// How a loose surface is bounded.
enum Bounds {
    /// its natural parameter box
    Natural,
    /// RECTANGULAR_TRIMMED_SURFACE's u1, u2 and v1, v2 (angles in the file's unit)
    Box([f64; 2], [f64; 2]),
    /// CURVE_BOUNDED_SURFACE's boundaries, and whether the surface's own bound is the outer one
    Curves(Vec<Value>, bool),
}

/// The box of a RECTANGULAR_TRIMMED_SURFACE: u1 … u2 and v1 … v2 in increasing order, an angle
/// in radians (\[ISO42\] `rectangular_trimmed_surface`: the trim values of an angular parameter
/// are in the plane-angle unit); an angular range that runs backwards goes the other way round.
fn rectangular_box(s: &Surface, u: [f64; 2], v: [f64; 2], angle: f64) -> ((f64, f64), (f64, f64)) {
    // per direction: whether it is an angle, and whether that angle wraps round (a sphere's
    // latitude does not)
    let (au, av) = match s {
        Surface::Cone(..) | Surface::Revolution(..) => ((true, true), (false, false)),
        Surface::Sphere(..) => ((true, true), (true, false)),
        Surface::Torus(..) => ((true, true), (true, true)),
        _ => ((false, false), (false, false)),
    };
    let range = |[a, b]: [f64; 2], (angular, wraps): (bool, bool)| {
        let (a, b) = if angular {
            (a * angle, b * angle)
        } else {
            (a, b)
        };
        if wraps {
            let b = if b <= a { b + std::f64::consts::TAU } else { b };
            (a, b.min(a + std::f64::consts::TAU))
        } else {
            (a.min(b), a.max(b))
        }
    };
    (range(u, au), range(v, av))
}

/// The boundary curves of CURVE_BOUNDED_SURFACE `id` as loops of points with their parameters on
/// `s`: each BOUNDARY_CURVE (or OUTER_BOUNDARY_CURVE) a composite curve whose segments are
/// sampled in order, each in its sense.
fn boundary_loops(
    m: &Model,
    id: u64,
    curves: &[Value],
    s: &Surface,
    angle: f64,
) -> R<Vec<BoundLoop>> {
    let mut inverter = Inverter::new(s);
    let mut out = Vec::new();
    for c in curves {
        let cid = m.reference(id, Some(c))?;
        let points = curve_points(m, cid, angle)?;
        let (params, found) = inverter.invert_loop(&points);
        out.push(BoundLoop {
            points,
            params,
            found,
            outer: m.kind(cid)? == "OUTER_BOUNDARY_CURVE",
            forward: true,
        });
    }
    Ok(out)
}
