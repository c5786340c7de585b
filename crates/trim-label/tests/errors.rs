//! Bad input gets a clear error, never a panic.

mod common;

use common::polygon_region;
use nurbs_core::{Point3, TriMesh};
use trim_label::{
    LabelError, LabelParams, LabeledFitParams, fit_labeled, label_region, parse_segments_json,
};

fn square() -> (TriMesh, Vec<Vec<usize>>) {
    polygon_region(
        &[
            vec![[0.0, 0.0], [4.0, 0.0]],
            vec![[4.0, 0.0], [4.0, 4.0]],
            vec![[4.0, 4.0], [0.0, 4.0]],
            vec![[0.0, 4.0], [0.0, 0.0]],
        ],
        1.0,
    )
}

fn err(mesh: &TriMesh, segs: Option<&[Vec<usize>]>) -> LabelError {
    label_region(mesh, segs, &LabelParams::default()).expect_err("must be rejected")
}

#[test]
fn non_manifold_edge() {
    // three triangles on edge (0, 1)
    let mesh = TriMesh {
        positions: vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.5, 1.0, 0.0),
            Point3::new(0.5, -1.0, 0.0),
            Point3::new(0.5, 0.0, 1.0),
        ],
        normals: vec![],
        faces: vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]],
    };
    let e = err(&mesh, None);
    assert!(
        matches!(
            e,
            LabelError::NonManifoldEdge {
                a: 0,
                b: 1,
                faces: 3
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("edge (0, 1) is used by 3 faces"));
}

#[test]
fn no_boundary() {
    // a closed tetrahedron
    let mesh = TriMesh {
        positions: vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(0.0, 0.0, 1.0),
        ],
        normals: vec![],
        faces: vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]],
    };
    assert_eq!(err(&mesh, None), LabelError::NoBoundary);
}

#[test]
fn degenerate_triangles() {
    let (mut mesh, _) = square();
    let f = mesh.faces[0];
    mesh.faces[0] = [f[0], f[0], f[2]];
    assert!(matches!(
        err(&mesh, None),
        LabelError::DegenerateTriangle { face: 0, .. }
    ));
    // zero area without a repeated vertex: three collinear points
    let mesh = TriMesh {
        positions: vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(2.0, 0.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
        ],
        normals: vec![],
        faces: vec![[0, 1, 3], [0, 1, 2]],
    };
    let e = err(&mesh, None);
    assert!(
        matches!(e, LabelError::DegenerateTriangle { face: 1, .. }),
        "{e}"
    );
}

#[test]
fn non_finite_vertex_and_bad_index() {
    let (mut mesh, _) = square();
    mesh.positions[3].y = f64::NAN;
    assert_eq!(err(&mesh, None), LabelError::NonFiniteVertex { vertex: 3 });
    let (mut mesh, _) = square();
    let count = mesh.positions.len();
    mesh.faces[2][1] = count + 5;
    assert!(matches!(
        err(&mesh, None),
        LabelError::FaceIndexOutOfRange { face: 2, .. }
    ));
}

#[test]
fn non_orientable_and_disconnected_and_empty() {
    let (mut mesh, _) = square();
    let f = mesh.faces[0];
    mesh.faces[0] = [f[0], f[2], f[1]];
    assert!(matches!(err(&mesh, None), LabelError::NonOrientable { .. }));
    let (mut mesh, _) = square();
    let shift = mesh.positions.len();
    let copy: Vec<Point3> = mesh
        .positions
        .iter()
        .map(|p| p + nurbs_core::Vector3::new(10.0, 0.0, 0.0))
        .collect();
    let faces: Vec<[usize; 3]> = mesh
        .faces
        .iter()
        .map(|f| [f[0] + shift, f[1] + shift, f[2] + shift])
        .collect();
    mesh.positions.extend(copy);
    mesh.faces.extend(faces);
    assert_eq!(err(&mesh, None), LabelError::Disconnected { components: 2 });
    assert_eq!(err(&TriMesh::default(), None), LabelError::EmptyMesh);
}

#[test]
fn bow_tie_vertex() {
    let mesh = TriMesh {
        positions: vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, -1.0, 0.0),
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(-1.0, 1.0, 0.0),
            Point3::new(-1.0, -1.0, 0.0),
        ],
        normals: vec![],
        faces: vec![[0, 1, 2], [0, 3, 4]],
    };
    assert!(matches!(
        err(&mesh, None),
        LabelError::NonManifoldVertex {
            vertex: 0,
            boundary_edges: 2
        }
    ));
}

