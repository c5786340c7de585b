//! Regression: G2 on realistic slaves (the fixture situation, built inline). Bicubic images of a
//! cubic height field z = f(x, y) over adjacent rectangles are C∞ across their common lines; seeded
//! noise on the control points at least two rows from every side keeps the joins G1 and breaks G2
//! by a correction of the order of the noise. Setting G2 must then move the slave by about that
//! much: the scalar-only minimal-deviation solve used to fit what the spline space could not
//! follow with tangential moves of 50 times the noise (a 0.03 mm correction moved control points
//! by 2.3 mm, thin-plate energy ×200, free boundaries by 0.8 mm).

use g_continuity::{
    ConnectParams, MeasureParams, SideLink, connect_slave, measure_link, prepare_slave, set_step,
};
use nurbs_core::energy::{max_deviation, thin_plate_energy};
use nurbs_core::testing::rng;
use nurbs_core::{
    BSplineSurface, Continuity, ControlMask, FitParams, KnotVector, Point3, Side, fit_surface,
};
use rand::Rng;

const NOISE: f64 = 0.03;

/// The cubic height field of the fixtures (mm): a gentle saddle with cubic terms.
fn height(x: f64, y: f64) -> f64 {
    0.004 * x * x - 0.003 * y * y + 5e-5 * x * x * x + 8e-5 * x * y * y + 2e-5 * x * x * y
}

/// The exact bicubic (nu × nv, uniform) of the height field over [x0, x1] × [y0, y1], u along x.
fn patch(x: (f64, f64), y: (f64, f64), nu: usize, nv: usize) -> BSplineSurface {
    let ku = KnotVector::clamped_uniform(3, nu).unwrap();
    let kv = KnotVector::clamped_uniform(3, nv).unwrap();
    let template = BSplineSurface::new(ku, kv, vec![Point3::origin(); nu * nv], None).unwrap();
    let (su, sv) = (3 * nu + 1, 3 * nv + 1);
    let mut params = Vec::new();
    let mut points = Vec::new();
    for a in 0..su {
        for b in 0..sv {
            let (s, t) = (a as f64 / (su - 1) as f64, b as f64 / (sv - 1) as f64);
            let (px, py) = (x.0 + (x.1 - x.0) * s, y.0 + (y.1 - y.0) * t);
            params.push((s, t));
            points.push(Point3::new(px, py, height(px, py)));
        }
    }
    let mask = ControlMask::for_surface(&template);
    fit_surface(&template, &mask, &params, &points, &FitParams::default())
        .unwrap()
        .0
}

/// Adds NOISE·uniform[-1, 1] to z of every control point at least two rows from each side.
fn noisy(mut s: BSplineSurface, seed: u64) -> BSplineSurface {
    let mut r = rng(seed);
    let (nu, nv) = (s.num_u(), s.num_v());
    for i in 2..nu - 2 {
        for j in 2..nv - 2 {
            let k = s.index(i, j);
            s.control_points_mut()[k].z += NOISE * r.random_range(-1.0..=1.0);
        }
    }
    s
}

/// Left master, right master, fillet between them (x ∈ [-8, 8], y ∈ [-20, 20], 6 × 9); the
/// masters span y ∈ [-y_master, y_master] and are noisy when `noisy_masters`.
fn fillet_model(
    y_master: f64,
    noisy_masters: bool,
    seed: u64,
) -> (BSplineSurface, BSplineSurface, BSplineSurface) {
    let master = |x: (f64, f64), seed: u64| {
        let m = patch(x, (-y_master, y_master), 9, 12);
        if noisy_masters { noisy(m, seed) } else { m }
    };
    let left = master((-40.0, -8.0), seed);
    let right = master((8.0, 40.0), seed + 1);
    let fillet = noisy(patch((-8.0, 8.0), (-20.0, 20.0), 6, 9), seed + 2);
    (left, right, fillet)
}

fn params() -> ConnectParams {
    let mut p = ConnectParams::default();
    p.tolerances.g2_rel = 5e-3;
    p
}

/// Largest distance between the boundary curves of `side` of `a` and `b` (sampled).
fn boundary_move(a: &BSplineSurface, b: &BSplineSurface, side: Side) -> f64 {
    let (t0, t1) = side.along_domain(a);
    (0..=200)
        .map(|k| {
            let t = t0 + (t1 - t0) * k as f64 / 200.0;
            let (u, v) = side.params(a, t);
            (a.point(u, v) - b.point(u, v)).norm()
        })
        .fold(0.0, f64::max)
}

/// Checks the G2 result of a fillet against its input; returns the largest deviation.
fn check_fillet(links: &[SideLink], input: &BSplineSurface, out: &BSplineSurface, what: &str) {
    for l in links {
        let m = measure_link(l.master, out, l.side, &MeasureParams::default()).unwrap();
        let before = measure_link(l.master, input, l.side, &MeasureParams::default()).unwrap();
        assert!(before.g2_rel.unwrap() > 0.1, "{what}: input must break G2");
        assert!(m.g0 <= 1e-9, "{what} {}: gap {}", l.side, m.g0);
        assert!(
            m.g1_deg.unwrap() <= 1e-2,
            "{what} {}: {:?}",
            l.side,
            m.g1_deg
        );
        assert!(
            m.g2_rel.unwrap() <= 5e-3,
            "{what} {}: curvature {:?}",
            l.side,
            m.g2_rel
        );
    }
    let deviation = max_deviation(input, out, 41);
    assert!(
        deviation <= 3.0 * NOISE,
        "{what}: deviation {deviation} (noise {NOISE})"
    );
    let (e0, e1) = (thin_plate_energy(input), thin_plate_energy(out));
    assert!(e1 <= 2.0 * e0, "{what}: energy {e0} -> {e1}");
}

