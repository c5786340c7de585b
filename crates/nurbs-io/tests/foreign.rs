//! Files written by other CAD systems (`fixtures/foreign/`, from the Open CASCADE test data):
//! each imports, its closed faces whole, checked against the closed-form surfaces the files
//! define.

use std::path::PathBuf;

use nurbs_core::{BSplineSurface, Point3};
use nurbs_io::{read_iges, read_step};

/// The bytes of `fixtures/foreign/NAME`.
fn fixture(name: &str) -> Vec<u8> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/foreign")
        .join(name);
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The largest distance from `centre` of the points of `s` on a 17 × 17 grid, minus `radius`,
/// in absolute value; and whether the domain is a full turn by a half turn (a whole sphere).
fn off_sphere(s: &BSplineSurface, centre: Point3, radius: f64) -> (f64, bool) {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let mut worst: f64 = 0.0;
    for a in 0..=16 {
        for b in 0..=16 {
            let p = s.point(
                u0 + (u1 - u0) * a as f64 / 16.0,
                v0 + (v1 - v0) * b as f64 / 16.0,
            );
            worst = worst.max(((p - centre).norm() - radius).abs());
        }
    }
    let whole = (u1 - u0 - std::f64::consts::TAU).abs() < 1e-12
        && (v1 - v0 - std::f64::consts::PI).abs() < 1e-12;
    (worst, whole)
}

/// SolidWorks' sphere whose face has no bounds: the whole sphere of radius 1 (the file writes
/// 1.0000000000000009, four ulps above 1), placed twice by the assembly — about the origin and
/// about the second usage's placement (-0.118…, 1.686…, -1.244…).
#[test]
fn a_sphere_face_with_no_bounds_is_the_whole_sphere() {
    let f = read_step(&String::from_utf8(fixture("bug24283_spheres.stp")).unwrap()).unwrap();
    assert!(f.warnings.is_empty(), "{:?}", f.warnings);
    assert_eq!(f.faces.len(), 2);
    let centres = [
        Point3::origin(),
        Point3::new(
            -0.118_478_102_591_744_71,
            1.686_317_213_533_462_3,
            -1.243_965_529_391_942_7,
        ),
    ];
    for face in &f.faces {
        let (off, whole) = centres
            .iter()
            .map(|&c| off_sphere(&face.surface, c, 1.000_000_000_000_001))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .unwrap();
        assert!(off < 1e-9 && whole, "{}: {off}", face.name);
    }
    assert!((f.faces[0].surface.point(0.0, 0.0) - f.faces[1].surface.point(0.0, 0.0)).norm() > 1.0);
}

/// SYRKO's primitives: eleven faces; the sphere (radius 100 about (200, 50, 50)) bounded by a
/// vertex loop is whole, so is the torus (both directions a full turn), and the cone between
/// two closed circle edges goes all round.
#[test]
fn vertex_loop_faces_and_closed_circle_edges_are_whole() {
    let f = read_step(&String::from_utf8(fixture("pr1sy.stp")).unwrap()).unwrap();
    assert!(f.warnings.is_empty(), "{:?}", f.warnings);
    assert_eq!(f.faces.len(), 11);
    let face = |id: u64| &f.faces.iter().find(|x| x.id == id).unwrap().surface;
    let (off, whole) = off_sphere(face(186), Point3::new(200.0, 50.0, 50.0), 100.0);
    assert!(off < 1e-9 && whole, "{off}");
    let torus = face(206);
    let turn = |(a, b): (f64, f64)| (b - a - std::f64::consts::TAU).abs() < 1e-12;
    assert!(turn(torus.domain_u()) && turn(torus.domain_v()));
    assert!(turn(face(256).domain_u()));
}

/// Alias's lone bicubic surface in a GEOMETRIC_SET: read, under its REPRESENTATION_ITEM name.
#[test]
fn a_bare_surface_in_a_geometric_set_is_read() {
    let f = read_step(&String::from_utf8(fixture("trj7_c2-al-214.stp")).unwrap()).unwrap();
    assert_eq!(f.faces.len(), 1);
    let s = &f.faces[0].surface;
    assert_eq!((s.degree_u(), s.degree_v()), (3, 3));
    assert_eq!(s.control_points().len(), 16);
    assert_eq!(f.faces[0].name, "plane");
}

