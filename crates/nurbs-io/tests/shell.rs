//! Faces written as one shell ([`nurbs_io::write_step_shell`]): faces that meet along a boundary
//! share that edge and its vertices, an edge another face's vertex lies on is split there, the
//! faces are oriented so that every shared edge is used once each way, each connected set of
//! faces is a shell (closed: a CLOSED_SHELL); without a join tolerance every face keeps its own
//! edges.

use std::collections::HashMap;

use nurbs_core::{BSplineSurface, Point3, Vector3};
use nurbs_io::{Face, read_step, write_step_shell};

/// The join tolerance of these tests (model units): the default G0 tolerance of a model.
const JOIN: f64 = 1e-3;

/// The plane patch origin + u·x + v·y over [0, 1]², its normal x × y.
fn patch(origin: Point3, x: Vector3, y: Vector3) -> BSplineSurface {
    nurbs_core::shapes::plane_patch(origin, x, y, (0.0, 1.0), (0.0, 1.0)).unwrap()
}

/// The STEP file's entities by id.
fn entities(text: &str) -> HashMap<usize, String> {
    text.lines()
        .filter_map(|l| {
            let l = l.strip_prefix('#')?;
            let (id, rest) = l.split_once(" = ")?;
            Some((id.parse().ok()?, rest.trim_end_matches(';').to_string()))
        })
        .collect()
}

/// How many entities of `kind` the file has.
fn count(e: &HashMap<usize, String>, kind: &str) -> usize {
    e.values()
        .filter(|v| v.starts_with(&format!("{kind}(")))
        .count()
}

/// The `#n` references of an entity's text, in order.
fn references(text: &str) -> Vec<usize> {
    text.split('#')
        .skip(1)
        .filter_map(|s| {
            s.chars()
                .take_while(char::is_ascii_digit)
                .collect::<String>()
                .parse()
                .ok()
        })
        .collect()
}

/// Whether an entity's text ends with the logical `.T.` before its closing parenthesis.
fn last_true(text: &str) -> bool {
    text.trim_end_matches(')').ends_with(".T.")
}

/// Per face name: its `same_sense`, and the uses of its edges (EDGE_CURVE id, the direction
/// the face's loops traverse it in: the oriented edge's sense unless the bound is reversed).
fn faces(e: &HashMap<usize, String>) -> HashMap<String, (bool, Vec<(usize, bool)>)> {
    let mut out = HashMap::new();
    for v in e.values().filter(|v| v.starts_with("ADVANCED_FACE(")) {
        let name = v.split('\'').nth(1).unwrap().to_string();
        let refs = references(v);
        let mut uses = Vec::new();
        for b in &refs[..refs.len() - 1] {
            let bound = &e[b];
            let orientation = last_true(bound);
            let lp = &e[&references(bound)[0]];
            for oe in references(lp) {
                let oriented = &e[&oe];
                let edge = references(oriented)[0];
                uses.push((edge, last_true(oriented) == orientation));
            }
        }
        out.insert(name, (last_true(v), uses));
    }
    out
}

/// The six faces of the unit cube, their surface normals pointing in and out at random.
fn cube() -> Vec<(String, BSplineSurface, Vector3)> {
    let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
    let o = Point3::origin();
    vec![
        // bottom, normal +z (inward)
        ("bottom".into(), patch(o, x, y), -z),
        // top, normal −z (inward): u along y, v along x
        ("top".into(), patch(Point3::new(0.0, 0.0, 1.0), y, x), z),
        // front y = 0, normal −y (outward)
        ("front".into(), patch(o, x, z), -y),
        // back y = 1, normal −y (inward)
        ("back".into(), patch(Point3::new(0.0, 1.0, 0.0), x, z), y),
        // left x = 0, normal +x (inward)
        ("left".into(), patch(o, y, z), -x),
        // right x = 1, normal −x... with u along z, v along y: z × y = −x (inward)
        ("right".into(), patch(Point3::new(1.0, 0.0, 0.0), z, y), x),
    ]
}

/// The cube's faces written as one STEP file, joined within `join`.
fn cube_text(parts: &[(String, BSplineSurface, Vector3)], join: f64) -> String {
    let list: Vec<Face<'_>> = parts
        .iter()
        .map(|(n, s, _)| Face::untrimmed(n, s))
        .collect();
    write_step_shell(&list, "mm", "cube.step", 0.0, join, &[]).unwrap()
}

#[test]
fn a_cube_is_one_closed_shell_oriented_outward_or_inward_throughout() {
    let parts = cube();
    let text = cube_text(&parts, JOIN);
    let e = entities(&text);
    assert_eq!(count(&e, "CLOSED_SHELL"), 1);
    assert_eq!(count(&e, "OPEN_SHELL"), 0);
    assert_eq!(count(&e, "EDGE_CURVE"), 12);
    assert_eq!(count(&e, "VERTEX_POINT"), 8);
    let faces = faces(&e);
    // every edge used twice, once each way
    let mut senses: HashMap<usize, Vec<bool>> = HashMap::new();
    for (_, uses) in faces.values() {
        for &(edge, forward) in uses {
            senses.entry(edge).or_default().push(forward);
        }
    }
    assert_eq!(senses.len(), 12);
    for (edge, s) in &senses {
        assert_eq!(s.len(), 2, "edge #{edge}");
        assert_ne!(s[0], s[1], "edge #{edge} used twice the same way");
    }
    // the faces' normals (the surface's, reversed where same_sense is false) all point out or
    // all in
    let out: Vec<bool> = parts
        .iter()
        .map(|(n, s, outward)| {
            let d = s.derivatives(0.5, 0.5);
            let normal = d.du.cross(&d.dv);
            let same = faces[n].0;
            (normal.dot(outward) > 0.0) == same
        })
        .collect();
    assert!(out.iter().all(|&o| o == out[0]), "{out:?}");
    // and it reads back as six faces
    assert_eq!(read_step(&text).unwrap().faces.len(), 6);
}

