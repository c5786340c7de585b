//! Assemblies: every face placed once per instance of its part (\[ISO41\] representation schema;
//! the product structure of AP203/AP214).
//!
//! A part's shape is a representation (its items: solids, shells, faces); an assembly places a
//! component's representation in its own by a `representation_relationship_with_transformation`
//! whose `rep_1` is the component's and `rep_2` the assembly's, the transformation an
//! `item_defined_transformation` from `transform_item_1` (the origin) to `transform_item_2` (the
//! target), both axis placements: a point p of the component is at F₂(F₁⁻¹(p)) in the assembly,
//! F the placement's frame map. A `mapped_item` in a representation places the mapped one the
//! same way (its map's origin to its target). A plain relationship (no transformation: a part's
//! shape representation and the B-rep it is made of) joins two representations into one
//! placement. The placements are composed from every representation that is no component down
//! to the faces; a face reached by n paths is n faces, each named by its path
//! (`NAUO id/…/face name`, the usage occurrence's id where a
//! `context_dependent_shape_representation` gives it, else `#relationship`). Some writers put
//! the assembly's representation in `rep_1`; the usage occurrence's related product definition
//! (the component) tells them apart, and their transformation is then inverted.

use std::collections::{BTreeMap, BTreeSet};

use nurbs_core::{Point3, Vector3};

use super::StepFace;
use super::entities::Model;
use super::lexer::Value;

/// Deepest assembly nesting followed: far beyond what a product structure has (the CAx-IF
/// assemblies nest three deep); a cycle in a corrupt file ends here.
const MAX_DEPTH: usize = 32;

/// Most face instances made: a bound on memory for a file whose structure multiplies (a
/// thousand placements of a thousand faces), beyond which the faces are kept unplaced.
const MAX_INSTANCES: usize = 1_000_000;

/// The entities through which a representation's items hold faces (or loose surfaces).
const CONTAINERS: [&str; 13] = [
    "MANIFOLD_SOLID_BREP",
    "BREP_WITH_VOIDS",
    "FACETED_BREP",
    "CLOSED_SHELL",
    "OPEN_SHELL",
    "ORIENTED_CLOSED_SHELL",
    "ORIENTED_OPEN_SHELL",
    "ORIENTED_FACE",
    "SHELL_BASED_SURFACE_MODEL",
    "FACE_BASED_SURFACE_MODEL",
    "CONNECTED_FACE_SET",
    "GEOMETRIC_SET",
    "GEOMETRIC_CURVE_SET",
];

/// A rigid placement p ↦ o + x·p.x + y·p.y + z·p.z.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Placement {
    o: Point3,
    x: Vector3,
    y: Vector3,
    z: Vector3,
}

impl Placement {
    const IDENTITY: Placement = Placement {
        o: Point3::new(0.0, 0.0, 0.0),
        x: Vector3::new(1.0, 0.0, 0.0),
        y: Vector3::new(0.0, 1.0, 0.0),
        z: Vector3::new(0.0, 0.0, 1.0),
    };

    fn apply(&self, p: &Point3) -> Point3 {
        self.o + self.x * p.x + self.y * p.y + self.z * p.z
    }

    fn apply_vector(&self, v: &Vector3) -> Vector3 {
        self.x * v.x + self.y * v.y + self.z * v.z
    }

    /// `self` after `inner`: p ↦ self(inner(p)).
    fn after(&self, inner: &Placement) -> Placement {
        Placement {
            o: self.apply(&inner.o),
            x: self.apply_vector(&inner.x),
            y: self.apply_vector(&inner.y),
            z: self.apply_vector(&inner.z),
        }
    }

    /// The inverse of a rigid placement (its frame orthonormal).
    fn inverse(&self) -> Placement {
        let d = -self.o.coords;
        Placement {
            o: Point3::new(self.x.dot(&d), self.y.dot(&d), self.z.dot(&d)),
            x: Vector3::new(self.x.x, self.y.x, self.z.x),
            y: Vector3::new(self.x.y, self.y.y, self.z.y),
            z: Vector3::new(self.x.z, self.y.z, self.z.z),
        }
    }

