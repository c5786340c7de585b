//! Fairs a model a CAD kernel exported (the plate with a filleted boss of `fixtures/occt/`) and
//! prints every link before and after, the way `hier-fair fair` does without the files.
//!
//!     cargo run --release -p hier-fair --example fair_kernel_model [MODEL.json]

use hier_fair::{FairParams, Model, RoleMethods, fair_model};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args().nth(1).unwrap_or_else(|| {
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../fixtures/occt/occt_plate_boss.json"
        )
        .into()
    });
    let model = Model::from_json(&std::fs::read_to_string(&path)?)?;
    // the default methods per role (energy fairing) and the model's own tolerances
    let (_faired, report) = fair_model(
        &model,
        &RoleMethods::default(),
        None,
        &FairParams::default(),
    )?;
    for l in &report.links {
        let (Some(b), Some(a)) = (&l.before, &l.after) else {
            continue;
        };
        println!(
            "{:32} {:?}  gap {:.1e} -> {:.1e}  angle {:.1e}° -> {:.1e}°  curvature {:.1e} -> {:.1e}  {}",
            l.label,
            l.target,
            b.g0,
            a.g0,
            b.g1_deg.unwrap_or(0.0),
            a.g1_deg.unwrap_or(0.0),
            b.g2_rel.unwrap_or(0.0),
            a.g2_rel.unwrap_or(0.0),
            if l.met { "met" } else { "NOT met" }
        );
    }
    for p in &report.problems {
        println!("{p}");
    }
    Ok(())
}