/// Rhino's IGES with a Terminate record that miscounts, and HarmonyWare's with an empty line
/// after it: each reads its one surface, the first with the miscount named, each in its unit.
#[test]
fn iges_with_wrong_counts_or_a_blank_last_line_reads() {
    let bad = read_iges(&fixture("bad_header.igs")).unwrap();
    assert_eq!(bad.surfaces.len(), 1);
    assert!(
        bad.warnings
            .iter()
            .any(|w| w.contains("Terminate record says"))
    );
    // its unit flag is 0, outside 1–11, with no unit name: read as the flag's default, inches
    assert_eq!((bad.unit_flag, bad.units.as_str()), (1, "IN"));
    let torus = read_iges(&fixture("OCC26138_Torus.igs")).unwrap();
    assert_eq!((torus.unit_flag, torus.units.as_str()), (2, "MM"));
    assert_eq!(torus.surfaces.len(), 1);
    assert!(torus.warnings.is_empty(), "{:?}", torus.warnings);
}

/// HarmonyWare's torus: one closed Bézier patch over [0, 2π]² trimmed (144, PREF 1) by a
/// parameter-space rectangle from u = −π/2 to π/2 — across the seam u = 0. The face comes in
/// as one surface over its box, u from 3π/2 to 5π/2 (the piece after the seam joined to the
/// piece before it, C⁰ at the old seam), with its trim loop on it; before, the box was clamped
/// to [0, π/2] and half the face was lost.
#[test]
fn a_trim_across_the_seam_of_a_closed_surface_keeps_the_whole_face() {
    use std::f64::consts::PI;
    let torus = read_iges(&fixture("OCC26138_Torus.igs")).unwrap();
    let s = &torus.surfaces[0];
    let ((u0, u1), (v0, v1)) = (s.surface.domain_u(), s.surface.domain_v());
    assert!(
        (u0 - 1.5 * PI).abs() < 1e-9 && (u1 - 2.5 * PI).abs() < 1e-9,
        "u [{u0}, {u1}]"
    );
    assert!((v0 - 2.889_739_012_8).abs() < 1e-9 && (v1 - 3.959_558_043_4).abs() < 1e-9);
    let seam = s
        .surface
        .knots_u()
        .knots()
        .iter()
        .filter(|&&k| (k - 2.0 * PI).abs() < 1e-12);
    assert_eq!(
        seam.count(),
        s.surface.degree_u(),
        "the old seam is a C0 knot"
    );
    // the trim runs round the whole face, on the surface
    let size = s.surface.size();
    let mut projector =
        nurbs_core::SurfaceProjector::new(&s.surface, nurbs_core::ProjectionParams::default());
    let mut seen = [f64::INFINITY, f64::NEG_INFINITY];
    for p in &s.trim {
        let f = projector.project(p);
        assert!(
            f.distance <= 1e-6 * size,
            "trim point {p:?} {} off",
            f.distance
        );
        seen = [seen[0].min(f.u), seen[1].max(f.u)];
    }
    assert!(
        seen[0] - u0 < 1e-6 && u1 - seen[1] < 1e-6,
        "trim spans u {seen:?}"
    );
}

/// CATIA V4's dome: a face bounded by two half circles between the two poles of a B-spline
/// whose knots run on past the face in a sliver span folded back beside it. The projection of
/// the bound's points next to a pole can end at the domain's corner, 1.7 mm off the surface;
/// such a point has no foot and no say in the face's box, which is the half dome u ∈ [0, 1]
/// (it came in over the sliver too, [0, 1.00017], and its export had a face of area 7·10²¹).
#[test]
fn a_bound_point_without_a_foot_does_not_widen_the_face() {
    let f = read_step(&String::from_utf8(fixture("pr1db.stp")).unwrap()).unwrap();
    assert_eq!(f.faces.len(), 15);
    // #565 = ADVANCED_FACE('*FAC7', …)
    let dome = f.faces.iter().find(|x| x.id == 565).unwrap();
    let (u, v) = (dome.surface.domain_u(), dome.surface.domain_v());
    assert!(u.0.abs() < 1e-9 && (u.1 - 1.0).abs() < 1e-9, "u {u:?}");
    assert!(v.0.abs() < 1e-9 && (v.1 - 1.0).abs() < 1e-9, "v {v:?}");
    // its sides u = 0 and u = 1 are the two half circles of its bound: radius 50 about
    // (0, 150, 50) in the plane y = 150
    let centre = Point3::new(0.0, 150.0, 50.0);
    for side in [u.0, u.1] {
        for k in 0..=20 {
            let p = dome.surface.point(side, k as f64 / 20.0);
            assert!((p.y - 150.0).abs() < 1e-6, "u {side}: {p:?}");
            assert!(((p - centre).norm() - 50.0).abs() < 1e-6, "u {side}: {p:?}");
        }
    }
    // and the trim runs round both
    assert!(dome.trim[0].iter().any(|p| p.x > 49.9) && dome.trim[0].iter().any(|p| p.x < -49.9));
}

