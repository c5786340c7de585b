//! What the framework reports: stages, surfaces, links and problems.

use g_continuity::LinkMeasure;
use nurbs_core::Continuity;

use super::GroupFair;
use crate::model::{Model, Role};

/// A step of the per-surface alternation (\[SV\] §3.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Stage {
    /// knot insertion, degree elevation, rational to polynomial
    Prepare,
    /// boundary rows onto the (faired) masters
    SetG0,
    /// fairing with the positional frames fixed
    FairC0,
    /// tangential rows
    SetG1,
    /// fairing with the tangential frames of G1/G2 sides fixed
    FairG1,
    /// curvature rows
    SetG2,
    /// fairing with the curvature frames of G2 sides fixed
    FairG2,
}

impl Stage {
    /// Short name for reports.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Prepare => "prepare",
            Stage::SetG0 => "set G0",
            Stage::FairC0 => "fair C0",
            Stage::SetG1 => "set G1",
            Stage::FairG1 => "fair G1",
            Stage::SetG2 => "set G2",
            Stage::FairG2 => "fair G2",
        }
    }
}

impl Stage {
    /// The set stage of `level`.
    pub fn set(level: Continuity) -> Stage {
        match level {
            Continuity::G0 => Stage::SetG0,
            Continuity::G1 => Stage::SetG1,
            Continuity::G2 => Stage::SetG2,
        }
    }

    /// The fairing stage keeping `level`.
    pub fn fair(level: Continuity) -> Stage {
        match level {
            Continuity::G0 => Stage::FairC0,
            Continuity::G1 => Stage::FairG1,
            Continuity::G2 => Stage::FairG2,
        }
    }
}

/// What one stage did.
#[derive(Debug, Clone, PartialEq)]
pub struct StageReport {
    /// the stage
    pub stage: Stage,
    /// wall time of the stage: from the end of the stage before it (or the start of the
    /// surface's run) to its record — `prepare` holds the dry run, the lead-in and section
    /// trials; a continuity setting the dry run computed and a later stage takes over is
    /// recorded in about no time. Work a fallback tried and dropped (the spread or the section
    /// run again without, a joint polish that is not kept) is in the surface's own seconds only.
    pub seconds: f64,
    /// largest control-point move of the stage (model units)
    pub max_move: f64,
    /// sampled deviation from the original after the stage
    pub deviation: f64,
    /// thin-plate energy after the stage
    pub energy: f64,
    /// fairing iterations (0 for continuity stages)
    pub iterations: usize,
    /// knots inserted by the stage
    pub knots_inserted: usize,
    /// the ball radius ε given to a fairing stage (0 for continuity stages)
    pub epsilon: f64,
    /// the prepare stage of a surface whose section was replaced by the one-hump profile
    /// ([`g_continuity::section`]): its ramp, as a fraction of the section at each G2 end
    pub section_ramp: Option<f64>,
}

/// What happened to one surface.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceFair {
    /// index into the model
    pub surface: usize,
    /// its name
    pub name: String,
    /// its role
    pub role: Role,
    /// method name
    pub method: String,
    /// thin-plate energy of the input
    pub energy_before: f64,
    /// thin-plate energy of the result
    pub energy_after: f64,
    /// sampled deviation of the result from the input (model units)
    pub max_deviation: f64,
    /// this surface's deviation tolerance (model units, [`Model::deviation_of`])
    pub tolerance: f64,
    /// degree (u, v) of the result
    pub degree: (usize, usize),
    /// control net (u, v) of the input and of the result
    pub net: ((usize, usize), (usize, usize)),
    /// fairing iterations, all stages
    pub iterations: usize,
    /// knots inserted, all stages
    pub knots_inserted: usize,
    /// seconds spent on this surface
    pub seconds: f64,
    /// the stages, in order
    pub stages: Vec<StageReport>,
    /// false when the surface was left as it was (see the problems)
    pub processed: bool,
    /// the largest normal jump (degrees) across the C⁰ knot lines of the input and of the
    /// result ([`nurbs_core::creases`]; 0 without such lines)
    pub crease_deg: (f64, f64),
    /// the fairness figures of the input and of the result ([`crate::fairness`])
    pub fairness: (nurbs_core::Fairness, nurbs_core::Fairness),
    /// the masters' largest curvature across this surface's G2 joins (1/model unit; 0 without
    /// G2 links): the peak-curvature reference where the input is flatter
    pub joint_curvature: f64,
}

