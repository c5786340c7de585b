//! Tests of the link measure against closed forms.
use super::*;
use nalgebra::DMatrix;
use nurbs_core::testing::assert_close;
use nurbs_core::{Continuity, KnotVector, Point3};

/// The bicubic Bézier patch over [0, 1]² of the polynomial map `f` (of degree ≤ 3 in each
/// parameter; exact up to rounding): its values on the uniform 4 × 4 grid interpolated.
fn bicubic_of(f: impl Fn(f64, f64) -> Point3) -> BSplineSurface {
    const BINOMIAL: [f64; 4] = [1.0, 3.0, 3.0, 1.0];
    let bernstein = DMatrix::from_fn(4, 4, |i, k| {
        let s = i as f64 / 3.0;
        BINOMIAL[k] * s.powi(k as i32) * (1.0 - s).powi(3 - k as i32)
    });
    let inverse = bernstein.try_inverse().unwrap();
    let values: Vec<Point3> = (0..16)
        .map(|k| f((k / 4) as f64 / 3.0, (k % 4) as f64 / 3.0))
        .collect();
    let points = (0..16)
        .map(|k| {
            let (a, b) = (k / 4, k % 4);
            let mut p = Vector3::zeros();
            for i in 0..4 {
                for j in 0..4 {
                    p += values[4 * i + j].coords * inverse[(a, i)] * inverse[(b, j)];
                }
            }
            Point3::from(p)
        })
        .collect();
    let k = KnotVector::bezier(3).unwrap();
    BSplineSurface::new(k.clone(), k, points, None).unwrap()
}

/// The graph z = a·y² + b·x·y over y ≤ 0, x ∈ [0, 1]: u runs from the side u = 0 on the x
/// axis down to y = −1.
fn twisted_master(a: f64, b: f64) -> BSplineSurface {
    bicubic_of(|u, v| Point3::new(v, -u, a * u * u - b * v * u))
}

/// The graph z = c·y² + b·x·y over y ≥ 0 with a skewed parametrization: x = v + u,
/// y = ε u, so that S_u = (1, ε, ·) runs at an angle of about ε radians to the side u = 0
/// on the x axis.
fn skewed_slave(c: f64, b: f64, eps: f64) -> BSplineSurface {
    bicubic_of(|u, v| {
        let (x, y) = (v + u, eps * u);
        Point3::new(x, y, c * y * y + b * x * y)
    })
}

#[test]
fn the_across_figure_shows_a_jump_the_skewed_parametric_figure_hides() {
    // both graphs share the boundary (the x axis) and the tangent plane along it (z_y = b x
    // on both sides): G1 exactly; across (along y) the master is flat (z_yy = 0) and the
    // slave curves (z_yy = 0.2). S_u of the slave runs at 0.03 rad to the boundary, where
    // both surfaces share the twist b: along S_u the curvatures differ by sin²(0.03)·0.2
    // against 2·0.03·b of the shared twist, a relative 0.1·0.03/(0.1·0.03 + 1) ≈ 0.003,
    // inside a class-A tolerance of 0.005
    let (b, eps) = (1.0, 0.03);
    let master = twisted_master(0.0, b);
    let slave = skewed_slave(0.1, b, eps);
    let m = measure_link(&master, &slave, Side::U0, &MeasureParams::default()).unwrap();
    assert_close(m.g0, 0.0, 1e-9, "gap");
    assert_close(m.g1_deg.unwrap(), 0.0, 1e-6, "angle");
    let parametric = m.g2_rel.unwrap();
    assert_close(parametric, 0.1 * eps / (0.1 * eps + b), 1e-3, "along S_u");
    assert!(parametric < 0.005, "the parametric figure meets 0.005");
    // the decisions are the parametric figure's: the link is met
    assert!(m.meets(Continuity::G2, 1e-3, 0.01, 0.005));
    assert!(m.excess(Continuity::G2, 1e-3, 0.01, 0.005) <= 1.0);
    // across the boundary: κ_s = 0.2/(1 + b²x²)^(3/2) against 0, whatever the
    // parametrization; largest at the vertex x = 0, in the interior at the next sample
    assert_close(m.g2_rel_across.unwrap(), 1.0, 1e-9, "across");
    let across = |x: f64| 0.2 / (1.0 + b * b * x * x).powf(1.5);
    assert_close(
        m.g2_abs_across.unwrap(),
        across(0.01),
        1e-9,
        "|κs − κm| across",
    );
    assert_close(m.vertex_g2_rel.unwrap(), 1.0, 1e-9, "at the vertices");
    let first = &m.detail[0];
    // (signed w.r.t. the slave's normal S_u × S_v, which points down)
    assert_close(
        first.kappa_slave_across.unwrap(),
        -across(0.0),
        1e-9,
        "κs at x = 0",
    );
    assert_close(first.kappa_master_across.unwrap(), 0.0, 1e-9, "κm at x = 0");
}

