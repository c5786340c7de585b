//! Closed and periodic STEP faces (ISO 10303-42 §5.4): closed circle edges, seams, faces with no
//! edge loop, halves of a sphere told apart by their loops' orientation; each checked against
//! the closed-form surface.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use nurbs_core::{BSplineSurface, Point3};
use nurbs_io::{StepFile, read_step};

/// A Part 21 file around the DATA section `body`.
fn step(body: &str) -> String {
    format!("ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n{body}ENDSEC;\nEND-ISO-10303-21;\n")
}

/// The file read, with no warnings.
fn read(body: &str) -> StepFile {
    let f = read_step(&step(body)).unwrap();
    assert!(f.warnings.is_empty(), "{:?}", f.warnings);
    f
}

/// Points of `s` on an (n + 1)² grid over its domain.
fn grid(s: &BSplineSurface, n: usize) -> Vec<Point3> {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let mut out = Vec::new();
    for a in 0..=n {
        for b in 0..=n {
            let t = |k: usize, lo: f64, hi: f64| lo + (hi - lo) * k as f64 / n as f64;
            out.push(s.point(t(a, u0, u1), t(b, v0, v1)));
        }
    }
    out
}

/// Placement at the origin with axis z and reference direction x (#1–#4).
const FRAME: &str = "#1 = CARTESIAN_POINT('',(0.,0.,0.));
#2 = DIRECTION('',(0.,0.,1.));
#3 = DIRECTION('',(1.,0.,0.));
#4 = AXIS2_PLACEMENT_3D('',#1,#2,#3);
";

/// A cylinder of radius 2 about z (#5) with circles at heights 0 (#30) and 3 (#33), each a
/// closed edge from one vertex (#40, #41), and a seam line edge between the vertices (#42).
const CYLINDER: &str = "#5 = CYLINDRICAL_SURFACE('',#4,2.);
#10 = CARTESIAN_POINT('',(2.,0.,0.));
#11 = CARTESIAN_POINT('',(2.,0.,3.));
#20 = VERTEX_POINT('',#10);
#21 = VERTEX_POINT('',#11);
#30 = CIRCLE('',#4,2.);
#31 = CARTESIAN_POINT('',(0.,0.,3.));
#32 = AXIS2_PLACEMENT_3D('',#31,#2,#3);
#33 = CIRCLE('',#32,2.);
#34 = LINE('',#10,#35);
#35 = VECTOR('',#2,1.);
#40 = EDGE_CURVE('',#20,#20,#30,.T.);
#41 = EDGE_CURVE('',#21,#21,#33,.T.);
#42 = EDGE_CURVE('',#20,#21,#34,.T.);
";

/// Every point of `s` at radius 2 from the z axis and heights 0 … 3; the u range a full turn.
fn assert_full_cylinder(s: &BSplineSurface) {
    let (u0, u1) = s.domain_u();
    assert!((u1 - u0 - TAU).abs() < 1e-12, "u {u0} … {u1}");
    let (mut zmin, mut zmax) = (f64::MAX, f64::MIN);
    for p in grid(s, 12) {
        assert!((p.x.hypot(p.y) - 2.0).abs() < 1e-9, "{p:?}");
        zmin = zmin.min(p.z);
        zmax = zmax.max(p.z);
    }
    assert!(zmin.abs() < 1e-12 && (zmax - 3.0).abs() < 1e-12);
}

/// A band between two circles, each a closed edge (start vertex = end vertex): the face covers
/// the whole turn, 2π.
#[test]
fn a_band_between_closed_circle_edges_is_the_full_cylinder() {
    let f = read(&format!(
        "{FRAME}{CYLINDER}#50 = ORIENTED_EDGE('',*,*,#40,.T.);
#51 = ORIENTED_EDGE('',*,*,#41,.F.);
#60 = EDGE_LOOP('',(#50));
#61 = EDGE_LOOP('',(#51));
#62 = FACE_OUTER_BOUND('',#60,.T.);
#63 = FACE_BOUND('',#61,.T.);
#70 = ADVANCED_FACE('band',(#62,#63),#5,.T.);
"
    ));
    assert_eq!(f.faces.len(), 1);
    assert_full_cylinder(&f.faces[0].surface);
    assert_eq!(f.faces[0].trim.len(), 2);
}

