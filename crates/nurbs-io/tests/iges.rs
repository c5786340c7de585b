//! Round trips, the impeller from a commercial CAD system, structure checks and bad input.

use nurbs_core::testing::{random_curve, random_surface};
use nurbs_io::{IgesError, IgesWriteParams, check_structure, read_iges, write_iges};
use proptest::prelude::*;

mod common;
use common::raw_iges;

fn impeller() -> Vec<u8> {
    std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/third_party/impeller.igs"
    ))
    .expect("the impeller is in the repository")
}

fn sample_file() -> String {
    let s = random_surface(5, 2..=3, 6, true);
    let c = random_curve(6, 3..=3, 7, false);
    write_iges(
        &[("panel", &s)],
        &[("edge", &c)],
        &IgesWriteParams::default(),
    )
    .unwrap()
}

#[test]
fn round_trip_is_bit_identical() {
    for seed in 0..24 {
        let rational = seed % 2 == 1;
        let s = random_surface(seed, 1..=5, 9, rational);
        let c = random_curve(seed + 100, 1..=5, 11, rational);
        let text = write_iges(
            &[("surface_with_a_long_name", &s)],
            &[("c", &c)],
            &IgesWriteParams::default(),
        )
        .unwrap();
        let report = check_structure(text.as_bytes()).unwrap();
        assert_eq!(report.entities, 2);
        let back = read_iges(text.as_bytes()).unwrap();
        assert_eq!(back.surfaces.len(), 1);
        assert_eq!(back.surfaces[0].surface, s, "seed {seed}");
        assert_eq!(back.surfaces[0].name, "surface_");
        assert_eq!(back.curves[0].curve, c, "seed {seed}");
        assert_eq!(back.units, "MM");
        // CRLF line endings read the same
        let crlf = text.replace('\n', "\r\n");
        assert_eq!(read_iges(crlf.as_bytes()).unwrap(), back);
    }
}

#[test]
fn written_files_have_strict_structure() {
    let text = sample_file();
    for (k, line) in text.lines().enumerate() {
        assert_eq!(line.len(), 80, "line {}", k + 1);
        assert!(matches!(
            line.as_bytes()[72],
            b'S' | b'G' | b'D' | b'P' | b'T'
        ));
    }
    let r = check_structure(text.as_bytes()).unwrap();
    assert_eq!(r.counts[0], 1);
    assert_eq!(r.counts[2], 4);
    // the terminate record counts every section
    let t = text.lines().last().unwrap();
    assert_eq!(&t[..8], "S      1");
    assert_eq!(&t[16..24], "D      4");
    // duplicate labels are told apart by subscripts
    let s = random_surface(1, 3..=3, 5, false);
    let text = write_iges(
        &[("wing", &s), ("wing", &s)],
        &[],
        &IgesWriteParams::default(),
    )
    .unwrap();
    let names: Vec<String> = read_iges(text.as_bytes())
        .unwrap()
        .surfaces
        .into_iter()
        .map(|s| s.name)
        .collect();
    assert_eq!(names, vec!["wing", "wing_1"]);
}

