//! `hier-fair connect MODEL.json -o OUT.json [--target G1|G2] [--report R.json]`: sets
//! continuity only (no fairing), slave by slave in hierarchy order (cli-contract.md).

use anyhow::{Result, anyhow};
use hier_fair::{ConnectOptions, Model, ModelConnectReport, connect};
use nurbs_core::Continuity;
use serde_json::{Value, json};

use hier_fair::check::continuity_name;

/// What `connect` produces.
#[derive(Debug, Clone)]
pub struct ConnectOutcome {
    /// the output model (JSON)
    pub model_json: String,
    /// the report (cli-contract.md `--report`)
    pub report: Value,
    /// a readable summary for stdout
    pub summary: String,
    /// the verdict line without its ending "; wrote OUT" (the caller knows what it wrote)
    pub verdict: String,
}

/// Runs `connect` on the text of a model (or bare surface) file; `source` names it in errors.
pub fn run(model_text: &str, source: &str, target: Option<Continuity>) -> Result<ConnectOutcome> {
    let model = Model::from_json(model_text).map_err(|e| anyhow!("{source}: {e}"))?;
    let options = ConnectOptions {
        target,
        ..ConnectOptions::default()
    };
    let (out, report) = connect(&model, &options).map_err(|e| anyhow!("{source}: {e}"))?;
    let mut text = summary(&report, &model);
    let t = &model.tolerances;
    let met = report
        .links
        .iter()
        .filter(|l| l.after.meets(l.target, t.g0, t.g1_deg, t.g2_rel))
        .count();
    let verdict = format!(
        "verdict: {}, each up to its target)",
        crate::check::links_met(met, report.links.len(), &model)
    );
    if model.links.is_empty() {
        text += &format!(
            "note: {source} has no links: nothing was set{} (`build` finds a model's links from its geometry)\n",
            if target.is_some() {
                ", and --target has nothing to apply to"
            } else {
                ""
            }
        );
    }
    // `--target` caps each link's own continuity; say so where it asks for more than any link
    if let (Some(t), Some(top)) = (target, model.links.iter().map(|l| l.continuity).max())
        && t > top
    {
        text += &format!(
            "note: --target {t:?} is a cap: no link of the model asks for more than {top:?}, so that is what was set (a link's continuity is its \"continuity\" in the model)\n"
        );
    }
    Ok(ConnectOutcome {
        model_json: out.to_json(),
        report: report_json(&model, &report),
        summary: text,
        verdict,
    })
}

fn brief(m: &g_continuity::LinkMeasure) -> Value {
    json!({ "g0": m.g0, "g1_deg": m.g1_deg, "g2_rel": m.g2_rel })
}

/// The report JSON of cli-contract.md (plus connect's own fields).
pub fn report_json(model: &Model, r: &ModelConnectReport) -> Value {
    let surfaces: Vec<Value> = r
        .surfaces
        .iter()
        .map(|s| {
            json!({
                "name": s.name, "role": s.role.name(), "method": "connect",
                "energy_before": s.energy_before, "energy_after": s.energy_after,
                "max_deviation": s.max_deviation, "iterations": s.refinements, "seconds": s.seconds,
                "max_control_movement": s.max_control_movement, "knots_inserted": s.knots_inserted,
                "twists_averaged": s.twists_averaged,
            })
        })
        .collect();
    let links: Vec<Value> = r
        .links
        .iter()
        .map(|l| {
            let link = &model.links[l.link];
            json!({
                "slave": model.surfaces[link.slave].name, "side": link.side.name(),
                "master": model.surfaces[link.master].name, "target": continuity_name(l.target),
                "before": brief(&l.before), "after": brief(&l.after),
            })
        })
        .collect();
    // the same shape as `fair`'s problems (cli-contract.md)
    let problems: Vec<Value> = r
        .surfaces
        .iter()
        .filter_map(|s| {
            let why = s.fallback.as_ref()?;
            Some(json!({
                "kind": "limited", "surface": s.name, "link": null, "message": why, "amount": null,
            }))
        })
        .collect();
    json!({ "seconds_total": r.seconds_total, "surfaces": surfaces, "links": links, "problems": problems })
}

/// The link table: gap, normal angle and relative curvature difference before and after side
/// by side, whether the link is met (up to its target, against the model's tolerances), and
/// the tolerances; then the slaves that fell back and the totals.
fn summary(r: &ModelConnectReport, model: &Model) -> String {
    let width = r
        .links
        .iter()
        .map(|l| l.label.len())
        .max()
        .unwrap_or(4)
        .max(4);
    let t = &model.tolerances;
    let mut out = String::new();
    if !r.links.is_empty() {
        out += &format!(
            "{:width$}  {:6}  {:>10} {:>10}  {:>10} {:>10}  {:>10} {:>10}  met\n",
            "link", "target", "gap before", "after", "angle° bef", "after", "g2 rel bef", "after"
        );
    }
    let f = |x: Option<f64>| x.map_or("-".to_string(), |v| format!("{v:.3e}"));
    for l in &r.links {
        let met = l.after.meets(l.target, t.g0, t.g1_deg, t.g2_rel);
        out += &format!(
            "{:width$}  {:6}  {:>10.3e} {:>10.3e}  {:>10} {:>10}  {:>10} {:>10}  {}\n",
            l.label,
            continuity_name(l.target),
            l.before.g0,
            l.after.g0,
            f(l.before.g1_deg),
            f(l.after.g1_deg),
            f(l.before.g2_rel),
            f(l.after.g2_rel),
            if met { "yes" } else { "no" }
        );
    }
    if !r.links.is_empty() {
        out += &format!(
            "model tolerances: g0 {} · g1 {}° · g2 {}\n",
            t.g0, t.g1_deg, t.g2_rel
        );
    }
    for s in &r.surfaces {
        if let Some(why) = &s.fallback {
            out += &format!("limited: {}: {why}\n", s.name);
        }
    }
    let moved = r
        .surfaces
        .iter()
        .map(|s| s.max_control_movement)
        .fold(0.0, f64::max);
    let knots: usize = r.surfaces.iter().map(|s| s.knots_inserted).sum();
    out += &format!(
        "{} slaves connected in {:.2} s; largest control point movement {moved:.3e}; {knots} knots inserted\n",
        r.surfaces.len(),
        r.seconds_total
    );
    out
}
