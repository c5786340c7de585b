//! Fillet rings whose seams the free G2 steps open (`framework/seams.rs`): only the parts on an
//! opened seam run again, the part that meets its links first and the other following it
//! along the seam, so the ring's other parts keep their one-hump sections and every link and
//! seam is kept. On AutoCAD's "t4m" part (`fixtures/foreign/trj1_t4m-ac.stp`: a ring of three
//! fillet parts on one plane) the ring run again as a whole, each part linked across its seams,
//! lost its sections: 1 of 5 links met. Now all five, and no shared edge leaves worse than it
//! came.

use hier_fair::{FairParams, RoleMethods, fair_model};

#[test]
fn a_ring_whose_seams_opened_keeps_its_links_and_its_seams() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/foreign/trj1_t4m-ac.stp");
    let model = hier_fair::exchange::read_cad(&std::fs::read(path).unwrap())
        .unwrap()
        .model;
    assert_eq!(model.links.len(), 5);
    let (_, report) = fair_model(
        &model,
        &RoleMethods::default(),
        None,
        &FairParams::default(),
    )
    .unwrap();
    let unmet: Vec<_> = report.links.iter().filter(|l| !l.met).collect();
    assert!(unmet.is_empty(), "{unmet:?}");
    let worse: Vec<_> = report.edges.iter().filter(|e| e.worse).collect();
    assert!(worse.is_empty(), "{worse:?}");
    // the seams did open in the free run and were closed by the ring's second run
    assert!(
        report
            .problems
            .iter()
            .any(|p| p.message.contains("its seam") && p.message.contains("linked G2")),
        "{:?}",
        report.problems
    );
}