#[test]
fn transformation_matrices_are_applied() {
    let s = random_surface(9, 2..=2, 4, false);
    let text = write_iges(&[("s", &s)], &[], &IgesWriteParams::default()).unwrap();
    // prepend a 124 entity (rotation by 90° about z, then translation (10, 0, 5)) and point the
    // surface's directory entry at it
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let d_start = lines.iter().position(|l| l.as_bytes()[72] == b'D').unwrap();
    let p_start = lines.iter().position(|l| l.as_bytes()[72] == b'P').unwrap();
    let renumber = |l: &str, letter: char, seq: usize| format!("{:<72}{letter}{seq:>7}", &l[..72]);
    let mut d: Vec<String> = lines[d_start..p_start].to_vec();
    let mut p: Vec<String> = lines[p_start..lines.len() - 1].to_vec();
    // shift the surface: DE 1 → 3, its P lines +1
    d[0] = format!("{:>8}{:>8}{}{:>8}{}", 128, 2, &d[0][16..48], 1, &d[0][56..]);
    for (k, l) in d.iter_mut().enumerate() {
        *l = renumber(l, 'D', k + 3);
    }
    for (k, l) in p.iter_mut().enumerate() {
        *l = format!("{}{:>8}P{:>7}", &l[..64], 3, k + 2);
    }
    let m_d1 = format!(
        "{:<72}D{:>7}",
        format!(
            "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}",
            124, 1, 0, 0, 0, 0, 0, 0, "00000000"
        ),
        1
    );
    let m_d2 = format!(
        "{:<72}D{:>7}",
        format!("{:>8}{:>8}{:>8}{:>8}{:>8}", 124, 0, 0, 1, 0),
        2
    );
    let m_p = format!(
        "{:<64}{:>8}P{:>7}",
        "124,0.,-1.,0.,10.,1.,0.,0.,0.,0.,0.,1.,5.;", 1, 1
    );
    let head: Vec<String> = lines[..d_start].to_vec();
    let t = format!(
        "{:<72}T{:>7}",
        format!(
            "S{:>7}G{:>7}D{:>7}P{:>7}",
            1,
            d_start - 1,
            d.len() + 2,
            p.len() + 1
        ),
        1
    );
    lines = head
        .into_iter()
        .chain([m_d1, m_d2])
        .chain(d)
        .chain([m_p])
        .chain(p)
        .chain([t])
        .collect();
    let text = lines.join("\n") + "\n";
    check_structure(text.as_bytes()).unwrap();
    let back = read_iges(text.as_bytes()).unwrap();
    let moved = &back.surfaces[0].surface;
    for (a, b) in s.control_points().iter().zip(moved.control_points()) {
        assert_eq!(*b, nurbs_core::Point3::new(-a.y + 10.0, a.x, a.z + 5.0));
    }
}

#[test]
fn impeller_from_a_commercial_system() {
    let bytes = impeller();
    let f = read_iges(&bytes).unwrap();
    // 247 B-spline surfaces (128) and 30 surfaces of revolution (120), each under a 144
    assert_eq!(f.surfaces.len(), 277);
    assert_eq!(f.trimmed_entities, 277);
    assert_eq!(f.surfaces.iter().filter(|s| s.trimmed).count(), 277);
    assert_eq!(
        f.surfaces
            .iter()
            .filter(|s| s.surface.is_rational())
            .count(),
        212 + 30
    );
    assert_eq!(f.curves.len(), 2342);
    assert_eq!(f.units, "MM");
    // hand-read from the file: directory entry 3, parameter lines 2–19
    let s = &f.surfaces[0];
    assert_eq!(s.de, 3);
    // the face uses u in [0.4399, 0.5593] of it (its 142's parameter curve): the entity's own
    // surface is kept beside the cut one
    assert_eq!(s.surface.domain_u(), (0.439938532, 0.559345007));
    let g = s.underlying.as_ref().expect("cut to its face");
    assert_eq!(
        (g.degree_u(), g.degree_v(), g.num_u(), g.num_v()),
        (3, 3, 4, 4)
    );
    assert_eq!(g.knots_u().knots(), &[0., 0., 0., 0., 1., 1., 1., 1.]);
    assert_eq!(g.weight(0, 0), 1.0);
    assert_eq!(g.weight(1, 0), 0.995697775241349);
    assert_eq!(g.weight(0, 1), 0.995162717606626);
    assert_eq!(
        g.control_point(0, 0),
        nurbs_core::Point3::new(-26.902905334, -16.51153913, -8.876323512)
    );
    assert_eq!(
        g.control_point(1, 0),
        nurbs_core::Point3::new(-25.851820351, -15.866440371, -21.167794775)
    );
    assert_eq!(s.param_range, [0.0, 1.0, 0.0, 1.0]);
    // the families the data notes list: bicubic Bézier patches and (3, 2) fillet strips
    let bezier = f
        .surfaces
        .iter()
        .filter(|s| {
            (
                s.surface.num_u(),
                s.surface.num_v(),
                s.surface.degree_u(),
                s.surface.degree_v(),
            ) == (4, 4, 3, 3)
        })
        .count();
    assert_eq!(bezier, 91);
    let strips = f.surfaces.iter().filter(|s| {
        let g = &s.surface;
        let (p, q) = (g.degree_u(), g.degree_v());
        ((p, q) == (3, 2) && g.num_v() == 3) || ((p, q) == (2, 3) && g.num_u() == 3)
    });
    // the data notes say 10 strips per blade; the file itself has 11 per blade, and only that
    // adds up: 247 = 91 Bézier + 2 bilinear + 11 blades × (2 bicubic + 1 quintic + 11 strips)
    assert_eq!(strips.count(), 121);
    let count = |p: usize, q: usize| {
        f.surfaces
            .iter()
            .filter(|s| (s.surface.degree_u(), s.surface.degree_v()) == (p, q))
            .count()
    };
    assert_eq!(count(1, 1), 2);
    assert_eq!(count(5, 5), 11);
    assert_eq!(
        f.surfaces
            .iter()
            .filter(|s| (s.surface.num_u(), s.surface.num_v()) == (17, 13))
            .count(),
        22
    );
    // every surface evaluates to finite points
    for s in &f.surfaces {
        let (u0, u1) = s.surface.domain_u();
        assert!(
            s.surface
                .point(0.5 * (u0 + u1), s.surface.domain_v().0)
                .coords
                .iter()
                .all(|c| c.is_finite())
        );
    }
}

