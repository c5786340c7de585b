//! Surfaces that are not faces of a shell (a GEOMETRIC_SET's B-spline surfaces in their
//! implied-knot forms, a CURVE_BOUNDED_SURFACE, a RECTANGULAR_TRIMMED_SURFACE), and faces that
//! cannot be read named while the rest of the file is read.

use std::f64::consts::FRAC_PI_2;

use nurbs_core::{BSplineSurface, KnotVector, Point3};
use nurbs_io::read_step;

/// A Part 21 file around the DATA section `body`.
fn step(body: &str) -> String {
    format!("ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n{body}ENDSEC;\nEND-ISO-10303-21;\n")
}

/// The largest distance between `a` and `b` on a 9 × 9 grid over `b`'s domain (the same as
/// `a`'s).
fn distance(a: &BSplineSurface, b: &BSplineSurface) -> f64 {
    assert_eq!((a.domain_u(), a.domain_v()), (b.domain_u(), b.domain_v()));
    let ((u0, u1), (v0, v1)) = (b.domain_u(), b.domain_v());
    let mut d: f64 = 0.0;
    for i in 0..=8 {
        for j in 0..=8 {
            let (u, v) = (
                u0 + (u1 - u0) * i as f64 / 8.0,
                v0 + (v1 - v0) * j as f64 / 8.0,
            );
            d = d.max((a.point(u, v) - b.point(u, v)).norm());
        }
    }
    d
}

/// Control points #11–#18 of a 4 × 2 net, u the outer index.
const NET: &str = "#11 = CARTESIAN_POINT('',(0.,0.,0.));
#12 = CARTESIAN_POINT('',(0.,1.,0.));
#13 = CARTESIAN_POINT('',(1.,0.,1.));
#14 = CARTESIAN_POINT('',(1.,1.,1.));
#15 = CARTESIAN_POINT('',(2.,0.,-1.));
#16 = CARTESIAN_POINT('',(2.,1.,0.));
#17 = CARTESIAN_POINT('',(3.,0.,0.));
#18 = CARTESIAN_POINT('',(3.,1.,0.5));
";

/// The net of [`NET`] as points.
fn net() -> Vec<Point3> {
    [
        [0., 0., 0.],
        [0., 1., 0.],
        [1., 0., 1.],
        [1., 1., 1.],
        [2., 0., -1.],
        [2., 1., 0.],
        [3., 0., 0.],
        [3., 1., 0.5],
    ]
    .iter()
    .map(|c| Point3::new(c[0], c[1], c[2]))
    .collect()
}

/// The net of [`NET`] with degree (du, 1) and the u knots `ku`, v knots `kv`.
fn expected(du: usize, ku: &[f64], kv: &[f64], weights: Option<Vec<f64>>) -> BSplineSurface {
    BSplineSurface::new(
        KnotVector::new(du, ku.to_vec()).unwrap(),
        KnotVector::new(1, kv.to_vec()).unwrap(),
        net(),
        weights,
    )
    .unwrap()
}

