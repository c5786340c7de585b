//! `hier-fair check MODEL.json [--samples K] [--json] [--fail-above PRESET]`: measures the
//! continuity of every link (cli-contract.md) as a readable table or JSON.

use std::path::PathBuf;

use crate::files;
use anyhow::{Result, anyhow};
use g_continuity::MeasureParams;
use hier_fair::check::{checks_json, continuity_name, optional_json};
use hier_fair::{LinkCheck, Model, Preset, SurfaceJoins, measure_model, surface_joins};
use serde_json::{Value, json};

/// What `check` prints and whether a preset was exceeded (exit code 1).
#[derive(Debug, Clone)]
pub struct CheckOutcome {
    /// the table or JSON text
    pub text: String,
    /// true when a link exceeds the `--fail-above` preset
    pub exceeded: bool,
    /// how many links were measured (`--samples` applies to them alone)
    pub links: usize,
    /// how many surfaces have C⁰ knot lines (`--fail-above` judges them with the links)
    pub joins: usize,
}

/// Runs `check` on the text of a model (or bare surface) file; `source` names it in errors.
pub fn run(
    model_text: &str,
    source: &str,
    samples: usize,
    as_json: bool,
    fail_above: Option<&str>,
) -> Result<CheckOutcome> {
    run_with(model_text, source, samples, as_json, fail_above, false)
}

/// [`run`], and with `fairness` the fairness figures of every surface too (`check --fairness`,
/// hier-fair's `fairness` module): a table after the links, or a `fairness` array in the JSON.
pub fn run_with(
    model_text: &str,
    source: &str,
    samples: usize,
    as_json: bool,
    fail_above: Option<&str>,
    fairness: bool,
) -> Result<CheckOutcome> {
    let preset = match fail_above {
        None => None,
        Some(name) => Some(Preset::named(name).ok_or_else(|| {
            anyhow!(
                "unknown preset {name:?} (expected one of {})",
                Preset::NAMES.join(", ")
            )
        })?),
    };
    let model = Model::from_json(model_text).map_err(|e| anyhow!("{source}: {e}"))?;
    // a preset's gap is millimetres; the model's measures are in its unit
    let preset = preset.map(|p| Preset {
        g0: p.g0 / model.mm_per_unit(),
        ..p
    });
    let params = MeasureParams {
        samples,
        ..MeasureParams::default()
    };
    // links that do not touch their masters are measured and reported too (their gap shows)
    let checks = measure_model(&model, &params).map_err(|e| anyhow!("{source}: {e}"))?;
    let flags: Vec<bool> = checks
        .iter()
        .map(|c| preset.is_some_and(|p| p.exceeded_by(c)))
        .collect();
    // the surfaces' own C0 knot lines: a normal jump across one is a G1 break inside the
    // surface, judged against the preset's angle like a link's
    let joins = surface_joins(&model);
    let join_flags: Vec<bool> = joins
        .iter()
        .map(|j| preset.is_some_and(|p| j.crease_deg.is_some_and(|d| d > p.g1_deg)))
        .collect();
    let exceeded = flags.iter().chain(&join_flags).any(|&f| f);
    let text = if as_json {
        let mut v = checks_json(&model, &checks, preset.map(|_| flags.as_slice()));
        if !joins.is_empty() {
            v["surfaces"] = joins_json(&joins, preset.map(|_| join_flags.as_slice()));
        }
        if fairness {
            v["fairness"] = fairness_json(&model);
        }
        serde_json::to_string_pretty(&v)? + "\n"
    } else {
        let mut text = table(
            &model,
            &checks,
            preset.map(|_| flags.as_slice()),
            fail_above,
        ) + &joins_table(&joins, preset.map(|_| join_flags.as_slice()), fail_above);
        if fairness {
            text += &fairness_table(&model);
        }
        text + &verdict(&model, &checks)
    };
    Ok(CheckOutcome {
        text,
        exceeded,
        links: checks.len(),
        joins: joins.len(),
    })
}

