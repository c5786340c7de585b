//! What `fair` on a model and `demo` print at the end of a run (cli-contract.md): the link
//! table with every measure before and after side by side and the model's tolerances they are
//! met against, the totals, the problems (the notes of a thin-plate energy rise once for all
//! surfaces, a rise below the numerical noise of the energy not at all), and the verdict line a
//! newcomer reads to know whether the run succeeded.

use std::fmt::Write;
use std::path::Path;

use hier_fair::{FairModelReport, Model, Problem};

/// Share of a surface's energy scale below which a rise of its thin-plate energy is numerical
/// noise and is not printed (the report keeps it): the scale is the larger of its energy
/// before and its size² (the energy of a surface bent once over its size, on the unit
/// parameter square). A flat surface's energy is rounding noise (1e-31 on a plane of 100 mm),
/// and a rise of 1e-12 of the energy is far below anything a fairing method changes.
pub(crate) const ENERGY_NOISE: f64 = 1e-12;

/// A measure in the table's scientific notation, `–` where it is undefined.
fn sci(v: Option<f64>) -> String {
    v.map_or("–".to_string(), |x| format!("{x:.3e}"))
}

/// "before → after", each right-aligned to the width of a measure.
fn pair(before: Option<f64>, after: Option<f64>) -> String {
    format!("{:>10} → {:>10}", sci(before), sci(after))
}

/// The link table of a model run: target, gap, normal angle and relative curvature difference
/// before → after, and whether the link is met; then the tolerances they are met against.
fn link_table(report: &FairModelReport, model: &Model) -> String {
    let mut s = String::new();
    if report.links.is_empty() {
        return s;
    }
    let width = report
        .links
        .iter()
        .map(|l| l.label.len())
        .max()
        .unwrap_or(4)
        .max(28);
    let _ = writeln!(
        s,
        "{:<width$} {:>6}  {:>23}  {:>23}  {:>23}  met",
        "link", "target", "gap before → after", "angle° before → after", "g2 rel before → after"
    );
    for l in &report.links {
        let (b, a) = (l.before.as_ref(), l.after.as_ref());
        let _ = writeln!(
            s,
            "{:<width$} {:>6}  {}  {}  {}  {}",
            l.label,
            format!("{:?}", l.target),
            pair(b.map(|m| m.g0), a.map(|m| m.g0)),
            pair(b.and_then(|m| m.g1_deg), a.and_then(|m| m.g1_deg)),
            pair(b.and_then(|m| m.g2_rel), a.and_then(|m| m.g2_rel)),
            if l.met { "yes" } else { "NO" }
        );
    }
    let t = &model.tolerances;
    let _ = writeln!(
        s,
        "model tolerances: g0 {} · g1 {}° · g2 {} (a link is met up to its target)",
        t.g0, t.g1_deg, t.g2_rel
    );
    s
}

/// A short readable summary of a model run: the link table, the totals, the fairness line and
/// the problems (`model` is the input, whose tolerances the links are met against).
pub fn summary(report: &FairModelReport, model: &Model, title: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{title}");
    s += &link_table(report, model);
    let (eb, ea): (f64, f64) = report.surfaces.iter().fold((0.0, 0.0), |(a, b), x| {
        (a + x.energy_before, b + x.energy_after)
    });
    let worst = report
        .surfaces
        .iter()
        .map(|x| x.max_deviation)
        .fold(0.0, f64::max);
    let _ = writeln!(
        s,
        "{} surfaces faired in {:.3} s; energy {:.4e} -> {:.4e}; largest deviation {:.4e} (tolerance {})",
        report.surfaces.len(),
        report.seconds_total,
        eb,
        ea,
        worst,
        report.tolerance
    );
    let unfair: Vec<String> = report
        .surfaces
        .iter()
        .filter_map(|x| {
            let v = x.fairness_verdict();
            (!v.fair()).then(|| format!("{} ({})", x.name, v.faults().join(", ")))
        })
        .collect();
    let _ = writeln!(
        s,
        "fairness: {} of {} surfaces fair against their input{}",
        report.surfaces.len() - unfair.len(),
        report.surfaces.len(),
        if unfair.is_empty() {
            String::new()
        } else {
            format!("; not: {}", unfair.join("; "))
        }
    );
    if let Some(hint) = pole_hint(report, model) {
        let _ = writeln!(s, "{hint}");
    }
    let noise = |p: &Problem| energy_rise_is_noise(p, report, model);
    for line in problem_lines(&report.problems, noise) {
        let _ = writeln!(s, "{line}");
    }
    s
}

/// The hint for corner patches with a pole whose faired peak curvature is beyond
/// [`hier_fair::fairness::PEAK_FACTOR`] × their input's: a lead-in of constant parameter width
/// narrows to nothing at a pole, which `--split-poles` avoids (cli-contract.md).
fn pole_hint(report: &FairModelReport, model: &Model) -> Option<String> {
    let spiked: Vec<&str> = report
        .surfaces
        .iter()
        .filter(|x| x.fairness_verdict().spike() > hier_fair::fairness::PEAK_FACTOR)
        .filter(|x| {
            model
                .find(&x.name)
                .is_some_and(|k| hier_fair::poles::pole_side(&model.surfaces[k]).is_some())
        })
        .map(|x| x.name.as_str())
        .collect();
    (!spiked.is_empty()).then(|| {
        format!(
            "hint: {} corner patch(es) with a pole peak beyond {}× their input's curvature ({}): `--split-poles` splits each into three quads without a pole, faired as a corner group",
            spiked.len(),
            hier_fair::fairness::PEAK_FACTOR,
            spiked.join(", ")
        )
    })
}

