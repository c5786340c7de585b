//! `hier-fair fair NAME.step` on the kernel models of `fixtures/occt_variants`: the six kinds of
//! `fixtures/occt` with other dimensions and radii, read as a CAD system writes them (STEP, the
//! hierarchy found from the geometry), with 0.05 mm on primaries and 0.5 mm on connecting and
//! corner surfaces. Whatever a model's links reach, no link and no shared edge may leave worse
//! than it came and no surface may leave its own deviation.

use std::path::Path;
use std::process::Command;

use serde_json::Value;

/// The model's default continuity tolerances (model-format.md): a link is worse than its input
/// when its gap or angle grew by more than these.
const G0: f64 = 1e-3;
const G1_DEG: f64 = 1e-2;

/// `fixtures/occt_variants/NAME.EXT`.
fn variant(name: &str, ext: &str) -> String {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/occt_variants");
    dir.join(format!("{name}.{ext}"))
        .to_str()
        .unwrap()
        .to_string()
}

/// Runs `hier-fair ARGS` and asserts that it wrote its outputs: exit 0, or 1 for links left
/// unmet only (cli-contract.md; the tests read the report for those).
fn hier_fair(args: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_hier-fair"))
        .args(args)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    let unmet_only = o.status.code() == Some(1)
        && err.contains("link(s) unmet")
        && !err.contains("could not be faired");
    assert!(o.status.success() || unmet_only, "{args:?}: {err}");
}

/// Fairs `fixtures/occt_variants/NAME.step` per role and returns the report.
fn fair(name: &str) -> Value {
    fair_with(name, &[])
}

/// [`fair`] with more arguments.
fn fair_with(name: &str, more: &[&str]) -> Value {
    fair_file(&variant(name, "step"), more)
}

/// The per-role deviations of every run here but [`fair_default`]'s.
const PER_ROLE: [&str; 6] = [
    "--tolerance-role",
    "primary=0.05",
    "--tolerance-role",
    "connecting=0.5",
    "--tolerance-role",
    "corner=0.5",
];

/// Fairs the model file `input` per role (with `more` arguments) and returns the report.
fn fair_file(input: &str, more: &[&str]) -> Value {
    fair_args(input, PER_ROLE.iter().copied().chain(more.iter().copied()))
}

/// Fairs `fixtures/occt_variants/NAME.step` with the model's default deviation (0.05 mm
/// everywhere) and returns the report.
fn fair_default(name: &str) -> Value {
    fair_args(&variant(name, "step"), std::iter::empty())
}

/// Fairs the model file `input` with the arguments `more` and returns the report.
fn fair_args<'a>(input: &str, more: impl Iterator<Item = &'a str>) -> Value {
    let tmp = tempfile::tempdir().unwrap();
    let (out, report) = (tmp.path().join("out.json"), tmp.path().join("report.json"));
    let (out, report) = (out.to_str().unwrap(), report.to_str().unwrap());
    let mut args: Vec<String> = ["fair", input, "-o", out, "--report", report, "--quiet"]
        .map(String::from)
        .to_vec();
    args.extend(more.map(String::from));
    hier_fair(&args.iter().map(String::as_str).collect::<Vec<_>>());
    serde_json::from_str(&std::fs::read_to_string(report).unwrap()).unwrap()
}

/// The links of `report` that end unmet, as "slave.side".
fn unmet(report: &Value) -> Vec<String> {
    let links = report["links"].as_array().unwrap();
    links
        .iter()
        .filter(|l| !l["met"].as_bool().unwrap())
        .map(|l| {
            format!(
                "{}.{}",
                l["slave"].as_str().unwrap(),
                l["side"].as_str().unwrap()
            )
        })
        .collect()
}