/// One loop of both circles and a seam edge used twice, once each way: the full cylinder.
#[test]
fn a_seam_used_twice_closes_the_cylinder() {
    let f = read(&format!(
        "{FRAME}{CYLINDER}#50 = ORIENTED_EDGE('',*,*,#40,.T.);
#51 = ORIENTED_EDGE('',*,*,#42,.T.);
#52 = ORIENTED_EDGE('',*,*,#41,.F.);
#53 = ORIENTED_EDGE('',*,*,#42,.F.);
#60 = EDGE_LOOP('',(#50,#51,#52,#53));
#62 = FACE_OUTER_BOUND('',#60,.T.);
#70 = ADVANCED_FACE('seamed',(#62),#5,.T.);
"
    ));
    assert_full_cylinder(&f.faces[0].surface);
}

/// A sphere of radius 3 about (1, 2, 3) bounded only by a VERTEX_LOOP, and the same sphere with
/// no bounds at all: the whole sphere, every point at the radius, both poles reached.
#[test]
fn a_sphere_with_a_vertex_loop_or_no_bounds_is_whole() {
    let body = "#1 = CARTESIAN_POINT('',(1.,2.,3.));
#2 = DIRECTION('',(0.,0.,1.));
#3 = DIRECTION('',(1.,0.,0.));
#4 = AXIS2_PLACEMENT_3D('',#1,#2,#3);
#5 = SPHERICAL_SURFACE('',#4,3.);
#10 = CARTESIAN_POINT('',(4.,2.,3.));
#20 = VERTEX_POINT('',#10);
#60 = VERTEX_LOOP('',#20);
#62 = FACE_BOUND('',#60,.T.);
#70 = ADVANCED_FACE('vertex',(#62),#5,.T.);
#71 = ADVANCED_FACE('none',(),#5,.T.);
";
    let f = read(body);
    assert_eq!(f.faces.len(), 2);
    let centre = Point3::new(1.0, 2.0, 3.0);
    for face in &f.faces {
        let s = &face.surface;
        let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
        assert!((u1 - u0 - TAU).abs() < 1e-12 && (v1 - v0 - PI).abs() < 1e-12);
        let points = grid(s, 16);
        for p in &points {
            assert!(((p - centre).norm() - 3.0).abs() < 1e-9, "{p:?}");
        }
        let top = points.iter().map(|p| p.z).fold(f64::MIN, f64::max);
        let bottom = points.iter().map(|p| p.z).fold(f64::MAX, f64::min);
        assert!((top - 6.0).abs() < 1e-9 && bottom.abs() < 1e-9);
    }
}

/// A sphere of radius 5 about the origin and its poles N, S (#10, #11); two half great circles
/// from N to S in the plane y = 0, through +x (#40) and through −x (#41).
const MERIDIANS: &str = "#5 = SPHERICAL_SURFACE('',#4,5.);
#6 = DIRECTION('',(0.,1.,0.));
#7 = DIRECTION('',(0.,-1.,0.));
#8 = AXIS2_PLACEMENT_3D('',#1,#6,#2);
#9 = AXIS2_PLACEMENT_3D('',#1,#7,#2);
#10 = CARTESIAN_POINT('',(0.,0.,5.));
#11 = CARTESIAN_POINT('',(0.,0.,-5.));
#20 = VERTEX_POINT('',#10);
#21 = VERTEX_POINT('',#11);
#30 = CIRCLE('',#8,5.);
#31 = CIRCLE('',#9,5.);
#40 = EDGE_CURVE('',#20,#21,#30,.T.);
#41 = EDGE_CURVE('',#20,#21,#31,.T.);
";

