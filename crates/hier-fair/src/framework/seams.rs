//! A seam the free continuity steps opened: the parts of the ring run again one after the
//! other, each later part linked G2 to the earlier ones along their seams.
//!
//! The parts of a fillet ring are faired in one wave, each to its own masters; a seam between
//! them is left to the continuity steps ([`crate::edges::is_seam`]), which set both parts alike
//! where their masters agree. Near a seam's ends both parts move the seam's columns to reach G2
//! at their links, each by its own row solve, and the seam can open there (a pipe tee's saddle
//! of r 3: 0.025–0.050° next to the ends with the fairing's limit set to 20,000 moves). Kept as
//! it came, the seam holds the input's rolling-ball cross-section at the corners, which no G2
//! join to the masters can follow. Linked instead, the later part takes the earlier one as the
//! master of its seam sides: at a seam's end the earlier part is G2 to the same masters, so the
//! later part's corner asks for one curvature from both its masters (\[SV\] §3.2: the slave follows
//! its master; its corner is the two-master corner of a vertex blend, [`super::vertex`]). Only the
//! parts on an opened seam run again: linked G2 across its seams, a fillet part would have G2
//! sides in both directions and lose its one-hump section, so the closed seams of a ring stay
//! as the free run left them (a ring of a metre part: 20 of its 126 links were lost
//! when every part of the ring ran again linked).

use nurbs_core::{BSplineSurface, Continuity};

use super::{Outcome, Plan};
use crate::edges::{EdgeMeasure, SharedEdge, is_seam, measure_edge};
use crate::model::{Link, Model};

/// Surfaces run again, each with its outcome.
type Outcomes = Vec<(usize, Outcome)>;

/// How unfair the parts run again are: their faults together, and the largest spike.
#[derive(Clone, Copy)]
struct Unfairness(usize, f64);

impl Unfairness {
    /// Fewer faults, or as many and a smaller spike.
    fn below(&self, other: &Self) -> bool {
        self.0 < other.0 || (self.0 == other.0 && self.1 < other.1)
    }
}

/// The [`Unfairness`] of the outcomes `rerun` (each judged against its input).
fn unfairness(rerun: &[(usize, Outcome)]) -> Unfairness {
    rerun.iter().fold(Unfairness(0, 0.0), |acc, (_, o)| {
        let v = o.report.fairness_verdict();
        Unfairness(acc.0 + v.faults().len(), acc.1.max(v.spike()))
    })
}

/// `out` with the surfaces of `results` in place of its own.
fn with_results(out: &Model, results: &[(usize, Outcome)]) -> Model {
    let mut current = out.clone();
    for (k, o) in results {
        current.surfaces[*k].surface = o.surface.clone();
    }
    current
}

/// Least share of a side a seam must cover to become a link: a link holds on the whole side
/// (model-format.md). The parts of a ring share whole sides; a partial seam stays free.
pub const LINKED_SEAM_FRACTION: f64 = 0.999;