    fn is_identity(&self) -> bool {
        let close = |a: Vector3, b: Vector3| (a - b).norm() <= 1e-15;
        close(self.o.coords, Vector3::zeros())
            && close(self.x, Vector3::x())
            && close(self.y, Vector3::y())
            && close(self.z, Vector3::z())
    }

    /// The frame of the AXIS2_PLACEMENT_3D `id`.
    fn of_axis(m: &Model, id: u64) -> Option<Placement> {
        let (o, x, y, z) = m.placement(id).ok()?;
        Some(Placement { o, x, y, z })
    }

    /// The map from axis `from` to axis `to` (F_to ∘ F_from⁻¹).
    fn between(m: &Model, from: u64, to: u64) -> Option<Placement> {
        Some(Self::of_axis(m, to)?.after(&Self::of_axis(m, from)?.inverse()))
    }
}

/// A placement of one representation group in another.
struct Child {
    group: usize,
    placement: Placement,
    label: String,
}

/// Union-find over representation ids.
struct Groups {
    parent: BTreeMap<u64, u64>,
}

impl Groups {
    fn find(&mut self, a: u64) -> u64 {
        let p = *self.parent.entry(a).or_insert(a);
        if p == a {
            return a;
        }
        let root = self.find(p);
        self.parent.insert(a, root);
        root
    }
    fn join(&mut self, a: u64, b: u64) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent.insert(ra.max(rb), ra.min(rb));
        }
    }
}

fn refs(v: Option<&Value>) -> Vec<u64> {
    match v {
        Some(Value::List(l)) => l
            .iter()
            .filter_map(|x| match x {
                Value::Ref(r) => Some(*r),
                _ => None,
            })
            .collect(),
        Some(Value::Ref(r)) => vec![*r],
        _ => Vec::new(),
    }
}

/// The representations of the file: (name, items, context) instances, by id, with their items.
pub(super) fn representations(m: &Model, ids: &[u64]) -> BTreeMap<u64, Vec<u64>> {
    let mut out = BTreeMap::new();
    for &id in ids {
        let Ok(inst) = m.get(id) else { continue };
        for (name, p) in &inst.parts {
            if name.ends_with("REPRESENTATION")
                && matches!(p.get(1), Some(Value::List(_)))
                && matches!(p.get(2), Some(Value::Ref(_)))
            {
                out.insert(id, refs(p.get(1)));
            }
        }
    }
    out
}

/// The faces (of `faces`) that the items `items` hold through the containers.
pub(super) fn faces_under(m: &Model, items: &[u64], faces: &BTreeSet<u64>) -> BTreeSet<u64> {
    let mut out = BTreeSet::new();
    let mut seen = BTreeSet::new();
    let mut stack: Vec<u64> = items.to_vec();
    while let Some(id) = stack.pop() {
        if !seen.insert(id) {
            continue;
        }
        if faces.contains(&id) {
            out.insert(id);
            continue;
        }
        let Ok(inst) = m.get(id) else { continue };
        for (name, p) in &inst.parts {
            if CONTAINERS.contains(&name.as_str()) {
                for v in p {
                    stack.extend(refs(Some(v)));
                }
            }
        }
    }
    out
}

/// What a CONTEXT_DEPENDENT_SHAPE_REPRESENTATION says of a placed relationship: the usage
/// occurrence's id and the component's representations (those of its related product
/// definition).
struct Occurrence {
    label: Option<String>,
    component: BTreeSet<u64>,
}

/// The representations of each product definition, through SHAPE_DEFINITION_REPRESENTATION →
/// PRODUCT_DEFINITION_SHAPE.
fn definition_reps(m: &Model, ids: &[u64]) -> BTreeMap<u64, BTreeSet<u64>> {
    let mut out: BTreeMap<u64, BTreeSet<u64>> = BTreeMap::new();
    for &id in ids {
        let Ok(p) = m.part(id, "SHAPE_DEFINITION_REPRESENTATION") else {
            continue;
        };
        let (Some(Value::Ref(pds)), Some(Value::Ref(rep))) = (p.first(), p.get(1)) else {
            continue;
        };
        if let Ok(q) = m.part(*pds, "PRODUCT_DEFINITION_SHAPE")
            && let Some(Value::Ref(pd)) = q.get(2)
        {
            out.entry(*pd).or_default().insert(*rep);
        }
    }
    out
}