impl SurfaceFair {
    /// The result's fairness against its input's ([`crate::fairness::FairnessVerdict`]).
    pub fn fairness_verdict(&self) -> crate::fairness::FairnessVerdict {
        crate::fairness::FairnessVerdict::new(
            &self.fairness.0,
            &self.fairness.1,
            self.joint_curvature,
        )
    }
}

/// Kind of a reported problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProblemKind {
    /// the surface could not be processed and was left as it was
    Failed,
    /// the continuity targets and the deviation tolerance cannot both be met
    Conflict,
    /// fairing was dropped or cut short to stay within the tolerance
    Limited,
    /// a link ends above the model's continuity tolerances (the amount is its worst measure
    /// divided by its tolerance)
    Unmet,
}

impl ProblemKind {
    /// Short name for reports.
    pub fn name(self) -> &'static str {
        match self {
            ProblemKind::Failed => "failed",
            ProblemKind::Conflict => "conflict",
            ProblemKind::Limited => "limited",
            ProblemKind::Unmet => "unmet",
        }
    }
}

/// A problem the run met, naming the surface and, where there is one, the link.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// what kind
    pub kind: ProblemKind,
    /// the surface
    pub surface: String,
    /// the link ("slave.side -> master"), when one is at fault
    pub link: Option<String>,
    /// what happened, readable
    pub message: String,
    /// the amount, e.g. the deviation a continuity step needs (model units)
    pub amount: Option<f64>,
}

impl Problem {
    /// The surface, and the link where one is at fault: "F02 (link F02.u0 -> P06)".
    pub fn place(&self) -> String {
        match &self.link {
            Some(l) => format!("{} (link {l})", self.surface),
            None => self.surface.clone(),
        }
    }
}

/// The end of the message of a surface whose thin-plate energy rose ([`Problem::is_energy_rise`]):
/// why it rose.
pub const ENERGY_RISE_WHY: &str =
    "what setting the continuity to its masters costs, which no fairing stage could take back";

impl Problem {
    /// Whether this is the note that a surface's thin-plate energy rose (its amount the ratio
    /// after / before): a summary can name those once for all surfaces.
    pub fn is_energy_rise(&self) -> bool {
        self.kind == ProblemKind::Limited && self.message.ends_with(ENERGY_RISE_WHY)
    }
}

impl std::fmt::Display for Problem {
    /// The report line: "limited: F02 (link F02.u0 -> P06): what happened".
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: {}: {}",
            self.kind.name(),
            self.place(),
            self.message
        )
    }
}

/// Before/after of one link.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkFair {
    /// index into `model.links`
    pub link: usize,
    /// "slave.side -> master"
    pub label: String,
    /// the link's target (capped by [`FairParams::target`](super::FairParams::target))
    pub target: Continuity,
    /// measured on the input (`None` when measuring failed)
    pub before: Option<LinkMeasure>,
    /// measured on the result
    pub after: Option<LinkMeasure>,
    /// whether `after` meets the model's tolerances up to the target
    pub met: bool,
}

/// What [`fair_model`](super::fair_model) did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FairModelReport {
    /// wall-clock seconds
    pub seconds_total: f64,
    /// the deviation tolerance used
    pub tolerance: f64,
    /// per surface, in processing order
    pub surfaces: Vec<SurfaceFair>,
    /// per link, in model order
    pub links: Vec<LinkFair>,
    /// the n-sided stage of each corner group (\[SV\] §3.4)
    pub groups: Vec<GroupFair>,
    /// everything that did not go as asked
    pub problems: Vec<Problem>,
    /// shared edges no link covers ([`crate::edges`]), before and after
    pub edges: Vec<crate::edges::EdgeFair>,
    /// the corner patches with a pole split into three quads before the run
    /// ([`crate::poles::split_pole_corners`]; empty unless the caller split them)
    pub pole_splits: Vec<crate::poles::PoleSplit>,
}

impl FairModelReport {
    /// Whether a surface failed (was left as it was).
    pub fn has_failures(&self) -> bool {
        self.problems.iter().any(|p| p.kind == ProblemKind::Failed)
    }

    /// The links the result leaves unmet, in the model's order: those a `conflict` problem
    /// names (the deviation it needs, verified by a second run, or a vertex zone), and the
    /// others — left unmet with no named conflict, which `fair` exits 1 for (cli-contract.md).
    /// A link is in one of the two, never both: met + conflicts + unmet = every link.
    pub fn unmet_links(&self) -> (Vec<&LinkFair>, Vec<&LinkFair>) {
        self.links.iter().filter(|l| !l.met).partition(|l| {
            self.problems
                .iter()
                .any(|p| p.kind == ProblemKind::Conflict && p.link.as_deref() == Some(&l.label))
        })
    }
}

