//! n-sided corners: central split, sampling with wings, fairing and refit against closed-form
//! truth (planes, the paraboloid z = x² + y², the sphere).

use nside_discrete::{
    CentralSplitParams, DiscreteFairingParams, Neighbour, NsideError, NsidedParams, SamplingParams,
    VertexOrigin, central_split, fair_mesh_with_layout, fill_corner, internal_angle_deg,
    refit_quads, sample_quads,
};
use nurbs_core::testing::rng;
use nurbs_core::{
    BSplineCurve, BSplineSurface, ControlMask, FitParams, KnotVector, Point3, Vector3, fit_curve,
    fit_surface,
};
use rand::Rng;

/// Corners of a regular n-gon of radius `r` in the xy-plane, counter-clockwise.
fn polygon(n: usize, r: f64) -> Vec<[f64; 2]> {
    (0..n)
        .map(|k| {
            let a = 2.0 * std::f64::consts::PI * k as f64 / n as f64 + 0.1;
            [r * a.cos(), r * a.sin()]
        })
        .collect()
}

fn curve(points: Vec<Point3>, degree: usize) -> BSplineCurve {
    let kv = KnotVector::clamped_uniform(degree, points.len()).unwrap();
    BSplineCurve::new(kv, points, None).unwrap()
}

/// The polygon's sides on the plane z = h(x, y) (affine): cubic curves with one interior knot
/// so that the halves carry knots of their own.
fn planar_sides(n: usize, h: impl Fn(f64, f64) -> f64) -> Vec<BSplineCurve> {
    let c = polygon(n, 1.0);
    (0..n)
        .map(|k| {
            let (a, b) = (c[k], c[(k + 1) % n]);
            let pts = (0..5)
                .map(|i| {
                    // Greville abscissae of the clamped uniform cubic with 5 points
                    let t = [0.0, 1.0 / 6.0, 0.5, 5.0 / 6.0, 1.0][i];
                    let (x, y) = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]));
                    Point3::new(x, y, h(x, y))
                })
                .collect();
            curve(pts, 3)
        })
        .collect()
}

/// The paraboloid z = x² + y² over the segment a → b: an exact quadratic Bézier.
fn lifted_segment(a: [f64; 2], b: [f64; 2]) -> BSplineCurve {
    let z = |p: [f64; 2], q: [f64; 2]| p[0] * q[0] + p[1] * q[1];
    curve(
        vec![
            Point3::new(a[0], a[1], z(a, a)),
            Point3::new(0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), z(a, b)),
            Point3::new(b[0], b[1], z(b, b)),
        ],
        2,
    )
}

/// The paraboloid over the strip a + t (b − a) + s w n (t, s ∈ [0, 1], n the outward normal of
/// the side in the plane): a biquadratic Bézier fitted exactly; its side v = 0 is the side.
fn lifted_strip(a: [f64; 2], b: [f64; 2], width: f64) -> BSplineSurface {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
    let out = [d[1] / len * width, -d[0] / len * width];
    let kv = KnotVector::bezier(2).unwrap();
    let template = BSplineSurface::new(kv.clone(), kv, vec![Point3::origin(); 9], None).unwrap();
    let mut params = Vec::new();
    let mut data = Vec::new();
    for i in 0..=6 {
        for j in 0..=6 {
            let (t, s) = (i as f64 / 6.0, j as f64 / 6.0);
            let x = a[0] + t * d[0] + s * out[0];
            let y = a[1] + t * d[1] + s * out[1];
            params.push((t, s));
            data.push(Point3::new(x, y, x * x + y * y));
        }
    }
    let mask = ControlMask::all_free(3, 3);
    fit_surface(&template, &mask, &params, &data, &FitParams::default())
        .unwrap()
        .0
}

/// An n-sided hole in the paraboloid with its neighbours.
fn paraboloid_hole(n: usize) -> (Vec<BSplineCurve>, Vec<BSplineSurface>) {
    let c = polygon(n, 0.5);
    let sides = (0..n)
        .map(|k| lifted_segment(c[k], c[(k + 1) % n]))
        .collect();
    let strips = (0..n)
        .map(|k| lifted_strip(c[k], c[(k + 1) % n], 0.3))
        .collect();
    (sides, strips)
}

fn neighbours(strips: &[BSplineSurface]) -> Vec<Option<Neighbour<'_>>> {
    strips
        .iter()
        .map(|s| {
            Some(Neighbour {
                surface: s,
                side: nurbs_core::Side::V0,
            })
        })
        .collect()
}

