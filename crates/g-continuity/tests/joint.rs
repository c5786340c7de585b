//! The joint polish ([`g_continuity::polish_joint`]): every link's conditions solved at once
//! over rows 0..=2 of all four sides of a slave, tested on a torus cut into nine pieces — the
//! centre piece is G2 (G∞) to its four neighbours in closed form, so every figure has an exact
//! truth.

use g_continuity::{ConnectParams, Error, MeasureParams, SideLink, polish_joint};
use nurbs_core::testing::rng;
use nurbs_core::{BSplineSurface, Continuity, Direction, Side, Vector3, shapes::torus};
use rand::Rng;

/// The torus (major 10, tube 3) cut at a third and two thirds of a quarter of both domains:
/// the centre piece, raised to degree 5 with knots at its thirds (room for three rows per side
/// and the samples of several spans), and its four neighbours in side order U0, U1, V0, V1.
fn torus_pieces() -> (BSplineSurface, Vec<BSplineSurface>) {
    let t = torus(10.0, 3.0).unwrap();
    let ((u0, u1), (v0, v1)) = (t.domain_u(), t.domain_v());
    let cut = |a: f64, b: f64, k: f64| a + (b - a) * k / 12.0;
    let piece = |i: usize, j: usize| {
        t.extract(
            (cut(u0, u1, i as f64), cut(u0, u1, i as f64 + 1.0)),
            (cut(v0, v1, j as f64), cut(v0, v1, j as f64 + 1.0)),
        )
        .unwrap()
    };
    let mut centre = piece(1, 1);
    for dir in [Direction::U, Direction::V] {
        let by = 5 - match dir {
            Direction::U => centre.degree_u(),
            Direction::V => centre.degree_v(),
        };
        centre = centre.elevate_degree(dir, by).unwrap();
        let (a, b) = match dir {
            Direction::U => centre.domain_u(),
            Direction::V => centre.domain_v(),
        };
        let xs: Vec<f64> = (1..6).map(|k| a + (b - a) * k as f64 / 6.0).collect();
        centre = centre.refine(dir, &xs).unwrap();
    }
    (
        centre,
        vec![piece(0, 1), piece(2, 1), piece(1, 0), piece(1, 2)],
    )
}

fn links(masters: &[BSplineSurface]) -> Vec<SideLink<'_>> {
    Side::ALL
        .into_iter()
        .zip(masters)
        .map(|(side, master)| SideLink {
            side,
            master,
            target: Continuity::G2,
            range: None,
            g2_zones: [0.0; 2],
        })
        .collect()
}

fn all_met(s: &BSplineSurface, links: &[SideLink], p: &ConnectParams) -> bool {
    let t = p.tolerances;
    links.iter().all(|l| {
        l.measure(s, &MeasureParams::default())
            .unwrap()
            .meets(l.target, t.g0, t.g1_deg, t.g2_rel)
    })
}

/// Rows 0..=2 of every side moved by up to `amount` in each coordinate (seeded).
fn perturb_frames(s: &BSplineSurface, seed: u64, amount: f64) -> BSplineSurface {
    let mut r = rng(seed);
    let mut out = s.clone();
    let (nu, nv) = (s.num_u(), s.num_v());
    let mut rows: Vec<(usize, usize)> = Side::ALL
        .into_iter()
        .flat_map(|side| (0..3).flat_map(move |k| side.row(k, nu, nv)))
        .collect();
    rows.sort_unstable();
    rows.dedup();
    for (i, j) in rows {
        let idx = out.index(i, j);
        out.control_points_mut()[idx] += Vector3::new(
            r.random_range(-amount..amount),
            r.random_range(-amount..amount),
            r.random_range(-amount..amount),
        );
    }
    out
}

#[test]
fn an_exact_slave_is_left_bit_identical() {
    let (centre, masters) = torus_pieces();
    let links = links(&masters);
    let p = ConnectParams::default();
    assert!(all_met(&centre, &links, &p));
    let (out, report) = polish_joint(&centre, &links, &p, 1.0).unwrap();
    assert_eq!(report.iterations, 0);
    assert_eq!(out.control_points(), centre.control_points());
}

/// Every frame point of the four sides moved by up to 2e-4 (a gap within the G0 tolerance, but
/// normals and curvatures far off, corners included): the polish brings every link back within
/// its tolerances, with moves of the order of the disturbance.
#[test]
fn disturbed_frames_of_four_sides_are_set_g2_at_once() {
    let (centre, masters) = torus_pieces();
    let links = links(&masters);
    let p = ConnectParams::default();
    for seed in 0..3 {
        let disturbed = perturb_frames(&centre, seed, 2e-4);
        assert!(
            !all_met(&disturbed, &links, &p),
            "seed {seed}: nothing to do"
        );
        let (out, report) = polish_joint(&disturbed, &links, &p, 1.0).unwrap();
        assert!(all_met(&out, &links, &p), "seed {seed}: {report:?}");
        assert!(report.worst_after < report.worst_before, "{report:?}");
        assert!(report.max_move < 2e-3, "seed {seed}: {report:?}");
        // the interior (rows 3 and beyond from every side) does not move
        let (nu, nv) = (out.num_u(), out.num_v());
        for i in 3..nu - 3 {
            for j in 3..nv - 3 {
                assert_eq!(out.control_point(i, j), disturbed.control_point(i, j));
            }
        }
    }
}