/// Progress of a run: `done` of `total` surfaces, the last one finished named.
#[derive(Debug, Clone, Copy)]
pub struct Progress<'a> {
    /// surfaces finished
    pub done: usize,
    /// surfaces in the model
    pub total: usize,
    /// the surface just finished
    pub name: &'a str,
}

/// The before/after record of every link of `model`, met or not against the model's
/// tolerances up to its (capped) target.
pub(super) fn link_reports(
    model: &Model,
    before: &[Option<LinkMeasure>],
    after: Vec<Option<LinkMeasure>>,
    cap: &dyn Fn(Continuity) -> Continuity,
) -> Vec<LinkFair> {
    let t = &model.tolerances;
    before
        .iter()
        .cloned()
        .zip(after)
        .enumerate()
        .map(|(k, (b, a))| {
            let target = cap(model.links[k].continuity);
            let met = a
                .as_ref()
                .is_some_and(|m| m.meets(target, t.g0, t.g1_deg, t.g2_rel));
            LinkFair {
                link: k,
                label: model.link_label(k),
                target,
                before: b,
                after: a,
                met,
            }
        })
        .collect()
}

/// The shared edges that became links ([`crate::edges::link_edges`]), as edge records from
/// their links' measures.
pub(super) fn found_edge_reports(
    model: &Model,
    found: &[crate::edges::FoundLink],
    links: &[LinkFair],
) -> Vec<crate::edges::EdgeFair> {
    let t = &model.tolerances;
    let mut out = Vec::new();
    for f in found {
        let l = &links[f.link];
        if let (Some(b), Some(a)) = (&l.before, &l.after) {
            let measure = |m: &LinkMeasure| crate::edges::EdgeMeasure {
                gap: m.g0,
                angle_deg: m.g1_deg.unwrap_or(0.0),
            };
            out.push(crate::edges::EdgeFair::new(
                model.surfaces[model.links[f.link].slave].name.clone(),
                format!(
                    "{} (linked {:?}: {:.0} % of the side lies on it)",
                    f.label,
                    l.target,
                    100.0 * f.fraction
                ),
                f.fraction,
                (measure(b), measure(a)),
                (t.g0, t.g1_deg),
            ));
        }
    }
    out
}

/// An `unmet` problem for every link not met, with its worst measure over its tolerance.
pub(super) fn unmet_problems(model: &Model, links: &[LinkFair]) -> Vec<Problem> {
    let t = &model.tolerances;
    let mut out = Vec::new();
    for l in links.iter().filter(|l| !l.met) {
        let slave = &model.surfaces[model.links[l.link].slave].name;
        let (message, amount) = match &l.after {
            Some(m) => {
                let parts = [
                    (m.g0 / t.g0, format!("gap {:.3e}", m.g0)),
                    (
                        if l.target >= Continuity::G1 {
                            m.g1_deg.map_or(0.0, |a| a / t.g1_deg)
                        } else {
                            0.0
                        },
                        format!("angle {:.3e}°", m.g1_deg.unwrap_or(0.0)),
                    ),
                    (
                        if l.target >= Continuity::G2 {
                            m.g2_rel.map_or(0.0, |r| r / t.g2_rel)
                        } else {
                            0.0
                        },
                        format!("curvature {:.3e}", m.g2_rel.unwrap_or(0.0)),
                    ),
                ];
                let worst = parts
                    .iter()
                    .max_by(|a, b| a.0.total_cmp(&b.0))
                    .map_or((0.0, String::new()), |p| p.clone());
                (
                    format!(
                        "{:?} not reached: {} is {:.1} × its tolerance",
                        l.target, worst.1, worst.0
                    ),
                    Some(worst.0),
                )
            }
            None => (
                "the link could not be measured after fairing".to_string(),
                None,
            ),
        };
        out.push(Problem {
            kind: ProblemKind::Unmet,
            surface: slave.clone(),
            link: Some(l.label.clone()),
            message,
            amount,
        });
    }
    out
}

/// The records of the shared edges no link covers, before and after.
pub(super) fn edge_reports(
    model: &Model,
    edges: &[crate::edges::SharedEdge],
    before: Vec<crate::edges::EdgeMeasure>,
    after: Vec<crate::edges::EdgeMeasure>,
) -> Vec<crate::edges::EdgeFair> {
    let t = &model.tolerances;
    edges
        .iter()
        .zip(before.into_iter().zip(after))
        .map(|(e, (before, after))| {
            crate::edges::EdgeFair::new(
                model.surfaces[e.surface].name.clone(),
                format!(
                    "{}.{} ~ {}",
                    model.surfaces[e.surface].name,
                    e.side.name(),
                    model.surfaces[e.other].name
                ),
                e.fraction,
                (before, after),
                (t.g0, t.g1_deg),
            )
        })
        .collect()
}

