//! The deviation an unmet link needs, as the report names it, holds: the model faired again with
//! those per-surface deviations meets the link.

use hier_fair::framework::VERIFY_FACTOR;
use hier_fair::{FairParams, Model, ProblemKind, RoleMethods, fair_model};

fn fixture(name: &str) -> Model {
    let path = format!(
        "{}/../../fixtures/models/{name}.json",
        env!("CARGO_MANIFEST_DIR")
    );
    Model::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// A freeform fillet between two primaries with a deviation of 1e-6: G2 on both sides needs
/// more, so both links are left unmet, and the report names each "met in a second run" with
/// the fillet and its primary at [`VERIFY_FACTOR`] × their deviation, or not. Set as
/// `deviation` of those surfaces in the model, as a user would, a run without the report's own
/// verification meets every link named met (and misses every one named not), each surface
/// within its raised figure; and at least one link is named met.
#[test]
fn an_unmet_links_named_deviation_meets_it() {
    let m = fixture("fillet_freeform");
    let tight = 1e-6;
    let params = FairParams {
        tolerance: Some(tight),
        ..FairParams::default()
    };
    let (_, report) = fair_model(&m, &RoleMethods::default(), None, &params).unwrap();
    let unmet: Vec<_> = report.links.iter().filter(|l| !l.met).collect();
    assert!(!unmet.is_empty(), "every link met within {tight}");
    let mut raised = m.clone();
    for l in &unmet {
        let link = m.links[l.link];
        for k in [link.slave, link.master] {
            raised.surfaces[k].deviation =
                Some(VERIFY_FACTOR * m.deviation_of(k, &[None; 3], Some(tight)));
        }
    }
    let again_params = FairParams {
        tolerance: Some(tight),
        verify_unmet: false,
        ..FairParams::default()
    };
    let (_, again) = fair_model(&raised, &RoleMethods::default(), None, &again_params).unwrap();
    let mut verified = 0;
    for l in &unmet {
        let named: Vec<_> = report
            .problems
            .iter()
            .filter(|p| {
                p.link.as_deref() == Some(l.label.as_str()) && p.message.contains("second run")
            })
            .collect();
        assert_eq!(named.len(), 1, "{}: {:#?}", l.label, report.problems);
        let link = m.links[l.link];
        let a = again.links.iter().find(|a| a.link == l.link).unwrap();
        // the report's word and the run agree, either way
        assert_eq!(
            named[0].kind == ProblemKind::Conflict,
            a.met,
            "{}: {:?}",
            l.label,
            a.after
        );
        if a.met {
            assert_eq!(named[0].amount, raised.surfaces[link.slave].deviation);
            verified += 1;
        }
    }
    for s in &again.surfaces {
        assert!(
            s.max_deviation <= s.tolerance,
            "{}: {} > {}",
            s.name,
            s.max_deviation,
            s.tolerance
        );
    }
    assert!(verified >= 1, "no unmet link met with its named deviation");
}
