//! The `connect` driver: continuity setting only (no fairing), slave by slave in hierarchy order
//! (\[SV\] §3.2 steps 3 and 5, §1.1 order).
//!
//! Surfaces are visited in [`Model::hierarchy_order`]; every surface that is the slave of some
//! links is connected to its masters — which are already final, as they come earlier — by
//! [`g_continuity::connect_slave`] (C0 → G1 → G2, twists, knot insertion). Masters never move.
//! Each link's target is its own continuity, capped by [`ConnectOptions::target`].
//!
//! Never worse than the input (\[SV\] §1.1: the hierarchy exists so that a slave adapts to its
//! masters, not the other way round, and a join already made must not be lost): a slave whose
//! result leaves any of its links with a larger gap, normal angle or curvature difference than
//! the input had is set again — step by step (each continuity level's refinement from the rows
//! the level below met, as the framework's dry run does), step by step with the corners' end
//! tangents turned into the neighbouring masters' tangent planes, in one call with the turned
//! tangents, with its G2 links capped at G1 — until a candidate keeps every gap and angle, and
//! is kept as it was when none is no worse; of the candidates the first no worse in every figure
//! wins, else the one whose links grow the least (a gap before an angle before a curvature), and
//! the report says which and why.

use std::time::Instant;

use g_continuity::{ConnectParams, ConnectReport, LinkMeasure, SideLink, connect_slave};
use nurbs_core::{BSplineSurface, Continuity};

use crate::check::{check_model, measure_model};
use crate::error::{Error, Result};
use crate::framework::LinkGrowth;
use crate::model::{Model, Role};

/// Settings of [`connect`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConnectOptions {
    /// The highest continuity set (`None`: each link's own target).
    pub target: Option<Continuity>,
    /// Continuity setting; its tolerances are replaced by the model's.
    pub params: ConnectParams,
}

impl Default for ConnectOptions {
    /// Each link's own target; the continuity setting with the widest curvature lead-in at its
    /// G2 sides ([`g_continuity::MAX_LEAD_IN`]) and nets bounded as in the framework
    /// ([`crate::framework::MAX_NET`], [`crate::framework::net_bound`]). Without a lead-in a G2 side whose three boundary rows
    /// are all there is (a kernel's degree-2 rolling-ball fillet) is rebuilt across its whole
    /// width: 0.52 for a fillet of radius 5, against 0.012 with the lead-in — the fairest
    /// transition is the widest (\[SV\] §4.2), and `connect` has no deviation budget to narrow it.
    fn default() -> Self {
        Self {
            target: None,
            params: ConnectParams {
                lead_in: Some(g_continuity::MAX_LEAD_IN),
                max_control_points: crate::framework::MAX_NET,
                ..ConnectParams::default()
            },
        }
    }
}

/// What happened to one slave surface.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceConnect {
    /// the surface's index
    pub surface: usize,
    /// its name
    pub name: String,
    /// its role
    pub role: Role,
    /// thin-plate energy before and after
    pub energy_before: f64,
    /// thin-plate energy after
    pub energy_after: f64,
    /// largest sampled distance of the result from the input surface
    pub max_deviation: f64,
    /// largest control point movement (against the input refined the same way)
    pub max_control_movement: f64,
    /// knots inserted
    pub knots_inserted: usize,
    /// rounds of knot insertion
    pub refinements: usize,
    /// twists averaged
    pub twists_averaged: usize,
    /// seconds spent
    pub seconds: f64,
    /// Why the plain continuity setting was not kept (it made a link worse than the input),
    /// and what was kept instead; `None` when it was kept.
    pub fallback: Option<String>,
}

/// Before/after of one link.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkConnect {
    /// index into `model.links`
    pub link: usize,
    /// "slave.side -> master"
    pub label: String,
    /// the continuity set (the link's, capped by the option)
    pub target: Continuity,
    /// measured on the input model
    pub before: LinkMeasure,
    /// measured on the result
    pub after: LinkMeasure,
}

/// What [`connect`] did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModelConnectReport {
    /// total seconds
    pub seconds_total: f64,
    /// per slave surface, in processing order
    pub surfaces: Vec<SurfaceConnect>,
    /// per link, in model order
    pub links: Vec<LinkConnect>,
}