/// A GEOMETRIC_SET of B-spline surfaces with their knots implied (ISO 10303-42 §4.3.4):
/// quasi-uniform (simple and rational in a complex instance), uniform and Bézier, a bare
/// surface with knots, a plane a face lies on (read once, as the face) and a curve (no
/// surface): each surface over its whole domain with the knots the standard implies.
#[test]
fn a_geometric_set_reads_its_surfaces_in_every_knot_form() {
    let body = format!(
        "{NET}#20 = QUASI_UNIFORM_SURFACE('quasi',2,1,((#11,#12),(#13,#14),(#15,#16),(#17,#18)),.UNSPECIFIED.,.F.,.F.,.U.);
#21 = (BOUNDED_SURFACE() B_SPLINE_SURFACE(2,1,((#11,#12),(#13,#14),(#15,#16),(#17,#18)),.UNSPECIFIED.,.F.,.F.,.U.) GEOMETRIC_REPRESENTATION_ITEM() QUASI_UNIFORM_SURFACE() RATIONAL_B_SPLINE_SURFACE(((1.,1.),(0.5,2.),(1.,1.),(1.,1.))) REPRESENTATION_ITEM('rational') SURFACE());
#22 = UNIFORM_SURFACE('uniform',2,1,((#11,#12),(#13,#14),(#15,#16),(#17,#18)),.UNSPECIFIED.,.F.,.F.,.U.);
#23 = BEZIER_SURFACE('bezier',3,1,((#11,#12),(#13,#14),(#15,#16),(#17,#18)),.UNSPECIFIED.,.F.,.F.,.U.);
#24 = B_SPLINE_SURFACE_WITH_KNOTS('bare',3,1,((#11,#12),(#13,#14),(#15,#16),(#17,#18)),.UNSPECIFIED.,.F.,.F.,.U.,(4,4),(2,2),(0.,2.),(0.,1.),.UNSPECIFIED.);
#30 = CARTESIAN_POINT('',(0.,0.,0.));
#31 = AXIS2_PLACEMENT_3D('',#30,$,$);
#32 = PLANE('',#31);
#33 = POLY_LOOP('',(#30,#34,#35));
#34 = CARTESIAN_POINT('',(1.,0.,0.));
#35 = CARTESIAN_POINT('',(0.,1.,0.));
#36 = FACE_OUTER_BOUND('',#33,.T.);
#37 = ADVANCED_FACE('face',(#36),#32,.T.);
#38 = LINE('',#30,#39);
#39 = VECTOR('',#40,1.);
#40 = DIRECTION('',(1.,0.,0.));
#50 = GEOMETRIC_SET('',(#20,#21,#22,#23,#24,#32,#38));
"
    );
    let f = read_step(&step(&body)).unwrap();
    assert!(f.warnings.is_empty(), "{:?}", f.warnings);
    let names: Vec<&str> = f.faces.iter().map(|x| x.name.as_str()).collect();
    assert_eq!(
        names,
        ["face", "quasi", "rational", "uniform", "bezier", "bare"]
    );
    let quasi = [0., 0., 0., 1., 2., 2., 2.];
    let wanted = [
        expected(2, &quasi, &[0., 0., 1., 1.], None),
        expected(
            2,
            &quasi,
            &[0., 0., 1., 1.],
            Some(vec![1., 1., 0.5, 2., 1., 1., 1., 1.]),
        ),
        expected(2, &[-2., -1., 0., 1., 2., 3., 4.], &[-1., 0., 1., 2.], None),
        expected(
            3,
            &[0., 0., 0., 0., 1., 1., 1., 1.],
            &[0., 0., 1., 1.],
            None,
        ),
        expected(
            3,
            &[0., 0., 0., 0., 2., 2., 2., 2.],
            &[0., 0., 1., 1.],
            None,
        ),
    ];
    for (face, want) in f.faces[1..].iter().zip(&wanted) {
        let d = distance(&face.surface, want);
        assert!(d < 1e-12, "{}: {d}", face.name);
    }
}

/// A CURVE_BOUNDED_SURFACE over a plane, bounded by a polyline: the plane over the box of its
/// boundary, kept as the trim loop; a RECTANGULAR_TRIMMED_SURFACE of a cylinder with its angle
/// in degrees (the file's plane-angle unit): a quarter turn.
#[test]
fn curve_bounded_and_rectangular_trimmed_surfaces_take_their_bounds() {
    let body = "#1 = CARTESIAN_POINT('',(0.,0.,0.));
#2 = DIRECTION('',(0.,0.,1.));
#3 = DIRECTION('',(1.,0.,0.));
#4 = AXIS2_PLACEMENT_3D('',#1,#2,#3);
#5 = PLANE('',#4);
#10 = CARTESIAN_POINT('',(4.,0.,0.));
#11 = CARTESIAN_POINT('',(4.,2.,0.));
#12 = CARTESIAN_POINT('',(0.,2.,0.));
#13 = POLYLINE('',(#1,#10,#11,#12,#1));
#14 = COMPOSITE_CURVE_SEGMENT(.CONTINUOUS.,.T.,#13);
#15 = OUTER_BOUNDARY_CURVE('',(#14),.F.);
#16 = CURVE_BOUNDED_SURFACE('bounded',#5,(#15),.F.);
#20 = CYLINDRICAL_SURFACE('',#4,3.);
#21 = RECTANGULAR_TRIMMED_SURFACE('quarter',#20,0.,90.,0.,5.,.T.,.T.);
#30 = ( CONVERSION_BASED_UNIT('DEGREE',#31) NAMED_UNIT(#32) PLANE_ANGLE_UNIT() );
#31 = PLANE_ANGLE_MEASURE_WITH_UNIT(PLANE_ANGLE_MEASURE(0.0174532925199433),#33);
#32 = DIMENSIONAL_EXPONENTS(0.,0.,0.,0.,0.,0.,0.);
#33 = ( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) );
#40 = GEOMETRIC_SET('',(#16,#21));
";
    let f = read_step(&step(body)).unwrap();
    assert!(f.warnings.is_empty(), "{:?}", f.warnings);
    assert_eq!(f.faces.len(), 2);
    let plane = &f.faces[0];
    assert_eq!(plane.trim.len(), 1);
    assert_eq!(plane.trim[0].len(), 4);
    let s = &plane.surface;
    let (lo, hi) = (s.point(s.domain_u().0, s.domain_v().0), {
        s.point(s.domain_u().1, s.domain_v().1)
    });
    assert!((lo - Point3::origin()).norm() < 1e-12);
    assert!((hi - Point3::new(4., 2., 0.)).norm() < 1e-12);
    let q = &f.faces[1].surface;
    let (u0, u1) = q.domain_u();
    assert!((u1 - u0 - FRAC_PI_2).abs() < 1e-12);
    let end = q.point(u1, q.domain_v().1);
    assert!((end - Point3::new(0., 3., 5.)).norm() < 1e-9, "{end:?}");
}

