//! The one-hump section as a candidate of the dry run ([`g_continuity::section`]): a surface
//! whose G2 sides lie across one direction (a fillet between two masters, or hanging on one)
//! also tries its section replaced by a ramped profile, with ramps as wide as the lead-in's
//! deviation budget allows; the candidate is taken when it meets every link the lead-in trial
//! met within that budget and is fairer by the figures of [`crate::fairness`]. The section is
//! carried through every control column's frame where that comes within the budget (exact for
//! a sweep), else taken section by section (a fillet whose section changes along it: a pipe
//! tee's, a lofted block's).

use g_continuity::{ConnectParams, RampShape, SideLink, prepare_slave};
use nurbs_core::energy::max_deviation;
use nurbs_core::{BSplineSurface, Continuity, Direction, Side};

use super::error::{StageError, StageResult};
use super::masks::free_rows;
use super::stages::StagePlan;
use super::{DryRun, Job, LEAD_IN_MARGIN, MIN_LEAD_IN, Run, Stage};
use crate::edges::SharedEdge;
use crate::fairness::{FairnessVerdict, surface_fairness};
use crate::model::Model;

/// Ramp trials: the first at [`g_continuity::MAX_RAMP`], each next one scaled by budget/d (the
/// section's deviation grows linearly with its ramps, [`g_continuity::section`]) and
/// [`LEAD_IN_MARGIN`]; the law is close to exact for a circular section, so the second trial is
/// usually within the budget and four are a bound.
pub const SECTION_TRIALS: usize = 4;

/// Narrowest ramp tried on a master, as a fraction of the section: [`MIN_LEAD_IN`]'s 1/64. Its
/// slaves must follow the changed end curves, and narrower ramps they could not: measured with
/// 1/256, boxes with sphere corners at 5 mm and variable radii had every fillet's section
/// withdrawn by default after runs 15–20 times as long (docs/benchmarks.md).
pub const MIN_RAMP: f64 = MIN_LEAD_IN;

/// Narrowest ramp tried on a surface that is no master: 1/256 of the section. The ramp is as
/// wide as the deviation budget allows (for a 90° arc of radius R about 0.15 f R with the
/// linear ramp, 0.31 f R with the flat one, [`RampShape`]; so by default's 0.025 mm a 5 mm
/// fillet needs f ≤ 1/31 or 1/62); a narrow monotone ramp is still one hump, where the lead-in
/// it replaces waves. Measured by default with flat ramps: a boss's torus fillet of radius 5
/// took f = 0.0138, one hump at 1.01× its input's peak (with 1/64 it kept the lead-in's five
/// extrema at 1.30×); with linear ramps it takes f = 0.029, 1.01×. Narrower ramps than 1/256
/// were not tried.
pub const MIN_FREE_RAMP: f64 = MIN_RAMP / 4.0;

/// How a section is built: carried through every column's frame
/// ([`g_continuity::one_hump_section`], exact for a sweep) or section by section
/// ([`g_continuity::one_hump_section_by_sections`], for a section that changes along).
#[derive(Clone, Copy, Debug)]
enum Build {
    Framed,
    BySections,
}

/// What a ramp search found ([`Job::ramp_search`]).
enum Found {
    /// no trial came within the deviation budget
    Nothing,
    /// a trial did, and the lead-in's result stays (the section missed links or was not fairer)
    LeadIn,
    /// the section's dry run, taken
    Section(Box<DryRun>),
}

/// The masters of the G2 sides at the start and the end of a section across `dir`: each ramp
/// rises from its master's curvature across ([`g_continuity::one_hump_section`]; an end
/// without a ramp, a collapsed side's, keeps the profile's own).
fn section_masters<'a>(links: &[SideLink<'a>], dir: Direction) -> [Option<&'a BSplineSurface>; 2] {
    let mut out = [None; 2];
    for l in links {
        if l.target >= Continuity::G2 && l.side.cross_direction() == dir {
            out[usize::from(!l.side.is_start())] = Some(l.master);
        }
    }
    out
}

