//! The reports of a fairing run: `report.json` (the CLI contract's `fair --report` format plus
//! optional fields) and `report.md` (per link a before/after continuity table, per surface energy
//! before/after, deviation, method and time, the totals, and every problem).

use std::fmt::Write;

use g_continuity::LinkMeasure;
use serde_json::{Value, json};

use nurbs_core::Fairness;

use crate::fairness::FairnessVerdict;
use crate::framework::{FairModelReport, LinkFair};

fn measure_json(m: &Option<LinkMeasure>) -> Value {
    match m {
        Some(m) => json!({
            "g0": m.g0,
            "g1_deg": m.g1_deg,
            "g2_rel": m.g2_rel,
            "g2_abs": m.g2_abs,
            "g2_rel_across": m.g2_rel_across,
            "g2_abs_across": m.g2_abs_across,
            "g1_deg_vertex": m.vertex_g1_deg,
            "g2_rel_vertex": m.vertex_g2_rel,
            "vertex_zones": m.vertex_zones,
        }),
        None => Value::Null,
    }
}

/// One surface of the report as JSON (cli-contract.md's `surfaces` entry).
fn surface_json(s: &crate::framework::SurfaceFair) -> Value {
    json!({
        "name": s.name,
        "role": s.role.name(),
        "method": s.method,
        "energy_before": s.energy_before,
        "energy_after": s.energy_after,
        "max_deviation": s.max_deviation,
        "tolerance": s.tolerance,
        "degree": [s.degree.0, s.degree.1],
        "net_before": [s.net.0.0, s.net.0.1],
        "net_after": [s.net.1.0, s.net.1.1],
        "iterations": s.iterations,
        "seconds": s.seconds,
        "knots_inserted": s.knots_inserted,
        "processed": s.processed,
        "crease_deg_before": s.crease_deg.0,
        "crease_deg_after": s.crease_deg.1,
        "fairness_before": fairness_json(&s.fairness.0),
        "fairness_after": fairness_json(&s.fairness.1),
        "fairness": verdict_json(&s.fairness_verdict()),
        "joint_curvature": s.joint_curvature,
        "section_ramp": s.stages.first().and_then(|st| st.section_ramp),
        "stages": s.stages.iter().map(|st| json!({
            "stage": st.stage.name(),
            "seconds": st.seconds,
            "max_move": if st.max_move.is_finite() { json!(st.max_move) } else { Value::Null },
            "deviation": st.deviation,
            "energy": st.energy,
            "iterations": st.iterations,
            "knots_inserted": st.knots_inserted,
            "epsilon": st.epsilon,
            "section_ramp": st.section_ramp,
        })).collect::<Vec<_>>(),
    })
}

/// The report as JSON (cli-contract.md: `seconds_total`, `surfaces`, `links`; plus
/// `tolerance`, per-surface `stages` and `knots_inserted`, per-link `met`, and `problems`).
pub fn report_json(report: &FairModelReport) -> Value {
    let surfaces: Vec<Value> = report.surfaces.iter().map(surface_json).collect();
    let links: Vec<Value> = report.links.iter().map(link_json).collect();
    let problems: Vec<Value> = report
        .problems
        .iter()
        .map(|p| {
            json!({
                "kind": p.kind.name(),
                "surface": p.surface,
                "link": p.link,
                "message": p.message,
                "amount": p.amount,
            })
        })
        .collect();
    let groups: Vec<Value> = report
        .groups
        .iter()
        .map(|g| {
            json!({
                "name": g.name,
                "applied": g.applied,
                "max_deviation": g.max_deviation,
                "mesh_vertices": g.mesh_vertices,
                "refit_max_error": g.refit_max_error,
                "internal_angle_deg": g.internal_angle_deg,
            })
        })
        .collect();
    let mut out = json!({
        "seconds_total": report.seconds_total,
        "tolerance": report.tolerance,
        "surfaces": surfaces,
        "links": links,
        "corner_groups": groups,
        "problems": problems,
        "shared_edges": report.edges.iter().map(|e| json!({
            "edge": e.label,
            "fraction": e.fraction,
            "before": {"g0": e.before.gap, "g1_deg": e.before.angle_deg},
            "after": {"g0": e.after.gap, "g1_deg": e.after.angle_deg},
            "worse": e.worse,
        })).collect::<Vec<_>>(),
    });
    if !report.pole_splits.is_empty() {
        out["pole_splits"] = report.pole_splits.iter().map(pole_split_json).collect();
    }
    out
}

/// One pole corner's split (or why it was kept) as JSON.
fn pole_split_json(p: &crate::poles::PoleSplit) -> Value {
    match &p.outcome {
        crate::poles::PoleOutcome::Split {
            quads,
            control_points,
            fit_error,
        } => json!({
            "surface": p.surface,
            "split": true,
            "quads": quads,
            "control_points": control_points,
            "fit_error": fit_error,
        }),
        crate::poles::PoleOutcome::Kept { reason } => json!({
            "surface": p.surface,
            "split": false,
            "reason": reason,
        }),
    }
}

