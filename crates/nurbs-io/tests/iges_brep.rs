//! Faces of a manifold solid B-rep (186 → 514 → 510, \[IGES\] §4.147–§4.151) read as trimmed
//! surfaces: a unit square face on a plane surface (190) bounded by a loop (508) of four edges
//! (504) between four vertices (502), checked against the square in closed form.

mod common;
use common::raw_iges;
use nurbs_io::read_iges;

/// The square [0, 1]² at z = 0 as one face: its first edge lies on a line twice as long (the
/// edge is the part between its vertices), its third on a line drawn the other way (the loop
/// runs it backwards, OF = 0).
fn square_face(outer_flag: i64) -> String {
    let e = |kind: i64, params: &str| (kind, 0, params.to_string());
    raw_iges(&[
        e(110, "0.,0.,0.,2.,0.,0."), // D1: past the edge's end
        e(110, "1.,0.,0.,1.,1.,0."), // D3
        e(110, "0.,1.,0.,1.,1.,0."), // D5: against the loop
        e(110, "0.,1.,0.,0.,0.,0."), // D7
        e(502, "4,0.,0.,0.,1.,0.,0.,1.,1.,0.,0.,1.,0."), // D9
        e(504, "4,1,9,1,9,2,3,9,2,9,3,5,9,4,9,3,7,9,4,9,1"), // D11
        e(508, "4,0,11,1,1,0,0,11,2,1,0,0,11,3,0,0,0,11,4,1,0"), // D13
        e(116, "0.5,0.5,0."),        // D15
        e(123, "0.,0.,1."),          // D17
        e(190, "15,17"),             // D19
        e(510, &format!("19,1,{outer_flag},13")), // D21
        e(514, "1,21,1"),            // D23
        e(186, "23,1,0"),            // D25
    ])
}

#[test]
fn a_brep_face_is_its_loop_on_its_plane() {
    let f = read_iges(square_face(1).as_bytes()).unwrap();
    assert_eq!(f.surfaces.len(), 1, "{:?}", f.skipped);
    assert_eq!(f.trimmed_entities, 1);
    let s = &f.surfaces[0];
    assert_eq!(s.de, 19, "the plane surface");
    // the loop: every point on the square's boundary, all four corners reached, nothing of
    // the first line beyond its edge
    let on_square = |p: &nurbs_core::Point3| {
        let (x, y) = (p.x, p.y);
        p.z.abs() < 1e-12
            && (-1e-12..=1.0 + 1e-12).contains(&x)
            && (-1e-12..=1.0 + 1e-12).contains(&y)
            && [x, 1.0 - x, y, 1.0 - y].iter().any(|d| d.abs() < 1e-12)
    };
    assert!(s.trim.iter().all(on_square), "{:?}", s.trim);
    for c in [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]] {
        assert!(
            s.trim
                .iter()
                .any(|p| (p.x - c[0]).abs() + (p.y - c[1]).abs() < 1e-12),
            "corner {c:?}"
        );
    }
    // the loop runs once round, in order: no jump longer than a side
    let closed: Vec<_> = s.trim.iter().chain(s.trim.first()).collect();
    assert!(
        closed
            .windows(2)
            .all(|w| (w[1] - w[0]).norm() <= 1.0 + 1e-12)
    );
    // the plane is the smallest rectangle holding the loop: the unit square
    let ((u0, u1), (v0, v1)) = (s.surface.domain_u(), s.surface.domain_v());
    let area = (u1 - u0) * (v1 - v0);
    assert!((area - 1.0).abs() < 1e-12, "area {area}");
    for (u, v) in [(u0, v0), (u1, v0), (u0, v1), (u1, v1)] {
        assert!(on_square(&s.surface.point(u, v)), "corner of the plane");
    }
    // the consumed entities are not reported skipped
    for t in [186, 514, 510, 508, 504, 502, 190] {
        assert!(!f.skipped.contains_key(&t), "{t}: {:?}", f.skipped);
    }
}

/// Without the outer-loop flag the face has no outer boundary: its loop is a hole, and a plane
/// has nothing to be bounded by — it is not read, and nothing panics.
#[test]
fn a_face_without_an_outer_loop_has_no_plane() {
    let f = read_iges(square_face(0).as_bytes()).unwrap();
    assert!(f.surfaces.is_empty());
    assert_eq!(f.trimmed_entities, 1);
}

/// An edge that names no vertex list, or an index past the edge list, is an error naming the
/// loop, not a panic.
#[test]
fn a_bad_edge_is_named() {
    let text = square_face(1).replace("4,0,11,1,1,0,0,11,2", "4,0,11,9,1,0,0,11,2");
    let err = read_iges(text.as_bytes()).unwrap_err().to_string();
    assert!(err.contains("edge 9") && err.contains("508"), "{err}");
}
