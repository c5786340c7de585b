//! The deviation budget of one surface: how its tolerance τ is shared between the continuity
//! steps, the fairing stages, a master's slaves and a corner group's mesh fairing (\[SV\] §3.2).
//!
//! The shares are settings ([`DeviationBudget`], [`super::FairParams::budget`]); their defaults
//! are the constants below, each with the reason for its value. Two things follow from the
//! geometry rather than from a share: a fairing stage's ball ε ([`DeviationBudget::stage_epsilon`],
//! the budget left over the stages left, so that the stages cannot add up past it — a control
//! move ≤ ε moves the surface ≤ ε, polynomial or rational, R_ij ≥ 0 with Σ R_ij = 1), and the
//! lead-in width, searched against [`DeviationBudget::lead_in`] (dry_run.rs).

/// Fraction of the deviation tolerance the fairing stages may plan to use (the rest absorbs the
/// difference between sampled and true deviation: the deviation is sampled on a 41 × 41 grid,
/// and between samples a surface moved within ε can deviate a little more than at them).
pub const DEVIATION_SAFETY: f64 = 0.95;

/// Share of the deviation tolerance the fairing stages of a *master* may use: its slaves must
/// follow whatever its fairing changes along their joins, and that costs them deviation too —
/// half for the master, half left for what its slaves have to follow.
pub const MASTER_SHARE: f64 = 0.5;

/// Share of the deviation tolerance the continuity steps alone may use when the framework
/// chooses the width of a G2 lead-in: the rest is left to the fairing stages. The lead-in's
/// width grows with the square root of the deviation it may use, so half the budget still
/// gives 1/√2 ≈ 71 % of the widest transition the whole budget would allow, and the fairing
/// keeps as much room as the continuity steps take.
pub const LEAD_IN_SHARE: f64 = 0.5;

/// Share of the deviation tolerance the n-sided mesh fairing of a corner group may use; a group
/// whose refitted patches deviate more is left as it was (reported), the per-patch stages then
/// fair it within the tolerance — and need the other half to set each patch's continuity.
pub const GROUP_SHARE: f64 = 0.5;

/// How a surface's deviation tolerance is shared (see the module docs; each field's default
/// is the constant of the same name).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeviationBudget {
    /// fraction of τ a surface's fairing stages plan with ([`DEVIATION_SAFETY`])
    pub safety: f64,
    /// fraction of τ a master's fairing stages plan with ([`MASTER_SHARE`])
    pub master_share: f64,
    /// fraction of τ the continuity steps alone may take when the lead-in width is chosen
    /// ([`LEAD_IN_SHARE`])
    pub lead_in_share: f64,
    /// fraction of τ a corner group's mesh fairing may move its patches ([`GROUP_SHARE`])
    pub group_share: f64,
}

impl Default for DeviationBudget {
    fn default() -> Self {
        Self {
            safety: DEVIATION_SAFETY,
            master_share: MASTER_SHARE,
            lead_in_share: LEAD_IN_SHARE,
            group_share: GROUP_SHARE,
        }
    }
}

impl DeviationBudget {
    /// The deviation the fairing stages of a surface with tolerance `tolerance` plan with: the
    /// master share for a surface some slave is linked to, the safety fraction otherwise.
    pub fn fairing(&self, tolerance: f64, is_master: bool) -> f64 {
        if is_master {
            self.master_share * tolerance
        } else {
            self.safety * tolerance
        }
    }

    /// The deviation the continuity steps alone may take when a G2 lead-in's width is chosen.
    pub fn lead_in(&self, tolerance: f64) -> f64 {
        self.lead_in_share * tolerance
    }

    /// The largest deviation of a corner group's refitted patches from their originals.
    pub fn group(&self, tolerance: f64) -> f64 {
        self.group_share * tolerance
    }

    /// The ball ε of the next fairing stage: the fairing budget `budget` less the deviation
    /// `deviation` the surface has now, shared equally by the `stages_left` stages (this one
    /// included); 0 when nothing is left. Each stage moves the surface at most ε, so the
    /// stages together stay within `budget`.
    pub fn stage_epsilon(budget: f64, deviation: f64, stages_left: usize) -> f64 {
        if stages_left == 0 {
            return 0.0;
        }
        ((budget - deviation) / stages_left as f64).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::{DEVIATION_SAFETY, DeviationBudget, GROUP_SHARE, LEAD_IN_SHARE, MASTER_SHARE};

    #[test]
    fn a_master_plans_with_its_share_and_the_others_with_the_safety_fraction() {
        let b = DeviationBudget::default();
        assert_eq!(b.fairing(0.2, true), MASTER_SHARE * 0.2);
        assert_eq!(b.fairing(0.2, false), DEVIATION_SAFETY * 0.2);
        assert!(b.fairing(0.2, true) < b.fairing(0.2, false));
        assert_eq!(b.lead_in(0.2), LEAD_IN_SHARE * 0.2);
        assert_eq!(b.group(0.2), GROUP_SHARE * 0.2);
        let own = DeviationBudget {
            master_share: 0.25,
            ..b
        };
        assert_eq!(own.fairing(0.2, true), 0.05);
    }

    #[test]
    fn stages_that_each_use_their_whole_ball_stay_within_the_budget() {
        // the worst case: every stage moves the surface by its whole ε, on top of a deviation
        // the continuity steps left between stages
        for (budget, start, continuity) in [(0.95, 0.0, 0.0), (0.5, 0.1, 0.05), (0.3, 0.29, 0.0)] {
            let mut d: f64 = start;
            for left in (1..=3).rev() {
                d += continuity / 3.0;
                d += DeviationBudget::stage_epsilon(budget, d, left);
            }
            assert!(
                d <= budget.max(start + continuity) + 1e-15,
                "{budget} {start}: {d}"
            );
        }
        assert_eq!(DeviationBudget::stage_epsilon(0.5, 0.6, 2), 0.0);
        assert_eq!(DeviationBudget::stage_epsilon(0.5, 0.1, 0), 0.0);
        assert_eq!(DeviationBudget::stage_epsilon(0.5, 0.1, 2), 0.2);
    }
}