/// The fairness figures of one surface as JSON ([`nurbs_core::fairness()`]).
pub fn fairness_json(f: &Fairness) -> Value {
    json!({
        "energy": f.energy,
        "peak_curvature": f.peak_curvature,
        "max_curvature": f.max_curvature,
        "mean_curvature_spread": f.mean_curvature_spread,
        "cross_extrema": f.cross_extrema,
        "cross_peak": f.cross_peak,
        "net": [f.net.0, f.net.1],
        "degree": [f.degree.0, f.degree.1],
    })
}

/// A result's fairness verdict as JSON ([`FairnessVerdict`]).
fn verdict_json(v: &FairnessVerdict) -> Value {
    json!({
        "fair": v.fair(),
        "peak_ratio": if v.peak_ratio.is_finite() { json!(v.peak_ratio) } else { Value::Null },
        "comb_ratio": if v.comb_ratio.is_finite() { json!(v.comb_ratio) } else { Value::Null },
        "energy_ratio": if v.energy_ratio.is_finite() { json!(v.energy_ratio) } else { Value::Null },
        "extrema_gained": v.extrema_gained,
        "net_within": v.net_within,
        "faults": v.faults(),
    })
}

fn link_json(l: &LinkFair) -> Value {
    let (slave, rest) = l.label.split_once('.').unwrap_or((&l.label, ""));
    let (side, master) = rest.split_once(" -> ").unwrap_or((rest, ""));
    json!({
        "slave": slave,
        "side": side,
        "master": master,
        "target": format!("{:?}", l.target),
        "before": measure_json(&l.before),
        "after": measure_json(&l.after),
        "met": l.met,
    })
}

/// A figure in scientific notation with `digits` after the point (a gap of 1e-11 and one of
/// 1e-3 both show), "–" when absent.
fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("–".to_string(), |x| format!("{x:.digits$e}"))
}

/// The report as Markdown, lengths in "model units".
pub fn report_markdown(report: &FairModelReport, title: &str) -> String {
    report_markdown_in(report, title, None)
}

/// The report as Markdown with lengths in `units` (the model's `units`, e.g. "mm"; `None`:
/// "model units"); curvatures are per unit, angles in degrees, figures in scientific notation.
pub fn report_markdown_in(report: &FairModelReport, title: &str, units: Option<&str>) -> String {
    let unit = units.unwrap_or("model units");
    let mut md = String::new();
    let _ = writeln!(md, "# {title}\n");
    let met = report.links.iter().filter(|l| l.met).count();
    let _ = writeln!(
        md,
        "{} surfaces, {} links ({} meet their targets), deviation tolerance {} {unit}, {:.3} s in total.\n",
        report.surfaces.len(),
        report.links.len(),
        met,
        report.tolerance,
        report.seconds_total
    );
    links_section(&mut md, report, unit);
    surfaces_section(&mut md, report, unit);
    fairness_section(&mut md, report, unit);
    groups_section(&mut md, report);
    problems_section(&mut md, report);
    md
}

/// The links table: before and after, met or not.
fn links_section(md: &mut String, report: &FairModelReport, unit: &str) {
    if !report.links.is_empty() {
        let _ = writeln!(md, "## Links\n");
        let _ = writeln!(
            md,
            "| link | target | gap before ({unit}) | gap after ({unit}) | angle before (°) | angle after (°) | curvature rel. before | curvature rel. after | across the boundary after | met |"
        );
        let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|");
        for l in &report.links {
            let b = l.before.as_ref();
            let a = l.after.as_ref();
            let _ = writeln!(
                md,
                "| {} | {:?} | {} | {} | {} | {} | {} | {} | {} | {} |",
                l.label,
                l.target,
                opt(b.map(|m| m.g0), 3),
                opt(a.map(|m| m.g0), 3),
                opt(b.and_then(|m| m.g1_deg), 3),
                opt(a.and_then(|m| m.g1_deg), 3),
                opt(b.and_then(|m| m.g2_rel), 3),
                opt(a.and_then(|m| m.g2_rel), 3),
                opt(a.and_then(|m| m.g2_rel_across), 3),
                if l.met { "yes" } else { "**no**" }
            );
        }
        md.push('\n');
    }
}