impl Plan<'_> {
    /// The surfaces on opened seams of one ring, `again`, run again one after the other from
    /// `out`, each linked G2 along its seams to the parts that ran before it and to those that
    /// keep their free result (the rest of the ring); the first has nothing to follow and keeps
    /// its free result (`free`). The part that meets most of its own links in its free run goes
    /// first (in index order among equals): a part that meets its links is the better master,
    /// and one that cannot follows it rather than drag it along; where that order fails, each
    /// other part first in turn (a fillet part linked across its seam has G2 sides in both
    /// directions and loses its one-hump section, so a vertex blend's part next to it may be the
    /// one to follow). Returns the first order's outcomes under which every seam of `again`'s
    /// parts stays within its tolerance, no part meets fewer of its own links than in its free
    /// run and every part run again is fair ([`crate::fairness`]); where every such order leaves
    /// a part unfair, the one with the fewest faults and then the least spike (a follower that
    /// meets its links only with wrinkles is no better master than the other order's: measured
    /// on a metre part's fillet ring, a part that followed its neighbour peaked at 58× its input's
    /// curvature, docs/benchmarks.md); `None` where no order closes the seams (the caller keeps
    /// the seams as they came).
    pub(super) fn seams_linked(
        &self,
        out: &Model,
        wave: &[usize],
        again: &[usize],
        free: &[(usize, Outcome)],
    ) -> Option<Vec<(usize, Outcome)>> {
        let current = with_results(out, free);
        let mut order: Vec<(usize, usize)> = again
            .iter()
            .map(|&k| (k, self.met_own(out, k, &current.surfaces[k].surface)))
            .collect();
        order.sort_by_key(|&(k, m)| (std::cmp::Reverse(m), k));
        let mut best: Option<(Unfairness, Outcomes)> = None;
        for first in 0..order.len() {
            let mut turn = order.clone();
            let lead = turn.remove(first);
            turn.insert(0, lead);
            let Some(rerun) = self.linked_in_order(out, wave, again, &turn, current.clone()) else {
                continue;
            };
            let score = unfairness(&rerun);
            if score.0 == 0 {
                return Some(rerun);
            }
            if best.as_ref().is_none_or(|(b, _)| score.below(b)) {
                best = Some((score, rerun));
            }
        }
        best.map(|(_, rerun)| rerun)
    }

    /// The rings whose parts `kept` no order of [`Self::seams_linked`] closed without losing a
    /// link: the parts linked again, the one that meets most links first, now where some lose
    /// links (those are then named unmet), else their whole rings (`again`) linked in index
    /// order; the outcomes and the parts run again where that closes every seam of theirs
    /// (never-worse holds for seams first), `None` otherwise.
    pub(super) fn linked_losing(
        &self,
        out: &Model,
        wave: &[usize],
        free: &[(usize, Outcome)],
        kept: &[usize],
        again: &[usize],
    ) -> Option<(Outcomes, Vec<usize>)> {
        let current = with_results(out, free);
        let lossy = |parts: &[usize]| {
            let order: Vec<(usize, usize)> = parts.iter().map(|&k| (k, 0)).collect();
            self.linked_in_order(out, wave, parts, &order, current.clone())
        };
        let mut first = kept.to_vec();
        first.sort_by_key(|&k| {
            let met = self.met_own(out, k, &current.surfaces[k].surface);
            (std::cmp::Reverse(met), k)
        });
        lossy(&first)
            .map(|l| (l, first.clone()))
            .or_else(|| lossy(again).map(|l| (l, again.to_vec())))
    }

    /// Surface `k`'s own links (of the model) that `surface` meets against its masters in
    /// `out` (earlier waves: the same in every run of this wave).
    fn met_own(&self, out: &Model, k: usize, surface: &BSplineSurface) -> usize {
        let own = self.job(self.model, out, k, true);
        let links: Vec<_> = own.links().into_iter().map(|(_, l)| l).collect();
        own.met_links(&links, surface)
    }

    /// [`Self::seams_linked`] in one order (`order`: each part with the links its free result
    /// meets, 0 where none may be lost to close the seams), from `current` (the wave's free
    /// results).
    pub(super) fn linked_in_order(
        &self,
        out: &Model,
        wave: &[usize],
        again: &[usize],
        order: &[(usize, usize)],
        mut current: Model,
    ) -> Option<Vec<(usize, Outcome)>> {
        let mut rerun = Vec::new();
        for (n, &(k, free_met)) in order.iter().enumerate().skip(1) {
            let followed = |j: usize| order[..n].iter().any(|o| o.0 == j) || !again.contains(&j);
            let mut linked = self.model.clone();
            linked.links.extend(
                self.edges
                    .iter()
                    .filter(|e| e.surface == k && followed(e.other))
                    .filter(|e| is_seam(self.model, e) && e.fraction >= LINKED_SEAM_FRACTION)
                    .map(|e| Link {
                        slave: k,
                        side: e.side,
                        master: e.other,
                        continuity: Continuity::G2,
                    }),
            );
            if linked.links.len() == self.model.links.len() {
                continue;
            }
            // from the input, against the earlier parts as they are now
            current.surfaces[k].surface = out.surfaces[k].surface.clone();
            let outcome = self.job(&linked, &current, k, true).run();
            if self.met_own(out, k, &outcome.surface) < free_met {
                return None;
            }
            current.surfaces[k].surface = outcome.surface.clone();
            rerun.push((k, outcome));
        }
        let now = |k: usize| &current.surfaces[k].surface;
        on_opened_seams(self.model, &now, self.edges, self.edges_before, wave, again)
            .is_empty()
            .then_some(rerun)
    }
}

/// `start` and every surface of `allowed` joined to one of them by a chain of seams
/// ([`is_seam`]) through surfaces of `allowed`, in index order.
fn along_seams(
    model: &Model,
    edges: &[SharedEdge],
    start: &[usize],
    allowed: &[usize],
) -> Vec<usize> {
    let seams: Vec<&SharedEdge> = edges.iter().filter(|e| is_seam(model, e)).collect();
    let mut grown = start.to_vec();
    loop {
        let more: Vec<usize> = seams
            .iter()
            .filter(|e| grown.contains(&e.surface) != grown.contains(&e.other))
            .flat_map(|e| [e.surface, e.other])
            .filter(|k| allowed.contains(k) && !grown.contains(k))
            .collect();
        if more.is_empty() {
            break;
        }
        grown.extend(more);
    }
    grown.sort_unstable();
    grown.dedup();
    grown
}

/// `start` and every surface of `wave` joined to one of them by a chain of seams: the rest of
/// their rings (kept on one side only, a seam would open too), in index order.
pub(super) fn ring_closure(
    model: &Model,
    edges: &[SharedEdge],
    wave: &[usize],
    start: &[usize],
) -> Vec<usize> {
    along_seams(model, edges, start, wave)
}

