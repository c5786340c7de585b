//! Reduction to an admissible configuration (\[VV18\], Fig. 3 and the paragraph after it).
//!
//! A configuration is a cyclic list of L labels (runs of candidate segments) with L junctions
//! between consecutive labels; C counts the junctions that are corners (real or virtual). The
//! six admissible (L, C) configurations are those of a rectangle's sides:
//! (0, 0), (1, 0), (2, 0) (opposite sides), (2, 1), (3, 2), (4, 4). C ≤ L always holds.
//!
//! While the configuration is not admissible, operations are applied:
//! - kill corner j: concatenate the labels at j (L → L−1, C → C−1); only for weak corners
//!   (strength below [`LabelParams::strong_strength`]) that are nearly flat (turning at most
//!   [`LabelParams::max_kill_turning_deg`]), and never when the joined label would
//!   turn more than [`LabelParams::max_label_turning_deg`];
//! - remove label k: the extensions of labels k−1 and k+1 define a new junction (L → L−1, and
//!   C → C−1 if it is a corner) — the hypothesis test of \[VV18\];
//! - remove labels k, k+1 together (L → L−2; C → C−3 when the new junction is no corner).
//!
//! After every operation labels whose new junction is a concatenation are merged, so L decreases
//! at every step and the search ends. Each configuration is scored by
//! F = min_j q_j + 0.1·(1/L) Σ_j q_j + w·ℓ_labeled/ℓ_loop (one weak corner spoils a
//! configuration, as in \[VV18\]'s examples; the mean only breaks ties), where q_j is the quality of junction j (a corner's
//! strength, [`LabelParams::none_quality`] for no corner), ℓ_labeled the length of the labeled
//! segments, ℓ_loop the perimeter and w [`LabelParams::coverage_weight`]. Rather than one greedy
//! step at a time, a beam of the [`LabelParams::beam_width`] best configurations is expanded
//! level by level; the admissible configuration with the largest F wins, and its path of
//! operations is the decision log.
//!
//! # Deviation from the paper
//! \[VV18\] applies the operations greedily, judging a removal by the strength of the corner left
//! behind; the score F and the beam (which sees that removing two labels can beat removing the
//! best single one, as in its Example 3) are ours.

use crate::candidates::signed_angle;
use crate::junction::{Corner, Junction, JunctionContext};
use crate::params::LabelParams;

/// A configuration: labels as lists of segment indices, in loop order.
#[derive(Debug, Clone, PartialEq)]
pub struct Configuration {
    /// segment indices of each label
    pub labels: Vec<Vec<usize>>,
}

/// True when (L, C) with these junction kinds is one of the six admissible configurations.
pub fn admissible(labels: usize, corners: usize) -> bool {
    matches!(
        (labels, corners),
        (0, 0) | (1, 0) | (2, 0) | (2, 1) | (3, 2) | (4, 4)
    )
}

/// One reduction operation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Operation {
    /// concatenate labels j and j+1
    KillCorner(usize),
    /// drop label k
    RemoveLabel(usize),
    /// drop labels k and k+1
    RemovePair(usize),
}

impl Configuration {
    /// Number of labels L.
    pub fn len(&self) -> usize {
        self.labels.len()
    }
    /// True when there is no label.
    pub fn is_empty(&self) -> bool {
        self.labels.is_empty()
    }

    /// Total turning of label k: its segments' turning plus the turns between them.
    pub fn turning(&self, ctx: &JunctionContext<'_, '_>, k: usize) -> f64 {
        let segs = &self.labels[k];
        let mut t: f64 = segs.iter().map(|&s| ctx.shapes[s].total_turning).sum();
        for w in segs.windows(2) {
            t += signed_angle(
                &ctx.shapes[w[0]].end_tangent,
                &ctx.shapes[w[1]].start_tangent,
            );
        }
        t
    }

    /// Length of label k (sum of its segments).
    pub fn length(&self, ctx: &JunctionContext<'_, '_>, k: usize) -> f64 {
        self.labels[k].iter().map(|&s| ctx.shapes[s].length).sum()
    }