/// The surfaces table with the totals.
fn surfaces_section(md: &mut String, report: &FairModelReport, unit: &str) {
    let _ = writeln!(md, "## Surfaces\n");
    let _ = writeln!(
        md,
        "| surface | role | method | energy before | energy after | change | deviation ({unit}) | iterations | knots inserted | seconds |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|");
    let (mut eb, mut ea) = (0.0, 0.0);
    for s in &report.surfaces {
        eb += s.energy_before;
        ea += s.energy_after;
        let change = if s.energy_before > 0.0 {
            format!("{:+.1} %", 100.0 * (s.energy_after / s.energy_before - 1.0))
        } else {
            "–".into()
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.4e} | {:.4e} | {} | {:.3e} | {} | {} | {:.4} |",
            s.name,
            s.role.name(),
            s.method,
            s.energy_before,
            s.energy_after,
            change,
            s.max_deviation,
            s.iterations,
            s.knots_inserted,
            s.seconds
        );
    }
    let worst = report
        .surfaces
        .iter()
        .map(|s| s.max_deviation)
        .fold(0.0, f64::max);
    let _ = writeln!(
        md,
        "| **total** | | | {eb:.4e} | {ea:.4e} | {} | {worst:.3e} | {} | {} | {:.4} |\n",
        if eb > 0.0 {
            format!("{:+.1} %", 100.0 * (ea / eb - 1.0))
        } else {
            "–".into()
        },
        report.surfaces.iter().map(|s| s.iterations).sum::<usize>(),
        report
            .surfaces
            .iter()
            .map(|s| s.knots_inserted)
            .sum::<usize>(),
        report.seconds_total
    );
}

/// The fairness table: per surface the peak curvature, the comb's extrema across its
/// boundary, the mean-curvature spread and the net, before and after, and the verdict.
fn fairness_section(md: &mut String, report: &FairModelReport, unit: &str) {
    if report.surfaces.is_empty() {
        return;
    }
    let fair = report
        .surfaces
        .iter()
        .filter(|s| s.fairness_verdict().fair())
        .count();
    let _ = writeln!(
        md,
        "## Fairness
"
    );
    let _ = writeln!(
        md,
        "{fair} of {} surfaces fair against their input (peak curvature ≤ {}× the input's or the masters' at the joins, energy ≤ {}×, at most {} more curvature extremum across the boundary, net ≤ max(2n, n + {})).\n",
        report.surfaces.len(),
        crate::fairness::PEAK_FACTOR,
        crate::fairness::ENERGY_FACTOR,
        crate::fairness::ONE_HUMP_EXTREMA,
        crate::fairness::NET_GROWTH_ROWS,
    );
    let _ = writeln!(
        md,
        "| surface | peak curvature before (1/{unit}) | after | ratio | extrema across before | after | mean-curvature spread before | after | net before | after | fair |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|");
    let count = |c: Option<usize>| c.map_or("–".to_string(), |n| n.to_string());
    for s in &report.surfaces {
        let (b, a) = &s.fairness;
        let v = s.fairness_verdict();
        let _ = writeln!(
            md,
            "| {} | {:.4} | {:.4} | {:.2} | {} | {} | {:.3e} | {:.3e} | {}×{} | {}×{} | {} |",
            s.name,
            b.peak_curvature,
            a.peak_curvature,
            v.peak_ratio,
            count(b.cross_extrema),
            count(a.cross_extrema),
            b.mean_curvature_spread,
            a.mean_curvature_spread,
            b.net.0,
            b.net.1,
            a.net.0,
            a.net.1,
            if v.fair() {
                "yes".to_string()
            } else {
                format!("**no**: {}", v.faults().join("; "))
            }
        );
    }
    md.push('\n');
}

/// The corner groups table, where there are groups.
fn groups_section(md: &mut String, report: &FairModelReport) {
    if !report.groups.is_empty() {
        let _ = writeln!(md, "## Corner groups (n-sided mesh fairing and refit)\n");
        let _ = writeln!(
            md,
            "| group | used | deviation | mesh vertices | refit max error | internal angle° |"
        );
        let _ = writeln!(md, "|---|---|---|---|---|---|");
        for g in &report.groups {
            let _ = writeln!(
                md,
                "| {} | {} | {:.5} | {} | {:.3e} | {:.4} |",
                g.name,
                if g.applied { "yes" } else { "no" },
                g.max_deviation,
                g.mesh_vertices,
                g.refit_max_error,
                g.internal_angle_deg
            );
        }
        md.push('\n');
    }
    if !report.pole_splits.is_empty() {
        let _ = writeln!(md, "## Pole corners split into three quads\n");
        for p in &report.pole_splits {
            let _ = match &p.outcome {
                crate::poles::PoleOutcome::Split {
                    quads,
                    control_points,
                    fit_error,
                } => writeln!(
                    md,
                    "- {}: split into {} ({control_points} × {control_points} control points, within {fit_error:.2e} of it)",
                    p.surface,
                    quads.join(", ")
                ),
                crate::poles::PoleOutcome::Kept { reason } => {
                    writeln!(md, "- {}: kept as it was: {reason}", p.surface)
                }
            };
        }
        md.push('\n');
    }
}

/// The problems, one line each.
fn problems_section(md: &mut String, report: &FairModelReport) {
    if !report.problems.is_empty() {
        let _ = writeln!(md, "## Problems\n");
        for p in &report.problems {
            let _ = writeln!(md, "- **{}** {}: {}", p.kind.name(), p.place(), p.message);
        }
        md.push('\n');
    }
}