#[test]
fn fillet_with_continuous_corners_moves_by_the_noise_and_keeps_free_boundaries() {
    // masters of the fillet's extent: the corners are G2 already (noise only two rows inside)
    let (left, right, fillet) = fillet_model(20.0, false, 31);
    let links = [
        SideLink {
            side: Side::U0,
            master: &left,
            target: Continuity::G2,
            range: None,
            g2_zones: [0.0; 2],
        },
        SideLink {
            side: Side::U1,
            master: &right,
            target: Continuity::G2,
            range: None,
            g2_zones: [0.0; 2],
        },
    ];
    let (out, report) = connect_slave(&fillet, &links, &params()).unwrap();
    assert!(report.sides.iter().all(|s| s.met), "{:?}", report.sides);
    check_fillet(&links, &fillet, &out, "connect");
    assert!(
        report.max_control_movement <= 3.0 * NOISE,
        "moved {}",
        report.max_control_movement
    );
    for side in [Side::V0, Side::V1] {
        let moved = boundary_move(&fillet, &out, side);
        assert!(
            moved <= 1e-6 * fillet.size(),
            "free boundary {side} moved {moved}"
        );
    }

    // the staged framework's path: prepare, then G0, G1, G2 one step at a time
    let p = params();
    let (mut s, _) = prepare_slave(&fillet, &links, &p).unwrap();
    for step in [Continuity::G0, Continuity::G1, Continuity::G2] {
        let (next, r) = set_step(&s, &links, step, &p).unwrap();
        assert!(
            r.max_move <= 3.0 * NOISE,
            "step {step:?} moved {}",
            r.max_move
        );
        s = next;
    }
    check_fillet(&links, &fillet, &s, "staged");
    for side in [Side::V0, Side::V1] {
        let moved = boundary_move(&fillet, &s, side);
        assert!(
            moved <= 1e-6 * fillet.size(),
            "staged: free boundary {side} moved {moved}"
        );
    }
}

#[test]
fn fillet_between_longer_masters_moves_by_the_noise() {
    // masters extending past the fillet's ends (other knots, noisy curvature at the corners):
    // the G2 correction is not in the fillet's spline space, knots are inserted
    let (left, right, fillet) = fillet_model(30.0, true, 3);
    let links = [
        SideLink {
            side: Side::U0,
            master: &left,
            target: Continuity::G2,
            range: None,
            g2_zones: [0.0; 2],
        },
        SideLink {
            side: Side::U1,
            master: &right,
            target: Continuity::G2,
            range: None,
            g2_zones: [0.0; 2],
        },
    ];
    let (out, report) = connect_slave(&fillet, &links, &params()).unwrap();
    assert!(report.sides.iter().all(|s| s.met), "{:?}", report.sides);
    check_fillet(&links, &fillet, &out, "connect");
    assert!(
        report.max_control_movement <= 3.0 * NOISE,
        "moved {}",
        report.max_control_movement
    );
    // the free boundaries change only by what their (noisy) corners need
    for side in [Side::V0, Side::V1] {
        let moved = boundary_move(&fillet, &out, side);
        assert!(moved <= 2.0 * NOISE, "free boundary {side} moved {moved}");
    }
    assert!(
        report.knots_inserted <= 40,
        "knots {}",
        report.knots_inserted
    );
}

#[test]
fn refinement_stops_when_a_side_cannot_be_met() {
    // the end points of the curvature rows are fixed (free boundaries kept) while the masters'
    // corners are noisy: the corner samples keep their error whatever knots are inserted, so the
    // refinement has to stop early instead of filling the side with knots
    let (left, right, fillet) = fillet_model(30.0, true, 3);
    let links = [
        SideLink {
            side: Side::U0,
            master: &left,
            target: Continuity::G2,
            range: None,
            g2_zones: [0.0; 2],
        },
        SideLink {
            side: Side::U1,
            master: &right,
            target: Continuity::G2,
            range: None,
            g2_zones: [0.0; 2],
        },
    ];
    let mut p = params();
    p.set.move_unlinked_boundaries = false;
    p.max_refinements = 20;
    let (out, report) = connect_slave(&fillet, &links, &p).unwrap();
    assert!(
        report.knots_inserted <= 2 * 9 * 2,
        "knots {} in {} rounds",
        report.knots_inserted,
        report.refinements
    );
    assert!(
        report.max_control_movement <= 3.0 * NOISE,
        "moved {}",
        report.max_control_movement
    );
    assert!(max_deviation(&fillet, &out, 41) <= 3.0 * NOISE);
}