    /// Junction between label k and the next one (a label alone has no corner with itself).
    pub fn junction(&self, ctx: &JunctionContext<'_, '_>, k: usize) -> Junction {
        let l = self.len();
        if l == 1 {
            return Junction::Corner(corner_none());
        }
        let next = (k + 1) % l;
        let a = *self.labels[k].last().expect("labels are non-empty");
        let b = self.labels[next][0];
        ctx.junction(a, b, self.turning(ctx, k), self.turning(ctx, next), true)
    }

    /// All junctions.
    pub fn junctions(&self, ctx: &JunctionContext<'_, '_>) -> Vec<Junction> {
        (0..self.len()).map(|k| self.junction(ctx, k)).collect()
    }

    /// Merges labels across concatenation junctions, best quality first; returns the merges
    /// made as (segment at the end of the first label, segment at the start of the second).
    pub fn merge_concatenations(&mut self, ctx: &JunctionContext<'_, '_>) -> Vec<(usize, usize)> {
        let mut merged = Vec::new();
        while self.len() >= 2 {
            let best = self
                .junctions(ctx)
                .iter()
                .enumerate()
                .filter_map(|(k, j)| match j {
                    Junction::Concatenate { quality } => Some((k, *quality)),
                    Junction::Corner(_) => None,
                })
                .max_by(|a, b| a.1.total_cmp(&b.1));
            let Some((k, _)) = best else { break };
            merged.push((
                *self.labels[k].last().expect("non-empty"),
                self.labels[(k + 1) % self.len()][0],
            ));
            self.concatenate(k);
        }
        merged
    }

    /// Joins label k with the next one.
    fn concatenate(&mut self, k: usize) {
        let next = (k + 1) % self.len();
        let tail = self.labels[next].clone();
        self.labels[k].extend(tail);
        // when next == 0 the joined label moves to the end, which keeps the cyclic order
        self.labels.remove(next);
    }

    /// Applies an operation (without merging).
    pub fn apply(&mut self, op: Operation) {
        let l = self.len();
        match op {
            Operation::KillCorner(j) => self.concatenate(j),
            Operation::RemoveLabel(k) => {
                self.labels.remove(k);
            }
            Operation::RemovePair(k) => {
                let k2 = (k + 1) % l;
                let (hi, lo) = (k.max(k2), k.min(k2));
                self.labels.remove(hi);
                self.labels.remove(lo);
            }
        }
    }

    /// Number of corners among the junctions.
    pub fn corner_count(junctions: &[Junction]) -> usize {
        junctions
            .iter()
            .filter(|j| matches!(j, Junction::Corner(c) if c.is_corner()))
            .count()
    }
}

fn corner_none() -> Corner {
    Corner {
        kind: crate::junction::CornerKind::None,
        position: None,
        position_2d: None,
        strength: 0.0,
        turning: 0.0,
        distance: 0.0,
        extension_from: None,
    }
}

/// Quality of a junction for scoring (see the module docs).
pub fn quality(j: &Junction, params: &LabelParams) -> f64 {
    match j {
        Junction::Concatenate { quality } => *quality,
        Junction::Corner(c) if c.is_corner() => c.strength,
        Junction::Corner(_) => params.none_quality,
    }
}

/// Weight of the mean junction quality beside the weakest one in F: a tie-breaker.
const MEAN_WEIGHT: f64 = 0.1;

/// Score F of a configuration (see the module docs).
pub fn objective(
    config: &Configuration,
    junctions: &[Junction],
    ctx: &JunctionContext<'_, '_>,
) -> f64 {
    let l = config.len();
    let coverage: f64 = (0..l).map(|k| config.length(ctx, k)).sum::<f64>()
        / ctx.region.perimeter().max(f64::MIN_POSITIVE);
    if l == 0 {
        return 0.0;
    }
    let q: Vec<f64> = junctions.iter().map(|j| quality(j, ctx.params)).collect();
    let mean = q.iter().sum::<f64>() / l as f64;
    let min = q.iter().copied().fold(f64::INFINITY, f64::min);
    min + MEAN_WEIGHT * mean + ctx.params.coverage_weight * coverage
}