fn expect_line_error(text: &str, what: &str) -> IgesError {
    let err = read_iges(text.as_bytes()).unwrap_err();
    assert!(
        err.to_string().contains(what),
        "expected {what:?} in: {err}"
    );
    err
}

#[test]
fn bad_input_names_the_line() {
    let text = sample_file();
    let lines: Vec<&str> = text.lines().collect();
    // truncated: the Terminate record is missing
    expect_line_error(&(lines[..lines.len() - 3].join("\n") + "\n"), "Terminate");
    // wrong column layout: a record cut short
    let mut cut: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
    cut[2] = cut[2][..60].to_string();
    let err = expect_line_error(&cut.join("\n"), "line 3:");
    assert!(matches!(err, IgesError::Layout { line: 3, .. }));
    // wrong sequence number
    let mut seq: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
    seq[1] = format!("{}{:>7}", &seq[1][..73], 9);
    expect_line_error(&seq.join("\n"), "sequence number");
    // a parameter pointer out of range
    let d = lines.iter().position(|l| l.as_bytes()[72] == b'D').unwrap();
    let mut ptr: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
    ptr[d] = format!("{:>8}{:>8}{}", 128, 999, &ptr[d][16..]);
    expect_line_error(&ptr.join("\n"), "out of range");
    // a count that does not match the data: K1 one larger
    let p = lines.iter().position(|l| l.as_bytes()[72] == b'P').unwrap();
    let mut count: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
    let first = count[p].clone();
    let k1: usize = first.split(',').nth(1).unwrap().parse().unwrap();
    count[p] = first.replacen(&format!("128,{k1},"), &format!("128,{},", k1 + 1), 1);
    let err = read_iges(count.join("\n").as_bytes()).unwrap_err();
    assert!(
        matches!(
            err,
            IgesError::Entity { .. } | IgesError::Geometry { .. } | IgesError::Parameter { .. }
        ),
        "{err}"
    );
    // NaN among the numbers
    let mut nan: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
    nan[p + 1] = nan[p + 1].replacen("1.", "NaN", 1);
    let err = read_iges(nan.join("\n").as_bytes()).unwrap_err();
    assert!(err.to_string().contains("line"), "{err}");
    // non-finite values cannot be written
    let mut s = random_surface(2, 2..=2, 4, false);
    s.control_points_mut()[0].x = f64::INFINITY;
    assert!(write_iges(&[("bad", &s)], &[], &IgesWriteParams::default()).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, .. ProptestConfig::default() })]

    /// Random byte edits never make the reader panic (the cargo-fuzz target does the same at length).
    #[test]
    fn mutated_files_never_panic(edits in proptest::collection::vec((0usize..4000, any::<u8>()), 1..6), cut in 0usize..5000) {
        let mut bytes = sample_file().into_bytes();
        for (at, b) in edits {
            let n = bytes.len();
            bytes[at % n] = b;
        }
        bytes.truncate(cut.max(1).min(bytes.len()));
        let _ = read_iges(&bytes);
        let _ = check_structure(&bytes);
    }
}

/// A 126 parameter list (without the type) of a polynomial or rational curve.
fn curve_126(c: &nurbs_core::BSplineCurve) -> String {
    let n = c.control_points().len();
    let mut v = vec![
        (n - 1).to_string(),
        c.degree().to_string(),
        "0".into(),
        "0".into(),
        if c.is_rational() { "0" } else { "1" }.into(),
        "0".into(),
    ];
    v.extend(c.knots().knots().iter().map(|t| format!("{t:?}")));
    let w = c.weights().map_or_else(|| vec![1.0; n], <[f64]>::to_vec);
    v.extend(w.iter().map(|x| format!("{x:?}")));
    for p in c.control_points() {
        v.extend([p.x, p.y, p.z].iter().map(|x| format!("{x:?}")));
    }
    let (a, b) = c.knots().domain();
    v.extend([
        format!("{a:?}"),
        format!("{b:?}"),
        "0.".into(),
        "0.".into(),
        "1.".into(),
    ]);
    v.join(",")
}