/// The surfaces of `wave` on a seam ([`is_seam`]) with one of `of` that the wave's results
/// (`now`: a surface as the wave leaves it) leave with a gap or angle beyond the input's plus
/// the G0/G1 tolerance (the rule of [`crate::edges::EdgeFair`]), in index order.
pub(super) fn on_opened_seams<'a>(
    model: &Model,
    now: &dyn Fn(usize) -> &'a BSplineSurface,
    edges: &[SharedEdge],
    edges_before: &[EdgeMeasure],
    wave: &[usize],
    of: &[usize],
) -> Vec<usize> {
    let t = &model.tolerances;
    let mut out = Vec::new();
    for (e, b) in edges.iter().zip(edges_before) {
        let touches = |k: usize| wave.contains(&k) && of.contains(&k);
        if !is_seam(model, e) || !(touches(e.surface) || touches(e.other)) {
            continue;
        }
        let m = measure_edge(e, now(e.surface), now(e.other));
        if m.worse_than(b, t.g0, t.g1_deg) {
            out.extend(
                [e.surface, e.other]
                    .into_iter()
                    .filter(|k| wave.contains(k)),
            );
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// The surfaces of `wave` joined by seams into rings, each ring in index order (rings ordered
/// by their first surface), from the surfaces `parts`: two parts are in one ring when a chain of
/// seams between parts joins them.
pub(super) fn seam_rings(model: &Model, edges: &[SharedEdge], parts: &[usize]) -> Vec<Vec<usize>> {
    let mut rings: Vec<Vec<usize>> = Vec::new();
    for &k in parts {
        if !rings.iter().any(|r| r.contains(&k)) {
            rings.push(along_seams(model, edges, &[k], parts));
        }
    }
    rings
}

#[cfg(test)]
mod tests {
    use super::{Unfairness, on_opened_seams, ring_closure, seam_rings};
    use crate::edges::tests::{lifted, strip};
    use crate::edges::{EdgeMeasure, measure_edge};
    use crate::model::Role;

    #[test]
    fn an_order_with_fewer_faults_is_fairer_and_then_the_smaller_spike() {
        let (two_small, one_large) = (Unfairness(2, 1.2), Unfairness(1, 58.0));
        assert!(one_large.below(&two_small) && !two_small.below(&one_large));
        let (a, b) = (Unfairness(1, 1.7), Unfairness(1, 36.0));
        assert!(a.below(&b) && !b.below(&a));
        // equal: neither is below, so the earlier order is kept
        assert!(!a.below(&a));
    }

    #[test]
    fn an_opened_seam_sends_its_surfaces_back_and_names_their_ring() {
        let (model, edges) = strip(Role::Connecting);
        let before: Vec<EdgeMeasure> = edges
            .iter()
            .map(|e| {
                measure_edge(
                    e,
                    &model.surfaces[e.surface].surface,
                    &model.surfaces[e.other].surface,
                )
            })
            .collect();
        let wave = [0, 1, 2];
        let g0 = model.tolerances.g0;
        // surface 1 moved its u0 side by a tenth of the gap tolerance: the seam stays
        let within = lifted(&model.surfaces[1].surface, 0.1 * g0);
        let now = |k: usize| {
            if k == 1 {
                &within
            } else {
                &model.surfaces[k].surface
            }
        };
        assert_eq!(
            on_opened_seams(&model, &now, &edges, &before, &wave, &wave),
            Vec::<usize>::new()
        );
        // ten times the tolerance on surface 0's side u1 (its far side stays): the seam 0 ~ 1
        // opened, the seam 1 ~ 2 did not; 0 and 1 run again, one ring; with the seams kept, 2,
        // joined to 1 by the other seam, runs again too (kept on one side only, that seam would
        // open)
        let mut beyond = model.surfaces[0].surface.clone();
        let nv = beyond.num_v();
        let n = beyond.control_points().len();
        for p in &mut beyond.control_points_mut()[n - nv..] {
            p.z += 10.0 * g0;
        }
        let now = |k: usize| {
            if k == 0 {
                &beyond
            } else {
                &model.surfaces[k].surface
            }
        };
        let opened = on_opened_seams(&model, &now, &edges, &before, &wave, &wave);
        assert_eq!(opened, vec![0, 1]);
        assert_eq!(seam_rings(&model, &edges, &opened), vec![vec![0, 1]]);
        assert_eq!(ring_closure(&model, &edges, &wave, &opened), vec![0, 1, 2]);
        // only the seams of the surfaces asked about count
        assert_eq!(
            on_opened_seams(&model, &now, &edges, &before, &wave, &[2]),
            Vec::<usize>::new()
        );
        // a surface outside the wave is not run again
        assert_eq!(
            on_opened_seams(&model, &now, &edges, &before, &[1], &[1]),
            vec![1]
        );
        assert_eq!(ring_closure(&model, &edges, &[1], &[1]), vec![1]);
    }
}