/// Sets continuity on every slave of `model` in hierarchy order; returns the new model and the
/// report. Links that do not touch their masters are errors (see [`check_model`]).
pub fn connect(model: &Model, options: &ConnectOptions) -> Result<(Model, ModelConnectReport)> {
    let start = Instant::now();
    let mut params = options.params;
    params.tolerances = model.tolerances.continuity();
    let before = check_model(model, &params.measure)?;
    let mut out = model.clone();
    let mut surfaces = Vec::new();
    for k in model.hierarchy_order()? {
        let link_ids = model.links_of_slave(k);
        if link_ids.is_empty() {
            continue;
        }
        let measures: Vec<&LinkMeasure> = link_ids.iter().map(|&i| &before[i].measure).collect();
        let (result, record) =
            connect_surface(model, &out, k, &link_ids, options, &params, &measures)?;
        surfaces.push(record);
        out.surfaces[k].surface = result;
    }
    // measured whether or not a link still touches: a link the candidates could not keep
    // touching is reported with its gap, not refused after the work
    let after = measure_model(&out, &params.measure)?;
    let links = before
        .into_iter()
        .zip(after)
        .map(|(b, a)| LinkConnect {
            link: b.link,
            label: b.label,
            target: options.target_of(b.target),
            before: b.measure,
            after: a.measure,
        })
        .collect();
    Ok((
        out,
        ModelConnectReport {
            seconds_total: start.elapsed().as_secs_f64(),
            surfaces,
            links,
        },
    ))
}

impl ConnectOptions {
    /// The continuity set on a link of continuity `c`: `c` capped by [`ConnectOptions::target`].
    fn target_of(&self, c: Continuity) -> Continuity {
        self.target.map_or(c, |t| c.min(t))
    }
}

/// Connects surface `k` of `model` to its masters as `out` has them (final, as they come
/// earlier in the hierarchy) over its links `link_ids`, whose measures on the input are
/// `before`; returns the result and its record.
fn connect_surface(
    model: &Model,
    out: &Model,
    k: usize,
    link_ids: &[usize],
    options: &ConnectOptions,
    params: &ConnectParams,
    before: &[&LinkMeasure],
) -> Result<(BSplineSurface, SurfaceConnect)> {
    let t0 = Instant::now();
    let original = &model.surfaces[k].surface;
    let links: Vec<SideLink> = link_ids
        .iter()
        .map(|&i| {
            let l = &model.links[i];
            SideLink {
                side: l.side,
                master: &out.surfaces[l.master].surface,
                target: options.target_of(l.continuity),
                range: None,
                g2_zones: [0.0; 2],
            }
        })
        .collect();
    // G2 relaxed next to a corner whose masters disagree, as the framework and `check` do
    let links = crate::zones::with_vertex_zones(links, original, &params.tolerances);
    let own = ConnectParams {
        max_control_points: crate::framework::net_bound(params.max_control_points, original),
        ..*params
    };
    let (result, report, fallback) =
        protected(original, &links, &own, before).map_err(|source| Error::Continuity {
            place: format!("surface {}", model.surfaces[k].name),
            source,
        })?;
    let record = SurfaceConnect {
        surface: k,
        name: model.surfaces[k].name.clone(),
        role: model.surfaces[k].role,
        energy_before: nurbs_core::energy::thin_plate_energy(original),
        energy_after: nurbs_core::energy::thin_plate_energy(&result),
        max_deviation: nurbs_core::energy::max_deviation(
            original,
            &result,
            crate::framework::DEVIATION_GRID,
        ),
        max_control_movement: report.max_control_movement,
        knots_inserted: report.knots_inserted,
        refinements: report.refinements,
        twists_averaged: report.twists_averaged,
        seconds: t0.elapsed().as_secs_f64(),
        fallback,
    };
    Ok((result, record))
}

/// One result [`protected`] may keep.
struct Candidate {
    /// what produced it (for the report)
    what: &'static str,
    /// the slave
    surface: BSplineSurface,
    /// its continuity setting's report
    report: ConnectReport,
    /// how much its links grow against the input: gap, angle, curvature
    /// the worst link's ([`LinkGrowth`])
    growth: LinkGrowth,
}

/// [`connect_slave`] with the never-worse rule of the module docs: the result and its report,
/// and the fallback phrase when the plain setting was not kept. `before` holds each link's
/// measure on the input model.
fn protected(
    original: &BSplineSurface,
    links: &[SideLink],
    params: &ConnectParams,
    before: &[&LinkMeasure],
) -> std::result::Result<(BSplineSurface, ConnectReport, Option<String>), g_continuity::Error> {
    let slave = Protected {
        original,
        links,
        params,
        before,
    };
    let first = slave.candidate(
        "the continuity setting",
        connect_slave(original, links, params)?,
    );
    if first.growth.no_worse() {
        return Ok((first.surface, first.report, None));
    }
    let mut candidates = vec![first];
    slave.alternatives(&mut candidates);
    let unchanged = (original.clone(), ConnectReport::default());
    candidates.push(slave.candidate("the surface as it was", unchanged));
    let pick = least_growth(&candidates);
    let figures: Vec<String> = candidates
        .iter()
        .map(|c| format!("{}: {}", c.what, c.growth))
        .collect();
    let why = format!(
        "the continuity setting would leave a link worse than the input; kept {}, whose links grow the least against the input — {}",
        candidates[pick].what,
        figures.join("; ")
    );
    let kept = candidates.swap_remove(pick);
    Ok((kept.surface, kept.report, Some(why)))
}