/// Two faces on one sphere, both bounded by the same great circle through the poles, run
/// opposite ways: each is the half on its loop's left (seen from outside), y ≥ 0 and y ≤ 0.
#[test]
fn the_halves_of_a_sphere_follow_their_loops_orientation() {
    let f = read(&format!(
        "{FRAME}{MERIDIANS}#50 = ORIENTED_EDGE('',*,*,#40,.T.);
#51 = ORIENTED_EDGE('',*,*,#41,.F.);
#52 = ORIENTED_EDGE('',*,*,#41,.T.);
#53 = ORIENTED_EDGE('',*,*,#40,.F.);
#60 = EDGE_LOOP('',(#50,#51));
#61 = EDGE_LOOP('',(#52,#53));
#62 = FACE_OUTER_BOUND('',#60,.T.);
#63 = FACE_OUTER_BOUND('',#61,.T.);
#70 = ADVANCED_FACE('plus',(#62),#5,.T.);
#71 = ADVANCED_FACE('minus',(#63),#5,.T.);
"
    ));
    assert_eq!(f.faces.len(), 2);
    for (face, sign) in f.faces.iter().zip([1.0, -1.0]) {
        let points = grid(&face.surface, 16);
        for p in &points {
            assert!((p.coords.norm() - 5.0).abs() < 1e-9);
            assert!(sign * p.y > -1e-9, "{}: {p:?}", face.name);
        }
        let reach = points.iter().map(|p| sign * p.y).fold(f64::MIN, f64::max);
        assert!((reach - 5.0).abs() < 1e-9, "{}", face.name);
    }
}

/// A sphere of radius 5 cut by the circle of latitude 30° (z = 2.5), a closed edge run
/// counterclockwise about z: with the face's sense the surface's, the face is the cap above it
/// up to the pole; with the opposite sense, the rest of the sphere down to the other pole.
#[test]
fn a_cap_bounded_by_one_circle_reaches_the_pole_on_its_side() {
    let body = format!(
        "{FRAME}#5 = SPHERICAL_SURFACE('',#4,5.);
#10 = CARTESIAN_POINT('',(4.330127018922193,0.,2.5));
#20 = VERTEX_POINT('',#10);
#31 = CARTESIAN_POINT('',(0.,0.,2.5));
#32 = AXIS2_PLACEMENT_3D('',#31,#2,#3);
#33 = CIRCLE('',#32,4.330127018922193);
#40 = EDGE_CURVE('',#20,#20,#33,.T.);
#50 = ORIENTED_EDGE('',*,*,#40,.T.);
#60 = EDGE_LOOP('',(#50));
#62 = FACE_OUTER_BOUND('',#60,.T.);
#70 = ADVANCED_FACE('cap',(#62),#5,.T.);
#71 = ADVANCED_FACE('rest',(#62),#5,.F.);
"
    );
    let f = read(&body);
    let (cap, rest) = (&f.faces[0].surface, &f.faces[1].surface);
    let z = |s: &BSplineSurface| {
        let points = grid(s, 16);
        for p in &points {
            assert!((p.coords.norm() - 5.0).abs() < 1e-9);
        }
        let zs: Vec<f64> = points.iter().map(|p| p.z).collect();
        (
            zs.iter().copied().fold(f64::MAX, f64::min),
            zs.iter().copied().fold(f64::MIN, f64::max),
        )
    };
    let (lo, hi) = z(cap);
    assert!(
        (lo - 2.5).abs() < 1e-9 && (hi - 5.0).abs() < 1e-9,
        "cap {lo} … {hi}"
    );
    let (lo, hi) = z(rest);
    assert!(
        (lo + 5.0).abs() < 1e-9 && (hi - 2.5).abs() < 1e-9,
        "rest {lo} … {hi}"
    );
    assert!((cap.domain_v().1 - FRAC_PI_2).abs() < 1e-12);
}