/// The operations allowed on `config`.
pub fn operations(
    config: &Configuration,
    junctions: &[Junction],
    ctx: &JunctionContext<'_, '_>,
) -> Vec<Operation> {
    let l = config.len();
    let mut out = Vec::new();
    for (j, junction) in junctions.iter().enumerate() {
        if let Junction::Corner(c) = junction {
            let merged = config.turning(ctx, j) + c.turning + config.turning(ctx, (j + 1) % l);
            if c.is_corner()
                && l >= 2
                && c.strength < ctx.params.strong_strength
                && c.turning.abs() <= ctx.params.max_kill_turning_deg.to_radians()
                && merged.abs() <= ctx.params.max_label_turning_deg.to_radians()
            {
                out.push(Operation::KillCorner(j));
            }
        }
    }
    if l >= 1 {
        out.extend((0..l).map(Operation::RemoveLabel));
    }
    if l >= 3 {
        out.extend((0..l).map(Operation::RemovePair));
    }
    out
}

/// One step of the chosen reduction, for the log.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// the configuration before the step
    pub before: Configuration,
    /// the operation
    pub op: Operation,
}

#[derive(Clone)]
struct Node {
    config: Configuration,
    junctions: Vec<Junction>,
    score: f64,
    path: Vec<Step>,
}

/// Reduces `start` to the best admissible configuration reachable (see the module docs); returns
/// it and the steps taken. An admissible `start` is returned as it is.
pub fn reduce(start: Configuration, ctx: &JunctionContext<'_, '_>) -> (Configuration, Vec<Step>) {
    let node = |config: Configuration, path: Vec<Step>| {
        let junctions = config.junctions(ctx);
        let score = objective(&config, &junctions, ctx);
        Node {
            config,
            junctions,
            score,
            path,
        }
    };
    let first = node(start, Vec::new());
    let is_admissible =
        |n: &Node| admissible(n.config.len(), Configuration::corner_count(&n.junctions));
    if is_admissible(&first) {
        return (first.config, first.path);
    }
    let width = ctx.params.beam_width.max(1);
    let mut best: Option<Node> = None;
    let mut beam = vec![first];
    let mut seen: std::collections::HashSet<Vec<Vec<usize>>> = std::collections::HashSet::new();
    while !beam.is_empty() {
        let mut next: Vec<Node> = Vec::new();
        for n in &beam {
            for op in operations(&n.config, &n.junctions, ctx) {
                let mut c = n.config.clone();
                c.apply(op);
                c.merge_concatenations(ctx);
                let mut key = c.labels.clone();
                if let Some(min) = (0..key.len()).min_by_key(|&k| key[k][0]) {
                    key.rotate_left(min);
                }
                if !seen.insert(key) {
                    continue;
                }
                let mut path = n.path.clone();
                path.push(Step {
                    before: n.config.clone(),
                    op,
                });
                let child = node(c, path);
                if is_admissible(&child) {
                    if best.as_ref().is_none_or(|b| child.score > b.score) {
                        best = Some(child);
                    }
                } else {
                    next.push(child);
                }
            }
        }
        next.sort_by(|a, b| b.score.total_cmp(&a.score));
        next.truncate(width);
        beam = next;
    }
    let best = best.unwrap_or_else(|| node(Configuration { labels: Vec::new() }, Vec::new()));
    (best.config, best.path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_six_admissible_configurations() {
        let mut ok = Vec::new();
        for l in 0..8 {
            for c in 0..=l {
                if admissible(l, c) {
                    ok.push((l, c));
                }
            }
        }
        assert_eq!(ok, [(0, 0), (1, 0), (2, 0), (2, 1), (3, 2), (4, 4)]);
    }

    #[test]
    fn removing_a_pair_across_the_start_keeps_cyclic_order() {
        let mut c = Configuration {
            labels: vec![vec![0], vec![1], vec![2], vec![3]],
        };
        c.apply(Operation::RemovePair(3));
        assert_eq!(c.labels, vec![vec![1], vec![2]]);
        let mut c = Configuration {
            labels: vec![vec![0], vec![1], vec![2]],
        };
        c.apply(Operation::KillCorner(2));
        assert_eq!(c.labels, vec![vec![1], vec![2, 0]]);
    }
}
