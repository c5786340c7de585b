//! STEP assemblies: a part's faces placed once per usage, by the transformation of each
//! placing relationship (\[ISO41\]; rep_1 the component, rep_2 the assembly — or, where the usage
//! occurrence says the component is rep_2, the other way round), named by their usage.

use nurbs_core::Point3;
use nurbs_io::read_step;

/// The id of the first instance whose line starts with `entity(` in `text`.
fn id_of(text: &str, entity: &str) -> u64 {
    text.lines()
        .find_map(|l| {
            let (id, rest) = l.split_once('=')?;
            rest.trim_start()
                .starts_with(&format!("{entity}("))
                .then(|| id.trim().trim_start_matches('#').parse().ok())?
        })
        .unwrap_or_else(|| panic!("no {entity}"))
}

/// A part (one bicubic face, written by `write_step`) placed twice in an assembly: by a
/// relationship whose rep_1 is the part (a quarter turn about z and 10 along x), and by one
/// written the other way round, rep_1 the assembly, with the usage occurrence `U2` naming the
/// part as its component (5 along z).
#[test]
fn a_part_is_placed_once_per_usage() {
    let s = nurbs_core::shapes::paraboloid_bicubic(&[0.5]).unwrap();
    let part = nurbs_io::write_step(&[("face", &s)], "mm", "part.step").unwrap();
    let rep = id_of(&part, "MANIFOLD_SURFACE_SHAPE_REPRESENTATION");
    let def = id_of(&part, "PRODUCT_DEFINITION");
    let ctx = part
        .lines()
        .find(|l| l.contains("GEOMETRIC_REPRESENTATION_CONTEXT"))
        .and_then(|l| {
            l.split_once('=')?
                .0
                .trim()
                .trim_start_matches('#')
                .parse::<u64>()
                .ok()
        })
        .unwrap();
    let formation = id_of(&part, "PRODUCT_DEFINITION_FORMATION");
    let dctx = id_of(&part, "PRODUCT_DEFINITION_CONTEXT");
    let asm = format!(
        "#9001=CARTESIAN_POINT('',(0.,0.,0.));
#9002=DIRECTION('',(0.,0.,1.));
#9003=DIRECTION('',(1.,0.,0.));
#9004=AXIS2_PLACEMENT_3D('',#9001,#9002,#9003);
#9005=CARTESIAN_POINT('',(10.,0.,0.));
#9007=DIRECTION('',(0.,1.,0.));
#9008=AXIS2_PLACEMENT_3D('',#9005,#9002,#9007);
#9010=SHAPE_REPRESENTATION('asm',(#9008,#9026),#{ctx});
#9011=ITEM_DEFINED_TRANSFORMATION('','',#9004,#9008);
#9012=(REPRESENTATION_RELATIONSHIP('','',#{rep},#9010)REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#9011)SHAPE_REPRESENTATION_RELATIONSHIP());
#9020=PRODUCT_DEFINITION('asm','',#{formation},#{dctx});
#9021=NEXT_ASSEMBLY_USAGE_OCCURRENCE('U2','','',#9020,#{def},$);
#9022=PRODUCT_DEFINITION_SHAPE('','',#9021);
#9023=PRODUCT_DEFINITION_SHAPE('','',#9020);
#9024=SHAPE_DEFINITION_REPRESENTATION(#9023,#9010);
#9025=CARTESIAN_POINT('',(0.,0.,5.));
#9026=AXIS2_PLACEMENT_3D('',#9025,#9002,#9003);
#9027=ITEM_DEFINED_TRANSFORMATION('','',#9026,#9004);
#9028=(REPRESENTATION_RELATIONSHIP('','',#9010,#{rep})REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#9027)SHAPE_REPRESENTATION_RELATIONSHIP());
#9029=CONTEXT_DEPENDENT_SHAPE_REPRESENTATION(#9028,#9022);
"
    );
    let text = part.replacen("ENDSEC;\nEND-ISO", &format!("{asm}ENDSEC;\nEND-ISO"), 1);
    assert_ne!(text, part, "the assembly was appended");
    let file = read_step(&text).unwrap();
    assert_eq!(
        file.faces.len(),
        2,
        "{:?}",
        file.faces.iter().map(|f| &f.name).collect::<Vec<_>>()
    );
    let turned = file
        .faces
        .iter()
        .find(|f| f.name == "#9012/face")
        .expect("first usage");
    let lifted = file
        .faces
        .iter()
        .find(|f| f.name == "U2/face")
        .expect("second usage");
    for (a, b) in [(0.1, 0.2), (0.5, 0.5), (0.9, 0.3)] {
        let p = s.point(a, b);
        let want = Point3::new(10.0 - p.y, p.x, p.z);
        assert!(
            (turned.surface.point(a, b) - want).norm() < 1e-12,
            "turned at ({a}, {b})"
        );
        let want = Point3::new(p.x, p.y, p.z + 5.0);
        assert!(
            (lifted.surface.point(a, b) - want).norm() < 1e-12,
            "lifted at ({a}, {b})"
        );
    }
}

/// The two instances of one sphere in Open CASCADE's bug24283 (its relationships written with
/// the assembly as rep_1): two faces, named by their usage occurrences, the same sphere moved
/// rigidly.
#[test]
fn both_instances_of_a_sphere_are_read() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/foreign/bug24283_spheres.stp");
    let file = read_step(&std::fs::read_to_string(path).unwrap()).unwrap();
    assert_eq!(file.faces.len(), 2);
    let mut names: Vec<&str> = file.faces.iter().map(|f| f.name.as_str()).collect();
    names.sort_unstable();
    assert!(
        names[0].starts_with("NAUO1/") && names[1].starts_with("NAUO2/"),
        "{names:?}"
    );
    let (a, b) = (&file.faces[0].surface, &file.faces[1].surface);
    let (pa, pb) = (a.control_points(), b.control_points());
    assert_eq!(pa.len(), pb.len());
    // rigid: the distances between control points agree, the positions do not
    for i in 0..pa.len().min(12) {
        for j in 0..i {
            let (da, db) = ((pa[i] - pa[j]).norm(), (pb[i] - pb[j]).norm());
            assert!((da - db).abs() < 1e-9, "{i} {j}: {da} vs {db}");
        }
    }
    assert!((pa[0] - pb[0]).norm() > 0.5, "both instances in one place");
}
