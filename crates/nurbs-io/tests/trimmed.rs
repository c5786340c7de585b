//! Faces written with their trim loops read back with them: a plane with a square hole through
//! STEP and IGES (both loops each), and a trim given off the surface lands on it; the kernel
//! models' IGES faces keep the inner boundaries their STEP faces have.

use nurbs_core::{BSplineSurface, Point3, Vector3};
use nurbs_io::bounds::distance_to_polyline;
use nurbs_io::{Face, IgesWriteParams, check_structure, read_iges, read_step};

/// Points of a read-back loop lie on the written polyline (closed) to this fraction of the part
/// size: the reader samples the degree-1 edges, rounding only.
const ON_POLYLINE_RELATIVE: f64 = 1e-9;

/// The plane z = `z` over [0, 10]², its normal +z.
fn plane(z: f64) -> BSplineSurface {
    nurbs_core::shapes::plane_patch(
        Point3::new(0.0, 0.0, z),
        Vector3::x(),
        Vector3::y(),
        (0.0, 10.0),
        (0.0, 10.0),
    )
    .unwrap()
}

/// A square of half side `h` about (`c`, `c`) at height `z`, counterclockwise about +z.
fn square(c: f64, h: f64, z: f64) -> Vec<Point3> {
    vec![
        Point3::new(c - h, c - h, z),
        Point3::new(c + h, c - h, z),
        Point3::new(c + h, c + h, z),
        Point3::new(c - h, c + h, z),
    ]
}

/// The largest distance of `back`'s points from the closed polyline through `written`.
fn off_polyline(back: &[Point3], written: &[Point3]) -> f64 {
    let mut closed = written.to_vec();
    closed.push(written[0]);
    back.iter()
        .map(|p| distance_to_polyline(p, &closed))
        .fold(0.0, f64::max)
}

/// A 10 × 10 plane trimmed to a 9 × 9 square with a 4 × 4 square hole, the trim given 0.01
/// above the plane (a surface that moved in fairing): STEP reads back the two loops on the
/// plane, on the squares, outer first; the face's box is the outer square's.
#[test]
fn a_plane_with_a_square_hole_reads_back_with_both_loops() {
    let s = plane(0.0);
    let trim = vec![square(5.0, 4.5, 0.01), square(5.0, 2.0, 0.01)];
    let faces = [Face {
        name: "holed",
        surface: &s,
        trim: &trim,
    }];
    let text = nurbs_io::write_step_faces(&faces, "mm", "holed.step").unwrap();
    assert_eq!(text.matches("FACE_OUTER_BOUND").count(), 1);
    assert_eq!(text.matches("FACE_BOUND(").count(), 1);
    assert_eq!(text.matches("EDGE_CURVE").count(), 8);
    let back = read_step(&text).unwrap();
    assert_eq!(back.faces.len(), 1);
    let f = &back.faces[0];
    assert_eq!(f.trim.len(), 2);
    for (l, given) in f.trim.iter().zip(&trim) {
        let on_plane: Vec<Point3> = given.iter().map(|p| Point3::new(p.x, p.y, 0.0)).collect();
        assert!(
            l.iter().all(|p| p.z.abs() <= 1e-12),
            "a point off the plane"
        );
        let d = off_polyline(l, &on_plane);
        assert!(d <= ON_POLYLINE_RELATIVE * 10.0, "{d:.3e} off the square");
    }
    let (u, v) = (f.surface.domain_u(), f.surface.domain_v());
    for (a, b) in [(u.0, 0.5), (u.1, 9.5), (v.0, 0.5), (v.1, 9.5)] {
        assert!((a - b).abs() <= 1e-9, "box {u:?} × {v:?}");
    }
}

/// A face whose bounds are all FACE_BOUNDs, the hole listed first (OCCT names no outer bound):
/// it reads back with the outer square first, the loop whose parameter box holds the other's.
#[test]
fn without_a_named_outer_bound_the_widest_loop_comes_first() {
    let s = plane(0.0);
    let trim = vec![square(5.0, 2.0, 0.0), square(5.0, 4.5, 0.0)];
    let faces = [Face {
        name: "holed",
        surface: &s,
        trim: &trim,
    }];
    let text = nurbs_io::write_step_faces(&faces, "mm", "holed.step")
        .unwrap()
        .replace("FACE_OUTER_BOUND", "FACE_BOUND");
    assert_eq!(text.matches("FACE_OUTER_BOUND").count(), 0);
    let back = read_step(&text).unwrap();
    let loops = &back.faces[0].trim;
    assert_eq!(loops.len(), 2);
    let reach = |l: &[Point3]| l.iter().map(|p| (p.x - 5.0).abs()).fold(0.0, f64::max);
    assert!(
        (reach(&loops[0]) - 4.5).abs() <= 1e-9 && (reach(&loops[1]) - 2.0).abs() <= 1e-9,
        "loops reach {} and {}",
        reach(&loops[0]),
        reach(&loops[1])
    );
}

