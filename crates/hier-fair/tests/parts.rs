//! The parts of an assembly are linked inside themselves only: two parts that touch (a bolt in
//! its hole, a plate on a bracket) are two surface models, not one (model-format.md, `part`).

use hier_fair::{Model, build_hierarchy};
use serde_json::Value;

/// plate_boss with its links and roles taken away, each surface in part `part(name)`.
fn plate_boss_in_parts(part: impl Fn(&str) -> Option<&'static str>) -> Model {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/occt/occt_plate_boss.json");
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    v["links"] = Value::Array(Vec::new());
    for s in v["surfaces"].as_array_mut().unwrap() {
        s["role"] = Value::from("primary");
        if let Some(p) = part(s["name"].as_str().unwrap()) {
            s["part"] = Value::from(p);
        }
    }
    Model::from_json(&v.to_string()).unwrap()
}

#[test]
fn links_stay_inside_a_part() {
    let mut whole = plate_boss_in_parts(|_| None);
    build_hierarchy(&mut whole);
    assert!(!whole.links.is_empty(), "plate_boss's links are found");
    // the fillets in one part, the planes in another: no link crosses
    let split = |name: &str| {
        Some(if name.starts_with('F') {
            "fillets"
        } else {
            "faces"
        })
    };
    let mut parts = plate_boss_in_parts(split);
    let log = build_hierarchy(&mut parts);
    for l in &parts.links {
        assert_eq!(
            parts.surfaces[l.slave].part, parts.surfaces[l.master].part,
            "{} -> {}",
            parts.surfaces[l.slave].name, parts.surfaces[l.master].name
        );
    }
    assert!(parts.links.len() < whole.links.len());
    assert!(
        log.lines
            .iter()
            .any(|l| l
                .contains("of its part fillets (another part's surfaces are not linked to it)")),
        "{:?}",
        log.lines
    );
    // the part goes through the model file
    let back = Model::from_json(&parts.to_json()).unwrap();
    assert_eq!(back.surfaces[0].part, parts.surfaces[0].part);
    assert!(back.surfaces.iter().all(|s| s.part.is_some()));
}
