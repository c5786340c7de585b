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
//! its master; its corner is the two-master corner of a vertex blend, [`super::vertex`]).

use super::*;
use crate::edges::{is_seam, opened_seams};
use crate::model::Link;

/// Least share of a side a seam must cover to become a link: a link holds on the whole side
/// (model-format.md). The parts of a ring share whole sides; a partial seam stays free.
pub const LINKED_SEAM_FRACTION: f64 = 0.999;

impl Plan<'_> {
    /// The parts of `again` (the wave's surfaces on opened seams, in file order) run again one
    /// after the other from `out`: the first keeps its free result (`free`), each later one is
    /// run with its seams to the earlier ones linked G2 (those as they are by then). Returns
    /// the new outcomes when every seam of the wave then stays within its tolerance, `None`
    /// otherwise (the caller keeps the seams as they came).
    pub(super) fn seams_linked(
        &self,
        out: &Model,
        wave: &[usize],
        again: &[usize],
        free: &[(usize, Outcome)],
    ) -> Option<Vec<(usize, Outcome)>> {
        let mut current = out.clone();
        for (k, o) in free {
            current.surfaces[*k].surface = o.surface.clone();
        }
        let mut rerun = Vec::new();
        for (n, &k) in again.iter().enumerate() {
            let mut linked = self.model.clone();
            linked.links.extend(
                self.edges
                    .iter()
                    .filter(|e| e.surface == k && again[..n].contains(&e.other))
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
            current.surfaces[k].surface = outcome.surface.clone();
            rerun.push((k, outcome));
        }
        let now = |k: usize| &current.surfaces[k].surface;
        opened_seams(self.model, &now, self.edges, self.edges_before, wave)
            .is_empty()
            .then_some(rerun)
    }
}