/// The same face through IGES: a trimmed surface (144) over the 128 with one inner boundary,
/// read back with both loops (outer first) on the plane and on their squares; the file passes
/// the structure check.
#[test]
fn a_plane_with_a_square_hole_is_a_trimmed_iges_surface() {
    let s = plane(0.0);
    let trim = vec![square(5.0, 4.5, 0.0), square(5.0, 2.0, 0.0)];
    let faces = [Face {
        name: "holed",
        surface: &s,
        trim: &trim,
    }];
    let text = nurbs_io::write_iges_faces(&faces, &[], &IgesWriteParams::default()).unwrap();
    check_structure(text.as_bytes()).unwrap();
    // the 144 names one inner boundary
    let p144 = text
        .lines()
        .find(|l| l.starts_with("144,"))
        .expect("a 144 entity");
    assert_eq!(p144.split(',').nth(3), Some("1"), "{p144}");
    let back = read_iges(text.as_bytes()).unwrap();
    assert_eq!(back.trimmed_entities, 1);
    assert_eq!(back.surfaces.len(), 1);
    let f = &back.surfaces[0];
    assert!(f.trimmed);
    assert_eq!(f.name, "holed");
    let loops = f.trim_loops();
    assert_eq!(loops.len(), 2);
    assert_eq!(f.holes.len(), 1);
    for (l, given) in loops.iter().zip(&trim) {
        assert!(l.len() >= 4);
        assert!(
            l.iter().all(|p| p.z.abs() <= 1e-12),
            "a point off the plane"
        );
        let d = off_polyline(l, given);
        assert!(d <= ON_POLYLINE_RELATIVE * 10.0, "{d:.3e} off the square");
    }
}

/// Each kernel model of `fixtures/occt` read from IGES has as many inner boundaries as its
/// STEP file has inner face bounds (one: plate_boss's plate around the boss), each a loop of
/// points on its face's surface.
#[test]
fn kernel_models_keep_their_inner_boundaries() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/occt");
    let mut total = 0;
    for name in [
        "occt_box12_r5",
        "occt_box12_variable",
        "occt_corner3_radii",
        "occt_loft_block",
        "occt_pipe_tee",
        "occt_plate_boss",
    ] {
        let iges = read_iges(&std::fs::read(dir.join(format!("{name}.igs"))).unwrap()).unwrap();
        let step =
            read_step(&std::fs::read_to_string(dir.join(format!("{name}.step"))).unwrap()).unwrap();
        let holes: usize = iges.surfaces.iter().map(|s| s.holes.len()).sum();
        let inner: usize = step
            .faces
            .iter()
            .map(|f| f.trim.len().saturating_sub(1))
            .sum();
        assert_eq!(holes, inner, "{name}");
        for s in &iges.surfaces {
            let mut projector = nurbs_core::SurfaceProjector::new(
                &s.surface,
                nurbs_core::ProjectionParams::default(),
            );
            for p in s.holes.iter().flatten() {
                let d = projector.project(p).distance;
                assert!(
                    d <= 1e-6 * s.surface.size(),
                    "{name} {}: {d:.3e} off",
                    s.name
                );
            }
        }
        total += holes;
    }
    assert_eq!(total, 1);
}

/// A face without trim is written as before: bounded by its box in STEP, a bare 128 in IGES.
#[test]
fn a_face_without_trim_keeps_its_box() {
    let s = plane(1.0);
    let faces = [Face::untrimmed("plain", &s)];
    assert_eq!(
        nurbs_io::write_step_faces(&faces, "mm", "a.step").unwrap(),
        nurbs_io::write_step(&[("plain", &s)], "mm", "a.step").unwrap()
    );
    let iges = nurbs_io::write_iges_faces(&faces, &[], &IgesWriteParams::default()).unwrap();
    assert!(!iges.contains("\n144,"));
    assert_eq!(read_iges(iges.as_bytes()).unwrap().trimmed_entities, 0);
}

