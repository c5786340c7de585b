//! The STEP reader on bad input: one error naming the line or the instance, never a panic.

use nurbs_io::read_step;

#[test]
fn bad_step_files_are_one_line_errors() {
    let head = "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n";
    for (body, expect) in [
        ("", "no ENDSEC"),
        ("#1 = CARTESIAN_POINT('',(0.,0.,0.));\n", "no ENDSEC"),
        (
            "#1 = CARTESIAN_POINT('',(0.,0.,0.)\nENDSEC;\n",
            "expected ',' or ')'",
        ),
        (
            "#1 = CARTESIAN_POINT('unterminated,(0.));\n",
            "string does not end",
        ),
        (
            "#1 = CARTESIAN_POINT('',(1.e999));\nENDSEC;\n",
            "malformed number",
        ),
        ("#1 = X('');\n#1 = Y('');\nENDSEC;\n", "defined twice"),
        (
            "#1 = ADVANCED_FACE('',(#2),#3,.T.);\nENDSEC;\n",
            "not defined",
        ),
        (
            "#3 = PLANE('',#9);\n#1 = ADVANCED_FACE('',(),#3,.T.);\nENDSEC;\n",
            "not defined",
        ),
        (
            "#3 = B_SPLINE_SURFACE_WITH_KNOTS('',1,1);\n#1 = ADVANCED_FACE('',(),#3,.T.);\nENDSEC;\n",
            "expected 13",
        ),
        ("#1 = ADVANCED_FACE();\nENDSEC;\n", "expected"),
        (
            "#4 = CARTESIAN_POINT('',(0.,0.,0.));\n#3 = B_SPLINE_SURFACE_WITH_KNOTS('',1,1,((#4,#4),(#4,#4)),.U.,.F.,.F.,.U.,(1.E300,2),(2,2),(0.,1.),(0.,1.),.U.);\n#1 = ADVANCED_FACE('',(),#3,.T.);\nENDSEC;\n",
            "#3 B_SPLINE_SURFACE_WITH_KNOTS: knot multiplicity",
        ),
        (
            "#4 = CARTESIAN_POINT('',(0.,0.,0.));\n#3 = QUASI_UNIFORM_SURFACE('',1000,1,((#4,#4),(#4,#4)),.U.,.F.,.F.,.U.);\n#1 = ADVANCED_FACE('',(),#3,.T.);\nENDSEC;\n",
            "degree 1000",
        ),
    ] {
        let text = format!("{head}{body}");
        let e = read_step(&text).expect_err(body).to_string();
        assert!(e.contains(expect), "{body:?}: {e}");
        assert!(!e.contains('\n'), "{e}");
    }
    assert!(read_step("no data here").is_err());
}

