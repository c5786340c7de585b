//! The X-node (\[SV\] Fig. 6, `fixtures/models/x_node.json`): four primaries, the four fillets
//! between them and the corner patch where the fillets meet, faired in the framework order —
//! primaries, then fillets (G2 to the primaries), then the corner (G2 to the fillets).
//!
//!     cargo run --release -p hier-fair --example fair_x_node

use hier_fair::{FairParams, Model, RoleMethods, fair_model};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../fixtures/models/x_node.json"
    );
    let model = Model::from_json(&std::fs::read_to_string(path)?)?;
    let (_faired, report) = fair_model(
        &model,
        &RoleMethods::default(),
        None,
        &FairParams::default(),
    )?;
    for s in &report.surfaces {
        println!(
            "{:10} {:10} energy {:.4e} -> {:.4e}, deviation {:.2e} (tolerance {})",
            s.name,
            s.role.name(),
            s.energy_before,
            s.energy_after,
            s.max_deviation,
            s.tolerance
        );
        assert!(
            s.max_deviation <= s.tolerance,
            "{} beyond its tolerance",
            s.name
        );
    }
    let met = report.links.iter().filter(|l| l.met).count();
    println!(
        "{met}/{} links met in {:.2} s",
        report.links.len(),
        report.seconds_total
    );
    for p in &report.problems {
        println!("{p}");
    }
    Ok(())
}
