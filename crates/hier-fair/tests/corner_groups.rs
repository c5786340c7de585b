//! n-sided corner groups found from the geometry (`build_hierarchy`, \[SV\] §3.4): the five-sided
//! fixture — five quads around one centre, bounded by five strips — with its links and its group
//! taken away gets them back; a model whose vertices are no such region gets none.

use hier_fair::{Model, Role, build_hierarchy};

fn fixture(name: &str) -> Model {
    let path = format!(
        "{}/../../fixtures/models/{name}",
        env!("CARGO_MANIFEST_DIR")
    );
    Model::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Whether `a` is `b` turned around the cycle, in either direction.
fn same_cycle(a: &[usize], b: &[usize]) -> bool {
    let n = b.len();
    a.len() == n
        && (0..n).any(|r| {
            (0..n).all(|i| a[i] == b[(i + r) % n]) || (0..n).all(|i| a[i] == b[(r + n - i) % n])
        })
}

#[test]
fn a_corner_split_into_quads_is_found_as_one_group_with_its_links() {
    let given = fixture("five_sided.json");
    let mut bare = given.clone();
    bare.links.clear();
    bare.corners.clear();
    let log = build_hierarchy(&mut bare);
    assert_eq!(bare.corners.len(), 1, "{}", log.lines.join("\n"));
    assert!(same_cycle(
        &bare.corners[0].patches,
        &given.corners[0].patches
    ));
    let key = |l: &hier_fair::Link| (l.slave, l.side, l.master, l.continuity);
    let theirs: Vec<_> = given.links.iter().map(key).collect();
    let ours: Vec<_> = bare.links.iter().map(key).collect();
    // every link found is the model's; the model's are all found but the G1 link between two
    // connecting strips (two surfaces of one role are not ordered: no link)
    assert!(ours.iter().all(|k| theirs.contains(k)), "{ours:?}");
    let missed: Vec<_> = theirs.iter().filter(|k| !ours.contains(k)).collect();
    assert_eq!(missed.len(), 1, "{missed:?}");
    assert_eq!(given.surfaces[missed[0].0].role, Role::Connecting);
    assert_eq!(given.surfaces[missed[0].2].role, Role::Connecting);
    // the found model fairs: the group's stage runs and every link is met
    let (_, report) = hier_fair::fair_model(
        &bare,
        &hier_fair::RoleMethods::default(),
        None,
        &hier_fair::FairParams::default(),
    )
    .unwrap();
    assert_eq!(report.groups.len(), 1);
    assert!(report.links.iter().all(|l| l.met), "{:#?}", report.problems);
}

#[test]
fn a_single_corner_patch_is_no_group() {
    // the X-node: one corner patch between four fillets, its vertices shared by fillets and
    // primaries, none of them a region split into quads
    let mut bare = fixture("x_node.json");
    bare.links.clear();
    build_hierarchy(&mut bare);
    assert!(bare.corners.is_empty(), "{:?}", bare.corners);
}