/// Largest distance of `quads` (sampled) from the surface given as a signed distance.
fn max_deviation(quads: &[BSplineSurface], dist: impl Fn(&Point3) -> f64) -> f64 {
    let mut worst: f64 = 0.0;
    for q in quads {
        for a in 0..=20 {
            for b in 0..=20 {
                let p = q.point(a as f64 / 20.0, b as f64 / 20.0);
                worst = worst.max(dist(&p).abs());
            }
        }
    }
    worst
}

/// Internal curve I_k must be the same control row in quads k (u1) and k + 1 (v1), bit for bit.
fn assert_shared_rows(quads: &[BSplineSurface]) {
    let n = quads.len();
    for k in 0..n {
        let (q, r) = (&quads[k], &quads[(k + 1) % n]);
        assert_eq!(q.knots_v(), r.knots_u(), "knots of internal curve {k}");
        for j in 0..q.num_v() {
            assert_eq!(
                q.control_point(q.num_u() - 1, j),
                r.control_point(j, r.num_v() - 1),
                "internal curve {k}, point {j}"
            );
        }
    }
}

#[test]
fn central_split_follows_the_convention() {
    for n in 3..=8 {
        let sides = planar_sides(n, |x, y| 0.1 * x * y);
        let (quads, rep) = central_split(&sides, None, &CentralSplitParams::default()).unwrap();
        assert_eq!(quads.len(), n);
        assert_shared_rows(&quads);
        for k in 0..n {
            let prev = (k + n - 1) % n;
            let q = &quads[k];
            assert_eq!(q.degree_u(), 3);
            assert_eq!(q.degree_v(), 3);
            let (a, b) = sides[k].domain();
            let (pa, pb) = sides[prev].domain();
            assert!((q.point(0.0, 0.0) - sides[k].point(a)).norm() <= 1e-12);
            assert_eq!(q.point(1.0, 0.0), rep.midpoints[k]);
            assert_eq!(q.point(0.0, 1.0), rep.midpoints[prev]);
            assert_eq!(q.point(1.0, 1.0), rep.centre);
            // outer sides: halves of the boundary curves, same parametrization up to the map
            for s in 0..=16 {
                let t = s as f64 / 16.0;
                let on_ck = sides[k].point(a + 0.5 * (b - a) * t);
                assert!((q.point(t, 0.0) - on_ck).norm() <= 1e-12, "v0 of quad {k}");
                let on_prev = sides[prev].point(pb - 0.5 * (pb - pa) * t);
                assert!(
                    (q.point(0.0, t) - on_prev).norm() <= 1e-12,
                    "u0 of quad {k}"
                );
            }
            // normals S_u × S_v point to the side from which the loop is counter-clockwise
            let d = q.derivatives(0.4, 0.4);
            let normal = d.du.cross(&d.dv).normalize();
            assert!(normal.dot(&rep.loop_normal) > 0.9, "n = {n}, quad {k}");
            assert!(rep.loop_normal.z > 0.9);
        }
    }
}

#[test]
fn planar_ngons_stay_planar() {
    let h = |x: f64, y: f64| 0.3 * x - 0.2 * y + 1.0;
    let normal = Vector3::new(-0.3, 0.2, 1.0).normalize();
    let off_plane = |p: &Point3| (p.z - h(p.x, p.y)) * normal.z;
    for n in 3..=8 {
        let sides = planar_sides(n, h);
        for fixed_rings in [0, 2] {
            let params = NsidedParams {
                fixed_rings,
                ..Default::default()
            };
            let nb = vec![None; n];
            let (quads, rep) = fill_corner(&sides, &nb, &params).unwrap();
            assert_shared_rows(&quads);
            let worst = quads
                .iter()
                .flat_map(|q| q.control_points().iter())
                .map(|p| off_plane(p).abs())
                .fold(0.0, f64::max);
            assert!(
                worst <= 1e-9,
                "n = {n}: control points {worst} off the plane"
            );
            assert!(rep.refit.max_internal_angle_deg <= 1e-6, "n = {n}");
            assert!(rep.refit.max_boundary_angle_deg.is_none());
        }
    }
}

#[test]
fn paraboloid_hole_with_wings_is_g1_and_shares_internal_curves() {
    for n in 3..=8 {
        let (sides, strips) = paraboloid_hole(n);
        let nb = neighbours(&strips);
        let (quads, rep) = fill_corner(&sides, &nb, &NsidedParams::default()).unwrap();
        assert_shared_rows(&quads);
        let r = rep.refit;
        let dev = max_deviation(&quads, |p| p.z - (p.x * p.x + p.y * p.y));
        eprintln!(
            "n = {n}: internal {:.4}°, boundary {:.4}°, refit max {:.2e} rms {:.2e}, off paraboloid {dev:.2e}, {} vertices",
            r.max_internal_angle_deg,
            r.max_boundary_angle_deg.unwrap(),
            r.max_error,
            r.rms_error,
            rep.mesh_vertices
        );
        assert!(r.max_internal_angle_deg <= 0.5, "n = {n}");
        assert!(r.max_boundary_angle_deg.unwrap() <= 0.1, "n = {n}");
        // the hole is 1 across: the faired corner stays close to the paraboloid
        assert!(dev <= 0.01, "n = {n}: {dev} off the paraboloid");
    }
}