/// Entity 122 (tabulated cylinder) read as the exact extrusion of its directrix: a 126
/// rational quarter circle and a 110 line, each moved to the terminate point of its generatrix.
#[test]
fn tabulated_cylinders_are_exact_extrusions() {
    use nurbs_core::{Point3, Vector3, shapes::arc};
    let quarter = arc(Point3::origin(), Vector3::x(), Vector3::y(), 2.0, 0.0, 1.5).unwrap();
    let text = raw_iges(&[
        (126, 0, curve_126(&quarter)),
        (122, 0, "1,2.0,0.0,5.0".into()),
        (110, 0, "0.,0.,0.,4.,3.,0.".into()),
        (122, 0, "5,1.,1.,2.".into()),
    ]);
    let file = read_iges(text.as_bytes()).unwrap();
    assert_eq!(file.surfaces.len(), 2, "{:?}", file.refused);
    let cyl = &file.surfaces[0].surface;
    let (u0, u1) = cyl.domain_u();
    for a in 0..=10 {
        for b in 0..=4 {
            let (u, v) = (u0 + (u1 - u0) * a as f64 / 10.0, b as f64 / 4.0);
            let p = cyl.point(u, v);
            assert!((p.x.hypot(p.y) - 2.0).abs() < 1e-12 && (p.z - 5.0 * v).abs() < 1e-12);
        }
    }
    // the line from (0,0,0) to (4,3,0) moved along (1,1,2): a parallelogram
    let plane = &file.surfaces[1].surface;
    let p = plane.point(plane.domain_u().1, 1.0);
    assert!((p - Point3::new(5.0, 4.0, 2.0)).norm() < 1e-12, "{p:?}");
}

/// Entity 118 (ruled surface): form 1 between two coaxial arcs is the cone frustum, DIRFLG 1
/// joins the first end of one curve to the last of the other, and a form-0 ruling between
/// curves of unlike speed (points of equal arc length are not those of equal parameter) is
/// named in `refused` while the rest of the file is read.
#[test]
fn ruled_surfaces_are_exact_or_named() {
    use nurbs_core::{BSplineCurve, KnotVector, Point3};
    // arcs about (0,0) from angle 0 to 90° at z = 0 (radius 1) and z = 4 (radius 3)
    let slow = BSplineCurve::new(
        KnotVector::new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).unwrap(),
        vec![
            Point3::new(0.0, 2.0, 0.0),
            Point3::new(0.1, 2.0, 0.0),
            Point3::new(6.0, 2.0, 0.0),
        ],
        None,
    )
    .unwrap();
    let text = raw_iges(&[
        (100, 0, "0.,0.,0.,1.,0.,0.,1.".into()),
        (100, 0, "4.,0.,0.,3.,0.,0.,3.".into()),
        (118, 1, "1,3,0,1".into()),
        (118, 1, "1,3,1,1".into()),
        (110, 0, "0.,0.,0.,6.,0.,0.".into()),
        (126, 0, curve_126(&slow)),
        (118, 0, "9,11,0,1".into()),
        (118, 0, "1,3,0,1".into()),
    ]);
    let file = read_iges(text.as_bytes()).unwrap();
    // three read: the form-1 pair, the reversed pair, and the form-0 arcs of one sweep
    assert_eq!(file.surfaces.len(), 3, "{:?}", file.refused);
    assert_eq!(file.refused.len(), 1);
    assert!(
        file.refused[0].contains("arc length"),
        "{}",
        file.refused[0]
    );
    for s in [&file.surfaces[0].surface, &file.surfaces[2].surface] {
        for a in 0..=10 {
            for b in 0..=4 {
                let (u, v) = (a as f64 / 10.0, b as f64 / 4.0);
                let p = s.point(u, v);
                assert!((p.x.hypot(p.y) - (1.0 + 2.0 * v)).abs() < 1e-12, "{u} {v}");
                assert!((p.z - 4.0 * v).abs() < 1e-12);
            }
        }
    }
    // reversed: u = 0 on the first arc (angle 0) meets the second arc's end (angle 90°)
    let r = &file.surfaces[1].surface;
    assert!((r.point(0.0, 1.0) - Point3::new(0.0, 3.0, 4.0)).norm() < 1e-12);
    assert!((r.point(0.0, 0.0) - Point3::new(1.0, 0.0, 0.0)).norm() < 1e-12);
}