/// A `limited` problem for every link that leaves worse than it came in up to its target — a
/// larger gap or angle, or a larger curvature difference across a join that came in tangent
/// ([`super::worse_than`]) — naming why where the slave came out as it went in: its master
/// moved at the join after it (the slave kept at its input continuity, a conflict), which a
/// master's stages cannot foresee. `given` is the input model, `out` the result.
pub(super) fn worse_link_problems(given: &Model, out: &Model, links: &[LinkFair]) -> Vec<Problem> {
    let t = given.tolerances.continuity();
    let mut problems = Vec::new();
    for l in links {
        let (Some(before), Some(after)) = (&l.before, &l.after) else {
            continue;
        };
        let tangent = before.g1_deg.is_some_and(|g| g <= t.g1_deg);
        let target = if tangent {
            l.target
        } else {
            l.target.min(Continuity::G1)
        };
        let Some(worse) = super::worse_than(before, after, target, &t) else {
            continue;
        };
        let link = &given.links[l.link];
        let slave = &given.surfaces[link.slave];
        let kept = out
            .surfaces
            .get(link.slave)
            .is_some_and(|s| s.surface == slave.surface);
        let why = if kept {
            format!(
                "its master {} moved at the join, and the slave was kept as it was",
                given.surfaces[link.master].name
            )
        } else {
            "no stage of the slave could keep it".to_string()
        };
        problems.push(Problem {
            kind: ProblemKind::Limited,
            surface: slave.name.clone(),
            link: Some(l.label.clone()),
            message: format!("the link leaves worse than it came in, {worse}: {why}"),
            amount: None,
        });
    }
    problems
}

/// A `limited` problem for every shared edge that leaves worse than it came.
pub(super) fn worse_edge_problems(edges: &[crate::edges::EdgeFair]) -> Vec<Problem> {
    edges
        .iter()
        .filter(|fair| fair.worse)
        .map(|fair| Problem {
            kind: ProblemKind::Limited,
            surface: fair.surface.clone(),
            link: None,
            message: format!(
                "the shared edge {} ({:.0} % of the side) leaves with gap {:.3e} and angle {:.3e}° (input {:.3e}, {:.3e}°)",
                fair.label,
                100.0 * fair.fraction,
                fair.after.gap,
                fair.after.angle_deg,
                fair.before.gap,
                fair.before.angle_deg
            ),
            amount: Some(fair.after.angle_deg),
        })
        .collect()
}

/// A length (model units) for a message: four decimals from 1e-3 on, else four significant
/// digits in exponent form, so that a tight tolerance (1e-6) does not read as 0.0000.
pub(super) fn length(x: f64) -> String {
    if x == 0.0 || x.abs() >= 1e-3 {
        format!("{x:.4}")
    } else {
        format!("{x:.3e}")
    }
}

#[cfg(test)]
mod tests {
    use nurbs_core::Continuity;

    use super::{FairModelReport, LinkFair, Problem, ProblemKind};

    fn link(k: usize, met: bool) -> LinkFair {
        LinkFair {
            link: k,
            label: format!("s{k}.u0 -> m"),
            target: Continuity::G2,
            before: None,
            after: None,
            met,
        }
    }

    fn problem(kind: ProblemKind, k: usize) -> Problem {
        Problem {
            kind,
            surface: format!("s{k}"),
            link: Some(format!("s{k}.u0 -> m")),
            message: String::new(),
            amount: None,
        }
    }

    /// A link missed and then verified as a conflict carries both an `unmet` and a `conflict`
    /// problem: it counts once, as a conflict; a met link named by a zone's conflict is met.
    #[test]
    fn every_link_is_met_a_conflict_or_unmet_once() {
        let report = FairModelReport {
            links: vec![
                link(0, true),
                link(1, false),
                link(2, false),
                link(3, false),
            ],
            problems: vec![
                problem(ProblemKind::Conflict, 0),
                problem(ProblemKind::Unmet, 1),
                problem(ProblemKind::Conflict, 1),
                problem(ProblemKind::Unmet, 2),
                problem(ProblemKind::Limited, 3),
            ],
            ..FairModelReport::default()
        };
        let (conflicts, unmet) = report.unmet_links();
        let labels = |ls: &[&LinkFair]| ls.iter().map(|l| l.link).collect::<Vec<_>>();
        assert_eq!(labels(&conflicts), [1]);
        assert_eq!(labels(&unmet), [2, 3]);
    }
}