/// Fairs each of `names` and checks that nothing leaves worse than it came: every link's gap and
/// angle, every shared edge, every surface's deviation. Returns the reports.
fn never_worse(names: &[&str]) -> Vec<Value> {
    names
        .iter()
        .map(|name| {
            let r = fair(name);
            for l in r["links"].as_array().unwrap() {
                let (b, a) = (&l["before"], &l["after"]);
                let grew =
                    |k: &str, tol: f64| a[k].as_f64().unwrap() > b[k].as_f64().unwrap() + tol;
                assert!(
                    !grew("g0", G0) && !grew("g1_deg", G1_DEG),
                    "{name}: {}.{} worse than its input: {b} -> {a}",
                    l["slave"],
                    l["side"]
                );
            }
            for e in r["shared_edges"].as_array().unwrap() {
                assert!(!e["worse"].as_bool().unwrap(), "{name}: edge {e}");
            }
            for s in r["surfaces"].as_array().unwrap() {
                let (d, t) = (
                    s["max_deviation"].as_f64().unwrap(),
                    s["tolerance"].as_f64().unwrap(),
                );
                assert!(d <= t, "{name}: {} deviates {d} > {t}", s["name"]);
            }
            r
        })
        .collect()
}

#[test]
fn boxes_with_spherical_corners_reach_g2_everywhere() {
    // the larger radius puts the blends' curvature above the flatness cut-off near their poles,
    // where the widest lead-in misses by accuracy: the narrower one the search tries meets
    for r in never_worse(&["box12_r4", "box12_r7"]) {
        assert!(unmet(&r).is_empty(), "unmet: {:?}", unmet(&r));
    }
}

#[test]
fn variable_radius_boxes_reach_g2_everywhere() {
    // box12_var2's freeform blend has two degenerate corners (a side meets a fillet's end
    // tangentially): the polished continuity setting met the two fillet sides there but left
    // the plane side's angle at 2.2 tolerances next to the corner, until the polish reweights
    // its residuals towards a minimax fit (47 of 49 links without)
    for r in never_worse(&["box12_var", "box12_var2"]) {
        assert!(unmet(&r).is_empty(), "unmet: {:?}", unmet(&r));
    }
}

/// box12_variable of `fixtures/occt` read from its STEP file, as a user brings it: its freeform
/// vertex blend comes as two C¹ spans of degree 6 (the JSON export of the same solid has one span
/// of degree 8). The blend's G2 step joins its sides at every sample but the corners only after
/// a refinement round, and which round is kept decides: keeping the first, which misses the
/// whole sides as far, left all four sides missed (45 of 49).
#[test]
fn the_variable_radius_box_as_its_step_file_has_it_reaches_g2_everywhere() {
    let input =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/occt/occt_box12_variable.step");
    let r = fair_file(input.to_str().unwrap(), &[]);
    assert_eq!(r["links"].as_array().unwrap().len(), 49);
    assert!(unmet(&r).is_empty(), "unmet: {:?}", unmet(&r));
}

/// By default too: box12_var's freeform blend at the varying edge met its last side only in
/// the polish's reweighted rounds with a whole round's iterations each (47 of 49 without, and
/// the second run that names what the misses need took as long as the first).
#[test]
fn the_variable_radius_box_meets_every_link_by_default() {
    let r = fair_default("box12_var");
    assert!(unmet(&r).is_empty(), "unmet: {:?}", unmet(&r));
}

#[test]
fn three_radii_corners_reach_g2_everywhere() {
    for r in never_worse(&["corner3_a", "corner3_b"]) {
        assert!(unmet(&r).is_empty(), "unmet: {:?}", unmet(&r));
    }
}

#[test]
fn plates_with_bosses_reach_g2_everywhere() {
    for r in never_worse(&["plate_boss_a", "plate_boss_b"]) {
        assert!(unmet(&r).is_empty(), "unmet: {:?}", unmet(&r));
    }
}

/// Every shared edge of `report` (the seams of a ring) leaves within the G0/G1 tolerances.
fn assert_seams_closed(report: &Value) {
    for e in report["shared_edges"].as_array().unwrap() {
        let after = &e["after"];
        assert!(
            after["g0"].as_f64().unwrap() <= G0 && after["g1_deg"].as_f64().unwrap() <= G1_DEG,
            "seam {} open: {after}",
            e["edge"]
        );
    }
}

