//! Sliver end spans of the input: a kernel's fillet may come with a first or last knot span a
//! ten-thousandth of its length (OCCT's lateral fillets on lofted blocks: 1e-4 mm and 8e-3 mm
//! long, a degree-7 piece joined C¹ to the rest). Its second derivatives are those of a piece
//! that short: the fairing folds it over (the normal turned by 180°), and its slaves' G2 rows,
//! whose feet fall on it, see curvatures that are not the surface's. Such a span is merged into
//! its neighbour before the stages — the neighbour's polynomial continued over it
//! ([`BSplineSurface::merge_end_span`]) — where that moves the surface by at most
//! [`SLIVER_MOVE_SHARE`] of the G0 tolerance; a span with a shape of its own moves more and stays.

use nurbs_core::{BSplineSurface, Direction};

use super::{Problem, ProblemKind};
use crate::model::Model;

/// The largest move a merge may make, as a share of the G0 tolerance: a tenth, so that a link
/// along the merged span keeps nine tenths of its gap tolerance for the continuity steps.
pub const SLIVER_MOVE_SHARE: f64 = 0.1;

/// Samples of the length and move tests across the span (per iso-line): eleven, ten chords of
/// a span that holds one polynomial piece, whose length they give within a few per cent.
const ACROSS: usize = 11;
/// Iso-lines of the length and move tests along the span: thirty-three, a third of the
/// measure's 101 samples per side.
const ALONG: usize = 33;

/// Merges the sliver end spans of every surface of `model` whose merge moves it by at most
/// [`SLIVER_MOVE_SHARE`] × `g0`; one problem per merge says what changed. An end span is taken
/// for a sliver when it is shorter across (the longest of its iso-lines over the span, measured
/// at [`ALONG`] places) than the surface's own deviation tolerance, `tolerance_of(k)`: whatever
/// shape it holds lies within that tolerance of its neighbour continued over it, so the design
/// cannot be in it (a kernel's slivers are 1e-4–9e-3 mm long; the shortest end span of a fitted
/// car panel is 0.12 mm, and stays at 0.05 mm), and the move test decides the rest.
pub(super) fn merge_slivers(
    model: &mut Model,
    g0: f64,
    tolerance_of: impl Fn(&Model, usize) -> f64,
) -> Vec<Problem> {
    let mut problems = Vec::new();
    for k in 0..model.surfaces.len() {
        let longest = tolerance_of(model, k);
        let e = &mut model.surfaces[k];
        for dir in [Direction::U, Direction::V] {
            for last in [false, true] {
                let Some((span, merged, moved)) = merged_end(&e.surface, dir, last, longest) else {
                    continue;
                };
                if moved > SLIVER_MOVE_SHARE * g0 {
                    continue;
                }
                problems.push(Problem {
                    kind: ProblemKind::Limited,
                    surface: e.name.clone(),
                    link: None,
                    message: format!(
                        "its {} {} knot span ({span:.1e} long, a sliver of the input) was merged into the next one, moving the surface by {moved:.1e}: the stages work on the neighbouring span continued over it",
                        if last { "last" } else { "first" },
                        if dir == Direction::U { "u" } else { "v" },
                    ),
                    amount: Some(moved),
                });
                e.surface = merged;
            }
        }
    }
    problems
}

/// The end span of `s` in direction `dir` (the last one where `last`) when it is a sliver, at
/// most `longest` across: its length, `s` with it merged, and how far the merge moved the
/// surface (the largest distance between the two at the same parameters over the span;
/// elsewhere they are the same surface).
fn merged_end(
    s: &BSplineSurface,
    dir: Direction,
    last: bool,
    longest: f64,
) -> Option<(f64, BSplineSurface, f64)> {
    let kv = match dir {
        Direction::U => s.knots_u(),
        Direction::V => s.knots_v(),
    };
    let (a, b) = kv.domain();
    let inner = kv.interior_knots();
    let (lo, hi) = match (inner.first(), inner.last()) {
        (Some(&(t, _)), _) if !last => (a, t),
        (_, Some(&(t, _))) if last => (t, b),
        _ => return None,
    };
    let (c, d) = match dir {
        Direction::U => s.domain_v(),
        Direction::V => s.domain_u(),
    };
    // the span's points on ACROSS × ALONG parameters (nurbs-core's grid evaluation), the same
    // grid on both surfaces: index (i across, j along)
    let across: Vec<f64> = (0..ACROSS)
        .map(|i| lo + (hi - lo) * i as f64 / (ACROSS - 1) as f64)
        .collect();
    let along: Vec<f64> = (0..ALONG)
        .map(|j| c + (d - c) * j as f64 / (ALONG - 1) as f64)
        .collect();
    let grid = |surface: &BSplineSurface| match dir {
        Direction::U => surface.eval_grid_points(&across, &along),
        Direction::V => surface.eval_grid_points(&along, &across),
    };
    let index = |i: usize, j: usize| match dir {
        Direction::U => i * ALONG + j,
        Direction::V => j * ACROSS + i,
    };
    let before = grid(s);
    let length = (0..ALONG)
        .map(|j| {
            (1..ACROSS)
                .map(|i| (before[index(i, j)] - before[index(i - 1, j)]).norm())
                .sum::<f64>()
        })
        .fold(0.0f64, f64::max);
    if !(length <= longest) {
        return None;
    }
    let merged = s.merge_end_span(dir, last).ok()?;
    let moved = grid(&merged)
        .iter()
        .zip(&before)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0f64, f64::max);
    // a merge that breaks the surface (a weight through zero) is no merge
    moved.is_finite().then_some((length, merged, moved))
}

#[cfg(test)]
mod tests {
    use nurbs_core::Direction;
    use nurbs_core::testing::random_surface;

    use super::{merge_slivers, merged_end};
    use crate::model::Model;

    #[test]
    fn a_sliver_merges_and_a_shaped_span_stays() {
        let s = random_surface(7, 3..=3, 8, true);
        let (a, _) = s.domain_v();
        let next = s
            .knots_v()
            .knots()
            .iter()
            .copied()
            .find(|&t| t > a)
            .unwrap();
        // a sliver cut off the first span: the same surface, merged back without a move
        let cut = s
            .insert_knot(Direction::V, a + 1e-4 * (next - a), 2)
            .unwrap();
        let (length, merged, moved) = merged_end(&cut, Direction::V, false, 1.0).unwrap();
        assert!(length < 1e-2, "{length}");
        assert!(moved < 1e-9, "{moved}");
        assert_eq!(merged.knots_v(), s.knots_v());
        let mut m = Model::from_primaries(vec![cut.clone()]);
        let problems = merge_slivers(&mut m, 1e-3, |_, _| 1.0);
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert_eq!(m.surfaces[0].surface.knots_v(), s.knots_v());
        // the input's own first span is no sliver, and one moved a shape out of it stays
        assert!(merged_end(&s, Direction::V, false, 1.0).is_none());
        assert!(merged_end(&cut, Direction::V, false, length / 2.0).is_none());
        let mut bent = cut.clone();
        let idx = bent.index(0, 0);
        bent.control_points_mut()[idx] += nurbs_core::Vector3::new(0.0, 0.0, 1.0);
        let (_, _, moved) = merged_end(&bent, Direction::V, false, 10.0).unwrap();
        assert!(moved > 1e-3, "{moved}");
        let mut m2 = m.clone();
        m2.surfaces[0].surface = bent.clone();
        assert!(merge_slivers(&mut m2, 1e-3, |_, _| 10.0).is_empty());
        assert_eq!(m2.surfaces[0].surface, bent);
    }
}
