//! The boundary's move spread into the interior, chosen per surface: the C0 steps of a surface
//! that is no master, one of whose masters took its one-hump section ([`super::section`]),
//! move its interior with its boundary ([`g_continuity::SetParams::spread_boundary_move`]);
//! where the result then misses a link, the stages run again without, and the result that
//! misses fewer links is kept.
//!
//! Why: a vertex blend bounded by fillets whose one-hump sections changed their end curves must
//! follow curves up to the deviation budget away (0.24 mm on a box's 5 mm fillets per role); moving
//! only its boundary rows turned that into a strip of curvature beside each side (its sphere
//! corners peaked at 11× their input's), spread it peaks at 1.8×. Elsewhere the masters moved only
//! where their lead-ins are, near the slave's vertices, and the spread is no help: with it a
//! variable-radius box's sphere corner by default (masters moved 0.024 mm) missed G2 in its dry run
//! and was kept at G1 with a peak of 14× its input's, against 6× without. A master keeps its
//! interior for its slaves (with the spread in a variable-radius box's fillets too, its B-spline
//! corner missed two links per role and three by default, whichever way it ran); a slave whose
//! stages miss with the spread (that B-spline corner, though its dry run met them) runs again
//! without (docs/benchmarks.md).

use nurbs_core::BSplineSurface;

use super::error::StageResult;
use super::{Job, Problem, StageReport};

/// What [`Job::stages`] returns.
type StagesResult = StageResult<(BSplineSurface, Vec<StageReport>)>;

impl Job<'_> {
    /// The stages of this surface from `original` (\[SV\] §3.2): the dry run decides the highest
    /// level the tolerance allows (conflicts and misses go to `problems` and `missed`), the set
    /// and fairing stages run up to it, and the never-worse fallback picks the result.
    ///
    /// With the boundary's move spread into the interior where the job's `spread` is set (a
    /// slave that is no master, one of whose masters took its section); where that result
    /// misses a link, the stages run again without, and that result is kept where it misses
    /// fewer links (module docs). A master whose result took its one-hump section and
    /// is not fair by every figure runs again without the section.
    pub(super) fn stages(
        &self,
        original: &BSplineSurface,
        problems: &mut Vec<Problem>,
        missed: &mut Vec<(usize, Problem)>,
    ) -> StagesResult {
        let (mut own_problems, mut own_missed) = (Vec::new(), Vec::new());
        let result = self.stages_spread(original, &mut own_problems, &mut own_missed);
        // a master keeps its one-hump section only where its faired result is fair by every
        // figure: its slaves pay for the changed section (measured: on the synthetic block
        // grid the sectioned fillets came out with 5 extrema across where their input had 2,
        // and a corner set against them rose in energy)
        let sectioned = |r: &StagesResult| {
            r.as_ref().is_ok_and(|(s, stages)| {
                stages.first().is_some_and(|st| st.section_ramp.is_some())
                    && !self.verdict_of(s).fair()
            })
        };
        if self.section_allowed && self.is_master() && sectioned(&result) {
            let plain = Job {
                section_allowed: false,
                ..*self
            };
            return plain.stages(original, problems, missed);
        }
        problems.append(&mut own_problems);
        missed.append(&mut own_missed);
        result
    }

    /// [`Job::stages`] with the spread where the job's `spread` is set, and without where that
    /// misses more links.
    fn stages_spread(
        &self,
        original: &BSplineSurface,
        problems: &mut Vec<Problem>,
        missed: &mut Vec<(usize, Problem)>,
    ) -> StagesResult {
        if !self.spread {
            return self.stages_with(original, problems, missed, false);
        }
        let (mut p1, mut m1) = (Vec::new(), Vec::new());
        let first = self.stages_with(original, &mut p1, &mut m1, true);
        let misses =
            |r: &StagesResult| r.as_ref().map_or(usize::MAX, |(s, _)| self.links_missed(s));
        let first_misses = misses(&first);
        if first_misses > 0 {
            let (mut p2, mut m2) = (Vec::new(), Vec::new());
            let second = self.stages_with(original, &mut p2, &mut m2, false);
            if misses(&second) < first_misses {
                problems.append(&mut p2);
                missed.append(&mut m2);
                return second;
            }
        }
        problems.append(&mut p1);
        missed.append(&mut m1);
        first
    }

    /// How many of this surface's links `s` misses (each measured against its target).
    fn links_missed(&self, s: &BSplineSurface) -> usize {
        let t = &self.connect.tolerances;
        self.links()
            .iter()
            .filter(|(_, l)| {
                l.measure(s, &self.connect.measure)
                    .map_or(true, |m| !m.meets(l.target, t.g0, t.g1_deg, t.g2_rel))
            })
            .count()
    }
}
