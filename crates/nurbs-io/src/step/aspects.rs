//! Shape aspects: representations of a portion of a part's shape (\[ISO41\] product property
//! definition schema). A `shape_definition_representation` ties a representation to a
//! `product_definition_shape`, whose definition is either a product definition (the part's own
//! shape) or a shape aspect — a form feature, a datum, a portion of the shape described again
//! on its own (CATIA V4's form features come with their "explicit geometry branch", a solid of
//! the hole they describe). A face that only such representations hold is no face of the part:
//! it repeats geometry the part's own representation already has, or describes a volume the
//! part does not have (a hole's solid), and Open CASCADE transfers only the shapes of product
//! definitions. Such faces are left out, named in one warning; where the file holds no face
//! but those, they are kept (they are then all the geometry there is).

use std::collections::BTreeSet;

use super::assembly::{faces_under, representations};
use super::entities::Model;
use super::lexer::Value;

/// Whether instance `id` is a shape aspect or a shape aspect relationship (any subtype, simple
/// or in a complex instance: `SHAPE_ASPECT`, `COMPOSITE_SHAPE_ASPECT`, `DATUM`,
/// `DATUM_FEATURE`, `INSTANCED_FEATURE` with its `SHAPE_ASPECT` part, …).
fn is_aspect(m: &Model, id: u64) -> bool {
    m.get(id).is_ok_and(|inst| {
        inst.parts
            .iter()
            .any(|(name, _)| name.contains("SHAPE_ASPECT") || name.starts_with("DATUM"))
    })
}

/// The representations that describe a shape aspect: a shape definition representation whose
/// product definition shape defines an aspect — and no other shape definition representation
/// makes the same representation a product definition's shape (a writer may name one
/// representation for both; it is then the part's).
fn aspect_reps(m: &Model, ids: &[u64]) -> BTreeSet<u64> {
    let (mut aspects, mut products) = (BTreeSet::new(), BTreeSet::new());
    for &id in ids {
        let Ok(p) = m.part(id, "SHAPE_DEFINITION_REPRESENTATION") else {
            continue;
        };
        let (Some(Value::Ref(pds)), Some(Value::Ref(rep))) = (p.first(), p.get(1)) else {
            continue;
        };
        let Ok(q) = m.part(*pds, "PRODUCT_DEFINITION_SHAPE") else {
            continue;
        };
        match q.get(2) {
            Some(Value::Ref(def)) if is_aspect(m, *def) => aspects.insert(*rep),
            _ => products.insert(*rep),
        };
    }
    aspects.difference(&products).copied().collect()
}

/// The faces of `faces` that representations of shape aspects hold and no other
/// representation does (module docs); empty where that would leave no face.
pub(super) fn aspect_only_faces(m: &Model, ids: &[u64], faces: &BTreeSet<u64>) -> BTreeSet<u64> {
    let aspects = aspect_reps(m, ids);
    if aspects.is_empty() {
        return BTreeSet::new();
    }
    let reps = representations(m, ids);
    let (mut of_aspects, mut of_others) = (BTreeSet::new(), BTreeSet::new());
    for (id, items) in &reps {
        let held = faces_under(m, items, faces);
        if aspects.contains(id) {
            of_aspects.extend(held);
        } else {
            of_others.extend(held);
        }
    }
    let only: BTreeSet<u64> = of_aspects.difference(&of_others).copied().collect();
    if only.len() == faces.len() {
        return BTreeSet::new();
    }
    only
}