/// `hier-fair check` (the subcommand's arguments as parsed).
pub fn command(
    model: PathBuf,
    samples: Option<usize>,
    json: bool,
    fail_above: Option<String>,
    fairness: bool,
    html: Option<PathBuf>,
) -> Result<()> {
    if let Some(h) = &html {
        crate::kind::expect_extension("--html", h, crate::kind::HTML_OUTPUTS)?;
        files::check_outputs(&[("--html", h.as_path())], &[&model])?;
    }
    crate::kind::expect(
        "check",
        &model,
        &[
            crate::kind::FileKind::Model,
            crate::kind::FileKind::Surfaces,
        ],
    )?;
    let text = files::read_text(&model)?;
    let outcome = crate::check::run_with(
        &text,
        &model.display().to_string(),
        samples.unwrap_or(101),
        json,
        fail_above.as_deref(),
        fairness,
    )?;
    if let Some(h) = &html {
        crate::check::write_html(
            &text,
            &model.display().to_string(),
            samples.unwrap_or(101),
            h,
        )?;
    }
    if let (Some(k), 0) = (samples, outcome.links) {
        eprintln!(
            "warning: --samples {k} applies to a model's links; {} has no links: nothing was sampled",
            model.display()
        );
    }
    if let (Some(p), 0, 0) = (&fail_above, outcome.links, outcome.joins) {
        eprintln!(
            "warning: --fail-above {p} has nothing to judge: {} has no links and no surface with C0 knot lines",
            model.display()
        );
    }
    print!("{}", outcome.text);
    if outcome.exceeded {
        use std::io::Write;
        let _ = std::io::stdout().flush();
        std::process::exit(1);
    }
    Ok(())
}

/// `check --html`: the model's quality report ([`hier_fair::html`]), its link table the links of
/// `check --json` measured with `samples` samples, written atomically to `path`.
pub fn write_html(
    model_text: &str,
    source: &str,
    samples: usize,
    path: &std::path::Path,
) -> Result<()> {
    let model = Model::from_json(model_text).map_err(|e| anyhow!("{source}: {e}"))?;
    let params = MeasureParams {
        samples,
        ..MeasureParams::default()
    };
    let checks = measure_model(&model, &params).map_err(|e| anyhow!("{source}: {e}"))?;
    let checks = checks_json(&model, &checks, None);
    let page = hier_fair::html::html_report(&hier_fair::html::HtmlReport {
        title: &format!("hier-fair check {source}"),
        model: &model,
        faired: None,
        report: None,
        checks: Some(&checks),
    });
    crate::files::write_atomic(path, page.as_bytes())
}

fn fmt_opt(x: Option<f64>, prec: usize) -> String {
    match x {
        Some(v) => format!("{v:.prec$e}"),
        None => "-".into(),
    }
}

fn table(
    model: &Model,
    checks: &[LinkCheck],
    flags: Option<&[bool]>,
    preset: Option<&str>,
) -> String {
    let width = checks
        .iter()
        .map(|c| c.label.len())
        .max()
        .unwrap_or(4)
        .max(4);
    let t = &model.tolerances;
    let met = |c: &LinkCheck| c.measure.meets(c.target, t.g0, t.g1_deg, t.g2_rel);
    let mut out = format!(
        "{:width$}  {:6}  {:>7}  {:>10}  {:>10}  {:>10}  {:>10}  {:>10}  {:4}  {}\n",
        "link",
        "target",
        "samples",
        "gap",
        "angle°",
        "g2 rel",
        "g2 abs",
        "g2 across",
        "met",
        "note"
    );
    for (k, c) in checks.iter().enumerate() {
        let m = &c.measure;
        let mut note = Vec::new();
        if !c.touches(model) {
            note.push(format!(
                "DOES NOT TOUCH its master (gap above {} × g0)",
                hier_fair::TOUCH_FACTOR
            ));
        }
        if m.collapsed {
            note.push("collapsed side".to_string());
        } else if m.undefined_normals > 0 {
            note.push(format!("{} samples without normal", m.undefined_normals));
        }
        if let (Some(f), Some(p)) = (flags, preset) {
            note.push(if f[k] {
                format!("EXCEEDS {p}")
            } else {
                format!("ok for {p}")
            });
        }
        out += &format!(
            "{:width$}  {:6}  {:>7}  {:>10.3e}  {:>10}  {:>10}  {:>10}  {:>10}  {:4}  {}\n",
            c.label,
            continuity_name(c.target),
            m.samples,
            m.g0,
            fmt_opt(m.g1_deg, 3),
            fmt_opt(m.g2_rel, 3),
            fmt_opt(m.g2_abs, 3),
            fmt_opt(m.g2_rel_across, 3),
            if met(c) { "yes" } else { "no" },
            note.join("; ")
        );
    }
    if checks.is_empty() {
        out += "(the model has no links)\n";
    }
    out += &format!(
        "model tolerances: g0 {} · g1 {}° · g2 {}\n",
        t.g0, t.g1_deg, t.g2_rel
    );
    out
}

