//! The Bézier-spline flow (\[H\] part ②): C⁰ joints become exactly C¹, C¹ joints lose their knot
//! exactly, joints that ε cannot close are reported.

mod common;

use common::{assert_contract, c0_joined, joined_bicubic};
use fair_energy::{
    BezierSplineParams, BezierSplineReport, KnotRemoval, fair_bezier_spline, fair_surface,
};
use nurbs_core::energy::thin_plate_energy;
use nurbs_core::{BSplineSurface, ControlMask, Frame};

/// The knots 1/3 and 2/3 of the test surfaces (the same in u and v).
const JOINTS: [f64; 2] = [1.0 / 3.0, 2.0 / 3.0];

/// Largest |X_u(ū⁻, v) − X_u(ū⁺, v)| (and the same in v) at the parameters `at`, evaluated
/// exactly at the knot from both sides (the one-sided pieces are extracted, so each side is
/// evaluated at its own domain end), with the largest one-sided |X_u| as the scale.
fn one_sided_jump(s: &BSplineSurface, at: &[f64]) -> (f64, f64) {
    let (du, dv) = (s.domain_u(), s.domain_v());
    let (mut jump, mut scale): (f64, f64) = (0.0, 0.0);
    for &t in at {
        let t_u = s
            .knots_u()
            .knots()
            .iter()
            .copied()
            .find(|k| (k - t).abs() < 1e-12);
        let t_v = s
            .knots_v()
            .knots()
            .iter()
            .copied()
            .find(|k| (k - t).abs() < 1e-12);
        let (t_u, t_v) = (t_u.expect("u knot"), t_v.expect("v knot"));
        let left = s.extract((du.0, t_u), dv).expect("left");
        let right = s.extract((t_u, du.1), dv).expect("right");
        let below = s.extract(du, (dv.0, t_v)).expect("below");
        let above = s.extract(du, (t_v, dv.1)).expect("above");
        for k in 0..=40 {
            let w = k as f64 / 40.0;
            let (a, b) = (left.derivatives(t_u, w).du, right.derivatives(t_u, w).du);
            let (c, d) = (below.derivatives(w, t_v).dv, above.derivatives(w, t_v).dv);
            jump = jump.max((a - b).norm()).max((c - d).norm());
            scale = scale
                .max(a.norm())
                .max(b.norm())
                .max(c.norm())
                .max(d.norm());
        }
    }
    (jump, scale)
}

/// The input point (i, j) of output point r.
fn source(report: &BezierSplineReport, r: usize) -> (usize, usize) {
    let nv = report.kept_v.len();
    (report.kept_u[r / nv], report.kept_v[r % nv])
}

/// Fixed points bit-identical and every kept point within ε of its original, through the maps.
fn assert_kept_points(
    original: &BSplineSurface,
    mask: &ControlMask,
    out: &BSplineSurface,
    out_mask: &ControlMask,
    report: &BezierSplineReport,
    eps: f64,
) {
    assert_eq!(
        (out.num_u(), out.num_v()),
        (report.kept_u.len(), report.kept_v.len())
    );
    for (r, p) in out.control_points().iter().enumerate() {
        let (i, j) = source(report, r);
        let o = original.control_point(i, j);
        let (oi, oj) = (r / out.num_v(), r % out.num_v());
        assert_eq!(out_mask.is_free(oi, oj), mask.is_free(i, j), "mask map");
        if !mask.is_free(i, j) {
            for c in 0..3 {
                assert_eq!(p[c].to_bits(), o[c].to_bits(), "fixed ({i}, {j}) changed");
            }
        }
        assert!((p - o).norm() <= eps, "({i}, {j}) moved {}", (p - o).norm());
    }
}