#[test]
fn one_surface_split_with_a_skewed_parametrization_reads_g2_both_ways() {
    // the same graph z = 0.1 y² + x y on both sides of the x axis
    let (c, b, eps) = (0.1, 1.0, 0.03);
    let master = twisted_master(c, b);
    let slave = skewed_slave(c, b, eps);
    let m = measure_link(&master, &slave, Side::U0, &MeasureParams::default()).unwrap();
    assert_close(m.g0, 0.0, 1e-9, "gap");
    assert_close(m.g1_deg.unwrap(), 0.0, 1e-6, "angle");
    assert_close(m.vertex_g1_deg.unwrap(), 0.0, 1e-6, "vertex angle");
    assert!(m.g2_rel.unwrap() < 1e-6, "parametric {:?}", m.g2_rel);
    assert!(
        m.g2_rel_across.unwrap() < 1e-6,
        "across {:?}",
        m.g2_rel_across
    );
    assert!(
        m.g2_abs_across.unwrap() < 1e-6,
        "across {:?}",
        m.g2_abs_across
    );
    assert!(
        m.vertex_g2_rel.unwrap() < 1e-6,
        "vertices {:?}",
        m.vertex_g2_rel
    );
    assert_eq!((m.undefined_normals, m.undefined_curvatures), (0, 0));
    // and two planes, one of them parametrized at 0.03 rad to the side
    let m = measure_link(
        &twisted_master(0.0, 0.0),
        &skewed_slave(0.0, 0.0, eps),
        Side::U0,
        &MeasureParams::default(),
    )
    .unwrap();
    assert_eq!((m.g2_rel, m.g2_abs), (Some(0.0), Some(0.0)));
    assert_eq!((m.g2_rel_across, m.g2_abs_across), (Some(0.0), Some(0.0)));
}

/// The constants (a, c0, c1, g) of [`growing_join`].
const GROWING: (f64, f64, f64, f64) = (0.05, 0.1, 0.4, 1e-4);

/// A join whose gap, angle and curvature difference grow towards the vertex x = 1: master
/// z = a y² (y ≤ 0), slave z = (c0 + c1 x) y² + g x³ (y ≥ 0), linked on the slave's side u0 (the
/// x axis), with (a, c0, c1, g) = [`GROWING`].
fn growing_join() -> (BSplineSurface, BSplineSurface) {
    let (a, c0, c1, g) = GROWING;
    let master = bicubic_of(|u, v| Point3::new(v, -u, a * u * u));
    let slave = bicubic_of(|u, v| Point3::new(v, u, (c0 + c1 * v) * u * u + g * v.powi(3)));
    (master, slave)
}

