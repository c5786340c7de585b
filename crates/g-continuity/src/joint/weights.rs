//! The weights of the polish's residuals: Lawson's update of a least-squares fit towards a
//! minimax one ([`JOINT_REWEIGHTS`]).

use nurbs_core::BSplineSurface;

use super::{JOINT_GOAL, JOINT_ITERATIONS, JOINT_REWEIGHTS, Problem, RES, normal, worst};
use crate::error::Result;
use crate::params::ConnectParams;

/// Lawson's update ([`JOINT_REWEIGHTS`]): each group of a sample's residuals (the gap, the
/// normals' difference, the curvature) has its weight multiplied by its length over
/// [`JOINT_GOAL`] where that is more than 1. `unweighted` holds the residuals without weights,
/// [`RES`] per sample like `weights`.
///
/// [`JOINT_REWEIGHTS`]: super::JOINT_REWEIGHTS
pub(super) fn lawson(weights: &mut [f64], unweighted: &[f64]) {
    for (w, r) in weights.chunks_mut(RES).zip(unweighted.chunks(RES)) {
        for group in [0..3, 3..5, 5..6] {
            let len = r[group.clone()].iter().map(|x| x * x).sum::<f64>().sqrt();
            let factor = (len / JOINT_GOAL).max(1.0);
            for x in &mut w[group] {
                *x *= factor;
            }
        }
    }
}

impl Problem<'_> {
    /// The residuals `r` (weighted) without their weights.
    pub(super) fn unweighted(&self, r: &[f64]) -> Vec<f64> {
        r.iter().zip(&self.weights).map(|(x, w)| x / w).collect()
    }

    /// The largest unweighted residual of `r`.
    pub(super) fn worst(&self, r: &[f64]) -> f64 {
        r.iter()
            .zip(&self.weights)
            .fold(0.0f64, |m, (x, w)| m.max((x / w).abs()))
    }

    /// [`lawson`]'s update of this problem's weights from the residuals `unweighted`.
    pub(super) fn reweight(&mut self, unweighted: &[f64]) {
        lawson(&mut self.weights, unweighted);
    }

    /// How many links `s` meets by the measure of `params`.
    pub(super) fn met(&self, s: &BSplineSurface, params: &ConnectParams) -> usize {
        let t = params.tolerances;
        self.links
            .iter()
            .filter(|l| {
                l.measure(s, &params.measure)
                    .is_ok_and(|m| m.meets(l.target, t.g0, t.g1_deg, t.g2_rel))
            })
            .count()
    }
}

/// A polish round's result: the links it meets, its worst residual (without weights), its
/// surface and residuals.
pub(super) struct Round {
    pub(super) met: usize,
    pub(super) worst: f64,
    pub(super) s: BSplineSurface,
    pub(super) r: Vec<f64>,
}

impl Round {
    /// Whether a round meeting `met` links with worst residual `worst` replaces this one: more
    /// links met, or as many with a smaller worst residual.
    fn beaten_by(&self, met: usize, worst: f64) -> bool {
        ranks_above((met, worst), (self.met, self.worst))
    }
}

/// Whether a round meeting `a.0` links with worst residual `a.1` ranks above one with `b`: more
/// links met, or as many with a smaller worst residual.
fn ranks_above(a: (usize, f64), b: (usize, f64)) -> bool {
    a.0 > b.0 || (a.0 == b.0 && a.1 < b.1)
}

impl Problem<'_> {
    /// The reweighted rounds after a first round (from `lm`'s state) that met `first.0` links
    /// with worst residual `first.1` and residuals `first.2`, where it met more than `slave`
    /// did but not all ([`JOINT_REWEIGHTS`]); `best` keeps the best round. Returns the
    /// iterations.
    pub(super) fn reweighted(
        &mut self,
        lm: &mut normal::Lm,
        first: (usize, f64, &[f64]),
        slave: &BSplineSurface,
        max_move: f64,
        params: &ConnectParams,
        best: &mut Round,
    ) -> Result<usize> {
        let (met, w) = (first.0, first.1);
        let mut iterations = 0;
        // the reweighted rounds run only after a first round that met more links than its
        // start, sharing one round's iterations; where none of them beat the first round (each
        // stopped as its worst residual rose: too short to solve its reweighted problem, which
        // Lawson's update assumes solved) they run again from the first round's state with a
        // whole round's iterations each
        if met < self.links.len() && met > self.met(slave, params) {
            let start = (lm.s.clone(), lm.r.clone(), lm.ds.clone(), lm.offset.clone());
            let weights = self.weights.clone();
            iterations += self.rounds(
                lm,
                first,
                JOINT_ITERATIONS / JOINT_REWEIGHTS,
                max_move,
                params,
                best,
            )?;
            if best.met == met && best.worst == w {
                (lm.s, lm.r, lm.ds, lm.offset) = start;
                self.weights = weights;
                iterations += self.rounds(lm, first, JOINT_ITERATIONS, max_move, params, best)?;
            }
        }
        Ok(iterations)
    }

    /// Up to [`JOINT_REWEIGHTS`] reweighted rounds of `limit` iterations each from the state of
    /// `lm`, whose first round met `first.0` links with worst residual `first.1` and residuals
    /// `first.2` (unweighted): Lawson's update, then a least-squares round, while each round's
    /// worst residual is below that of the best round of these rounds so far and links are
    /// missed; `best` keeps the round meeting the most links (then with the smallest worst
    /// residual). Returns the iterations.
    fn rounds(
        &mut self,
        lm: &mut normal::Lm,
        first: (usize, f64, &[f64]),
        limit: usize,
        max_move: f64,
        params: &ConnectParams,
        best: &mut Round,
    ) -> Result<usize> {
        let (mut kept_met, mut kept_worst) = (first.0, first.1);
        let mut unweighted = first.2.to_vec();
        let mut iterations = 0;
        for _ in 0..JOINT_REWEIGHTS {
            self.reweight(&unweighted);
            (lm.r, lm.ds) = self.residual(&lm.s);
            iterations += self.least_squares(lm, limit, max_move, params)?;
            unweighted = self.unweighted(&lm.r);
            let (w, met) = (worst(&unweighted), self.met(&lm.s, params));
            let improved = w < kept_worst;
            if best.beaten_by(met, w) {
                *best = Round {
                    met,
                    worst: w,
                    s: lm.s.clone(),
                    r: unweighted.clone(),
                };
            }
            if ranks_above((met, w), (kept_met, kept_worst)) {
                (kept_met, kept_worst) = (met, w);
            }
            if met == self.links.len() || !improved {
                break;
            }
        }
        Ok(iterations)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_groups_beyond_the_goal_gain_weight_by_their_excess() {
        let mut w = vec![1.0; 2 * RES];
        // sample 0: a gap within the goal, normals 10 goals off (|(3, 4)| = 5 tolerances),
        // a curvature at the goal; sample 1: a gap 4 goals off, the rest zero
        let r = [
            0.1,
            0.2,
            0.2,
            3.0,
            4.0,
            JOINT_GOAL,
            0.0,
            2.0 * JOINT_GOAL * 2.0,
            0.0,
            0.0,
            0.0,
            0.0,
        ];
        lawson(&mut w, &r);
        assert_eq!(&w[..RES], &[1.0, 1.0, 1.0, 10.0, 10.0, 1.0]);
        assert_eq!(&w[RES..], &[4.0, 4.0, 4.0, 1.0, 1.0, 1.0]);
        // a second round multiplies
        lawson(&mut w, &r);
        assert_eq!(&w[..RES], &[1.0, 1.0, 1.0, 100.0, 100.0, 1.0]);
    }
}