#[test]
fn c0_joined_surface_becomes_c1() {
    let (s, _, _) = c0_joined();
    let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
    let eps = 0.1;
    let params = BezierSplineParams::default();
    let (out, out_mask, report) = fair_bezier_spline(&s, &mask, eps, &params).expect("fairs");
    let (before, _) = one_sided_jump(&s, &JOINTS);
    let (after, scale) = one_sided_jump(&out, &JOINTS);
    eprintln!("{report:#?}\njump {before} -> {after} (scale {scale})");
    assert!(before > 0.1, "the test surface has kinks ({before})");
    assert_eq!(report.joints, 4);
    assert_eq!(report.knots_removed_before, 0, "no joint is C¹ yet");
    assert_eq!(report.joints_made_c1, 4);
    assert!(report.open_joints.is_empty(), "{:?}", report.open_joints);
    assert!(
        after <= 1e-9 * scale,
        "jump {before} -> {after} (scale {scale})"
    );
    assert!(report.max_jump_after <= 1e-9 * scale);
    assert_eq!(out_mask, mask, "no knot removed: the mask is unchanged");
    assert_contract(&s, &out, &mask, eps);
    let (e0, e1) = (thin_plate_energy(&s), thin_plate_energy(&out));
    assert!(e1 <= e0, "energy {e0} -> {e1}");
    assert!((report.energy_after - e1).abs() <= 1e-12 * e1);
    // the plain thin plate alone leaves the kinks
    let (plain, _) = fair_surface(&s, &mask, eps, &params.energy).expect("fairs");
    assert!(one_sided_jump(&plain, &JOINTS).0 > 1e3 * after.max(1e-15));

    // the same with the knots removed at the end: C¹ by construction, same geometry
    let removing = BezierSplineParams {
        final_removal: KnotRemoval::ThroughFixedFrames,
        ..params
    };
    let (reduced, reduced_mask, r2) = fair_bezier_spline(&s, &mask, eps, &removing).expect("fairs");
    assert_eq!(r2.knots_removed_after, 4);
    assert_eq!(
        (reduced.num_u(), reduced.num_v()),
        (s.num_u() - 2, s.num_v() - 2)
    );
    for t in JOINTS {
        let k = |kv: &nurbs_core::KnotVector| {
            kv.knots().iter().filter(|x| (*x - t).abs() < 1e-12).count()
        };
        assert_eq!((k(reduced.knots_u()), k(reduced.knots_v())), (2, 2));
    }
    assert_kept_points(&s, &mask, &reduced, &reduced_mask, &r2, eps);
    for a in 0..=20 {
        for b in 0..=20 {
            let (u, v) = (a as f64 / 20.0, b as f64 / 20.0);
            let d = (reduced.point(u, v) - out.point(u, v)).norm();
            assert!(
                d <= 1e-12,
                "removal changed the surface by {d} at ({u}, {v})"
            );
        }
    }
    assert!((r2.energy_after - e1).abs() <= 1e-9 * e1);
}

#[test]
fn c1_joints_lose_their_knot_exactly() {
    let s = joined_bicubic(0.0);
    assert_eq!(s.knots_u().multiplicity(s.knots_u().knots()[4]), 3);
    // every point fixed: only the exact removal acts
    let fixed = ControlMask::all_fixed(s.num_u(), s.num_v());
    let params = BezierSplineParams::default();
    let (out, out_mask, report) = fair_bezier_spline(&s, &fixed, 0.1, &params).expect("runs");
    assert_eq!(report.knots_removed_before, 4);
    assert_eq!((out.num_u(), out.num_v()), (8, 8));
    assert_eq!(report.kept_u, vec![0, 1, 2, 4, 5, 7, 8, 9]);
    assert_eq!(out_mask.free_count(), 0);
    assert_kept_points(&s, &fixed, &out, &out_mask, &report, 0.1);
    for a in 0..=30 {
        for b in 0..=30 {
            let (u, v) = (a as f64 / 30.0, b as f64 / 30.0);
            let d = (out.point(u, v) - s.point(u, v)).norm();
            assert!(
                d <= 1e-12,
                "removal changed the surface by {d} at ({u}, {v})"
            );
        }
    }
    // the positional frame crosses every joint: removed through it, kept when only free rows may go
    let frame = ControlMask::with_boundary_frame(&s, Frame::Positional);
    let (_, _, through) = fair_bezier_spline(&s, &frame, 0.1, &params).expect("runs");
    assert_eq!(through.knots_removed_before, 4);
    let only_free = BezierSplineParams {
        initial_removal: KnotRemoval::WhereFree,
        ..params
    };
    let (kept, kept_mask, r) = fair_bezier_spline(&s, &frame, 0.1, &only_free).expect("runs");
    assert_eq!(r.knots_removed_before, 0);
    assert_eq!(kept_mask, frame);
    assert!(r.open_joints.is_empty());
    assert!(one_sided_jump(&kept, &JOINTS).0 <= 1e-9 * one_sided_jump(&kept, &JOINTS).1);
    // an all-free net may lose its joint rows under `WhereFree`
    let free = ControlMask::all_free(s.num_u(), s.num_v());
    let (_, _, r) = fair_bezier_spline(&s, &free, 0.1, &only_free).expect("runs");
    assert_eq!(r.knots_removed_before, 4);
}

#[test]
fn joints_that_epsilon_cannot_close_are_reported() {
    let (s, _, _) = c0_joined();
    let mask = ControlMask::with_boundary_frame(&s, Frame::Positional);
    let eps = 2e-3;
    let (out, _, report) =
        fair_bezier_spline(&s, &mask, eps, &BezierSplineParams::default()).expect("fairs");
    eprintln!("{report:#?}");
    assert_contract(&s, &out, &mask, eps);
    assert!(
        !report.open_joints.is_empty(),
        "ε = {eps} cannot close a 0.03 kink"
    );
    let worst = report
        .open_joints
        .iter()
        .map(|g| g.jump)
        .fold(0.0, f64::max);
    assert_eq!(worst, report.max_jump_after);
    assert!(report.max_jump_after > 0.0 && report.max_jump_after < report.max_jump_before);
    assert_eq!(report.joints_made_c1 + report.open_joints.len(), 4);
    let (measured, _) = one_sided_jump(&out, &JOINTS);
    // the reported jump bounds the jump function (its control coefficients' maximum)
    assert!(
        measured > 0.0 && measured <= report.max_jump_after * (1.0 + 1e-9),
        "reported {} vs measured {measured}",
        report.max_jump_after
    );
}