/// I-DEAS' part as bounded surfaces (143) with boundaries (141) of lines and arcs: all eleven
/// faces Open CASCADE reads (nine planes, two tabulated cylinders), each with its outer
/// boundary as a trim loop on its surface — before, the planes were skipped, and the two
/// cylinders came in untrimmed.
#[test]
fn bounded_surfaces_with_boundaries_are_read() {
    let f = read_iges(&fixture("UKI60998.igs")).unwrap();
    assert_eq!(f.surfaces.len(), 11);
    assert_eq!(f.trimmed_entities, 11);
    let planes = f
        .surfaces
        .iter()
        .filter(|s| (s.surface.degree_u(), s.surface.degree_v()) == (1, 1))
        .count();
    assert_eq!(planes, 9, "nine bilinear planes");
    for s in &f.surfaces {
        assert!(s.trim.len() >= 3, "{}: no trim", s.de);
        // the trim lies on the surface read
        let mut projector =
            nurbs_core::SurfaceProjector::new(&s.surface, nurbs_core::ProjectionParams::default());
        for p in &s.trim {
            let d = projector.project(p).distance;
            assert!(d < 1e-6 * s.surface.size(), "{}: trim point {d} off", s.de);
        }
    }
    assert!(
        !f.skipped.keys().any(|&t| t == 143 || t == 108),
        "{:?}",
        f.skipped
    );
    // the plate whose 143 lists its round hole before its rim: the rim (70 × 100) is the outer
    // boundary (on the plane read, as every trim above), the circle (radius 15) its hole — before, the hole
    // was taken as the outer boundary and the plane cut to its box (the face's export had area
    // −1920 where Open CASCADE reads 6293 = 7000 − 225π)
    let extent = |pts: &[Point3]| {
        let (lo, hi) = pts.iter().fold(
            (
                Point3::from([f64::INFINITY; 3]),
                Point3::from([f64::NEG_INFINITY; 3]),
            ),
            |(lo, hi), p| (lo.inf(p), hi.sup(p)),
        );
        hi - lo
    };
    let z0 = |s: &&nurbs_io::reader::IgesSurface| s.trim.iter().all(|p| p.z.abs() < 1e-9);
    let plates: Vec<_> = f
        .surfaces
        .iter()
        .filter(|s| !s.holes.is_empty())
        .filter(z0)
        .collect();
    assert_eq!(plates.len(), 1, "one plate with a hole at z = 0");
    let plate = plates[0];
    let rim = extent(&plate.trim);
    assert!(
        (rim.x - 70.0).abs() < 1e-6 && (rim.y - 100.0).abs() < 1e-6,
        "{rim:?}"
    );
    assert_eq!(plate.holes.len(), 1);
    let hole = extent(&plate.holes[0]);
    assert!(
        (hole.x - 30.0).abs() < 1e-3 && (hole.y - 30.0).abs() < 1e-3,
        "{hole:?}"
    );
}