/// The representations of the top-level products: those of the product definitions that no
/// usage occurrence relates as a component.
fn top_level_reps(m: &Model, ids: &[u64]) -> BTreeSet<u64> {
    let reps = definition_reps(m, ids);
    let mut components = BTreeSet::new();
    for &id in ids {
        let Ok(inst) = m.get(id) else { continue };
        let Some((name, q)) = inst.parts.first() else {
            continue;
        };
        if name.ends_with("USAGE_OCCURRENCE")
            && let Some(Value::Ref(pd)) = q.get(4)
        {
            components.insert(*pd);
        }
    }
    reps.into_iter()
        .filter(|(pd, _)| !components.contains(pd))
        .flat_map(|(_, r)| r)
        .collect()
}

/// The usage occurrence of each placed relationship, through the
/// CONTEXT_DEPENDENT_SHAPE_REPRESENTATION → PRODUCT_DEFINITION_SHAPE → usage occurrence chain
/// (its id names the instance; its related product definition is the component).
fn occurrences(m: &Model, ids: &[u64]) -> BTreeMap<u64, Occurrence> {
    let reps = definition_reps(m, ids);
    let mut out = BTreeMap::new();
    for &id in ids {
        let Ok(p) = m.part(id, "CONTEXT_DEPENDENT_SHAPE_REPRESENTATION") else {
            continue;
        };
        let (Some(Value::Ref(rel)), Some(Value::Ref(pds))) = (p.first(), p.get(1)) else {
            continue;
        };
        let usage = m
            .part(*pds, "PRODUCT_DEFINITION_SHAPE")
            .ok()
            .and_then(|q| match q.get(2) {
                Some(Value::Ref(nauo)) => m.get(*nauo).ok(),
                _ => None,
            })
            .and_then(|n| n.parts.first().map(|(_, q)| q));
        let Some(usage) = usage else { continue };
        let label = match usage.first() {
            Some(Value::Text(t)) if !t.trim().is_empty() => Some(t.clone()),
            _ => None,
        };
        let component = match usage.get(4) {
            Some(Value::Ref(pd)) => reps.get(pd).cloned().unwrap_or_default(),
            _ => BTreeSet::new(),
        };
        out.insert(*rel, Occurrence { label, component });
    }
    out
}

/// The placed relationships (child rep, parent rep, placement, label) and the plain ones.
type Relations = (Vec<(u64, u64, Placement, String)>, Vec<(u64, u64)>);

