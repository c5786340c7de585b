//! `hier-fair import` / `export`: IGES in and out through the command line.

use std::path::Path;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_hier-fair"))
}

#[test]
fn export_then_import_keeps_geometry_and_names() {
    let dir = tempfile::tempdir().unwrap();
    let fixture =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/surfaces/sphere_patch_r50.json");
    let igs = dir.path().join("out.igs");
    let o = bin()
        .args([
            "export",
            fixture.to_str().unwrap(),
            "-o",
            igs.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    nurbs_io::check_structure(&std::fs::read(&igs).unwrap()).unwrap();
    let model = dir.path().join("model.json");
    let o = bin()
        .args([
            "import",
            igs.to_str().unwrap(),
            "-o",
            model.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let back = hier_fair::Model::from_json(&std::fs::read_to_string(&model).unwrap()).unwrap();
    let original =
        nurbs_core::io::surfaces_from_json(&std::fs::read_to_string(&fixture).unwrap()).unwrap();
    assert_eq!(back.surfaces.len(), 1);
    assert_eq!(back.surfaces[0].name, "surface");
    assert_eq!(back.surfaces[0].surface, original[0]);
    assert!(back.links.is_empty());
    // the input is never overwritten
    let o = bin()
        .args(["import", igs.to_str().unwrap(), "-o", igs.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("refusing to overwrite"));
}

#[test]
fn impeller_imports_as_primaries() {
    let igs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/third_party/impeller.igs");
    assert!(igs.exists(), "{} is in the repository", igs.display());
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("impeller.json");
    let o = bin()
        .args([
            "import",
            igs.to_str().unwrap(),
            "-o",
            model.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("imported 277 surfaces"));
    let m = hier_fair::Model::from_json(&std::fs::read_to_string(&model).unwrap()).unwrap();
    assert_eq!(m.surfaces.len(), 277);
    assert_eq!(m.units.as_deref(), Some("mm"));
}

#[test]
fn bad_iges_is_one_line_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.igs");
    std::fs::write(&bad, "not an iges file\n").unwrap();
    let o = bin()
        .args([
            "import",
            bad.to_str().unwrap(),
            "-o",
            dir.path().join("m.json").to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.trim_end().lines().count(), 1);
    assert!(err.contains("line 1"), "{err}");
    assert!(!dir.path().join("m.json").exists());
}

/// The IGES files Open CASCADE writes (`fixtures/occt/*.igs`): cylinders, spheres and tori come
/// as surfaces of revolution (entity 120 of a 110 line or a 100 arc about a 110 axis) and are
/// read as exact rational surfaces. Each lies on the surface of the same face in the model the
/// kernel exported directly (`NAME.json`): its points project onto one of that model's surfaces
/// within 1e-9 of the model size, and it has its face's curvature (1/R for a fillet of radius R)
/// there.
#[test]
fn kernel_iges_surfaces_of_revolution_are_exact() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/occt");
    let params = nurbs_core::ProjectionParams::default();
    let (mut revolved, mut on_face) = (0, 0);
    for name in [
        "occt_box12_r5",
        "occt_corner3_radii",
        "occt_plate_boss",
        "occt_pipe_tee",
    ] {
        let bytes = std::fs::read(dir.join(format!("{name}.igs"))).unwrap();
        let file = nurbs_io::read_iges(&bytes).unwrap();
        let model = hier_fair::Model::from_json(
            &std::fs::read_to_string(dir.join(format!("{name}.json"))).unwrap(),
        )
        .unwrap();
        let size = model
            .surfaces
            .iter()
            .map(|s| s.surface.size())
            .fold(0.0, f64::max);
        for s in &file.surfaces {
            if !s.surface.is_rational() {
                continue;
            }
            revolved += 1;
            // the face's own surface: the JSON surface nearest to the imported one's centre
            let (u0, u1) = s.surface.knots_u().domain();
            let (v0, v1) = s.surface.knots_v().domain();
            let mid = s.surface.point(0.5 * (u0 + u1), 0.5 * (v0 + v1));
            let own = model
                .surfaces
                .iter()
                .map(|m| {
                    let f = nurbs_core::project_to_surface(&m.surface, &mid, &params);
                    (f.distance, m)
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .unwrap();
            assert!(
                own.0 <= 1e-9 * size,
                "{name}: {} centre {:.3e} off",
                s.name,
                own.0
            );
            for a in [0.1, 0.3, 0.5, 0.7, 0.9] {
                for b in [0.1, 0.3, 0.5, 0.7, 0.9] {
                    let (u, v) = (u0 + a * (u1 - u0), v0 + b * (v1 - v0));
                    let d = s.surface.derivatives(u, v);
                    let f = nurbs_core::project_to_surface(&own.1.surface, &d.point, &params);
                    // inside the face's box the point lies on the face's surface; outside it the
                    // foot is clamped to the box and the distance is that of the box edge
                    if f.distance <= 1e-6 * size {
                        on_face += 1;
                        assert!(
                            f.distance <= 1e-9 * size,
                            "{name}: {} at ({a}, {b})",
                            s.name
                        );
                        let dm = own.1.surface.derivatives(f.u, f.v);
                        // the orientations may differ: compare the sorted magnitudes
                        let sorted = |d: &nurbs_core::SurfaceDerivatives| {
                            let k = d.principal_curvatures().unwrap();
                            let (a, b) = (k.k1.abs(), k.k2.abs());
                            (a.min(b), a.max(b))
                        };
                        let (k1, k2) = (sorted(&d), sorted(&dm));
                        let diff = (k1.0 - k2.0).abs().max((k1.1 - k2.1).abs());
                        assert!(diff <= 1e-6, "{name}: {} curvatures {k1:?} {k2:?}", s.name);
                    }
                }
            }
        }
    }
    assert!(revolved >= 28, "{revolved} surfaces of revolution");
    // the curvature comparison ran: most grid points of a revolved face lie on its face's box
    assert!(on_face >= 10 * revolved, "{on_face} points on the faces");
}

/// Importing the IGES files Open CASCADE writes gives the faces of the model the kernel exported
/// directly (every surface of `NAME.json` lies on an imported surface within 1e-9 of the model
/// size: planes, cylinders, spheres, tori and B-splines alike) and the hierarchy: links between
/// the matching surfaces with the same targets, and the same roles. Printed per model; the
/// figures asserted are those reached (`docs/benchmarks.md`).
#[test]
fn kernel_iges_imports_with_its_hierarchy() {
    let (hit, all) = kernel_imports("igs");
    assert!(hit * 100 >= 95 * all, "{hit}/{all}");
}

/// The same for the STEP files Open CASCADE writes (AP214: PLANE, CYLINDRICAL_SURFACE,
/// SPHERICAL_SURFACE, TOROIDAL_SURFACE, B-spline surfaces, faces bounded by edge loops).
#[test]
fn kernel_step_imports_with_its_hierarchy() {
    let (hit, all) = kernel_imports("step");
    assert!(hit * 100 >= 95 * all, "{hit}/{all}");
}

/// Imports every kernel model from its `ext` file and compares it with its JSON (see
/// [`kernel_iges_imports_with_its_hierarchy`]); returns the links found and the links there are.
/// Every face of an imported kernel model keeps its bounds as trim loops (each at least three
/// points), and every trim point lies on the face's surface within the G0 tolerance.
fn trims_lie_on_their_surfaces(model: &hier_fair::Model, name: &str) {
    let g0 = model.tolerances.g0;
    for s in &model.surfaces {
        assert!(!s.trim.is_empty(), "{name}: {} has no trim", s.name);
        let mut projector =
            nurbs_core::SurfaceProjector::new(&s.surface, nurbs_core::ProjectionParams::default());
        for l in &s.trim {
            assert!(
                l.len() >= 3,
                "{name}: {} has a loop of {} points",
                s.name,
                l.len()
            );
            for p in l {
                let d = projector.project(p).distance;
                assert!(
                    d <= g0,
                    "{name}: {} trim point {p:?} is {d:.3e} off",
                    s.name
                );
            }
        }
    }
}

fn kernel_imports(ext: &str) -> (usize, usize) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/occt");
    let params = nurbs_core::ProjectionParams::default();
    let (mut links_hit, mut links_all, mut roles_hit, mut surfaces_all) = (0, 0, 0, 0);
    let index: Vec<serde_json::Value> =
        serde_json::from_str(&std::fs::read_to_string(dir.join("index.json")).unwrap()).unwrap();
    assert!(index.len() >= 6);
    for entry in &index {
        let name = entry["name"].as_str().expect("a name per model");
        let tmp = tempfile::tempdir().unwrap();
        let out = tmp.path().join("m.json");
        let o = bin()
            .args([
                "import",
                dir.join(format!("{name}.{ext}")).to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let ours = hier_fair::Model::from_json(&std::fs::read_to_string(&out).unwrap()).unwrap();
        trims_lie_on_their_surfaces(&ours, name);
        let theirs = hier_fair::Model::from_json(
            &std::fs::read_to_string(dir.join(format!("{name}.json"))).unwrap(),
        )
        .unwrap();
        let size = theirs
            .surfaces
            .iter()
            .map(|s| s.surface.size())
            .fold(0.0, f64::max);
        // each JSON surface: the imported surface it lies on, or that lies on it (a trimmed
        // plane: the JSON has it over its UV box, the import over the face's own rectangle)
        // points at the fractions `f` of both domains
        let at = |s: &nurbs_core::BSplineSurface, f: [f64; 3]| -> Vec<nurbs_core::Point3> {
            let (u0, u1) = s.domain_u();
            let (v0, v1) = s.domain_v();
            f.iter()
                .flat_map(|a| f.map(|b| s.point(u0 + a * (u1 - u0), v0 + b * (v1 - v0))))
                .collect()
        };
        let grid = |s: &nurbs_core::BSplineSurface| at(s, [0.2, 0.5, 0.8]);
        let on = |pts: &[nurbs_core::Point3], s: &nurbs_core::BSplineSurface| {
            pts.iter()
                .all(|p| nurbs_core::project_to_surface(s, p, &params).distance <= 1e-9 * size)
        };
        let matched: Vec<Option<usize>> = theirs
            .surfaces
            .iter()
            .map(|t| {
                let pts = grid(&t.surface);
                ours.surfaces
                    .iter()
                    .position(|s| on(&pts, &s.surface))
                    .or_else(|| {
                        ours.surfaces
                            .iter()
                            .position(|s| on(&grid(&s.surface), &t.surface))
                    })
            })
            .collect();
        for (t, m) in theirs.surfaces.iter().zip(&matched) {
            assert!(
                m.is_some(),
                "{name}: {} lies on no imported surface",
                t.name
            );
            // a curved face is the same surface over the same box both ways (a plane is the
            // import's rectangle around its trim, the JSON's is the UV box of its face)
            let o = &ours.surfaces[m.unwrap()].surface;
            let whole = |s: &nurbs_core::BSplineSurface| at(s, [0.0, 0.5, 1.0]);
            // a fillet or corner blend is its whole face: the same surface over the same box
            // both ways, corners and side midpoints included (a box wider on one side shows
            // there). A trimmed primary's box in the JSON is the kernel's UV bound of its trim,
            // which may exceed the trim's extremes: its interior is checked both ways.
            // The box edges agree to the G0 tolerance (the kernel's UV bounds against our
            // sampled trim: an edge off by less than a link's allowed gap changes no link).
            let within = |pts: &[nurbs_core::Point3], s: &nurbs_core::BSplineSurface| {
                pts.iter().all(|p| {
                    nurbs_core::project_to_surface(s, p, &params).distance <= theirs.tolerances.g0
                })
            };
            if t.surface.degree_u().max(t.surface.degree_v()) > 1 {
                let box_ok = t.role == hier_fair::Role::Primary
                    || (within(&whole(o), &t.surface) && within(&whole(&t.surface), o));
                assert!(
                    box_ok && on(&grid(o), &t.surface) && on(&grid(&t.surface), o),
                    "{name}: {} and its import are not the same surface over the same box",
                    t.name
                );
            }
        }
        let roles = theirs
            .surfaces
            .iter()
            .zip(&matched)
            .filter(|(t, m)| m.is_some_and(|m| ours.surfaces[m].role == t.role))
            .count();
        // the same slave side: interior points of the JSON link's side lie on the imported
        // link's side (the two surfaces may be parametrized differently, so side names differ)
        let same_side = |l: &hier_fair::model::Link, o: &hier_fair::model::Link| {
            let (st, so) = (
                &theirs.surfaces[l.slave].surface,
                &ours.surfaces[o.slave].surface,
            );
            let (a, b) = l.side.along_domain(st);
            let (c0, c1) = match o.side.cross_direction() {
                nurbs_core::Direction::U => so.domain_u(),
                nurbs_core::Direction::V => so.domain_v(),
            };
            let edge = o.side.boundary_param(so);
            [0.3, 0.5, 0.7].iter().all(|f| {
                let (u, v) = l.side.params(st, a + f * (b - a));
                let pr = nurbs_core::project_to_surface(so, &st.point(u, v), &params);
                let cross = match o.side.cross_direction() {
                    nurbs_core::Direction::U => pr.u,
                    nurbs_core::Direction::V => pr.v,
                };
                pr.distance <= 1e-9 * size && (cross - edge).abs() <= 1e-6 * (c1 - c0)
            })
        };
        let hit = theirs
            .links
            .iter()
            .filter(|l| {
                let (s, m) = (matched[l.slave].unwrap(), matched[l.master].unwrap());
                ours.links.iter().any(|o| {
                    o.slave == s && o.master == m && o.continuity == l.continuity && same_side(l, o)
                })
            })
            .count();
        // no link that is not geometrically there: every imported link's side lies on its
        // master within the model's G0 tolerance
        for o in &ours.links {
            let m = g_continuity::measure_link(
                &ours.surfaces[o.master].surface,
                &ours.surfaces[o.slave].surface,
                o.side,
                &g_continuity::MeasureParams::default(),
            )
            .unwrap();
            assert!(
                m.g0 <= ours.tolerances.g0,
                "{name}: imported link {} {:?} -> {} has a gap of {:.3e}",
                ours.surfaces[o.slave].name,
                o.side,
                ours.surfaces[o.master].name,
                m.g0
            );
        }
        eprintln!(
            "{name}: surfaces {}/{} matched, links {hit}/{}, roles {roles}/{}",
            theirs.surfaces.len(),
            theirs.surfaces.len(),
            theirs.links.len(),
            theirs.surfaces.len()
        );
        links_hit += hit;
        links_all += theirs.links.len();
        roles_hit += roles;
        surfaces_all += theirs.surfaces.len();
    }
    eprintln!("{ext}: links {links_hit}/{links_all}, roles {roles_hit}/{surfaces_all}");
    // the roles of the JSON for at least 90 % of the surfaces
    assert!(
        roles_hit * 100 >= 90 * surfaces_all,
        "{ext}: roles {roles_hit}/{surfaces_all}"
    );
    (links_hit, links_all)
}

/// A CAD file in, a CAD file out: `fair NAME.igs -o OUT.igs` imports (hierarchy found), fairs
/// and writes IGES; the output reads back with the same surfaces and links, and the report says
/// every link of the plate with the boss is met.
#[test]
fn fair_round_trips_iges() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/occt");
    let tmp = tempfile::tempdir().unwrap();
    let (out, report) = (tmp.path().join("out.igs"), tmp.path().join("r.json"));
    let o = bin()
        .args([
            "fair",
            dir.join("occt_plate_boss.igs").to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--report",
            report.to_str().unwrap(),
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let links = r["links"].as_array().unwrap();
    assert_eq!(links.len(), 4);
    assert!(links.iter().all(|l| l["met"] == true), "{links:?}");
    let back = nurbs_io::read_iges(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!(back.surfaces.len(), 10);
}

/// The trims an import keeps go through `fair` unchanged: data the fairing does not touch.
#[test]
fn fair_keeps_the_trims_of_an_imported_model() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/occt");
    let tmp = tempfile::tempdir().unwrap();
    let (model, out) = (tmp.path().join("m.json"), tmp.path().join("out.json"));
    let step = dir.join("occt_plate_boss.step");
    let o = bin()
        .args([
            "import",
            step.to_str().unwrap(),
            "-o",
            model.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = bin()
        .args([
            "fair",
            model.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--quiet",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let read =
        |p: &Path| hier_fair::Model::from_json(&std::fs::read_to_string(p).unwrap()).unwrap();
    let (before, after) = (read(&model), read(&out));
    assert!(before.surfaces.iter().any(|s| !s.trim.is_empty()));
    for (a, b) in before.surfaces.iter().zip(&after.surfaces) {
        assert_eq!(a.trim, b.trim, "{}", a.name);
    }
}

/// A writer that gives a trimmed face's boundary (142) only its model-space curve: the face is
/// cut to the box of that curve projected onto its surface. The lofted block's IGES with every
/// parameter-space curve removed imports with all 25 links of its JSON, each within the G0
/// tolerance of its master (an uncut fillet runs millimetres past its master's end).
#[test]
fn iges_faces_without_parameter_curves_are_cut_by_projection() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/occt");
    let text = std::fs::read_to_string(dir.join("occt_loft_block.igs")).unwrap();
    let mut rewritten = 0;
    let lines: Vec<String> = text
        .lines()
        .map(|l| {
            // "142,0,SURFACE,PARAMETRIC,MODEL,PREF;" in the parameter columns 1–64
            let fields: Vec<&str> = l
                .get(..64)
                .unwrap_or("")
                .trim_end()
                .trim_end_matches(';')
                .split(',')
                .collect();
            if l.len() >= 72 && fields.len() == 6 && fields[0] == "142" {
                rewritten += 1;
                let p = format!("142,0,{},0,{},1;", fields[2], fields[4]);
                format!("{p:<64}{}", &l[64..])
            } else {
                l.to_string()
            }
        })
        .collect();
    assert_eq!(rewritten, 18);
    let tmp = tempfile::tempdir().unwrap();
    let (input, out) = (tmp.path().join("m.igs"), tmp.path().join("m.json"));
    std::fs::write(&input, lines.join("\n") + "\n").unwrap();
    let o = bin()
        .args([
            "import",
            input.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let model = hier_fair::Model::from_json(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(model.links.len(), 25);
    for l in &model.links {
        let m = g_continuity::measure_link(
            &model.surfaces[l.master].surface,
            &model.surfaces[l.slave].surface,
            l.side,
            &g_continuity::MeasureParams::default(),
        )
        .unwrap();
        assert!(
            m.g0 <= model.tolerances.g0,
            "{}: gap {:.3e}",
            model.surfaces[l.slave].name,
            m.g0
        );
    }
}

/// `fair NAME.step -o OUT.step` on a kernel model: the written STEP reads back with every face
/// on the faired model's surface (the same run written as JSON) to 1e-9 of the model size, at
/// the same parameters over the read-back face's box — the box of its trim loops, within the
/// faired surface's — and with the face's trim loops, every point on the face within the G0
/// tolerance.
fn step_round_trip(name: &str) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/occt");
    let tmp = tempfile::tempdir().unwrap();
    let step = dir.join(format!("{name}.step"));
    let (out_step, out_json) = (tmp.path().join("out.step"), tmp.path().join("out.json"));
    for out in [&out_step, &out_json] {
        let o = bin()
            .args([
                "fair",
                step.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
                "--quiet",
            ])
            .output()
            .unwrap();
        // 1 where a link is left unmet (the three-radii corner by default): the result is
        // written all the same (cli-contract.md), and its round trip is what is tested here
        assert!(
            matches!(o.status.code(), Some(0 | 1)),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    let faired = hier_fair::Model::from_json(&std::fs::read_to_string(&out_json).unwrap()).unwrap();
    let back = nurbs_io::read_step(&std::fs::read_to_string(&out_step).unwrap()).unwrap();
    assert_eq!(back.faces.len(), faired.surfaces.len(), "{name}");
    let size = faired
        .surfaces
        .iter()
        .map(|s| s.surface.size())
        .fold(0.0, f64::max);
    for (f, s) in back.faces.iter().zip(&faired.surfaces) {
        let (a, b) = (&f.surface, &s.surface);
        let ((u0, u1), (v0, v1)) = (a.domain_u(), a.domain_v());
        let ((bu0, bu1), (bv0, bv1)) = (b.domain_u(), b.domain_v());
        assert!(
            u0 >= bu0 && u1 <= bu1 && v0 >= bv0 && v1 <= bv1,
            "{name}: {} read back over a wider box",
            s.name
        );
        for i in 0..=8 {
            for j in 0..=8 {
                let (fu, fv) = (f64::from(i) / 8.0, f64::from(j) / 8.0);
                let (u, v) = (u0 + (u1 - u0) * fu, v0 + (v1 - v0) * fv);
                let d = (a.point(u, v) - b.point(u, v)).norm();
                assert!(d <= 1e-9 * size, "{name}: {} off by {d:.3e}", s.name);
            }
        }
        assert_eq!(f.trim.len(), s.trim.len(), "{name}: {}", s.name);
        let mut projector =
            nurbs_core::SurfaceProjector::new(a, nurbs_core::ProjectionParams::default());
        for p in f.trim.iter().flatten() {
            // the sampled starts, else Newton from a spread of starts (the sampled starts alone
            // can stall at a pole, where every sample of the collapsed row is one point)
            let mut d = projector.project(p).distance;
            for (i, j) in (1..8).flat_map(|i| (1..8).map(move |j| (i, j))) {
                if d <= faired.tolerances.g0 {
                    break;
                }
                let start = (
                    u0 + (u1 - u0) * f64::from(i) / 8.0,
                    v0 + (v1 - v0) * f64::from(j) / 8.0,
                );
                d = d.min(projector.project_from(p, start).distance);
            }
            assert!(
                d <= faired.tolerances.g0,
                "{name}: {} trim {d:.3e} off",
                s.name
            );
        }
    }
}

#[test]
fn fair_round_trips_step_box12_r5() {
    step_round_trip("occt_box12_r5");
}

#[test]
fn fair_round_trips_step_box12_variable() {
    step_round_trip("occt_box12_variable");
}

#[test]
fn fair_round_trips_step_corner3_radii() {
    step_round_trip("occt_corner3_radii");
}

#[test]
fn fair_round_trips_step_loft_block() {
    step_round_trip("occt_loft_block");
}

#[test]
fn fair_round_trips_step_pipe_tee() {
    step_round_trip("occt_pipe_tee");
}

#[test]
fn fair_round_trips_step_plate_boss() {
    step_round_trip("occt_plate_boss");
}