/// A slave under the never-worse rule: the input, its links and their measures on the input.
struct Protected<'a> {
    /// the slave as it came
    original: &'a BSplineSurface,
    /// its links
    links: &'a [SideLink<'a>],
    /// the continuity setting
    params: &'a ConnectParams,
    /// each link's measure on the input model
    before: &'a [&'a LinkMeasure],
}

impl Protected<'_> {
    /// The worst growth of the links on `s` against the input: gap, angle, curvature (a link
    /// that cannot be measured on `s` counts as opened).
    fn growth(&self, s: &BSplineSurface) -> LinkGrowth {
        let params = self.params;
        let mut worst = LinkGrowth::default();
        for (l, b) in self.links.iter().zip(self.before) {
            // (with its vertex zones, as `before` was measured by `check_model`)
            let Ok(a) = l.measure(s, &params.measure) else {
                worst.gap = f64::INFINITY;
                continue;
            };
            worst = worst.max(LinkGrowth::of(b, &a, l.target, &params.tolerances));
        }
        worst
    }

    /// The candidate `what` of the result `(surface, report)`, its growth measured.
    fn candidate(
        &self,
        what: &'static str,
        (surface, report): (BSplineSurface, ConnectReport),
    ) -> Candidate {
        let growth = self.growth(&surface);
        Candidate {
            what,
            surface,
            report,
            growth,
        }
    }

    /// Adds the other settings to `candidates`, in order, until one keeps every join: step by
    /// step, step by step with the corner tangents turned, in one call with the turned
    /// tangents, with the G2 links capped at G1. A setting that fails is no candidate.
    fn alternatives(&self, candidates: &mut Vec<Candidate>) {
        let (original, links, params) = (self.original, self.links, self.params);
        let turned = ConnectParams {
            set: g_continuity::SetParams {
                tangent_corners: true,
                ..params.set
            },
            ..*params
        };
        // the steps one by one, as the framework's dry run takes them: each step's refinement
        // starts from the rows the step below met, where the single call refines for all at once
        for (what, p) in [
            ("the setting step by step", params),
            (
                "the setting step by step with the corner tangents turned",
                &turned,
            ),
        ] {
            if candidates.iter().any(|c| c.growth.joins_kept()) {
                return;
            }
            if let Ok(s) = stepwise(original, links, p) {
                candidates.push(self.candidate(what, s));
            }
        }
        let g1_links: Vec<SideLink> = links
            .iter()
            .map(|l| SideLink {
                target: l.target.min(Continuity::G1),
                ..*l
            })
            .collect();
        let mut variants: Vec<(&'static str, &[SideLink], &ConnectParams)> = vec![(
            "the setting with the corner tangents turned",
            links,
            &turned,
        )];
        if links.iter().any(|l| l.target >= Continuity::G2) {
            variants.push(("the setting capped at G1", &g1_links, params));
        }
        for (what, ls, p) in variants {
            if candidates.iter().any(|c| c.growth.joins_kept()) {
                return;
            }
            if let Ok(s) = connect_slave(original, ls, p) {
                candidates.push(self.candidate(what, s));
            }
        }
    }
}

/// The candidate to keep: the first no worse than the input in every figure, else the one whose
/// links grow the least ([`LinkGrowth`]'s order; the first of equals).
fn least_growth(candidates: &[Candidate]) -> usize {
    (0..candidates.len())
        .find(|&k| candidates[k].growth.no_worse())
        .unwrap_or_else(|| {
            (1..candidates.len()).fold(0, |best, k| {
                if candidates[k].growth < candidates[best].growth {
                    k
                } else {
                    best
                }
            })
        })
}

/// C0, then G1, then G2 (as far as the links ask), each by [`g_continuity::set_step`] on the
/// result of the one below, after [`g_continuity::prepare_slave`].
fn stepwise(
    original: &BSplineSurface,
    links: &[SideLink],
    params: &ConnectParams,
) -> std::result::Result<(BSplineSurface, ConnectReport), g_continuity::Error> {
    let (mut s, mut report) = g_continuity::prepare_slave(original, links, params)?;
    let top = links.iter().map(|l| l.target).max();
    for step in [Continuity::G0, Continuity::G1, Continuity::G2] {
        if Some(step) > top {
            break;
        }
        let (next, r) = g_continuity::set_step(&s, links, step, params)?;
        report.knots_inserted += r.knots_inserted;
        report.max_control_movement = report.max_control_movement.max(r.max_move);
        s = next;
    }
    Ok((s, report))
}