fn relations(m: &Model, ids: &[u64], reps: &BTreeMap<u64, Vec<u64>>) -> Relations {
    let occurrences = occurrences(m, ids);
    let (mut placed, mut plain) = (Vec::new(), Vec::new());
    for &id in ids {
        let Ok(inst) = m.get(id) else { continue };
        // the relationship's attributes: in the REPRESENTATION_RELATIONSHIP part of a complex
        // instance, or a simple instance of a subtype (SHAPE_REPRESENTATION_RELATIONSHIP, …)
        let Some((_, p)) = inst.parts.iter().find(|(n, q)| {
            n.ends_with("REPRESENTATION_RELATIONSHIP")
                && matches!(
                    (q.get(2), q.get(3)),
                    (Some(Value::Ref(_)), Some(Value::Ref(_)))
                )
        }) else {
            continue;
        };
        let (Some(Value::Ref(r1)), Some(Value::Ref(r2))) = (p.get(2), p.get(3)) else {
            continue;
        };
        let transform = inst
            .parts
            .iter()
            .find(|(n, _)| n == "REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION")
            .and_then(|(_, q)| match q.first() {
                Some(Value::Ref(t)) => Some(*t),
                _ => None,
            });
        match transform {
            None => plain.push((*r1, *r2)),
            Some(t) => {
                let placement = m
                    .part(t, "ITEM_DEFINED_TRANSFORMATION")
                    .ok()
                    .and_then(|q| match (q.get(2), q.get(3)) {
                        (Some(Value::Ref(a)), Some(Value::Ref(b))) => Placement::between(m, *a, *b),
                        _ => None,
                    })
                    .unwrap_or(Placement::IDENTITY);
                let occurrence = occurrences.get(&id);
                let label = occurrence
                    .and_then(|o| o.label.clone())
                    .unwrap_or_else(|| format!("#{id}"));
                // rep_1 is the component's and rep_2 the assembly's (the recommended practice);
                // where the usage occurrence's component is rep_2, a writer has them the other
                // way round, and the transformation maps the assembly's frame to the component's
                let reversed = occurrence
                    .is_some_and(|o| o.component.contains(r2) && !o.component.contains(r1));
                if reversed {
                    placed.push((*r2, *r1, placement.inverse(), label));
                } else {
                    placed.push((*r1, *r2, placement, label));
                }
            }
        }
    }
    // mapped items: the mapped representation placed in the one holding the item
    for (&rep, items) in reps {
        for &item in items {
            let Ok(p) = m.part(item, "MAPPED_ITEM") else {
                continue;
            };
            let (Some(Value::Ref(map)), Some(Value::Ref(target))) = (p.get(1), p.get(2)) else {
                continue;
            };
            let Ok(q) = m.part(*map, "REPRESENTATION_MAP") else {
                continue;
            };
            let (Some(Value::Ref(origin)), Some(Value::Ref(mapped))) = (q.first(), q.get(1)) else {
                continue;
            };
            let placement = Placement::between(m, *origin, *target).unwrap_or(Placement::IDENTITY);
            placed.push((*mapped, rep, placement, format!("#{item}")));
        }
    }
    (placed, plain)
}

/// The representation groups (joined by plain relationships) with their faces and the
/// placements of one group in another.
struct Tree {
    /// group of each representation id
    index: BTreeMap<u64, usize>,
    faces: Vec<BTreeSet<u64>>,
    children: Vec<Vec<Child>>,
    is_child: Vec<bool>,
}

impl Tree {
    fn new(
        m: &Model,
        reps: &BTreeMap<u64, Vec<u64>>,
        relations: Relations,
        faces: &BTreeSet<u64>,
    ) -> Tree {
        let (placed, plain) = relations;
        let mut groups = Groups {
            parent: BTreeMap::new(),
        };
        for &r in reps.keys() {
            groups.find(r);
        }
        for &(c, p, _, _) in &placed {
            groups.find(c);
            groups.find(p);
        }
        for &(a, b) in &plain {
            groups.join(a, b);
        }
        let all: Vec<u64> = groups.parent.keys().copied().collect();
        let roots: BTreeSet<u64> = all.iter().map(|&r| groups.find(r)).collect();
        let number: BTreeMap<u64, usize> = roots.iter().enumerate().map(|(k, &r)| (r, k)).collect();
        let index: BTreeMap<u64, usize> =
            all.iter().map(|&r| (r, number[&groups.find(r)])).collect();
        let mut tree = Tree {
            faces: vec![BTreeSet::new(); roots.len()],
            children: (0..roots.len()).map(|_| Vec::new()).collect(),
            is_child: vec![false; roots.len()],
            index,
        };
        for (rep, items) in reps {
            let g = tree.index[rep];
            tree.faces[g].extend(faces_under(m, items, faces));
        }
        for (c, p, placement, label) in placed {
            let (cg, pg) = (tree.index[&c], tree.index[&p]);
            if cg != pg {
                tree.is_child[cg] = true;
                tree.children[pg].push(Child {
                    group: cg,
                    placement,
                    label,
                });
            }
        }
        tree
    }
}

