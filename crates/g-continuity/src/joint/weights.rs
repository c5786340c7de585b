//! The weights of the polish's residuals: Lawson's update of a least-squares fit towards a
//! minimax one ([`JOINT_REWEIGHTS`]).

use nurbs_core::BSplineSurface;

use super::{JOINT_GOAL, Problem, RES};
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