/// "N of M links met (G0 ≤ …, G1 ≤ …°, G2 ≤ … relative" — the start of every verdict line
/// (`check`, `connect`, `fair`), the parenthesis left open for what follows; the gap in the
/// model's unit, named where the model is not in millimetres.
pub fn links_met(met: usize, total: usize, model: &Model) -> String {
    let t = &model.tolerances;
    let unit = match model.units.as_deref() {
        Some(u) if model.mm_per_unit() != 1.0 => format!(" {u}"),
        _ => String::new(),
    };
    let g0 = match format!("{}", t.g0) {
        short if short.len() <= 8 => short,
        _ => format!("{:.3e}", t.g0),
    };
    format!(
        "{met} of {total} links met (G0 ≤ {g0}{unit}, G1 ≤ {}°, G2 ≤ {} relative",
        t.g1_deg, t.g2_rel
    )
}

/// The last line of `check`'s table: how many links meet the model's tolerances.
fn verdict(model: &Model, checks: &[LinkCheck]) -> String {
    let t = &model.tolerances;
    let met = |c: &LinkCheck| c.measure.meets(c.target, t.g0, t.g1_deg, t.g2_rel);
    let untouched = checks.iter().filter(|c| !c.touches(model)).count();
    format!(
        "verdict: {}, each up to its target){}\n",
        links_met(
            checks.iter().filter(|c| met(c)).count(),
            checks.len(),
            model
        ),
        if untouched > 0 {
            format!("; {untouched} do not touch their masters")
        } else {
            String::new()
        }
    )
}

fn joins_json(joins: &[SurfaceJoins], flags: Option<&[bool]>) -> Value {
    let list: Vec<Value> = joins
        .iter()
        .enumerate()
        .map(|(k, j)| {
            let mut v = json!({
                "name": j.name,
                "knot_lines": j.lines,
                "crease_deg": optional_json(j.crease_deg),
            });
            if let Some(f) = flags {
                v["exceeded"] = json!(f[k]);
            }
            v
        })
        .collect();
    Value::Array(list)
}

fn joins_table(joins: &[SurfaceJoins], flags: Option<&[bool]>, preset: Option<&str>) -> String {
    let mut out = String::new();
    for (k, j) in joins.iter().enumerate() {
        let note = match (flags, preset) {
            (Some(f), Some(p)) if f[k] => format!("  EXCEEDS {p}"),
            (Some(_), Some(p)) => format!("  ok for {p}"),
            _ => String::new(),
        };
        out += &format!(
            "surface {}: {} C0 knot line(s), largest normal jump across them {}°{}\n",
            j.name,
            j.lines,
            fmt_opt(j.crease_deg, 3),
            note
        );
    }
    out
}

/// Every surface's fairness figures (hier-fair `fairness`), as `check --json --fairness` lists
/// them: the name and role with the fields of a fair report's `fairness_after`.
fn fairness_json(model: &Model) -> Value {
    let list: Vec<Value> = model
        .surfaces
        .iter()
        .zip(hier_fair::fairness::model_fairness(model))
        .map(|(s, f)| {
            let mut v = hier_fair::report::fairness_json(&f);
            v["name"] = json!(s.name);
            v["role"] = json!(s.role.name());
            v
        })
        .collect();
    Value::Array(list)
}

/// Every surface's fairness figures as a table (units per model unit).
fn fairness_table(model: &Model) -> String {
    let unit = model.units.as_deref().unwrap_or("unit");
    let mut out = format!(
        "\n{:<24} {:<10} {:>12} {:>12} {:>12} {:>8} {:>12} {:>9} {:>6}\n",
        "surface",
        "role",
        format!("peak 1/{unit}"),
        format!("max 1/{unit}"),
        "H spread",
        "extrema",
        "energy",
        "net",
        "degree"
    );
    for (s, f) in model
        .surfaces
        .iter()
        .zip(hier_fair::fairness::model_fairness(model))
    {
        out += &format!(
            "{:<24} {:<10} {:>12.4e} {:>12.4e} {:>12.3e} {:>8} {:>12.4e} {:>9} {:>6}\n",
            s.name,
            s.role.name(),
            f.peak_curvature,
            f.max_curvature,
            f.mean_curvature_spread,
            f.cross_extrema.map_or("–".to_string(), |n| n.to_string()),
            f.energy,
            format!("{}×{}", f.net.0, f.net.1),
            format!("{}/{}", f.degree.0, f.degree.1),
        );
    }
    out += "peak: the 99th percentile of the largest principal curvature; extrema: of the normal curvature along the iso-lines across a slave's linked sides (links found on shared edges included)\n";
    out
}
