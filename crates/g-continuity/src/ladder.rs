//! The minimal-deviation G2 solve (\[SV\] §4.2): the paper's well-conditioned system first, then
//! the lightest tangential weight of a ladder whose moves stay within a factor of the first.

use nalgebra::DMatrix;
use nurbs_core::BandedQr;

use crate::lsq::{
    SINGULAR_RELATIVE, SolveError, banded_factor, banded_solve_with, solve_least_squares,
    solve_min_norm,
};

/// Factors applied to [`SetParams::g2_tangential_weight`](crate::SetParams::g2_tangential_weight) after the first G2 solve, from the
/// heaviest to the lightest: each lets the tangential components help the scalar condition more,
/// with less conditioning. The lightest, 1e-8, stands for the scalar condition alone: its
/// remaining scalar residual is of order weight² (1e-16) times the tangential change, and among
/// the solutions of the scalar rows it picks the one with the least tangential change (where
/// the scalar rows leave directions free, as the minimum-norm solution would, but without an SVD).
pub const G2_WEIGHT_LADDER: [f64; 6] = [1e-1, 1e-2, 1e-3, 1e-4, 1e-6, 1e-8];

/// Largest 3D displacement of a stacked solution (x, y, z per point).
fn largest_point_move(x: &DMatrix<f64>) -> f64 {
    (0..x.nrows() / 3)
        .map(|c| {
            (x[(3 * c, 0)].powi(2) + x[(3 * c + 1, 0)].powi(2) + x[(3 * c + 2, 0)].powi(2)).sqrt()
        })
        .fold(0.0, f64::max)
}

/// R factor and Qᵀb of a block (rows beyond the rank dropped): min |A x − b| and
/// min |R x − Qᵀb| differ by a constant.
fn reduce(a: DMatrix<f64>, b: DMatrix<f64>) -> (DMatrix<f64>, DMatrix<f64>) {
    let n = a.nrows().min(a.ncols());
    let qr = a.qr();
    let mut qtb = b;
    qr.q_tr_mul(&mut qtb);
    (qr.r(), qtb.rows(0, n).into_owned())
}

/// The minimal-deviation G2 solve. `a` holds the `rows` scalar G2 rows, then two tangential rows
/// per sample (weight [`SetParams::g2_tangential_weight`](crate::SetParams::g2_tangential_weight)); `b` is zero on the tangential rows.
///
/// The scalar rows alone (the crate's original system) constrain only n_k · d_j: the tangential
/// components of the d_j enter through the variation of the normal n_k along the side, with
/// singular values 1e-2 … 1e-6 of the largest. Whatever part of the right-hand side the spline
/// space cannot follow (a master of other knots, noise in its curvature) is then fitted with
/// tangential moves of 10–1000 times the needed correction: millimetres of movement for a
/// 0.03 mm curvature correction, the surface wrecked while G2 looks met. So the solve starts with
/// the paper's well-conditioned system (weight 1: change β_k n_k, minimal deviation) and then
/// takes the lightest weight of [`G2_WEIGHT_LADDER`] whose largest move stays within
/// `move_factor` times the first one's (tried from the lightest up; the weight-1 solution when
/// none does). Where an exact join exists with comparable moves (the same spline space on both
/// sides) this reaches it; where it does not, the remaining error is left to knot insertion,
/// which adds real freedom.
///
/// Both blocks are banded (a sample touches the q + 1 control points of its span): they are
/// reduced once to banded triangular factors R1, R2 by Givens QR, and each weight costs one
/// banded QR of [R1; w R2]. Systems that are not banded take the dense Householder path.
pub(crate) fn solve_g2_ladder(
    a: DMatrix<f64>,
    b: &DMatrix<f64>,
    rows: usize,
    move_factor: f64,
) -> std::result::Result<(DMatrix<f64>, f64), SolveError> {
    let n = a.ncols();
    let tangential = a.rows(rows, a.nrows() - rows);
    let scalar = a.rows(0, rows);
    let rhs = b.rows(0, rows);
    let zeros = DMatrix::zeros(tangential.nrows(), 1);
    if let (Some(f1), Some(f2)) = (
        banded_factor(&scalar, &rhs),
        banded_factor(&tangential, &zeros.as_view()),
    ) {
        let width = f1.width().max(f2.width());
        return ladder(move_factor, |w| {
            let mut qr = BandedQr::new(n, width, 1);
            let mut scaled = vec![0.0; width];
            for (i, row, rhs) in f1.rows() {
                let len = row.len().min(n - i);
                qr.add_row(i, &row[..len], rhs)?;
            }
            for (i, row, _) in f2.rows() {
                let len = row.len().min(n - i);
                for (s, r) in scaled.iter_mut().zip(&row[..len]) {
                    *s = w * r;
                }
                qr.add_row(i, &scaled[..len], &[0.0])?;
            }
            // [R1; w R2] has full rank for w > 0 (R2 does): only round-off pivots are refused
            match banded_solve_with(&qr, SINGULAR_RELATIVE) {
                Some(x) => Ok(x),
                None => solve_min_norm(crate::lsq::dense_r(&qr), &crate::lsq::dense_qtb(&qr)),
            }
        });
    }
    let (r1, c1) = reduce(scalar.into_owned(), rhs.into_owned());
    let (r2, _) = reduce(tangential.into_owned(), zeros);
    ladder(move_factor, |w| {
        let (n1, n2) = (r1.nrows(), r2.nrows());
        let mut m = DMatrix::zeros(n1 + n2, n);
        m.rows_mut(0, n1).copy_from(&r1);
        m.rows_mut(n1, n2).copy_from(&(&r2 * w));
        let mut rhs = DMatrix::zeros(n1 + n2, 1);
        rhs.rows_mut(0, n1).copy_from(&c1);
        solve_least_squares(m, &rhs)
    })
}

