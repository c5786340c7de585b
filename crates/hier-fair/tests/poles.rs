//! Pole corners split into three quads (`hier_fair::poles`), against closed-form truth: the exact
//! rational sphere octant (its pole a collapsed side), with its pole turned to each of the four
//! sides, between the three quarter cylinders tangent to it along its sides.

use hier_fair::poles::{FIT_SHARE, PoleOutcome, split_pole_corners};
use hier_fair::synthetic::sphere_corner;
use hier_fair::{Link, Role};
use nurbs_core::{BSplineSurface, Continuity, ProjectionParams, Side, SurfaceProjector};

const R: f64 = 5.0;

/// The largest distance from `side` of `slave` (at 17 points) to `master`.
fn side_distance(slave: &BSplineSurface, side: Side, master: &BSplineSurface) -> f64 {
    let mut projector = SurfaceProjector::new(master, ProjectionParams::default());
    let (a, b) = side.along_domain(slave);
    (0..=16)
        .map(|k| {
            let (u, v) = side.params(slave, a + (b - a) * k as f64 / 16.0);
            projector.project(&slave.point(u, v)).distance
        })
        .fold(0.0, f64::max)
}

/// With the pole on any side, the octant becomes three quads on the sphere (within the fit's
/// share of the G0 tolerance), none with a collapsed side, each oriented as the octant; their
/// outer sides are linked to the masters they lie on (G2, as the octant's), their
/// internal curves linked G2 and shared exactly, and they form one corner group.
#[test]
fn a_sphere_octant_splits_into_three_quads_on_the_sphere() {
    for turn in 0..4 {
        let model = sphere_corner(R, turn).unwrap();
        assert_eq!(
            model.links.len(),
            3,
            "turn {turn}: a link per side but the pole"
        );
        let allowed = FIT_SHARE * model.tolerances.g0;
        let (split, record) = split_pole_corners(&model);
        assert_eq!(record.len(), 1);
        let PoleOutcome::Split {
            quads, fit_error, ..
        } = &record[0].outcome
        else {
            panic!("turn {turn}: kept: {:?}", record[0].outcome);
        };
        assert!(*fit_error <= allowed, "turn {turn}: fit error {fit_error}");
        assert_eq!(split.surfaces.len(), 6);
        assert_eq!(split.corners.len(), 1);
        assert_eq!(split.corners[0].name, "pole");
        let ids: Vec<usize> = quads.iter().map(|q| split.find(q).unwrap()).collect();
        assert_eq!(split.corners[0].patches, ids);
        let octant = &model.surfaces[3].surface;
        let d = octant.derivatives(0.5, 0.5);
        let outward = d.du.cross(&d.dv).dot(&d.point.coords).signum();
        for &k in &ids {
            let q = &split.surfaces[k].surface;
            assert_eq!(split.surfaces[k].role, Role::Corner);
            for i in 0..=10 {
                for j in 0..=10 {
                    let p = q.point(i as f64 / 10.0, j as f64 / 10.0);
                    let off = (p.coords.norm() - R).abs();
                    assert!(off <= allowed, "turn {turn}: {off} off the sphere");
                }
            }
            for side in Side::ALL {
                assert!(!g_continuity::measure::is_collapsed(q, side));
            }
            let d = q.derivatives(0.5, 0.5);
            assert_eq!(d.du.cross(&d.dv).dot(&d.point.coords).signum(), outward);
        }
        assert_eq!(
            split.links.len(),
            9,
            "six outer sides and three internal curves"
        );
        for l in &split.links {
            let (slave, master) = (&split.surfaces[l.slave], &split.surfaces[l.master]);
            let gap = side_distance(&slave.surface, l.side, &master.surface);
            if ids.contains(&l.master) {
                assert_eq!(l.continuity, Continuity::G2);
                assert!(gap <= 1e-12 * R, "turn {turn}: internal gap {gap}");
            } else {
                assert_eq!(l.continuity, Continuity::G2);
                assert!(gap <= allowed, "turn {turn}: {} gap {gap}", slave.name);
            }
        }
        for (j, &k) in ids.iter().enumerate() {
            let outer = split.links.iter().filter(|l| l.slave == k).count();
            // quad 0 has its two outer links; quad 1 one internal more, quad 2 two
            assert_eq!(outer, 2 + j, "turn {turn}: quad {j}");
        }
    }
}

/// A patch with a pole that is a master, or not a corner, is not split; a master is named with
/// why.
#[test]
fn a_master_or_a_non_corner_keeps_its_pole() {
    let mut model = sphere_corner(R, 0).unwrap();
    model.links.push(Link {
        slave: 0,
        side: Side::U1,
        master: 3,
        continuity: Continuity::G0,
    });
    let (split, record) = split_pole_corners(&model);
    assert_eq!(split, model);
    match &record[0].outcome {
        PoleOutcome::Kept { reason } => assert!(reason.contains("master"), "{reason}"),
        other => panic!("split: {other:?}"),
    }
    let mut primary = sphere_corner(R, 0).unwrap();
    primary.surfaces[3].role = Role::Primary;
    let (split, record) = split_pole_corners(&primary);
    assert!(record.is_empty());
    assert_eq!(split, primary);
}