#[test]
fn without_a_join_tolerance_every_face_keeps_its_own_edges() {
    let text = cube_text(&cube(), 0.0);
    let e = entities(&text);
    // each face a shell of its own
    assert_eq!(count(&e, "OPEN_SHELL"), 6);
    assert_eq!(count(&e, "EDGE_CURVE"), 24);
    assert_eq!(count(&e, "VERTEX_POINT"), 24);
}

#[test]
fn faces_apart_by_less_than_the_join_tolerance_share_and_farther_do_not() {
    let (x, y) = (Vector3::x(), Vector3::y());
    let a = patch(Point3::origin(), x, y);
    let near = patch(Point3::new(1.0 + 0.5 * JOIN, 0.0, 0.0), x, y);
    let far = patch(Point3::new(1.0 + 5.0 * JOIN, 0.0, 0.0), x, y);
    for (b, shared) in [(&near, true), (&far, false)] {
        let list = [Face::untrimmed("a", &a), Face::untrimmed("b", b)];
        let text = write_step_shell(&list, "mm", "two.step", 0.0, JOIN, &[]).unwrap();
        let e = entities(&text);
        let (edges, shells) = if shared { (7, 1) } else { (8, 2) };
        assert_eq!(count(&e, "EDGE_CURVE"), edges, "shared: {shared}");
        assert_eq!(count(&e, "OPEN_SHELL"), shells);
    }
}

#[test]
fn an_edge_another_faces_vertex_lies_on_is_split_there() {
    // a 2 × 1 plane below two unit squares side by side: its top edge meets the corner the two
    // squares share
    let (x, y) = (Vector3::x(), Vector3::y());
    let long =
        nurbs_core::shapes::plane_patch(Point3::origin(), x, y, (0.0, 2.0), (0.0, 1.0)).unwrap();
    let left = patch(Point3::new(0.0, 1.0, 0.0), x, y);
    let right = patch(Point3::new(1.0, 1.0, 0.0), x, y);
    let list = [
        Face::untrimmed("long", &long),
        Face::untrimmed("left", &left),
        Face::untrimmed("right", &right),
    ];
    let text = write_step_shell(&list, "mm", "t.step", 0.0, JOIN, &[]).unwrap();
    let e = entities(&text);
    // long: 5 edges (its top split), left 4 − 1, right 4 − 2
    assert_eq!(count(&e, "EDGE_CURVE"), 10);
    assert_eq!(count(&e, "VERTEX_POINT"), 8);
    let faces = faces(&e);
    assert_eq!(faces["long"].1.len(), 5);
    let mut uses: HashMap<usize, usize> = HashMap::new();
    for (_, u) in faces.values() {
        for &(edge, _) in u {
            *uses.entry(edge).or_default() += 1;
        }
    }
    assert_eq!(uses.values().filter(|&&n| n == 2).count(), 3);
    let back = read_step(&text).unwrap();
    assert_eq!(back.faces.len(), 3);
}

#[test]
fn a_trimmed_face_shares_its_edge_with_a_boxed_neighbour() {
    // a plane trimmed to the triangle (0,0) (1,0) (0,1) next to the unit square below it
    let (x, y) = (Vector3::x(), Vector3::y());
    let big =
        nurbs_core::shapes::plane_patch(Point3::origin(), x, y, (0.0, 2.0), (0.0, 2.0)).unwrap();
    let triangle = vec![vec![
        Point3::new(0.0, 0.0, 0.0),
        Point3::new(1.0, 0.0, 0.0),
        Point3::new(0.0, 1.0, 0.0),
    ]];
    let below = patch(Point3::new(0.0, -1.0, 0.0), x, y);
    let list = [
        Face {
            name: "triangle",
            surface: &big,
            trim: &triangle,
        },
        Face::untrimmed("below", &below),
    ];
    let text = write_step_shell(&list, "mm", "tri.step", 0.0, JOIN, &[]).unwrap();
    let e = entities(&text);
    assert_eq!(count(&e, "EDGE_CURVE"), 3 + 4 - 1);
    let back = read_step(&text).unwrap();
    assert_eq!(back.faces.len(), 2);
}

#[test]
fn faces_of_two_parts_are_never_joined() {
    // two unit squares side by side: one shell in one part, two shells in two parts (two
    // solids of an assembly that touch stay two)
    let (x, y) = (Vector3::x(), Vector3::y());
    let a = patch(Point3::origin(), x, y);
    let b = patch(Point3::new(1.0, 0.0, 0.0), x, y);
    let list = [Face::untrimmed("a", &a), Face::untrimmed("b", &b)];
    for (parts, edges, shells) in [(vec![0, 0], 7, 1), (vec![0, 1], 8, 2)] {
        let text = write_step_shell(&list, "mm", "two.step", 0.0, JOIN, &parts).unwrap();
        let e = entities(&text);
        assert_eq!(count(&e, "EDGE_CURVE"), edges, "{parts:?}");
        assert_eq!(count(&e, "OPEN_SHELL"), shells, "{parts:?}");
    }
}