/// Whether `p` notes a rise of a surface's thin-plate energy below [`ENERGY_NOISE`] of its
/// energy scale.
fn energy_rise_is_noise(p: &Problem, report: &FairModelReport, model: &Model) -> bool {
    if !p.is_energy_rise() {
        return false;
    }
    let Some(s) = report.surfaces.iter().find(|s| s.name == p.surface) else {
        return false;
    };
    let size = model
        .surfaces
        .iter()
        .find(|m| m.name == p.surface)
        .map_or(0.0, |m| m.surface.size());
    s.energy_after - s.energy_before <= ENERGY_NOISE * s.energy_before.max(size * size)
}

/// The problems as summary lines: each on its own, except the notes that a surface's
/// thin-plate energy rose, which are one line naming every such surface and its ratio (the
/// report keeps one problem per surface); the problems `noise` picks are left out.
pub fn problem_lines(problems: &[Problem], noise: impl Fn(&Problem) -> bool) -> Vec<String> {
    let shown: Vec<&Problem> = problems.iter().filter(|p| !noise(p)).collect();
    let rises: Vec<String> = shown
        .iter()
        .filter(|p| p.is_energy_rise())
        .map(|p| format!("{} ×{:.3}", p.surface, p.amount.unwrap_or(f64::NAN)))
        .collect();
    let mut lines: Vec<String> = shown
        .iter()
        .filter(|p| !p.is_energy_rise())
        .map(ToString::to_string)
        .collect();
    if !rises.is_empty() {
        lines.push(format!(
            "limited: the thin-plate energy rose on {} surface(s) — {}: {}",
            rises.len(),
            hier_fair::ENERGY_RISE_WHY,
            rises.join(", ")
        ));
    }
    lines
}

/// The verdict of a model run without what it wrote: links met against the model's
/// tolerances, the links named as conflicts or unmet, the surfaces within their deviation,
/// the fair ones ("verdict: N of M links met (…), K conflicts, U unmet; S of T surfaces within
/// their deviation; F of T fair against their input").
pub fn verdict_line(report: &FairModelReport, model: &Model) -> String {
    let met = report.links.iter().filter(|l| l.met).count();
    // met links whose G2 figure across the boundary (n × T, what a checker reads) is above the
    // tolerance that the framework's parametric figure meets (g-continuity's measure module)
    let across = report
        .links
        .iter()
        .filter(|l| {
            l.met
                && l.target == nurbs_core::Continuity::G2
                && l.after
                    .as_ref()
                    .and_then(|m| m.g2_rel_across)
                    .is_some_and(|r| r > model.tolerances.g2_rel)
        })
        .count();
    // links relaxed within a vertex zone (hier-fair's `zones`): their zones are named as
    // conflicts, but a met one is counted with the met links, not as a conflict
    let zoned = report
        .links
        .iter()
        .filter(|l| {
            l.after
                .as_ref()
                .is_some_and(|m| m.vertex_zones.iter().any(|&z| z > 0.0))
        })
        .count();
    // the links left unmet: named conflicts, and the others (cli-contract.md's exit 1)
    let (conflicts, unmet) = report.unmet_links();
    let within = report
        .surfaces
        .iter()
        .filter(|s| s.max_deviation <= s.tolerance)
        .count();
    let fair = report
        .surfaces
        .iter()
        .filter(|s| s.fairness_verdict().fair())
        .count();
    format!(
        "verdict: {}{}{}), {} conflicts, {} unmet; {within} of {} surfaces within their deviation; {fair} of {} fair against their input",
        crate::check::links_met(met, report.links.len(), model),
        if across > 0 {
            format!("; {across} of them above it across the boundary, n × T")
        } else {
            String::new()
        },
        if zoned > 0 {
            format!("; {zoned} with G2 relaxed in a vertex zone")
        } else {
            String::new()
        },
        conflicts.len(),
        unmet.len(),
        report.surfaces.len(),
        report.surfaces.len(),
    )
}

/// The last line of `fair` on a model: [`verdict_line`] and the file written.
pub fn verdict(report: &FairModelReport, model: &Model, output: &Path) -> String {
    format!(
        "{}; wrote {}\n",
        verdict_line(report, model),
        output.display()
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use hier_fair::{Problem, ProblemKind};

    fn problem(surface: &str, message: String, amount: Option<f64>) -> Problem {
        Problem {
            kind: ProblemKind::Limited,
            surface: surface.into(),
            link: None,
            message,
            amount,
        }
    }

    fn rise(s: &str, r: f64) -> Problem {
        let why = hier_fair::ENERGY_RISE_WHY;
        problem(
            s,
            format!("its thin-plate energy rose from 1 to {r}: {why}"),
            Some(r),
        )
    }

    #[test]
    fn energy_rises_are_explained_once() {
        let other = problem("C1", "the continuity setting was faired once".into(), None);
        let lines = problem_lines(&[rise("F1", 1.026), other.clone(), rise("F2", 1.5)], |_| {
            false
        });
        assert_eq!(lines.len(), 2, "{lines:?}");
        assert_eq!(lines[0], other.to_string());
        assert_eq!(
            lines[1],
            format!(
                "limited: the thin-plate energy rose on 2 surface(s) — {}: F1 ×1.026, F2 ×1.500",
                hier_fair::ENERGY_RISE_WHY
            )
        );
    }

    /// A rise the noise test picks is not printed; with no other rise, no energy line at all.
    #[test]
    fn rises_below_the_noise_are_not_printed() {
        let problems = [rise("plane", 1.15), rise("fillet", 1.2)];
        let lines = problem_lines(&problems, |p| p.surface == "plane");
        assert_eq!(lines.len(), 1);
        assert!(lines[0].ends_with(": fillet ×1.200"), "{lines:?}");
        assert!(problem_lines(&problems, |_| true).is_empty());
    }
}