#[test]
fn the_vertex_figures_are_the_two_end_samples() {
    // master z = a y² (y ≤ 0); slave z = (c0 + c1 x) y² + g x³ (y ≥ 0): a gap g x³ and a
    // normal angle ≈ 3 g x² along the side, and a curvature jump across, all largest at the
    // vertex x = 1; S_u is perpendicular to the side, so both directions agree. K = 11
    // samples, the interior's worst at x = 0.9
    let (a, c0, c1, g) = GROWING;
    let (master, slave) = growing_join();
    let params = MeasureParams {
        samples: 11,
        ..MeasureParams::default()
    };
    let m = measure_link(&master, &slave, Side::U0, &params).unwrap();
    assert_eq!(m.detail.len(), 11, "detail holds every sample");
    let angle = |x: f64| (3.0 * g * x * x).atan().to_degrees();
    let rel = |x: f64| 1.0 - a / (c0 + c1 * x);
    let abs = |x: f64| 2.0 * (c0 + c1 * x - a);
    // the framework's figures: every sample, the vertex x = 1 included
    assert_close(m.g0, g, 1e-9, "gap");
    assert_close(m.g1_deg.unwrap(), angle(1.0), 1e-6, "angle");
    assert_close(m.worst_g1_t.unwrap(), 1.0, 1e-12, "angle at");
    assert_close(m.g2_rel.unwrap(), rel(1.0), 1e-6, "relative");
    assert_close(m.worst_g2_t.unwrap(), 1.0, 1e-12, "relative at");
    // the checker's: the interior across, the vertices apart
    assert_close(m.g2_rel_across.unwrap(), rel(0.9), 1e-6, "interior across");
    assert_close(
        m.worst_g2_across_t.unwrap(),
        0.9,
        1e-12,
        "interior across at",
    );
    assert_close(
        m.g2_abs_across.unwrap(),
        abs(0.9),
        1e-6,
        "interior |κs − κm|",
    );
    assert_close(m.vertex_g1_deg.unwrap(), angle(1.0), 1e-6, "vertex angle");
    assert_close(m.vertex_g2_rel.unwrap(), rel(1.0), 1e-6, "vertex relative");
    // the decision is the framework's: a tolerance between the interior's and the
    // vertex's figure is missed
    let between = 0.5 * (rel(0.9) + rel(1.0));
    assert!(!m.meets(Continuity::G2, 2.0 * g, 1.0, between));
    // two samples: both are vertices, no interior
    let params = MeasureParams {
        samples: 2,
        ..MeasureParams::default()
    };
    let m = measure_link(&master, &slave, Side::U0, &params).unwrap();
    assert_eq!((m.g2_rel_across, m.g2_abs_across), (None, None));
    assert_close(
        m.vertex_g2_rel.unwrap(),
        rel(1.0),
        1e-6,
        "vertex relative, K = 2",
    );
    assert_close(m.g2_rel.unwrap(), rel(1.0), 1e-6, "relative, K = 2");
}

#[test]
fn a_vertex_zone_leaves_the_decision_and_counts_with_the_vertex() {
    // the slave and master of the previous test: the curvature difference grows towards the
    // vertex x = 1 (relative 1 − a/(c0 + c1 x)). A zone of 0.25 at the end (K = 11: the
    // samples x = 0.8, 0.9, 1.0 inside, strictly past 0.75) takes them out of the figures
    // decisions read: the worst is then x = 0.7; the zone's samples go with the vertex.
    let (a, c0, c1, g) = GROWING;
    let (master, slave) = growing_join();
    let params = MeasureParams {
        samples: 11,
        ..MeasureParams::default()
    };
    let rel = |x: f64| 1.0 - a / (c0 + c1 * x);
    let m = measure_link_zoned(&master, &slave, Side::U0, None, [0.0, 0.25], &params).unwrap();
    assert_close(
        m.g2_rel.unwrap(),
        rel(0.7),
        1e-6,
        "relative outside the zone",
    );
    assert_close(m.worst_g2_t.unwrap(), 0.7, 1e-12, "worst outside at");
    assert_close(m.g2_rel_across.unwrap(), rel(0.7), 1e-6, "across outside");
    assert_close(m.vertex_g2_rel.unwrap(), rel(1.0), 1e-6, "the zone's worst");
    let inside: Vec<f64> = m.detail.iter().filter(|x| x.in_zone).map(|x| x.t).collect();
    assert_eq!(inside.len(), 3, "{inside:?}");
    // gaps and angles are judged everywhere, the vertex included
    assert_close(m.g0, g, 1e-9, "gap");
    assert_close(m.worst_g1_t.unwrap(), 1.0, 1e-12, "angle at the vertex");
    // the zone is the stretch x ∈ [0.75, 1] of the straight side y = x: length 0.25
    assert_eq!(m.vertex_zones[0], 0.0);
    // (the side bends by g x³, so its length is 0.25 to 1e-8)
    assert_close(m.vertex_zones[1], 0.25, 1e-7, "zone length");
    // a tolerance between the two figures is met with the zone and missed without
    let between = 0.5 * (rel(0.7) + rel(1.0));
    assert!(m.meets(Continuity::G2, 2.0 * g, 1.0, between));
    let plain = measure_link(&master, &slave, Side::U0, &params).unwrap();
    assert!(!plain.meets(Continuity::G2, 2.0 * g, 1.0, between));
    assert_eq!(plain.vertex_zones, [0.0; 2]);
}