/// A face of a cylinder of radius 2 about z, bounded by two lines and two quarter arcs: the
/// surface is the quarter cylinder, every point at the radius, heights 0 … 3.
#[test]
fn a_cylinder_face_is_its_quarter() {
    let text = "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;
#1 = CARTESIAN_POINT('',(0.,0.,0.));
#2 = DIRECTION('',(0.,0.,1.));
#3 = DIRECTION('',(1.,0.,0.));
#4 = AXIS2_PLACEMENT_3D('',#1,#2,#3);
#5 = CYLINDRICAL_SURFACE('',#4,2.);
#10 = CARTESIAN_POINT('',(2.,0.,0.));
#11 = CARTESIAN_POINT('',(0.,2.,0.));
#12 = CARTESIAN_POINT('',(0.,2.,3.));
#13 = CARTESIAN_POINT('',(2.,0.,3.));
#20 = VERTEX_POINT('',#10);
#21 = VERTEX_POINT('',#11);
#22 = VERTEX_POINT('',#12);
#23 = VERTEX_POINT('',#13);
#30 = CIRCLE('',#4,2.);
#31 = CARTESIAN_POINT('',(0.,0.,3.));
#32 = AXIS2_PLACEMENT_3D('',#31,#2,#3);
#33 = CIRCLE('',#32,2.);
#34 = LINE('',#10,#35);
#35 = VECTOR('',#2,1.);
#40 = EDGE_CURVE('',#20,#21,#30,.T.);
#41 = EDGE_CURVE('',#21,#22,#34,.T.);
#42 = EDGE_CURVE('',#23,#22,#33,.T.);
#43 = EDGE_CURVE('',#20,#23,#34,.T.);
#50 = ORIENTED_EDGE('',*,*,#40,.T.);
#51 = ORIENTED_EDGE('',*,*,#41,.T.);
#52 = ORIENTED_EDGE('',*,*,#42,.F.);
#53 = ORIENTED_EDGE('',*,*,#43,.F.);
#60 = EDGE_LOOP('',(#50,#51,#52,#53));
#61 = FACE_OUTER_BOUND('',#60,.T.);
#70 = ADVANCED_FACE('quarter',(#61),#5,.T.);
#80 = ( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) );
ENDSEC;
END-ISO-10303-21;
";
    let f = read_step(text).unwrap();
    assert_eq!(f.units, "mm");
    assert_eq!(f.faces.len(), 1);
    let s = &f.faces[0].surface;
    assert_eq!(f.faces[0].name, "quarter");
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    let (mut zmin, mut zmax, mut amin, mut amax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for a in 0..=10 {
        for b in 0..=10 {
            let p = s.point(
                u0 + (u1 - u0) * a as f64 / 10.0,
                v0 + (v1 - v0) * b as f64 / 10.0,
            );
            assert!((p.x.hypot(p.y) - 2.0).abs() < 1e-12);
            zmin = zmin.min(p.z);
            zmax = zmax.max(p.z);
            let ang = p.y.atan2(p.x);
            amin = amin.min(ang);
            amax = amax.max(ang);
        }
    }
    assert!(zmin.abs() < 1e-12 && (zmax - 3.0).abs() < 1e-12);
    assert!(amin.abs() < 1e-12 && (amax - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
}

/// What `write_step` writes reads back as the same surfaces (rational and polynomial, a pole
/// included), with the unit and the names.
#[test]
fn written_step_reads_back_the_same_surfaces() {
    let surfaces = [
        ("cylinder", nurbs_core::shapes::cylinder(5.0, 30.0).unwrap()),
        ("octant", nurbs_core::shapes::sphere_octant(4.0).unwrap()),
        (
            "paraboloid",
            nurbs_core::shapes::paraboloid_bicubic(&[0.3, 0.6]).unwrap(),
        ),
    ];
    let named: Vec<(&str, &nurbs_core::BSplineSurface)> =
        surfaces.iter().map(|(n, s)| (*n, s)).collect();
    let text = nurbs_io::write_step(&named, "in", "three.step").unwrap();
    let back = read_step(&text).unwrap();
    assert_eq!(back.units, "in");
    assert_eq!(back.faces.len(), 3);
    for ((name, s), f) in surfaces.iter().zip(&back.faces) {
        assert_eq!(&f.name, name);
        let (u0, u1) = s.domain_u();
        let (v0, v1) = s.domain_v();
        for a in 0..=8 {
            for b in 0..=8 {
                let (u, v) = (
                    u0 + (u1 - u0) * a as f64 / 8.0,
                    v0 + (v1 - v0) * b as f64 / 8.0,
                );
                let d = (f.surface.point(u, v) - s.point(u, v)).norm();
                assert!(d < 1e-12, "{name} at ({u}, {v}): {d}");
            }
        }
    }
}

/// Every unit a model can be in is written as the LENGTH_UNIT it is (\[ISO41\]: the metre with its
/// SI prefix, or a CONVERSION_BASED_UNIT defined in millimetres) and read back as the same unit;
/// a unit the writer does not know is refused rather than written as millimetres.
#[test]
fn units_are_written_and_read_back() {
    let s = nurbs_core::shapes::cylinder(5.0, 30.0).unwrap();
    for unit in ["mm", "cm", "m", "km", "um", "in", "ft", "12.5 mm"] {
        let text = nurbs_io::write_step(&[("c", &s)], unit, "u.step").unwrap();
        let back = read_step(&text).unwrap();
        assert_eq!(back.units, unit, "{text}");
        assert_eq!(
            nurbs_io::units::mm_per_unit(&back.units),
            nurbs_io::units::mm_per_unit(unit)
        );
    }
    // a conversion-based unit with a name of its own is read by its size: 'UNKNOWN' as 10 mm
    let text = nurbs_io::write_step(&[("c", &s)], "12.5 mm", "u.step")
        .unwrap()
        .replace("LENGTH_MEASURE(12.5)", "LENGTH_MEASURE(10.)")
        .replace("'12.5 MM'", "'UNKNOWN'");
    assert_eq!(read_step(&text).unwrap().units, "cm");
    let err = nurbs_io::write_step(&[("c", &s)], "parsec", "u.step").unwrap_err();
    assert!(err.to_string().contains("parsec"), "{err}");
}

/// SURFACE_OF_LINEAR_EXTRUSION of a rational quarter circle (radius 2) along a vector of
/// magnitude 1.5, bounded by the circle, its copy 3 higher and two lines: the face is the
/// exact quarter cylinder of height 3 (v from 0 to 2 in units of the vector).
#[test]
fn a_linear_extrusion_face_is_its_exact_cylinder() {
    let arc = |id: u64, a: u64, b: u64, c: u64| {
        format!(
            "#{id} = ( BOUNDED_CURVE() B_SPLINE_CURVE(2,(#{a},#{b},#{c}),.CIRCULAR_ARC.,.F.,.F.) B_SPLINE_CURVE_WITH_KNOTS((3,3),(0.,1.),.UNSPECIFIED.) CURVE() GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_CURVE((1.,0.7071067811865476,1.)) REPRESENTATION_ITEM('') );"
        )
    };
    let text = format!(
        "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;
#1 = CARTESIAN_POINT('',(2.,0.,0.));
#2 = CARTESIAN_POINT('',(2.,2.,0.));
#3 = CARTESIAN_POINT('',(0.,2.,0.));
#4 = CARTESIAN_POINT('',(2.,0.,3.));
#5 = CARTESIAN_POINT('',(2.,2.,3.));
#6 = CARTESIAN_POINT('',(0.,2.,3.));
{}
{}
#9 = DIRECTION('',(0.,0.,1.));
#10 = VECTOR('',#9,1.5);
#11 = SURFACE_OF_LINEAR_EXTRUSION('',#7,#10);
#20 = VERTEX_POINT('',#1);
#21 = VERTEX_POINT('',#3);
#22 = VERTEX_POINT('',#6);
#23 = VERTEX_POINT('',#4);
#30 = LINE('',#1,#10);
#40 = EDGE_CURVE('',#20,#21,#7,.T.);
#41 = EDGE_CURVE('',#21,#22,#30,.T.);
#42 = EDGE_CURVE('',#23,#22,#8,.T.);
#43 = EDGE_CURVE('',#20,#23,#30,.T.);
#50 = ORIENTED_EDGE('',*,*,#40,.T.);
#51 = ORIENTED_EDGE('',*,*,#41,.T.);
#52 = ORIENTED_EDGE('',*,*,#42,.F.);
#53 = ORIENTED_EDGE('',*,*,#43,.F.);
#60 = EDGE_LOOP('',(#50,#51,#52,#53));
#61 = FACE_OUTER_BOUND('',#60,.T.);
#70 = ADVANCED_FACE('swept',(#61),#11,.T.);
ENDSEC;
END-ISO-10303-21;
",
        arc(7, 1, 2, 3),
        arc(8, 4, 5, 6)
    );
    let f = read_step(&text).unwrap();
    assert_eq!(f.faces.len(), 1, "{:?}", f.skipped);
    assert_eq!(f.faces[0].kind, "SURFACE_OF_LINEAR_EXTRUSION");
    let s = &f.faces[0].surface;
    assert!(s.is_rational());
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    assert!(u0.abs() < 1e-9 && (u1 - 1.0).abs() < 1e-9, "{u0} {u1}");
    assert!(v0.abs() < 1e-9 && (v1 - 2.0).abs() < 1e-9, "{v0} {v1}");
    for a in 0..=10 {
        for b in 0..=10 {
            let p = s.point(
                u0 + (u1 - u0) * a as f64 / 10.0,
                v0 + (v1 - v0) * b as f64 / 10.0,
            );
            assert!((p.x.hypot(p.y) - 2.0).abs() < 1e-12, "{p:?}");
            assert!((p.z - 3.0 * b as f64 / 10.0).abs() < 1e-9, "{p:?}");
        }
    }
}