/// A circle of radius `r` about (`c`, `c`) at height 0 through `n` points, counterclockwise.
fn circle(c: f64, r: f64, n: usize) -> Vec<Point3> {
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            Point3::new(c + r * a.cos(), c + r * a.sin(), 0.0)
        })
        .collect()
}

/// A trim edge of 400 points along a circle of radius 3 fitted within 0.5 µm: a cubic of far
/// fewer control points, its ends the edge's, every point within the tolerance of it (at its
/// chord-length parameter, an upper bound of the distance); 0 keeps the polyline; an edge of a
/// few points stays a polyline.
#[test]
fn a_trim_edge_is_fitted_within_its_tolerance() {
    let mut pts = circle(5.0, 3.0, 400);
    pts.truncate(201); // half the circle: an open edge
    let tol = 5e-4;
    let c = nurbs_io::bounds::fitted_edge(&pts, tol).unwrap();
    assert_eq!(c.degree(), 3);
    assert!(
        c.control_points().len() <= 40,
        "{} points",
        c.control_points().len()
    );
    assert_eq!(c.control_points()[0], pts[0]);
    assert_eq!(*c.control_points().last().unwrap(), pts[200]);
    let dense: Vec<Point3> = (0..=2000).map(|k| c.point(k as f64 / 2000.0)).collect();
    for p in &pts {
        let d = distance_to_polyline(p, &dense);
        assert!(d <= tol + 1e-6, "a point {d:.2e} from the curve");
    }
    assert_eq!(
        nurbs_io::bounds::fitted_edge(&pts, 0.0).unwrap().degree(),
        1
    );
    assert_eq!(
        nurbs_io::bounds::fitted_edge(&pts[..5], tol)
            .unwrap()
            .degree(),
        1
    );
}

/// An edge of 400 points with a kink of 10° in its middle (two faces' boundaries meeting at a
/// small angle, not a corner of the loop): knots gather at the kink and the edge is a cubic of
/// a few dozen control points within the tolerance, where uniform spans would have needed one
/// per point and written the polyline.
#[test]
fn a_kinked_edge_is_fitted_with_knots_at_its_kink() {
    let turn = 10f64.to_radians();
    let pts: Vec<Point3> = (0..400)
        .map(|k| {
            let s = k as f64 / 10.0 - 20.0;
            if s <= 0.0 {
                Point3::new(s, 0.0, 0.0)
            } else {
                Point3::new(s * turn.cos(), s * turn.sin(), 0.0)
            }
        })
        .collect();
    let tol = 5e-4;
    let c = nurbs_io::bounds::fitted_edge(&pts, tol).unwrap();
    assert_eq!(c.degree(), 3);
    assert!(
        c.control_points().len() <= 60,
        "{} points",
        c.control_points().len()
    );
    let dense: Vec<Point3> = (0..=20000).map(|k| c.point(k as f64 / 20000.0)).collect();
    for p in &pts {
        let d = distance_to_polyline(p, &dense);
        assert!(d <= tol + 1e-6, "a point {d:.2e} from the curve");
    }
}

/// The plane of [`plane`] trimmed to a 9 × 9 square with a round hole of radius 3 through 400
/// points.
fn round_hole() -> (BSplineSurface, Vec<Vec<Point3>>) {
    (
        plane(0.0),
        vec![square(5.0, 4.5, 0.0), circle(5.0, 3.0, 400)],
    )
}

/// A plane with a round hole of 400 points written with fitted edges: a file a fraction of the
/// polyline's size, the hole read back within the tolerance of the circle.
#[test]
fn fitted_edges_make_a_compact_file_that_reads_back_within_the_tolerance() {
    let (s, trim) = round_hole();
    let faces = [Face {
        name: "round hole",
        surface: &s,
        trim: &trim,
    }];
    let tol = 5e-4;
    let plain = nurbs_io::write_step_faces(&faces, "mm", "hole.step").unwrap();
    let fitted = nurbs_io::write_step_faces_within(&faces, "mm", "hole.step", tol).unwrap();
    let points = |t: &str| t.matches("CARTESIAN_POINT").count();
    assert!(
        4 * points(&fitted) < points(&plain),
        "{} points against {}",
        points(&fitted),
        points(&plain)
    );
    let back = read_step(&fitted).unwrap();
    let hole = &back.faces[0].trim[1];
    let worst = hole
        .iter()
        .map(|p| ((p.x - 5.0).hypot(p.y - 5.0) - 3.0).abs())
        .fold(0.0, f64::max);
    // the fit's tolerance, plus the polyline's own chord error on the circle (r (1 − cos(π/400)))
    let chord = 3.0 * (1.0 - (std::f64::consts::PI / 400.0).cos());
    assert!(
        worst <= tol + chord,
        "the hole reads back {worst:.2e} off the circle"
    );
}