/// The sphere of radius `r` about the origin: a cap boundary of n great-circle arcs at polar
/// angle 25° (the hole spans 50°, wider than the 37° square of tests/discrete.rs), each fitted by a cubic B-spline (deviation ~1e-7 r).
fn sphere_sides(n: usize, r: f64) -> Vec<BSplineCurve> {
    let theta = 25f64.to_radians();
    let corner = |k: usize| {
        let a = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
        Vector3::new(theta.sin() * a.cos(), theta.sin() * a.sin(), theta.cos()) * r
    };
    (0..n)
        .map(|k| {
            let (p, q) = (corner(k), corner((k + 1) % n));
            let on = |t: f64| Point3::from((p + t * (q - p)).normalize() * r);
            let kv = KnotVector::clamped_uniform(3, 7).unwrap();
            let mut pts = vec![Point3::origin(); 7];
            pts[0] = Point3::from(p);
            pts[6] = Point3::from(q);
            let template = BSplineCurve::new(kv, pts, None).unwrap();
            let ts: Vec<f64> = (0..=60).map(|i| i as f64 / 60.0).collect();
            let data: Vec<Point3> = ts.iter().map(|&t| on(t)).collect();
            let mut free = vec![true; 7];
            free[0] = false;
            free[6] = false;
            fit_curve(&template, &free, &ts, &data, &FitParams::default())
                .unwrap()
                .0
        })
        .collect()
}

#[test]
fn sphere_hole_with_two_fixed_rings_comes_back_near_the_sphere() {
    let radius = 10.0;
    for n in 3..=8 {
        let sides = sphere_sides(n, radius);
        let (quads, _) = central_split(&sides, None, &CentralSplitParams::default()).unwrap();
        let nb = vec![None; n];
        let sampled = sample_quads(&quads, &nb, &SamplingParams::default()).unwrap();
        // the surface with the hole: every sample on the sphere; then the hole (beyond ring 2)
        // sinks by 3 % of the radius plus noise
        let mut mesh = sampled.mesh.clone();
        let dist =
            nside_discrete::ring_distance(&nside_discrete::MeshTopology::new(&mesh).unwrap());
        let mut r = rng(n as u64);
        for (p, &d) in mesh.positions.iter_mut().zip(&dist) {
            *p = Point3::from(p.coords.normalize() * radius);
            if d > 2 {
                *p = Point3::from(p.coords * (0.97 + r.random_range(-0.005..0.005)));
            }
        }
        // the weights of fair_corner: mean-value weights of the flat layout
        let params = DiscreteFairingParams {
            weights: NsidedParams::default().weights,
            ..Default::default()
        };
        let (faired, _) =
            fair_mesh_with_layout(&mesh, &sampled.flat_layout(), &[], &params).unwrap();
        let worst_mesh = faired
            .positions
            .iter()
            .map(|p| (p.coords.norm() - radius).abs())
            .fold(0.0, f64::max);
        let (refit, rep) = refit_quads(&quads, &sampled, &faired.positions, &nb).unwrap();
        assert_shared_rows(&refit);
        let worst = max_deviation(&refit, |p| p.coords.norm() - radius);
        eprintln!(
            "sphere n = {n}: mesh {worst_mesh:.3e}, quads {worst:.3e} of r = {radius}; internal {:.4}°",
            rep.max_internal_angle_deg
        );
        assert!(worst_mesh <= 0.01 * radius, "n = {n}: mesh {worst_mesh}");
        assert!(worst <= 0.01 * radius, "n = {n}: quads {worst}");
        assert!(rep.max_internal_angle_deg <= 0.5, "n = {n}");
    }
}

