//! The kernel models with per-role deviation (\[SV\] §1.1: primaries 0.05 mm, connecting and
//! corner surfaces 0.5 mm): every link meets its target as `hier-fair check` measures the output
//! — G2 within 0.001 mm, 0.01° and 0.005 relative curvature, G0 within 0.001 mm — every surface
//! stays within its own deviation, and no link or shared edge leaves worse than it came.

mod common;
use common::{model, models};

use hier_fair::framework::worse_than;
use hier_fair::{FairParams, Role, RoleMethods, check_model, fair_model};
use nurbs_core::Continuity;

#[test]
fn every_kernel_model_meets_every_link_with_per_role_deviation() {
    let params = FairParams {
        role_tolerance: [Some(0.05), Some(0.5), Some(0.5)],
        ..FairParams::default()
    };
    for name in models() {
        let m = model(&name).unwrap();
        let (out, report) = fair_model(&m, &RoleMethods::default(), None, &params).unwrap();
        for c in check_model(&out, &Default::default()).unwrap() {
            let a = &c.measure;
            assert!(a.g0 <= 1e-3, "{name}: {} {a:?}", c.label);
            if c.target == Continuity::G2 {
                assert!(
                    a.g1_deg.is_none_or(|x| x <= 1e-2),
                    "{name}: {} {a:?}",
                    c.label
                );
                assert!(
                    a.g2_rel.is_none_or(|x| x <= 5e-3),
                    "{name}: {} {a:?}",
                    c.label
                );
            }
        }
        for s in &report.surfaces {
            let own = if s.role == Role::Primary { 0.05 } else { 0.5 };
            assert_eq!(s.tolerance, own, "{name}: {}", s.name);
            assert!(
                s.max_deviation <= own,
                "{name}: {} {}",
                s.name,
                s.max_deviation
            );
        }
        let t = m.tolerances.continuity();
        for l in &report.links {
            assert!(l.met, "{name}: {} {:?}", l.label, l.after);
            let (b, a) = (l.before.as_ref().unwrap(), l.after.as_ref().unwrap());
            assert_eq!(worse_than(b, a, l.target, &t), None, "{name}: {}", l.label);
        }
        assert!(
            report.edges.iter().all(|e| !e.worse),
            "{name}: {:#?}",
            report.edges
        );
    }
}