/// The weight search of [`solve_g2_ladder`] over a solve for a given tangential weight; with
/// the solution, the smallest move ratio of a rejected weight ([`RowMove::g2_slack`]).
fn ladder(
    move_factor: f64,
    mut solve: impl FnMut(f64) -> std::result::Result<DMatrix<f64>, SolveError>,
) -> std::result::Result<(DMatrix<f64>, f64), SolveError> {
    let first = solve(1.0)?;
    let reference = largest_point_move(&first);
    let limit = move_factor * reference;
    let mut slack = f64::INFINITY;
    for &w in G2_WEIGHT_LADDER.iter().rev() {
        let x = solve(w)?;
        let moved = largest_point_move(&x);
        if moved <= limit {
            return Ok((x, slack));
        }
        // (a zero reference rejects every move whatever the factor)
        if reference > 0.0 {
            slack = slack.min(moved / reference);
        }
    }
    Ok((first, slack))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stand-in solve: weight w gives one point moved by `moves(w)` along x.
    fn solve_with(
        moves: impl Fn(f64) -> f64,
    ) -> impl FnMut(f64) -> Result<DMatrix<f64>, SolveError> {
        move |w| Ok(DMatrix::from_column_slice(3, 1, &[moves(w), 0.0, 0.0]))
    }

    #[test]
    fn ladder_slack_is_the_least_rejected_ratio_and_a_factor_below_it_changes_nothing() {
        // lighter weights move more: 1e-8 → 9, 1e-6 → 5, 1e-4 → 3, 1e-3 → 1.5 (× the
        // weight-1 move of 1)
        let moves = |w: f64| match w {
            w if w < 1e-7 => 9.0,
            w if w < 1e-5 => 5.0,
            w if w < 1e-3 * 0.5 => 3.0,
            w if w < 1e-2 * 0.5 => 1.5,
            _ => 1.0,
        };
        let (x, slack) = ladder(2.0, solve_with(moves)).expect("solves");
        assert_eq!(x[(0, 0)], 1.5, "the lightest weight within 2×");
        assert_eq!(slack, 3.0, "the least ratio the search rejected");
        // any factor in [1.5, 3): the same pick; at 3 the search takes the lighter one
        for f in [1.5, 2.5, 2.999] {
            assert_eq!(ladder(f, solve_with(moves)).expect("solves").0, x);
        }
        assert_eq!(
            ladder(3.0, solve_with(moves)).expect("solves").0[(0, 0)],
            3.0
        );
        // nothing rejected: no bound
        let (_, none) = ladder(10.0, solve_with(moves)).expect("solves");
        assert_eq!(none, f64::INFINITY);
    }
}