/// The ramp shape of surface `k`'s section across `dir`: [`RampShape::Linear`], the narrower
/// deficit, unless a seam ([`crate::edges::is_seam`]) among `edges` lies on one of the section's
/// end curves — there a part of the same ring follows the end curve and meets its own masters
/// at the contact points, and takes a curvature that leaves them flat ([`RampShape::Flat`]).
/// Measured on a metre part's fillet ring: with linear ramps on its parts, two parts across
/// their seams could not follow and four G2 links were lost; with flat ones every part follows
/// (docs/benchmarks.md).
fn ramp_shape(model: &Model, edges: &[SharedEdge], k: usize, dir: Direction) -> RampShape {
    let on_an_end = edges.iter().any(|e| {
        e.surface == k && e.side.cross_direction() != dir && crate::edges::is_seam(model, e)
    });
    if on_an_end {
        RampShape::Flat
    } else {
        RampShape::Linear
    }
}

impl Job<'_> {
    /// The cross direction and the ramps (start, end) of a one-hump section for this surface:
    /// every G2 side that is not collapsed lies across one direction, and each such side gets
    /// a ramp of width `f`; `None` without one.
    fn section_ends(&self, links: &[SideLink<'_>], f: f64) -> Option<(Direction, (f64, f64))> {
        if !self.section_allowed {
            return None;
        }
        let g2: Vec<Side> = links
            .iter()
            .filter(|l| {
                l.target >= Continuity::G2
                    && !g_continuity::measure::is_collapsed(self.start, l.side)
            })
            .map(|l| l.side)
            .collect();
        let dir = g2.first()?.cross_direction();
        if g2.iter().any(|s| s.cross_direction() != dir) {
            return None;
        }
        // a slave hanging on this surface (a vertex blend on a fillet's end) is set against
        // the curve it shares with it, which the section changes across the whole fillet: the
        // slave's C0 step then spreads that move over its interior
        // ([`g_continuity::SetParams::spread_boundary_move`]). Measured before that spread,
        // with the section on those masters a box's sphere corners per role met 42 of 48 links
        // and a three-radii corner 8 of 12; with it every link (docs/benchmarks.md)
        let at = |start: bool| {
            if g2.iter().any(|s| s.is_start() == start) {
                f
            } else {
                0.0
            }
        };
        Some((dir, (at(true), at(false))))
    }

    /// The ramp shape of this surface's section across `dir` ([`ramp_shape`]).
    fn ramp_shape(&self, dir: Direction) -> RampShape {
        ramp_shape(self.model, self.edges, self.surface, dir)
    }

    /// The fairness verdict of `result` against the input ([`FairnessVerdict`]).
    pub(super) fn verdict_of(&self, result: &BSplineSurface) -> FairnessVerdict {
        let original = &self.model.surfaces[self.surface].surface;
        let before = surface_fairness(self.model, self.surface, original);
        let after = surface_fairness(self.model, self.surface, result);
        FairnessVerdict::new(&before, &after, self.joint_curvature(result))
    }

    /// `regular` (the lead-in search's pick), or the one-hump section's dry run where that meets
    /// its links within `budget` and is fairer (module docs). Any error of the section's
    /// construction or of its continuity steps only means the surface has no such candidate:
    /// `regular` stays.
    pub(super) fn with_section(
        &self,
        links: &[SideLink<'_>],
        budget: f64,
        regular: DryRun,
    ) -> StageResult<DryRun> {
        let Some(_) = self.section_ends(links, g_continuity::MAX_RAMP) else {
            return Ok(regular);
        };
        let regular_last = regular.steps.last().map(|s| s.1.clone());
        let regular_verdict = regular_last.as_ref().map(|s| self.verdict_of(s));
        if regular.met && regular_verdict.as_ref().is_some_and(|v| v.fair()) {
            return Ok(regular);
        }
        // framed first: exact for a sweep (a cylinder's or torus's weights kept); section by
        // section only where no framed trial came within the budget (a section that changes
        // along). Measured with the nearer of the two taken at every trial, a pipe tee's two
        // fillet halves took different sections and the one run again across their seam peaked
        // at 2.76× (docs/benchmarks.md)
        for build in [Build::Framed, Build::BySections] {
            match self.ramp_search(links, budget, &regular, regular_verdict.as_ref(), build) {
                Found::Nothing => continue,
                Found::LeadIn => break,
                Found::Section(dry) => return Ok(*dry),
            }
        }
        Ok(regular)
    }

    /// The ramp search of [`Job::with_section`] with sections built by `build`, against the
    /// lead-in's dry run `regular` and its verdict.
    fn ramp_search(
        &self,
        links: &[SideLink<'_>],
        budget: f64,
        regular: &DryRun,
        regular_verdict: Option<&FairnessVerdict>,
        build: Build,
    ) -> Found {
        let original = &self.model.surfaces[self.surface].surface;
        let min_ramp = if self.is_master() {
            MIN_RAMP
        } else {
            MIN_FREE_RAMP
        };
        let mut f = g_continuity::MAX_RAMP;
        for _ in 0..SECTION_TRIALS {
            let Some((dir, ramps)) = self.section_ends(links, f) else {
                break;
            };
            let shape = self.ramp_shape(dir);
            let masters = section_masters(links, dir);
            let built = match build {
                Build::Framed => {
                    g_continuity::one_hump_section(self.start, dir, ramps, shape, masters)
                }
                Build::BySections => g_continuity::one_hump_section_by_sections(
                    self.start, dir, ramps, shape, masters,
                ),
            };
            let Ok(section) = built else {
                break;
            };
            let d_section = max_deviation(original, &section, self.params.deviation_grid);
            // a section whose continuity steps fail (a singular system, a master it cannot
            // follow) is no candidate: the lead-in's result stays, the surface is not lost
            let dry = if d_section <= budget {
                self.section_dry_run(&section, links, f, regular.spread)
                    .ok()
            } else {
                None
            };
            let d = dry.as_ref().map_or(d_section, |t| t.deviation());
            if d <= budget {
                let Some(dry) = dry.filter(|t| t.met || !regular.met) else {
                    return Found::LeadIn;
                };
                let Some(last) = dry.steps.last() else {
                    return Found::LeadIn;
                };
                let verdict = self.verdict_of(&last.1);
                // a master's section changes what its slaves are set against: it is taken only
                // where it is fair by every figure, not merely fairer than the lead-in (its
                // faired result is judged again, [`Job::stages`])
                let better = (!self.is_master() || verdict.fair())
                    && regular_verdict.is_none_or(|r| {
                        (dry.met && !regular.met)
                            || verdict.fairer_than(r, self.connect.tolerances.g2_rel)
                    });
                return if better {
                    Found::Section(Box::new(dry))
                } else {
                    Found::LeadIn
                };
            }
            // the narrowest ramp is tried once where the law predicts less
            if f <= min_ramp {
                break;
            }
            f = (f * budget / d * LEAD_IN_MARGIN).max(min_ramp);
        }
        Found::Nothing
    }

    /// The continuity steps alone from the one-hump `section` (prepared without a lead-in: the
    /// section's ramps are its lead-in).
    fn section_dry_run(
        &self,
        section: &BSplineSurface,
        links: &[SideLink<'_>],
        ramp: f64,
        spread: bool,
    ) -> StageResult<DryRun> {
        let name = &self.model.surfaces[self.surface].name;
        let connect = ConnectParams {
            lead_in: None,
            ..*self.connect
        };
        let (prepared, _) =
            prepare_slave(section, links, &connect).map_err(|source| StageError::Prepare {
                surface: format!("{name}'s one-hump section"),
                source,
            })?;
        let (prepared, _) =
            free_rows(prepared, links, self.params.min_free_rows).map_err(|source| {
                StageError::Knots {
                    surface: format!("{name}'s one-hump section"),
                    source,
                }
            })?;
        let mut dry = self.dry_run(&prepared, links, spread)?;
        dry.section_ramp = Some(ramp);
        Ok(dry)
    }

    /// The stages of a surface whose dry run started from its one-hump section: its setting
    /// faired once keeping G2 ([`Job::faired_once`]), or the setting alone where that fairing
    /// is not kept.
    pub(super) fn section_stages(&self, plan: &StagePlan<'_>, run: &mut Run<'_>) -> BSplineSurface {
        if let Some((faired, stages)) = self.faired_once(plan, run.original, &run.stages[0]) {
            run.stages = stages;
            return faired;
        }
        if let Some(h) = plan.highest {
            run.record(Stage::set(h), &plan.prepared, &plan.connected);
        }
        plan.connected.clone()
    }
}

#[cfg(test)]
mod tests {
    use g_continuity::{RampShape, SideLink};
    use nurbs_core::{BSplineSurface, Continuity, Direction, Side};

    use super::{ramp_shape, section_masters};
    use crate::edges::tests::strip;
    use crate::model::Role;

    #[test]
    fn a_section_takes_the_masters_of_its_g2_sides_at_its_start_and_end() {
        let plane = |z: f64| {
            nurbs_core::shapes::plane_patch(
                nurbs_core::Point3::new(0.0, 0.0, z),
                nurbs_core::Vector3::x(),
                nurbs_core::Vector3::y(),
                (0.0, 1.0),
                (0.0, 1.0),
            )
            .unwrap()
        };
        let (a, b, c) = (plane(0.0), plane(1.0), plane(2.0));
        let link = |side, master, target| SideLink {
            side,
            master,
            target,
            range: None,
            g2_zones: [0.0; 2],
        };
        let is =
            |m: Option<&BSplineSurface>, s: &BSplineSurface| m.is_some_and(|m| std::ptr::eq(m, s));
        let links = [
            link(Side::U1, &a, Continuity::G2),
            link(Side::U0, &b, Continuity::G2),
            link(Side::V0, &c, Continuity::G2),
        ];
        // across u: the start side u0's master first, the end side u1's second
        let m = section_masters(&links, Direction::U);
        assert!(is(m[0], &b) && is(m[1], &a));
        // across v: only v0 has one
        let m = section_masters(&links, Direction::V);
        assert!(is(m[0], &c) && m[1].is_none());
        // a G1 side gives no curvature to start from
        let g1 = [link(Side::U0, &b, Continuity::G1)];
        assert!(
            section_masters(&g1, Direction::U)
                .iter()
                .all(Option::is_none)
        );
    }

    #[test]
    fn a_ring_part_takes_flat_ramps_where_its_seams_end_the_section() {
        // three squares in a row sharing the sides u1/u0: the middle one has seams on both
        // u sides, the outer ones on one
        let (model, edges) = strip(Role::Connecting);
        for k in 0..3 {
            // a section across v ends on the u sides, where the seams are
            assert_eq!(ramp_shape(&model, &edges, k, Direction::V), RampShape::Flat);
            // a section across u ends on the v sides: no seam there
            assert_eq!(
                ramp_shape(&model, &edges, k, Direction::U),
                RampShape::Linear
            );
        }
    }

    #[test]
    fn a_shared_edge_with_another_role_is_no_seam() {
        // the middle square between two primaries: its shared edges are no seams
        let (mut model, edges) = strip(Role::Connecting);
        model.surfaces[0].role = Role::Primary;
        model.surfaces[2].role = Role::Primary;
        assert_eq!(
            ramp_shape(&model, &edges, 1, Direction::V),
            RampShape::Linear
        );
    }
}
