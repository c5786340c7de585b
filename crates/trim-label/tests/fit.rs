//! Labeled parameterization and fit on synthetic regions.

mod common;

use common::{arc, grid_region, polygon_region};
use nurbs_core::TriMesh;
use trim_label::{
    Label, LabelParams, LabeledFitParams, Labeling, fit_labeled, label_region, parameterize,
};

/// Checks the parameterization of a labeled region: labeled sides on their lines of the unit
/// square, everything inside it, no flipped triangle. Returns the smallest signed uv area.
fn check_parameterization(mesh: &TriMesh, l: &Labeling) -> f64 {
    let p = parameterize(mesh, l).expect("parameterization");
    for seg in &l.segments {
        for &v in &seg.loop_vertices {
            let (u, w) = p.uv[v];
            let on = match seg.label {
                Label::South => w == 0.0,
                Label::North => w == 1.0,
                Label::West => u == 0.0,
                Label::East => u == 1.0,
                Label::Unlabeled => true,
            };
            assert!(on, "vertex {v} of a {:?} segment at ({u}, {w})", seg.label);
        }
    }
    let mut min_area = f64::INFINITY;
    for f in &mesh.faces {
        let (a, b, c) = (p.uv[f[0]], p.uv[f[1]], p.uv[f[2]]);
        for q in [a, b, c] {
            assert!((0.0..=1.0).contains(&q.0) && (0.0..=1.0).contains(&q.1));
        }
        let area = 0.5 * ((b.0 - a.0) * (c.1 - a.1) - (c.0 - a.0) * (b.1 - a.1));
        min_area = min_area.min(area);
    }
    assert!(
        min_area > 0.0,
        "a triangle flipped (signed area {min_area:e})"
    );
    min_area
}

fn labeled(pieces: &[Vec<[f64; 2]>]) -> (TriMesh, Labeling) {
    let (mesh, segs) = polygon_region(pieces, 0.25);
    let l = label_region(&mesh, Some(&segs), &LabelParams::default()).expect("labels");
    (mesh, l)
}

#[test]
fn four_labels_lie_on_their_sides() {
    let (mesh, l) = labeled(&[
        vec![[0.0, 0.0], [4.0, 0.0]],
        vec![[4.0, 0.0], [4.0, 2.0]],
        vec![[4.0, 2.0], [6.0, 2.0]],
        vec![[6.0, 2.0], [6.0, 0.0]],
        vec![[6.0, 0.0], [10.0, 0.0]],
        vec![[10.0, 0.0], [10.0, 6.0]],
        vec![[10.0, 6.0], [1.5, 6.0]],
        arc([0.0, 6.0], 1.5, 0.0, -90.0, 12),
        vec![[0.0, 4.5], [0.0, 0.0]],
    ]);
    assert_eq!((l.labels, l.corner_count), (4, 4));
    check_parameterization(&mesh, &l);
}

#[test]
fn partial_configurations_parameterize() {
    let half_disk = vec![
        vec![[-5.0, 0.0], [5.0, 0.0]],
        arc([0.0, 0.0], 5.0, 0.0, 180.0, 64),
    ];
    let stadium = vec![
        vec![[0.0, 0.0], [10.0, 0.0]],
        arc([10.0, 2.0], 2.0, -90.0, 90.0, 32),
        vec![[10.0, 4.0], [0.0, 4.0]],
        arc([0.0, 2.0], 2.0, 90.0, 270.0, 32),
    ];
    let quarter = vec![
        vec![[0.0, 0.0], [8.0, 0.0]],
        (0..=64)
            .map(|i| {
                let t = i as f64 / 64.0;
                let off = (2.0 * std::f64::consts::PI * t).sin() / std::f64::consts::SQRT_2;
                [8.0 - 8.0 * t + off, 8.0 * t + off]
            })
            .collect(),
        vec![[0.0, 8.0], [0.0, 0.0]],
    ];
    let round_end = vec![
        vec![[0.0, 0.0], [10.0, 0.0]],
        vec![[10.0, 0.0], [10.0, 4.0]],
        vec![[10.0, 4.0], [0.0, 4.0]],
        arc([0.0, 2.0], 2.0, 90.0, 270.0, 32),
    ];
    let disk = vec![
        arc([0.0, 0.0], 3.0, 0.0, 180.0, 48),
        arc([0.0, 0.0], 3.0, 180.0, 360.0, 48),
    ];
    for (pieces, config) in [
        (half_disk, (1, 0)),
        (stadium, (2, 0)),
        (quarter, (2, 1)),
        (round_end, (3, 2)),
        (disk, (0, 0)),
    ] {
        let (mesh, l) = labeled(&pieces);
        assert_eq!((l.labels, l.corner_count), config);
        check_parameterization(&mesh, &l);
    }
}

/// A curved grid region with a notch and a hole: automatic labels, then the fit.
#[test]
fn fit_curved_region_with_notch_and_hole() {
    let keep = |x: f64, y: f64| {
        let notch = (4.0..6.0).contains(&x) && y < 1.5;
        let hole = (6.5..8.5).contains(&x) && (2.5..4.0).contains(&y);
        !(notch || hole)
    };
    let lift = |x: f64, y: f64| 0.8 * (x / 4.0).sin() + 0.03 * y * y;
    let mesh = grid_region(10.0, 6.0, 0.2, keep, lift);
    let l = label_region(&mesh, None, &LabelParams::default()).expect("labels");
    for line in &l.log {
        eprintln!("{line}");
    }
    assert_eq!((l.labels, l.corner_count), (4, 4));
    check_parameterization(&mesh, &l);
    let (surface, rep) = fit_labeled(&mesh, &l, &LabeledFitParams::default()).expect("fit");
    eprintln!("{rep:?}");
    assert!(
        rep.rms_distance < 3e-5 * rep.size,
        "rms {:e}",
        rep.rms_distance
    );
    assert!(
        rep.max_distance < 2e-4 * rep.size,
        "max {:e}",
        rep.max_distance
    );
    assert!(rep.rms_distance <= rep.rms_param_error * (1.0 + 1e-9));
    // the surface covers the whole domain, the hole and the notch included
    let p = surface.point(0.5, 0.0);
    assert!(p.coords.iter().all(|c| c.is_finite()));
}
