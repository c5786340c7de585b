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