/// Inventor's spring as a manifold solid B-rep (186 → 514 → six 510 faces with 508 loops over
/// a 504 edge list): all six faces Open CASCADE reads — the two helical sweeps (128) cut to
/// their faces, and the four plane surfaces (190) each through its point (116) and along its
/// normal (123) as the file gives them, bounded by its loop. Before, the faces were skipped
/// and only the two sweeps came in, untrimmed.
#[test]
fn brep_solid_faces_are_read() {
    let f = read_iges(&fixture("bug22869_Spring.igs")).unwrap();
    assert_eq!(f.surfaces.len(), 6);
    assert_eq!(f.trimmed_entities, 6);
    for t in [186, 514, 510, 508, 504, 502, 190] {
        assert!(!f.skipped.contains_key(&t), "{t} skipped: {:?}", f.skipped);
    }
    // the plane surfaces: (D of the 190, its 116 point, its 123 normal)
    let planes = [
        (
            31,
            [23.9105317365664, 0.0, 0.586137973858172],
            [0.0, 0.0, -1.0],
        ),
        (47, [-15.0, 0.0, 0.586137973858172], [0.0, 1.0, 0.0]),
        (
            63,
            [-1.94682718328477, 18.5228233511589, 73.0861379738582],
            [0.0, 0.0, 1.0],
        ),
        (
            79,
            [1.56792694901481, -14.9178284305241, 73.0861379738582],
            [0.994521895368273, 0.104528463267654, 0.0],
        ),
    ];
    for (de, at, normal) in planes {
        let s = f
            .surfaces
            .iter()
            .find(|s| s.de == de)
            .unwrap_or_else(|| panic!("D{de}"));
        assert_eq!(
            (s.surface.degree_u(), s.surface.degree_v()),
            (1, 1),
            "D{de}"
        );
        let ((u0, u1), (v0, v1)) = (s.surface.domain_u(), s.surface.domain_v());
        let d = s.surface.derivatives(0.5 * (u0 + u1), 0.5 * (v0 + v1));
        let n = d.normal().unwrap();
        let want = nurbs_core::Vector3::new(normal[0], normal[1], normal[2]).normalize();
        assert!(n.cross(&want).norm() < 1e-12, "D{de}: normal {n:?}");
        let p = Point3::new(at[0], at[1], at[2]);
        assert!(
            (p - d.point).dot(&want).abs() < 1e-9,
            "D{de}: the 116 point off the plane"
        );
        // the loop is the trim, in the plane up to the edge curves' own fit (the sweeps' ends
        // are cubic B-splines that Inventor fits to the planar end curves: within 2e-3 mm of
        // the 75 mm part)
        assert!(s.trim.len() >= 3, "D{de}");
        for q in &s.trim {
            assert!(
                (q - d.point).dot(&want).abs() < 3e-3,
                "D{de}: trim point off"
            );
        }
    }
    // the sweeps are cut to their faces, their trims on them (a sweep runs seven turns over 96
    // spans along the wire: the projector's default starts sample it finely enough,
    // nurbs_core::projection::MAX_START_SAMPLES)
    let sweeps: Vec<_> = f
        .surfaces
        .iter()
        .filter(|s| s.surface.degree_u() == 3)
        .collect();
    assert_eq!(sweeps.len(), 2);
    for s in sweeps {
        assert!(s.underlying.is_some() && s.trim.len() >= 3, "D{}", s.de);
        let mut projector =
            nurbs_core::SurfaceProjector::new(&s.surface, nurbs_core::ProjectionParams::default());
        for p in s.trim.iter().step_by((s.trim.len() / 200).max(1)) {
            let d = projector.project(p).distance;
            assert!(d < 1e-9 * s.surface.size(), "D{}: trim point {d} off", s.de);
        }
    }
}

/// CATIA V4's part with two form features: the twelve faces of the part's solid, which Open
/// CASCADE transfers; the eight faces of the features' "explicit geometry branch" solids
/// (representations of a SHAPE_ASPECT, not of the product definition) are left out and named
/// in one warning. Before, all twenty came in.
#[test]
fn faces_of_shape_aspects_are_not_the_parts() {
    let text = String::from_utf8(fixture("trj2_f1-db-214.stp")).unwrap();
    let f = read_step(&text).unwrap();
    assert_eq!(f.faces.len(), 12);
    let ids: Vec<u64> = f.faces.iter().map(|x| x.id).collect();
    let aspects = [896, 964, 1005, 1016, 1191, 1259, 1300, 1311];
    assert!(aspects.iter().all(|id| !ids.contains(id)), "{ids:?}");
    let warning = f
        .warnings
        .iter()
        .find(|w| w.contains("shape aspects"))
        .expect("the faces left out are named");
    assert!(
        warning.starts_with("8 faces") && warning.contains("#1311"),
        "{warning}"
    );
}

/// A representation that is both a shape aspect's and the product's (one more shape definition
/// representation names the first feature's "explicit geometry branch" as the part's shape) is
/// the part's: its four faces are read, the other feature's four are still left out.
#[test]
fn a_representation_of_the_product_is_kept_though_an_aspect_names_it() {
    let text = String::from_utf8(fixture("trj2_f1-db-214.stp")).unwrap();
    // before the DATA section's end, the file's last ENDSEC
    let at = text.rfind("ENDSEC;").unwrap();
    let text = format!(
        "{}#99999=SHAPE_DEFINITION_REPRESENTATION(#21,#1028);\n{}",
        &text[..at],
        &text[at..]
    );
    let f = read_step(&text).unwrap();
    assert_eq!(f.faces.len(), 16);
    let warning = f.warnings.iter().find(|w| w.contains("shape aspects"));
    assert!(
        warning.is_some_and(|w| w.starts_with("4 faces")),
        "{warning:?}"
    );
}