/// The placed instances of each face of `faces` (id → placements with their path labels);
/// [`Placed::None`] when the file places nothing (no transformed relationship, no mapped item:
/// every face is where it is read).
pub(super) fn instances(m: &Model, ids: &[u64], faces: &BTreeSet<u64>) -> Placed {
    let reps = representations(m, ids);
    let relations = relations(m, ids, &reps);
    if relations.0.is_empty() {
        return Placed::None;
    }
    let tree = Tree::new(m, &reps, relations, faces);
    // depth-first from the top-level products' representations (a representation of a
    // property that holds a part's solid too is no instance of it), else from every group
    // that is no component
    let top: BTreeSet<usize> = top_level_reps(m, ids)
        .into_iter()
        .filter_map(|r| tree.index.get(&r).copied())
        .filter(|&g| !tree.is_child[g])
        .collect();
    let starts: Vec<usize> = if top.is_empty() {
        (0..tree.faces.len())
            .filter(|&g| !tree.is_child[g])
            .collect()
    } else {
        top.into_iter().collect()
    };
    let mut stack: Vec<(usize, Placement, String, usize)> = starts
        .into_iter()
        .rev()
        .map(|g| (g, Placement::IDENTITY, String::new(), 0))
        .collect();
    let mut out: BTreeMap<u64, Vec<(Placement, String)>> = BTreeMap::new();
    let mut made = 0usize;
    while let Some((g, at, path, depth)) = stack.pop() {
        for &f in &tree.faces[g] {
            made += 1;
            if made > MAX_INSTANCES {
                return Placed::TooMany;
            }
            out.entry(f).or_default().push((at, path.clone()));
        }
        if depth >= MAX_DEPTH {
            continue;
        }
        for c in tree.children[g].iter().rev() {
            let label = if path.is_empty() {
                c.label.clone()
            } else {
                format!("{path}/{}", c.label)
            };
            stack.push((c.group, at.after(&c.placement), label, depth + 1));
        }
    }
    Placed::Faces(out)
}

/// What [`instances`] found.
pub(super) enum Placed {
    /// the file places nothing
    None,
    /// more than [`MAX_INSTANCES`] face instances
    TooMany,
    /// the placements of each face, with their path labels
    Faces(BTreeMap<u64, Vec<(Placement, String)>>),
}

/// `faces` with every face placed once per instance (see the module docs); a face no
/// placement reaches stays as it is read. Where the instances would pass [`MAX_INSTANCES`],
/// the faces stay as read and the warning says so.
pub(super) fn place(
    m: &Model,
    ids: &[u64],
    faces: Vec<StepFace>,
    warnings: &mut Vec<String>,
) -> Vec<StepFace> {
    let face_ids: BTreeSet<u64> = faces.iter().map(|f| f.id).collect();
    let placed = match instances(m, ids, &face_ids) {
        Placed::None => return faces,
        Placed::TooMany => {
            warnings.push(format!(
                "the assembly places more than {MAX_INSTANCES} faces: each face is read once, where its part's own coordinates put it"
            ));
            return faces;
        }
        Placed::Faces(p) => p,
    };
    let mut out = Vec::with_capacity(faces.len());
    for f in faces {
        let Some(list) = placed.get(&f.id) else {
            out.push(f);
            continue;
        };
        for (at, path) in list {
            let mut g = f.clone();
            if !at.is_identity() {
                for p in g.surface.control_points_mut() {
                    *p = at.apply(p);
                }
                for l in &mut g.trim {
                    for p in l.iter_mut() {
                        *p = at.apply(p);
                    }
                }
            }
            if !path.is_empty() {
                g.name = format!("{path}/{}", f.name);
                g.part = Some(path.clone());
            }
            out.push(g);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn placements_compose_and_invert() {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let a = Placement {
            o: Point3::new(1.0, 2.0, 3.0),
            x: Vector3::new(s, s, 0.0),
            y: Vector3::new(-s, s, 0.0),
            z: Vector3::z(),
        };
        let p = Point3::new(0.3, -0.7, 2.0);
        let back = a.inverse().apply(&a.apply(&p));
        assert!((back - p).norm() < 1e-14);
        let round = a.after(&a.inverse());
        assert!((round.apply(&p) - p).norm() < 1e-14);
        let twice = a.after(&a);
        assert!((twice.apply(&p) - a.apply(&a.apply(&p))).norm() < 1e-14);
    }
}
