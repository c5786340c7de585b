//! A fill-reducing elimination order for the global system: geometric nested dissection on the
//! control grid.
//!
//! K couples control points (i, j) and (k, l) only when |i − k| ≤ w_u and |j − l| ≤ w_v. A band of
//! w_u consecutive rows therefore separates the rows above it from the rows below: the two halves
//! are ordered first (recursively) and the separator last, so the Cholesky factor fills only
//! inside the separators' blocks (George's nested dissection, 1973).

/// Boxes with at most this many grid points are ordered row by row (splitting them further saves
/// no fill).
const LEAF_POINTS: usize = 64;

/// The free flat indices (i·n_v + j) in elimination order.
pub(crate) fn nested_dissection(
    nu: usize,
    nv: usize,
    free: &[bool],
    (wu, wv): (usize, usize),
) -> Vec<usize> {
    let mut out = Vec::with_capacity(free.len());
    dissect(nv, free, (wu, wv), (0, nu), (0, nv), &mut out);
    out
}

fn push_box(
    nv: usize,
    free: &[bool],
    (i0, i1): (usize, usize),
    (j0, j1): (usize, usize),
    out: &mut Vec<usize>,
) {
    for i in i0..i1 {
        out.extend((j0..j1).map(|j| i * nv + j).filter(|&r| free[r]));
    }
}

fn dissect(
    nv: usize,
    free: &[bool],
    (wu, wv): (usize, usize),
    (i0, i1): (usize, usize),
    (j0, j1): (usize, usize),
    out: &mut Vec<usize>,
) {
    let (h, w) = (i1 - i0, j1 - j0);
    let can_u = wu > 0 && h > 2 * wu + 2;
    let can_v = wv > 0 && w > 2 * wv + 2;
    if h * w <= LEAF_POINTS || !(can_u || can_v) {
        push_box(nv, free, (i0, i1), (j0, j1), out);
        return;
    }
    // split across the direction whose separator has fewer points
    if can_u && (!can_v || wu * w <= wv * h) {
        let m = i0 + (h - wu) / 2;
        dissect(nv, free, (wu, wv), (i0, m), (j0, j1), out);
        dissect(nv, free, (wu, wv), (m + wu, i1), (j0, j1), out);
        push_box(nv, free, (m, m + wu), (j0, j1), out);
    } else {
        let m = j0 + (w - wv) / 2;
        dissect(nv, free, (wu, wv), (i0, i1), (j0, m), out);
        dissect(nv, free, (wu, wv), (i0, i1), (m + wv, j1), out);
        push_box(nv, free, (i0, i1), (m, m + wv), out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn is_a_permutation_of_the_free_points() {
        let (nu, nv) = (23, 17);
        let free: Vec<bool> = (0..nu * nv).map(|r| r % 7 != 3).collect();
        let order = nested_dissection(nu, nv, &free, (3, 2));
        let mut sorted = order.clone();
        sorted.sort_unstable();
        let expected: Vec<usize> = (0..nu * nv).filter(|&r| free[r]).collect();
        assert_eq!(sorted, expected);
    }
}