/// `text` (an IGES file of one 128 at DE 1, as `write_iges` writes it) with an offset surface
/// (140) of that surface by `d`, offset indicator `(nx, ny, nz)`, appended.
fn with_offset(text: &str, d: f64, indicator: [f64; 3]) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let count = |letter: char| {
        lines
            .iter()
            .filter(|l| l.as_bytes().get(72) == Some(&(letter as u8)))
            .count()
    };
    let (nd, np) = (count('D'), count('P'));
    let de = nd + 1;
    let p_seq = np + 1;
    let params = format!(
        "140,{:?},{:?},{:?},{:?},1;",
        indicator[0], indicator[1], indicator[2], d
    );
    let p_line = format!("{params:<64}{de:>8}P{p_seq:>7}");
    let d1 = format!(
        "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}D{:>7}",
        140, p_seq, 0, 0, 0, 0, 0, 0, "00000000", de
    );
    let d2 = format!(
        "{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}D{:>7}",
        140,
        0,
        0,
        1,
        0,
        "",
        "",
        "OFFSET",
        0,
        de + 1
    );
    let mut out = Vec::new();
    for l in &lines {
        match l.as_bytes().get(72) {
            Some(b'P') if out.iter().all(|x: &String| x != &d2) => {
                out.push(d1.clone());
                out.push(d2.clone());
                out.push(l.to_string());
            }
            Some(b'T') => {
                out.push(p_line.clone());
                let t = format!(
                    "S{:>7}G{:>7}D{:>7}P{:>7}",
                    count('S'),
                    count('G'),
                    nd + 2,
                    np + 1
                );
                out.push(format!("{t:<72}T{:>7}", 1));
            }
            _ => out.push(l.to_string()),
        }
    }
    out.join("\n") + "\n"
}

/// Offset surfaces (140) are read as polynomial B-splines within 1e-6 of the base's size of the
/// exact offset: a rational quarter cylinder of radius 10 offset outward by 2.5 is a cylinder of
/// radius 12.5 (closed form), inward by 2.5 one of radius 7.5 (the indicator picks the side).
#[test]
fn an_offset_surface_is_approximated_within_its_tolerance() {
    let base = nurbs_core::shapes::cylinder(10.0, 20.0).unwrap();
    let text = write_iges(&[("cyl", &base)], &[], &IgesWriteParams::default()).unwrap();
    let (u, v) = (base.domain_u(), base.domain_v());
    let mid = base.derivatives(0.5 * (u.0 + u.1), 0.5 * (v.0 + v.1));
    let n = mid.normal().unwrap();
    let outward = if (mid.point.coords.xy()).dot(&n.xy()) > 0.0 {
        1.0
    } else {
        -1.0
    };
    for (sign, radius) in [(1.0, 12.5), (-1.0, 7.5)] {
        let ind = n * (outward * sign);
        let file = read_iges(with_offset(&text, 2.5, [ind.x, ind.y, ind.z]).as_bytes()).unwrap();
        assert!(file.refused.is_empty(), "{:?}", file.refused);
        let off = file
            .surfaces
            .iter()
            .find(|s| s.surface.weights().is_none() && s.name.contains("OFFSET"))
            .unwrap_or_else(|| {
                panic!(
                    "no offset surface in {:?}",
                    file.surfaces.iter().map(|s| &s.name).collect::<Vec<_>>()
                )
            });
        let s = &off.surface;
        let tol = 1e-6 * base.size();
        let ((a, b), (c, d)) = (s.domain_u(), s.domain_v());
        for i in 0..=20 {
            for j in 0..=20 {
                let p = s.point(
                    a + (b - a) * f64::from(i) / 20.0,
                    c + (d - c) * f64::from(j) / 20.0,
                );
                let r = p.x.hypot(p.y);
                assert!((r - radius).abs() <= tol, "radius {r} against {radius}");
                assert!(p.z >= -tol && p.z <= 20.0 + tol);
            }
        }
    }
}