/// A cylinder of radius 2 about z written as a closed rational B-spline surface (the 9-point
/// circle of \[NB\] §7.5 in u, degree 1 in v), bounded by its two circles as closed rational
/// B-spline edges from one vertex and a seam in the QUASI_UNIFORM_CURVE form used both ways:
/// the face is the whole surface, u over its whole closed domain.
#[test]
fn a_closed_b_spline_face_with_closed_edges_is_whole() {
    let w = std::f64::consts::FRAC_1_SQRT_2;
    let circle = [
        (2., 0.),
        (2., 2.),
        (0., 2.),
        (-2., 2.),
        (-2., 0.),
        (-2., -2.),
        (0., -2.),
        (2., -2.),
        (2., 0.),
    ];
    let weights = [1., w, 1., w, 1., w, 1., w, 1.];
    let mut body = String::new();
    for (k, (x, y)) in circle.iter().enumerate() {
        body += &format!("#{} = CARTESIAN_POINT('',({x},{y},0.));\n", 100 + k);
        body += &format!("#{} = CARTESIAN_POINT('',({x},{y},3.));\n", 200 + k);
    }
    let rows: Vec<String> = (0..9)
        .map(|k| format!("(#{},#{})", 100 + k, 200 + k))
        .collect();
    let list = |base: usize| {
        (0..9)
            .map(|k| format!("#{}", base + k))
            .collect::<Vec<_>>()
            .join(",")
    };
    let wl = |ws: &[f64]| {
        ws.iter()
            .map(|x| format!("{x}"))
            .collect::<Vec<_>>()
            .join(",")
    };
    let knots = "B_SPLINE_CURVE_WITH_KNOTS((3,2,2,2,3),(0.,1.,2.,3.,4.),.UNSPECIFIED.)";
    body += &format!(
        "#5 = (BOUNDED_SURFACE() B_SPLINE_SURFACE(2,1,({}),.CYLINDRICAL_SURF.,.T.,.F.,.U.) B_SPLINE_SURFACE_WITH_KNOTS((3,2,2,2,3),(2,2),(0.,1.,2.,3.,4.),(0.,1.),.UNSPECIFIED.) GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_SURFACE(({})) REPRESENTATION_ITEM('') SURFACE());
#30 = (BOUNDED_CURVE() B_SPLINE_CURVE(2,({}),.CIRCULAR_ARC.,.T.,.U.) {knots} CURVE() GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_CURVE(({})) REPRESENTATION_ITEM(''));
#33 = (BOUNDED_CURVE() B_SPLINE_CURVE(2,({}),.CIRCULAR_ARC.,.T.,.U.) {knots} CURVE() GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_CURVE(({})) REPRESENTATION_ITEM(''));
#34 = QUASI_UNIFORM_CURVE('',1,(#100,#200),.POLYLINE_FORM.,.F.,.U.);
#20 = VERTEX_POINT('',#100);
#21 = VERTEX_POINT('',#200);
#40 = EDGE_CURVE('',#20,#20,#30,.T.);
#41 = EDGE_CURVE('',#21,#21,#33,.T.);
#42 = EDGE_CURVE('',#20,#21,#34,.T.);
#50 = ORIENTED_EDGE('',*,*,#40,.T.);
#51 = ORIENTED_EDGE('',*,*,#42,.T.);
#52 = ORIENTED_EDGE('',*,*,#41,.F.);
#53 = ORIENTED_EDGE('',*,*,#42,.F.);
#60 = EDGE_LOOP('',(#50,#51,#52,#53));
#62 = FACE_OUTER_BOUND('',#60,.T.);
#70 = ADVANCED_FACE('closed',(#62),#5,.T.);
",
        rows.join(","),
        weights.map(|x| format!("({x},{x})")).join(","),
        list(100),
        wl(&weights),
        list(200),
        wl(&weights),
    );
    let f = read(&body);
    let s = &f.faces[0].surface;
    assert_eq!(s.domain_u(), (0.0, 4.0));
    assert_eq!(s.domain_v(), (0.0, 1.0));
    for p in grid(s, 12) {
        assert!((p.x.hypot(p.y) - 2.0).abs() < 1e-9, "{p:?}");
    }
}

/// The entity instances of `text` whose type is `kind`, as (id, parameters) text.
fn instances<'a>(text: &'a str, kind: &str) -> Vec<&'a str> {
    let key = format!("= {kind}(");
    text.lines().filter(|l| l.contains(&key)).collect()
}

