//! Bare multi-patch files (the Utah teapot, teacup and teaspoon of `fixtures/third_party`, bicubic
//! Bézier patches): fairing keeps every shared edge's gap and normal angle within
//! max(input, 0.01°), knots inserted where a patch has too few rows for its frames.

use g_continuity::{MeasureParams, measure_link};
use hier_fair_cli::fair::{FairOptions, fair_surfaces};
use nurbs_core::{BSplineSurface, Continuity};

fn patches(name: &str) -> Vec<BSplineSurface> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/third_party")
        .join(name);
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{} is in the repository: {e}", path.display()));
    nurbs_core::io::surfaces_from_json(&text).unwrap()
}

#[test]
fn shared_edges_keep_their_continuity() {
    for name in ["teapot.json", "teacup.json", "teaspoon.json"] {
        let input = patches(name);
        let shared = hier_fair::patches::shared_sides(&input);
        let edges = shared.iter().flatten().flatten().count();
        assert!(edges >= input.len(), "{name}: {edges} shared sides");
        let options = FairOptions {
            method: "energy",
            tolerance: 0.02,
            iterations: None,
            keep: Continuity::G0,
        };
        let (output, report) = fair_surfaces(&input, &options).unwrap();
        let measure = MeasureParams::default();
        for (a, sides) in shared.iter().enumerate() {
            for (side, s) in sides.iter() {
                let Some(s) = s else { continue };
                let before = measure_link(&input[s.other], &input[a], side, &measure).unwrap();
                let after = measure_link(&output[s.other], &output[a], side, &measure).unwrap();
                assert!(
                    after.g0 <= before.g0.max(1e-9),
                    "{name}: patch {a} {side:?} gap {} -> {}",
                    before.g0,
                    after.g0
                );
                if s.tangent() {
                    // the kept rows are fixed in fairing; the knots inserted first into a
                    // patch with too few rows recompute its rows exactly up to round-off, which
                    // turns a normal by about 1e-12 rad: 1e-9° (2e-11 rad) allows for it
                    let (b, f) = (before.g1_deg.unwrap(), after.g1_deg.unwrap());
                    assert!(
                        f <= b.max(0.01) + 1e-9,
                        "{name}: patch {a} {side:?} angle {b}° -> {f}°"
                    );
                }
            }
        }
        // and the fairing did something: the total energy went down
        let (e0, e1) = report.surfaces.iter().fold((0.0, 0.0), |(x, y), l| {
            (x + l.energy_before, y + l.energy_after)
        });
        assert!(e1 < e0, "{name}: {e0} -> {e1}");
    }
}