#[test]
fn sampling_welds_internal_curves_and_the_centre() {
    let n = 5;
    let (sides, strips) = paraboloid_hole(n);
    let (quads, _) = central_split(&sides, None, &CentralSplitParams::default()).unwrap();
    let nb = neighbours(&strips);
    let params = SamplingParams {
        samples_per_span: 3,
        wing_rows: 2,
    };
    let s = sample_quads(&quads, &nb, &params).unwrap();
    let per_quad = s.grids[0].us.len() * s.grids[0].vs.len();
    // shared: n internal curves of (m − 1) vertices each, the centre n − 1 times
    let m = s.grids[0].vs.len();
    let chain = s.side_chains[0].len();
    let expected = n * per_quad - n * (m - 1) - (n - 1) + n * 2 * chain;
    assert_eq!(s.mesh.positions.len(), expected);
    assert_eq!(s.mesh.boundary_loops().len(), 1);
    nside_discrete::MeshTopology::new(&s.mesh).unwrap();
    for (v, o) in s.origins.iter().enumerate() {
        let p = match *o {
            VertexOrigin::Quad { quad, u, v } => quads[quad].point(u, v),
            VertexOrigin::Wing { side, u, v, .. } => strips[side].point(u, v),
        };
        assert_eq!(p, s.mesh.positions[v]);
        if matches!(o, VertexOrigin::Wing { .. }) {
            assert!(s.fixed[v] && !s.patch_boundary[v]);
        }
    }
    // every welded vertex is seen by both quads at the same point
    for k in 0..n {
        let (g, h) = (&s.grids[k], &s.grids[(k + 1) % n]);
        let (mu, mv, hv) = (g.us.len(), g.vs.len(), h.vs.len());
        for b in 0..mv {
            assert_eq!(g.vertices[(mu - 1) * mv + b], h.vertices[b * hv + hv - 1]);
        }
    }
    assert!(internal_angle_deg(&quads).is_finite());
}

#[test]
fn bad_input_is_an_error() {
    let sides = planar_sides(5, |_, _| 0.0);
    let p = CentralSplitParams::default();
    assert!(matches!(
        central_split(&sides[..2], None, &p),
        Err(NsideError::SideCount { count: 2, .. })
    ));
    let nine = planar_sides(9, |_, _| 0.0);
    assert!(matches!(
        central_split(&nine, None, &p),
        Err(NsideError::SideCount { count: 9, .. })
    ));
    // a side moved away: the loop does not close
    let mut open = sides.clone();
    for q in open[2].control_points_mut() {
        q.z += 1e-3;
    }
    match central_split(&open, None, &p) {
        Err(NsideError::OpenLoop {
            curve, next, gap, ..
        }) => {
            assert_eq!((curve, next), (1, 2));
            assert!((gap - 1e-3).abs() < 1e-12);
        }
        other => panic!("expected OpenLoop, got {other:?}"),
    }
    // a bow tie: corners 0, 2, 1, 3 of a square
    let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let order = [0, 2, 1, 3];
    let bow: Vec<BSplineCurve> = (0..4)
        .map(|k| {
            let (a, b) = (sq[order[k]], sq[order[(k + 1) % 4]]);
            curve(
                vec![Point3::new(a[0], a[1], 0.0), Point3::new(b[0], b[1], 0.0)],
                1,
            )
        })
        .collect();
    assert!(matches!(
        central_split(&bow, None, &p),
        Err(NsideError::SelfIntersecting { .. })
    ));
    // all on a line
    let line: Vec<BSplineCurve> = [[0.0, 1.0], [1.0, 2.0], [2.0, 0.0]]
        .iter()
        .map(|&[a, b]| curve(vec![Point3::new(a, 0.0, 0.0), Point3::new(b, 0.0, 0.0)], 1))
        .collect();
    assert!(matches!(
        central_split(&line, None, &p),
        Err(NsideError::DegenerateLoop { .. } | NsideError::SelfIntersecting { .. })
    ));
    // rational and quartic sides
    let mut rational = sides.clone();
    rational[1] = BSplineCurve::new(
        sides[1].knots().clone(),
        sides[1].control_points().to_vec(),
        Some(vec![1.0, 2.0, 1.0, 1.0, 1.0]),
    )
    .unwrap();
    assert!(matches!(
        central_split(&rational, None, &p),
        Err(NsideError::UnsupportedCurve { curve: 1, .. })
    ));
    let mut quartic = sides.clone();
    quartic[3] = sides[3].elevate_degree(1).unwrap();
    assert!(matches!(
        central_split(&quartic, None, &p),
        Err(NsideError::UnsupportedCurve { curve: 3, .. })
    ));
    // wrong counts, broken quads
    let (quads, _) = central_split(&sides, None, &p).unwrap();
    assert!(matches!(
        sample_quads(&quads, &[None; 4], &SamplingParams::default()),
        Err(NsideError::CountMismatch {
            expected: 5,
            got: 4,
            ..
        })
    ));
    assert!(matches!(
        fill_corner(&sides, &[None; 3], &NsidedParams::default()),
        Err(NsideError::CountMismatch { .. })
    ));
    let mut broken = quads.clone();
    let (nu, nv) = (broken[2].num_u(), broken[2].num_v());
    broken[2].control_points_mut()[(nu - 1) * nv + 1].z += 0.1;
    assert!(matches!(
        sample_quads(&broken, &[None; 5], &SamplingParams::default()),
        Err(NsideError::BadQuad { quad: 2, .. })
    ));
}