/// A side linked G1 moves its rows 0 and 1 only, and its curvature is not a condition: the
/// polish of a slave whose U0 side targets G1 leaves U0's row 2 where it was, except where that
/// row is another G2 side's frame.
#[test]
fn a_g1_side_keeps_its_row_two() {
    let (centre, masters) = torus_pieces();
    let mut links = links(&masters);
    links[0].target = Continuity::G1;
    let p = ConnectParams::default();
    let disturbed = perturb_frames(&centre, 7, 2e-4);
    let (out, _) = polish_joint(&disturbed, &links, &p, 1.0).unwrap();
    assert!(all_met(&out, &links, &p));
    let nv = out.num_v();
    for j in 3..nv - 3 {
        assert_eq!(out.control_point(2, j), disturbed.control_point(2, j));
    }
}

/// The move bound is a trust region: with a bound below what the disturbance needs no point
/// moves more than it (and the surface, R_ij ≥ 0 with Σ R_ij = 1, no more either), and the
/// residuals still fall.
#[test]
fn no_point_moves_beyond_the_bound() {
    let (centre, masters) = torus_pieces();
    let links = links(&masters);
    let p = ConnectParams::default();
    let disturbed = perturb_frames(&centre, 3, 2e-4);
    let bound = 2e-5;
    let (out, report) = polish_joint(&disturbed, &links, &p, bound).unwrap();
    assert!(report.iterations > 0, "{report:?}");
    assert!(report.worst_after < report.worst_before, "{report:?}");
    for (a, b) in out.control_points().iter().zip(disturbed.control_points()) {
        assert!((a - b).norm() <= bound, "{}", (a - b).norm());
    }
    assert!(nurbs_core::energy::max_deviation(&disturbed, &out, 21) <= bound);
}

/// A side shared with a surface no link covers (`SetParams::kept_sides`) keeps its tangential
/// frame: with U0 unlinked and kept, its rows 0 and 1 stay bit-identical, corners included,
/// while the three linked sides are set.
#[test]
fn a_kept_side_keeps_its_frame() {
    let (centre, masters) = torus_pieces();
    let links: Vec<SideLink> = links(&masters).into_iter().skip(1).collect();
    let mut p = ConnectParams::default();
    p.set.kept_sides[0] = true;
    // the linked sides' frames disturbed, the kept side's exact (it is the other surface's
    // join, which no step here may change)
    let mut disturbed = perturb_frames(&centre, 11, 2e-4);
    let (nu, nv) = (centre.num_u(), centre.num_v());
    let frame: Vec<(usize, usize)> = Side::U0
        .row(0, nu, nv)
        .into_iter()
        .chain(Side::U0.row(1, nu, nv))
        .collect();
    for &(i, j) in &frame {
        let idx = disturbed.index(i, j);
        disturbed.control_points_mut()[idx] = centre.control_point(i, j);
    }
    let (out, report) = polish_joint(&disturbed, &links, &p, 1.0).unwrap();
    assert!(report.iterations > 0, "{report:?}");
    assert!(all_met(&out, &links, &p), "{report:?}");
    for &(i, j) in &frame {
        assert_eq!(out.control_point(i, j), centre.control_point(i, j));
    }
}

#[test]
fn bad_settings_are_errors() {
    let (centre, masters) = torus_pieces();
    let links = links(&masters);
    let mut p = ConnectParams::default();
    p.tolerances.g2_rel = 0.0;
    assert!(matches!(
        polish_joint(&centre, &links, &p, 1.0),
        Err(Error::InvalidParameter { name: "g2_rel", .. })
    ));
    assert!(matches!(
        polish_joint(&centre, &links, &ConnectParams::default(), 0.0),
        Err(Error::InvalidParameter {
            name: "max_move",
            ..
        })
    ));
    let twice = [links[0], links[0]];
    assert!(matches!(
        polish_joint(&centre, &twice, &ConnectParams::default(), 1.0),
        Err(Error::DuplicateSide { side: Side::U0 })
    ));
}

/// A slave with fewer control rows across a G2 side than the curvature frame needs (a kernel's
/// 2 × 3 net as it comes, unprepared) is an error naming the side, not an index past the net.
#[test]
fn too_few_rows_for_the_frame_is_an_error_naming_the_side() {
    let (_, masters) = torus_pieces();
    let small = masters[0].clone();
    // the same corner points on a bilinear 2 × 2 net raised to 2 × 3 in v: 2 rows across U0/U1
    let (nu, nv) = (small.num_u(), small.num_v());
    let corners = [(0, 0), (0, nv - 1), (nu - 1, 0), (nu - 1, nv - 1)]
        .map(|(i, j)| small.control_point(i, j));
    let flat = BSplineSurface::new(
        nurbs_core::KnotVector::bezier(1).unwrap(),
        nurbs_core::KnotVector::bezier(2).unwrap(),
        vec![
            corners[0],
            nurbs_core::Point3::from((corners[0].coords + corners[1].coords) * 0.5),
            corners[1],
            corners[2],
            nurbs_core::Point3::from((corners[2].coords + corners[3].coords) * 0.5),
            corners[3],
        ],
        None,
    )
    .unwrap();
    assert_eq!((flat.num_u(), flat.num_v()), (2, 3));
    let links = [SideLink {
        side: Side::U1,
        master: &masters[1],
        target: Continuity::G2,
        range: None,
        g2_zones: [0.0; 2],
    }];
    let err = polish_joint(&flat, &links, &ConnectParams::default(), 1.0).unwrap_err();
    assert_eq!(
        err,
        Error::TooFewRows {
            side: Side::U1,
            target: Continuity::G2,
            rows: 2,
            needed: 3
        }
    );
    assert!(err.to_string().contains("side u1"), "{err}");
}