/// The closed faces the writer bounds by their parameter boxes, as ISO 10303-42 bounds them:
/// a corner shared with another corner is one VERTEX_POINT, a collapsed side (a pole) has no
/// edge, and a side that coincides with its opposite side is one EDGE_CURVE used both ways (a
/// seam). Each file reads back as the whole surface, and every real in it has its decimal point
/// (ISO 10303-21 §6.4.4: the file's accuracy, 1e-7, was written "1E-7").
#[test]
fn closed_faces_are_written_with_shared_vertices_and_seams_used_twice() {
    use nurbs_core::Vector3;
    use nurbs_core::shapes::{arc, full_cylinder, revolve_curve, torus};
    let o = Point3::origin();
    // pole to pole through the x axis, turned a full turn about z
    let meridian = arc(o, Vector3::x(), Vector3::z(), 3.0, -FRAC_PI_2, FRAC_PI_2).unwrap();
    let sphere = revolve_curve(&meridian, o, Vector3::z(), 0.0, TAU).unwrap();
    let cylinder = full_cylinder(2.0, 7.0).unwrap();
    let ring = torus(5.0, 1.5).unwrap();
    // (name, surface, vertices, edge curves, oriented edges in the loop)
    let cases = [
        ("sphere", &sphere, 2, 1, 2),
        ("cylinder", &cylinder, 2, 3, 4),
        ("torus", &ring, 1, 2, 4),
    ];
    for (name, s, vertices, curves, oriented) in cases {
        let text = nurbs_io::write_step(&[(name, s)], "mm", "closed.step").unwrap();
        assert_eq!(instances(&text, "VERTEX_POINT").len(), vertices, "{name}");
        assert_eq!(instances(&text, "EDGE_CURVE").len(), curves, "{name}");
        assert_eq!(instances(&text, "ORIENTED_EDGE").len(), oriented, "{name}");
        assert!(text.contains("LENGTH_MEASURE(1.E-7)"), "{name}");
        for token in text.split(|c: char| !(c.is_ascii_alphanumeric() || "+-.".contains(c))) {
            let numeric = token.starts_with(|c: char| c.is_ascii_digit() || c == '-');
            if let Some((mantissa, _)) = token.split_once('E').filter(|_| numeric) {
                assert!(
                    mantissa.contains('.'),
                    "{name}: real {token} has no decimal point"
                );
            }
        }
        let back = read_step(&text).unwrap();
        assert_eq!(back.faces.len(), 1, "{name}");
        let (u0, u1) = s.domain_u();
        let (v0, v1) = s.domain_v();
        let f = &back.faces[0].surface;
        let (fu0, fu1) = f.domain_u();
        let (fv0, fv1) = f.domain_v();
        for a in 0..=8 {
            for b in 0..=8 {
                let (x, y) = (a as f64 / 8.0, b as f64 / 8.0);
                let p = s.point(u0 + (u1 - u0) * x, v0 + (v1 - v0) * y);
                let q = f.point(fu0 + (fu1 - fu0) * x, fv0 + (fv1 - fv0) * y);
                assert!(
                    (p - q).norm() < 1e-9,
                    "{name} at ({x}, {y}): {}",
                    (p - q).norm()
                );
            }
        }
    }
}

/// A closed cylinder's face whose trim is the loop round its parameter box (the circle at each
/// end, the seam both ways, as it comes in from a file) is exported bounded by its box — the
/// same file as the untrimmed face, its seam one edge used both ways — and IGES writes its
/// 128 alone: curves through the trim points left a reader to guess on which side of the seam
/// each run lay (Open CASCADE read half of such a cylinder, the face invalid).
#[test]
fn a_closed_face_trimmed_round_its_box_is_written_by_its_box() {
    use nurbs_io::bounds::Face;
    let s = nurbs_core::shapes::full_cylinder(15.0, 50.0).unwrap();
    let ((a, b), (c, d)) = (s.domain_u(), s.domain_v());
    let side = |u: f64, from: f64, to: f64| -> Vec<Point3> {
        (0..64)
            .map(|k| s.point(u, from + (to - from) * k as f64 / 64.0))
            .collect()
    };
    let end = |v: f64, from: f64, to: f64| -> Vec<Point3> {
        (0..8)
            .map(|k| s.point(from + (to - from) * k as f64 / 8.0, v))
            .collect()
    };
    let mut round = side(a, c, d);
    round.extend(end(d, a, b));
    round.extend(side(b, d, c));
    round.extend(end(c, b, a));
    let trim = vec![round];
    let trimmed = [Face {
        name: "wall",
        surface: &s,
        trim: &trim,
    }];
    let whole = [Face::untrimmed("wall", &s)];
    let step = |f: &[Face<'_>]| nurbs_io::write_step_faces(f, "mm", "wall.step").unwrap();
    assert_eq!(step(&trimmed), step(&whole));
    let params = nurbs_io::writer::IgesWriteParams::default();
    let iges = |f: &[Face<'_>]| nurbs_io::writer::write_iges_faces(f, &[], &params).unwrap();
    let written = iges(&trimmed);
    assert_eq!(written, iges(&whole));
    assert!(
        !written.lines().any(|l| l.starts_with("     144")),
        "no 144"
    );
}