/// A face whose surface is malformed and a face on an unbounded plane with no bounds are
/// skipped, each named with why, and the good face is read; a file whose only face cannot be
/// read is that face's one-line error.
#[test]
fn a_face_that_cannot_be_read_is_named_and_the_rest_read() {
    let good = "#1 = CARTESIAN_POINT('',(0.,0.,0.));
#2 = CARTESIAN_POINT('',(1.,0.,0.));
#3 = CARTESIAN_POINT('',(0.,1.,0.));
#4 = AXIS2_PLACEMENT_3D('',#1,$,$);
#5 = PLANE('',#4);
#6 = POLY_LOOP('',(#1,#2,#3));
#7 = FACE_OUTER_BOUND('',#6,.T.);
#8 = ADVANCED_FACE('good',(#7),#5,.T.);
";
    let bad = "#90 = B_SPLINE_SURFACE_WITH_KNOTS('',1,1);
#91 = ADVANCED_FACE('short',(),#90,.T.);
#92 = ADVANCED_FACE('unbounded',(),#5,.T.);
";
    let f = read_step(&step(&format!("{good}{bad}"))).unwrap();
    assert_eq!(f.faces.len(), 1);
    assert_eq!(f.faces[0].name, "good");
    assert_eq!(f.warnings.len(), 2, "{:?}", f.warnings);
    assert!(f.warnings[0].contains("#91") && f.warnings[0].contains("#90"));
    assert!(f.warnings[0].contains("expected 13"), "{}", f.warnings[0]);
    assert!(f.warnings[1].contains("#92") && f.warnings[1].contains("unbounded"));
    for w in &f.warnings {
        assert!(!w.contains('\n'));
    }
    let e = read_step(&step(bad)).unwrap_err().to_string();
    assert!(e.contains("#90") && !e.contains('\n'), "{e}");
}

/// A CURVE_BOUNDED_SURFACE whose boundary is a pcurve alone (a curve in the surface's
/// parameters, not read): a B-spline surface comes in over its whole domain, untrimmed, and
/// that is said; a plane, which has no such box, is skipped and named.
#[test]
fn a_boundary_that_is_not_read_leaves_the_surface_whole_or_skipped() {
    let body = format!(
        "{NET}#24 = B_SPLINE_SURFACE_WITH_KNOTS('bare',3,1,((#11,#12),(#13,#14),(#15,#16),(#17,#18)),.UNSPECIFIED.,.F.,.F.,.U.,(4,4),(2,2),(0.,2.),(0.,1.),.UNSPECIFIED.);
#30 = CARTESIAN_POINT('',(0.,0.));
#31 = DIRECTION('',(1.,0.));
#32 = VECTOR('',#31,1.);
#33 = LINE('',#30,#32);
#34 = DEFINITIONAL_REPRESENTATION('',(#33),#35);
#35 = ( GEOMETRIC_REPRESENTATION_CONTEXT(2) PARAMETRIC_REPRESENTATION_CONTEXT() REPRESENTATION_CONTEXT('','') );
#36 = PCURVE('',#24,#34);
#37 = COMPOSITE_CURVE_SEGMENT(.CONTINUOUS.,.T.,#36);
#38 = OUTER_BOUNDARY_CURVE('',(#37),.F.);
#39 = CURVE_BOUNDED_SURFACE('spline',#24,(#38),.F.);
#40 = CARTESIAN_POINT('',(0.,0.,0.));
#41 = AXIS2_PLACEMENT_3D('',#40,$,$);
#42 = PLANE('',#41);
#43 = PCURVE('',#42,#34);
#44 = COMPOSITE_CURVE_SEGMENT(.CONTINUOUS.,.T.,#43);
#45 = OUTER_BOUNDARY_CURVE('',(#44),.F.);
#46 = CURVE_BOUNDED_SURFACE('plane',#42,(#45),.F.);
#50 = GEOMETRIC_SET('',(#39,#46));
"
    );
    let f = read_step(&step(&body)).unwrap();
    assert_eq!(f.faces.len(), 1);
    let s = &f.faces[0].surface;
    assert_eq!((s.domain_u(), s.domain_v()), ((0.0, 2.0), (0.0, 1.0)));
    assert!(f.faces[0].trim.is_empty());
    assert_eq!(f.warnings.len(), 2, "{:?}", f.warnings);
    assert!(f.warnings[0].contains("#39") && f.warnings[0].contains("untrimmed"));
    assert!(f.warnings[1].contains("#46") && f.warnings[1].contains("unbounded"));
}
