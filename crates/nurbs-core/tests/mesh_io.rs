//! Tessellation, mesh topology, OBJ output and the JSON surface format.

use nurbs_core::io::{surface_to_json, surfaces_from_json};
use nurbs_core::shapes::{paraboloid_bicubic, sphere_patch};
use nurbs_core::testing::random_surface;
use nurbs_core::{BSplineSurface, Error, KnotVector, Point3, TriMesh};

#[test]
fn tessellation_topology() {
    let s = paraboloid_bicubic(&[0.5]).unwrap();
    let m = TriMesh::from_surface(&s, 6, 5);
    assert_eq!(m.positions.len(), 30);
    assert_eq!(m.faces.len(), 2 * 5 * 4);
    // faces follow S_u × S_v (the normal points up on this paraboloid)
    for f in &m.faces {
        assert!(m.face_normal_area(f).z > 0.0);
    }
    let loops = m.boundary_loops();
    assert_eq!(loops.len(), 1);
    assert_eq!(loops[0].len(), 2 * (6 + 5) - 4);
    let rings = m.one_rings();
    // interior vertex (2, 2) of the grid has valence 6; a corner 2 or 3
    assert_eq!(rings[2 * 5 + 2].len(), 6);
    assert!(rings[0].len() <= 3);
    let mut obj = Vec::new();
    m.write_obj(&mut obj).unwrap();
    let text = String::from_utf8(obj).unwrap();
    assert_eq!(text.lines().filter(|l| l.starts_with("v ")).count(), 30);
    assert_eq!(text.lines().filter(|l| l.starts_with("f ")).count(), 40);
}

#[test]
fn collapsed_sides_are_welded() {
    // a cone-like patch: row u = 0 collapsed to one point
    let mut pts = Vec::new();
    for i in 0..3 {
        for j in 0..3 {
            pts.push(if i == 0 {
                Point3::new(0.0, 0.0, 1.0)
            } else {
                Point3::new(i as f64, j as f64 - 1.0, 0.0)
            });
        }
    }
    let s = BSplineSurface::new(
        KnotVector::bezier(2).unwrap(),
        KnotVector::bezier(2).unwrap(),
        pts,
        None,
    )
    .unwrap();
    let m = TriMesh::from_surface(&s, 5, 5);
    assert_eq!(m.positions.len(), 1 + 4 * 5);
    assert!(
        m.normals.iter().all(|n| (n.norm() - 1.0).abs() < 1e-12),
        "every vertex gets a normal"
    );
    assert_eq!(m.boundary_loops().len(), 1);
}

#[test]
fn json_round_trip_is_exact() {
    for seed in 0..10 {
        let s = random_surface(seed, 1..=5, 8, seed % 2 == 0);
        let back = surfaces_from_json(&surface_to_json(&s)).unwrap();
        assert_eq!(back, vec![s]);
    }
    let sphere = sphere_patch(2.0).unwrap();
    let text = format!(
        "{{\"surfaces\": [{}, {}]}}",
        surface_to_json(&sphere),
        surface_to_json(&sphere)
    );
    assert_eq!(surfaces_from_json(&text).unwrap().len(), 2);
}

#[test]
fn bezier_patches_without_knots() {
    let text = r#"{"patches": [{"degree_u": 1, "degree_v": 1, "control_points": [[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1]]]}]}"#;
    let s = surfaces_from_json(text).unwrap();
    assert_eq!(s[0].knots_u().knots(), &[0.0, 0.0, 1.0, 1.0]);
    assert_eq!(s[0].point(1.0, 1.0), Point3::new(1.0, 1.0, 1.0));
}

#[test]
fn bad_files_name_the_problem() {
    let cases = [
        (
            r#"{"degree_u": 1, "degree_v": 1, "knots_u": [0,0,2,1], "control_points": [[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1]]]}"#,
            "knots_u",
        ),
        (
            r#"{"degree_u": 1, "degree_v": 1, "knots_u": [0,0,1,1,1], "control_points": [[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1]]]}"#,
            "knots_u",
        ),
        (
            r#"{"degree_u": 1, "degree_v": 1, "control_points": [[[0,0,0],[0,1,0]],[[1,0,0]]]}"#,
            "row 1 has 1 points",
        ),
        (
            r#"{"degree_u": 1, "degree_v": 1, "control_points": [[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1]]], "weights": [[1,1],[1,-2]]}"#,
            "weight [1][1] is -2",
        ),
        (
            r#"{"degree_u": 0, "degree_v": 1, "control_points": [[[0,0,0],[0,1,0]]]}"#,
            "degree must be at least 1",
        ),
        (
            r#"{"degree_u": 1, "degree_v": 1, "control_points": [[[0,0,0],[0,1,0]],[[1,0,0],[1,1,1e999]]]}"#,
            "malformed JSON",
        ),
        (
            r#"{"degree_u": 1, "degree_v": 1, "control_points": "#,
            "malformed JSON",
        ),
        (r#"[{"degree_u": 1, "control_points": []}]"#, "surface 0"),
    ];
    for (text, expected) in cases {
        let err = surfaces_from_json(text).unwrap_err();
        assert!(
            err.to_string().contains(expected),
            "{text}\n  gave: {err}\n  expected to mention: {expected}"
        );
    }
    assert!(matches!(
        surfaces_from_json("[]"),
        Err(Error::Format { .. })
    ));
}

#[test]
fn teapot_patches_load() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/third_party/teapot.json"
    );
    let text = std::fs::read_to_string(path).expect("the teapot is in the repository");
    let patches = surfaces_from_json(&text).unwrap();
    assert_eq!(patches.len(), 32);
    // lid-top patches have a collapsed first row: no normal there, a welded vertex in the mesh
    let lid = &patches[20];
    assert!(lid.derivatives(0.0, 0.5).normal().is_none());
    let mesh = TriMesh::from_surface(lid, 9, 9);
    assert_eq!(mesh.positions.len(), 1 + 8 * 9);
}

#[test]
fn obj_reading_keeps_vertex_order() {
    let text = "# comment\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\nf -4 -2 -1\n";
    let m = TriMesh::from_obj_str(text).unwrap();
    assert_eq!(m.positions.len(), 4);
    assert_eq!(m.positions[2], Point3::new(1.0, 1.0, 0.0));
    assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3], [0, 2, 3]]);
    for (bad, what) in [
        ("v 0 0\n", "three coordinates"),
        ("v 0 0 nan\n", "finite"),
        ("v 0 0 0\nf 1 2 3\n", "out of range"),
        ("v 0 0 0\nf 1\n", "at least 3"),
    ] {
        let e = TriMesh::from_obj_str(bad).unwrap_err().to_string();
        assert!(e.contains(what) && e.contains("OBJ line"), "{e}");
    }
    let mut bytes = Vec::new();
    m.write_obj(&mut bytes).unwrap();
    assert_eq!(
        TriMesh::from_obj_str(std::str::from_utf8(&bytes).unwrap())
            .unwrap()
            .positions,
        m.positions
    );
}