/// The same face through IGES with fitted trim curves: each loop composite curves (102) of
/// pieces between its corners, in model and parameter space; the file a fraction of the
/// polyline one's size and structurally valid, the hole read back within the tolerance of the
/// circle and the outer square on its square (its corners kept).
#[test]
fn fitted_iges_loops_are_composites_that_read_back_within_the_tolerance() {
    let (s, trim) = round_hole();
    let faces = [Face {
        name: "round hole",
        surface: &s,
        trim: &trim,
    }];
    let tol = 5e-4;
    let plain = nurbs_io::write_iges_faces(&faces, &[], &IgesWriteParams::default()).unwrap();
    let params = IgesWriteParams {
        edge_tolerance: tol,
        ..IgesWriteParams::default()
    };
    let fitted = nurbs_io::write_iges_faces(&faces, &[], &params).unwrap();
    check_structure(fitted.as_bytes()).unwrap();
    assert!(
        4 * fitted.len() < plain.len(),
        "{} bytes against {}",
        fitted.len(),
        plain.len()
    );
    assert!(
        fitted.lines().any(|l| l.starts_with("102,")),
        "no composite"
    );
    let back = read_iges(fitted.as_bytes()).unwrap();
    let loops = back.surfaces[0].trim_loops();
    assert_eq!(loops.len(), 2);
    let chord = 3.0 * (1.0 - (std::f64::consts::PI / 400.0).cos());
    let worst = loops[1]
        .iter()
        .map(|p| ((p.x - 5.0).hypot(p.y - 5.0) - 3.0).abs())
        .fold(0.0, f64::max);
    assert!(
        worst <= tol + chord,
        "the hole reads back {worst:.2e} off the circle"
    );
    let d = off_polyline(&loops[0], &trim[0]);
    assert!(d <= ON_POLYLINE_RELATIVE * 10.0, "{d:.3e} off the square");
}

/// A loop on a full cylinder that crosses its seam: the walk in parameter space jumps from one
/// end of the turn to the other once each way, and nothing is drawn across the face between
/// (halving the jump drew a detour of 64 points over the face and back): every parameter's
/// image lies on the loop.
#[test]
fn a_loop_across_a_seam_jumps_without_a_detour() {
    let s = nurbs_core::shapes::full_cylinder(4.0, 10.0).unwrap();
    // angles −30°…30° (across the seam at 0), heights 2…6, 20 points a side
    let at = |deg: f64, z: f64| {
        let a = deg.to_radians();
        Point3::new(4.0 * a.cos(), 4.0 * a.sin(), z)
    };
    let mut pts = Vec::new();
    for k in 0..20 {
        pts.push(at(-30.0 + 3.0 * k as f64, 2.0));
    }
    for k in 0..20 {
        pts.push(at(30.0, 2.0 + 0.2 * k as f64));
    }
    for k in 0..20 {
        pts.push(at(30.0 - 3.0 * k as f64, 6.0));
    }
    for k in 0..20 {
        pts.push(at(-30.0, 6.0 - 0.2 * k as f64));
    }
    let uv = nurbs_io::bounds::loop_params(&s, &pts);
    let mut jumps = 0;
    for (k, &(u, v)) in uv.iter().enumerate() {
        let p = s.point(u, v);
        let off = (p.z.clamp(2.0, 6.0) - p.z).abs()
            + (p.coords.xy().norm() - 4.0).abs()
            + (p.y.atan2(p.x).to_degrees().abs() - 30.0).max(0.0);
        assert!(
            off <= 1e-6,
            "parameter {k} ({u}, {v}) images off the loop: {p:?}"
        );
        let next = uv[(k + 1) % uv.len()];
        if nurbs_io::bounds::is_seam_jump(&s, (u, v), next) {
            jumps += 1;
        }
    }
    assert_eq!(jumps, 2, "one jump each way across the seam");
}