#[test]
fn pipe_tees_reach_g2_everywhere_with_their_seams_closed() {
    // the saddle fillet is two halves joined by seams, faired in the same wave: each half turns
    // its boundaries' end tangents at the seams into its masters' planes, so both take the
    // masters' normals there and the seams stay within the G1 tolerance (pipe_tee_b per role
    // opened them to 0.0118° without it, and lost G2 when run again with them kept)
    for r in never_worse(&["pipe_tee_a", "pipe_tee_b"]) {
        assert!(unmet(&r).is_empty(), "unmet: {:?}", unmet(&r));
        assert_seams_closed(&r);
    }
}

#[test]
fn an_opened_seam_is_closed_by_linking_the_later_part_to_the_earlier() {
    // a ring of fillet parts from another system (`fixtures/foreign/trj1_t4m-ac.stp`) by
    // default: the continuity steps of part 20DD open its seams with the parts B1 and 20DB
    // (3.2e-3 mm, 0.02°; input 1e-11 mm); 20DD is run again with its seams linked G2 to them,
    // which keep their free results. (The kernel's pipe tee opened its halves' seams with the
    // fairing limited by hand until its halves took one-hump sections, whose seams stay shut.)
    let ring = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/foreign/trj1_t4m-ac.stp");
    let r = fair_args(ring.to_str().unwrap(), std::iter::empty());
    let problems = r["problems"].as_array().unwrap();
    let linked: Vec<&str> = problems
        .iter()
        .filter(|p| {
            p["message"]
                .as_str()
                .unwrap()
                .contains("seams to it linked G2")
        })
        .map(|p| p["surface"].as_str().unwrap())
        .collect();
    assert!(
        !linked.is_empty(),
        "the free run no longer opens a seam here: pick a setting that does ({problems:#?})"
    );
    assert_seams_closed(&r);
    // the earlier parts keep their free results, whose links are met
    for l in r["links"].as_array().unwrap() {
        let slave = l["slave"].as_str().unwrap();
        if !linked.contains(&slave) {
            assert!(l["met"].as_bool().unwrap(), "{slave}.{} unmet", l["side"]);
        }
        let (b, a) = (&l["before"], &l["after"]);
        for (k, tol) in [("g0", G0), ("g1_deg", G1_DEG)] {
            assert!(
                a[k].as_f64().unwrap() <= b[k].as_f64().unwrap() + tol,
                "{l}"
            );
        }
    }
}

#[test]
fn lofted_blocks_reach_g2_everywhere() {
    // loft_block_b's lateral fillet step1734 starts with a sliver span 0.008 mm long (degree 7,
    // joined C¹): the fairing folded it over and the vertex blend on that fillet missed all four
    // G2 sides (20 of 24 links) until the sliver is merged into its neighbour before the stages
    for r in never_worse(&["loft_block_a", "loft_block_b"]) {
        assert!(unmet(&r).is_empty(), "unmet: {:?}", unmet(&r));
    }
}

/// `hier-fair import fixtures/occt_variants/NAME.EXT`: the surfaces' roles, counted (primary,
/// connecting, corner).
fn roles(name: &str, ext: &str) -> [usize; 3] {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("model.json");
    hier_fair(&["import", &variant(name, ext), "-o", out.to_str().unwrap()]);
    let model: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let count = |role: &str| {
        let surfaces = model["surfaces"].as_array().unwrap();
        surfaces.iter().filter(|s| s["role"] == role).count()
    };
    [count("primary"), count("connecting"), count("corner")]
}

#[test]
fn iges_and_step_give_every_variant_the_same_roles() {
    // the three-radii corner's blend turns 90° between two opposite sides and is long and
    // narrow (radii 4, 10 and 7): read from IGES (faces cut to other boxes) it came out a
    // fillet, 0.48 as wide as long; it lies across the ends of three fillets, a vertex blend
    assert_eq!(roles("corner3_b", "igs"), [6, 3, 1]);
    let names = [
        "box12_r4",
        "box12_r7",
        "box12_var",
        "box12_var2",
        "corner3_a",
        "corner3_b",
        "loft_block_a",
        "loft_block_b",
        "pipe_tee_a",
        "pipe_tee_b",
        "plate_boss_a",
        "plate_boss_b",
    ];
    for name in names {
        assert_eq!(roles(name, "igs"), roles(name, "step"), "{name}");
    }
}