#[test]
fn segments_that_do_not_cover_the_loop() {
    let (mesh, segs) = square();
    let e = err(&mesh, Some(&segs[..3]));
    assert!(
        matches!(e, LabelError::SegmentsDoNotCoverLoop { .. }),
        "{e}"
    );
    assert!(e.to_string().contains("segments do not cover"), "{e}");
    // a gap of one edge inside the list
    let mut gap = segs.clone();
    gap[1].remove(0);
    gap[1].remove(0);
    assert!(matches!(
        err(&mesh, Some(&gap)),
        LabelError::SegmentsDoNotCoverLoop { .. }
    ));
    // overlap: twice round the loop
    let twice: Vec<Vec<usize>> = segs.iter().chain(&segs).cloned().collect();
    assert!(matches!(
        err(&mesh, Some(&twice)),
        LabelError::SegmentsDoNotCoverLoop { .. }
    ));
    // skipping a vertex inside a segment
    let mut skip = segs.clone();
    skip[0].remove(2);
    assert!(matches!(
        err(&mesh, Some(&skip)),
        LabelError::SegmentNotContiguous { segment: 0, .. }
    ));
    assert!(matches!(
        err(&mesh, Some(&[vec![0]])),
        LabelError::SegmentTooShort {
            segment: 0,
            count: 1
        }
    ));
    assert!(matches!(
        err(&mesh, Some(&[])),
        LabelError::SegmentsDoNotCoverLoop { .. }
    ));
}

#[test]
fn segment_vertex_off_the_boundary() {
    let (mut mesh, segs) = square();
    // add an interior vertex by splitting a face
    let f = mesh.faces[0];
    let c = Point3::from(
        (mesh.positions[f[0]].coords + mesh.positions[f[1]].coords + mesh.positions[f[2]].coords)
            / 3.0,
    );
    mesh.positions.push(c);
    let k = mesh.positions.len() - 1;
    mesh.faces[0] = [f[0], f[1], k];
    mesh.faces.push([f[1], f[2], k]);
    mesh.faces.push([f[2], f[0], k]);
    let mut bad = segs.clone();
    bad[1][1] = k;
    assert_eq!(
        err(&mesh, Some(&bad)),
        LabelError::SegmentOffBoundary {
            segment: 1,
            vertex: k
        }
    );
}

#[test]
fn reversed_and_partition_segments_are_accepted() {
    let (mesh, segs) = square();
    let forward = label_region(&mesh, Some(&segs), &LabelParams::default()).unwrap();
    let reversed: Vec<Vec<usize>> = segs
        .iter()
        .rev()
        .map(|s| s.iter().rev().copied().collect())
        .collect();
    let back = label_region(&mesh, Some(&reversed), &LabelParams::default()).unwrap();
    assert_eq!((back.labels, back.corner_count), (4, 4));
    assert_eq!(
        back.segments[0].vertices, reversed[0],
        "output keeps the caller's order"
    );
    // partition style: drop each segment's last vertex
    let part: Vec<Vec<usize>> = segs.iter().map(|s| s[..s.len() - 1].to_vec()).collect();
    let p = label_region(&mesh, Some(&part), &LabelParams::default()).unwrap();
    assert_eq!(p.segment_labels(), forward.segment_labels());
}

#[test]
fn bad_json_and_bad_params() {
    assert!(matches!(
        parse_segments_json("{\"segments\": 3}"),
        Err(LabelError::SegmentFormat { .. })
    ));
    assert_eq!(
        parse_segments_json("[[1, 2], [2, 3]]").unwrap(),
        vec![vec![1, 2], vec![2, 3]]
    );
    assert_eq!(
        parse_segments_json(r#"{"segments": [{"vertices": [4, 5], "label": "south"}]}"#).unwrap(),
        vec![vec![4, 5]]
    );
    let (mesh, segs) = square();
    let params = LabelParams {
        smooth_join_deg: f64::NAN,
        ..LabelParams::default()
    };
    assert!(matches!(
        label_region(&mesh, Some(&segs), &params),
        Err(LabelError::InvalidParameter {
            name: "smooth_join_deg",
            ..
        })
    ));
    let l = label_region(&mesh, Some(&segs), &LabelParams::default()).unwrap();
    let bad = LabeledFitParams {
        smoothing: -1.0,
        ..LabeledFitParams::default()
    };
    assert!(matches!(
        fit_labeled(&mesh, &l, &bad),
        Err(LabelError::InvalidParameter { .. })
    ));
}