/// A plane with coarse loops of a few corners, each with one step longer than half the domain:
/// no seam (a plane is not closed), so the loops stay an outer and an inner boundary — a long
/// straight step is no jump across a seam.
#[test]
fn coarse_loops_on_a_plane_are_not_taken_for_seam_jumps() {
    let s = plane(0.0);
    let p = |x: f64, y: f64| Point3::new(x, y, 0.0);
    let outer = vec![
        p(0.5, 0.5),
        p(9.5, 0.5),
        p(9.5, 4.0),
        p(5.0, 4.5),
        p(0.5, 4.0),
    ];
    let inner = vec![
        p(1.0, 1.0),
        p(1.0, 3.0),
        p(4.0, 3.5),
        p(7.0, 3.0),
        p(7.0, 1.0),
    ];
    for (a, b) in [((0.5, 0.5), (9.5, 0.5)), ((1.0, 1.0), (7.0, 1.0))] {
        assert!(!nurbs_io::bounds::is_seam_jump(&s, a, b));
    }
    let trim = vec![outer, inner];
    let faces = [Face {
        name: "coarse",
        surface: &s,
        trim: &trim,
    }];
    let params = IgesWriteParams {
        edge_tolerance: 5e-4,
        ..IgesWriteParams::default()
    };
    let text = nurbs_io::write_iges_faces(&faces, &[], &params).unwrap();
    let p144 = text
        .lines()
        .find(|l| l.starts_with("144,"))
        .expect("a 144 entity");
    assert_eq!(p144.split(',').nth(3), Some("1"), "{p144}");
}

/// A loop that repeats a point in a row (as one of pr1db.stp's faces does) is written: the
/// repeated point is dropped (a degree-1 curve cannot carry a double knot), in IGES and STEP.
#[test]
fn a_loop_repeating_a_point_is_written() {
    let s = plane(0.0);
    let mut outer = square(5.0, 4.5, 0.0);
    outer.insert(2, outer[1]);
    let trim = vec![outer];
    let faces = [Face {
        name: "repeated",
        surface: &s,
        trim: &trim,
    }];
    let iges = nurbs_io::write_iges_faces(&faces, &[], &IgesWriteParams::default()).unwrap();
    assert_eq!(read_iges(iges.as_bytes()).unwrap().surfaces.len(), 1);
    let step = nurbs_io::write_step_faces(&faces, "mm", "r.step").unwrap();
    assert_eq!(read_step(&step).unwrap().faces.len(), 1);
    let c = nurbs_io::bounds::polyline(&[trim[0][0], trim[0][1], trim[0][2], trim[0][3]]).unwrap();
    assert_eq!(c.control_points().len(), 3);
    // a point nearer its predecessor than the chord-length parameter resolves, after a long
    // chord (a jump across a seam in parameter space)
    let far = Point3::new(1000.0, 0.0, 0.0);
    let near = Point3::new(1000.0 + 1e-14, 0.0, 0.0);
    let c =
        nurbs_io::bounds::polyline(&[Point3::origin(), far, near, Point3::new(1000.0, 5.0, 0.0)])
            .unwrap();
    assert_eq!(c.control_points().len(), 3);
    assert_eq!(c.control_points()[2], Point3::new(1000.0, 5.0, 0.0));
}

/// A straight trim edge is written as its two ends, whatever its points: 40 points along a
/// line, waved by a tenth of the tolerance, give a degree-1 curve of two control points; waved
/// by twice the tolerance they give a curve through the points within the tolerance.
#[test]
fn a_straight_edge_is_its_two_ends() {
    let tol = 1e-3;
    let line = |wave: f64| -> Vec<Point3> {
        (0..40)
            .map(|k| {
                let t = k as f64 / 39.0;
                Point3::new(10.0 * t, wave * (7.0 * t).sin(), 0.0)
            })
            .collect()
    };
    let straight = nurbs_io::bounds::fitted_edge(&line(0.1 * tol), tol).unwrap();
    assert_eq!(straight.degree(), 1);
    assert_eq!(straight.control_points().len(), 2);
    let waved = line(2.0 * tol);
    let curve = nurbs_io::bounds::fitted_edge(&waved, tol).unwrap();
    assert!(curve.control_points().len() > 2);
    let (t0, t1) = curve.domain();
    let samples: Vec<Point3> = (0..=400)
        .map(|k| curve.point(t0 + (t1 - t0) * k as f64 / 400.0))
        .collect();
    for p in &waved {
        assert!(distance_to_polyline(p, &samples) <= 1.01 * tol);
    }
}
