//! Least-squares solves of the overdetermined row systems of [SV] §4.
//!
//! # Deviation from the paper
//! The paper solves A x = b through the normal equations AᵀA x = Aᵀb. We use Householder QR when
//! A has full column rank (condition squared by the normal equations is avoided), and the SVD
//! with a relative cut-off otherwise, which returns the minimum-norm least-squares solution: the
//! smallest control point movement among all best fits. The row systems are banded (a sample
//! touches the q + 1 control points of its span), so the full-rank case first tries nurbs-core's
//! banded Givens QR ([`BandedQr`]), O(rows × width²) instead of O(rows × columns²).
//!
//! # Tolerance
//! [`SINGULAR_RELATIVE`]: singular values (or |R_ii| of the QR) below this fraction of the largest
//! are treated as zero.

use nalgebra::{DMatrix, DMatrixView};
use nurbs_core::BandedQr;

/// Relative cut-off of singular values (and QR pivots): ~1e4 rounding units, well above the
/// noise of the sampled coefficients, well below any real direction of the system.
pub const SINGULAR_RELATIVE: f64 = 1e-12;

/// Minimum-norm least-squares solution of A X = B by the SVD. A tall A is first reduced by QR
/// (A = QR, so min |AX − B| and min |RX − QᵀB| have the same solutions, and the same minimum-norm
/// one): the SVD then works on the small square R.
pub fn solve_min_norm(a: DMatrix<f64>, b: &DMatrix<f64>) -> Result<DMatrix<f64>, String> {
    let (m, n) = a.shape();
    if m > n && n > 0 {
        let qr = a.qr();
        let mut qtb = b.clone();
        qr.q_tr_mul(&mut qtb);
        return svd_solve(qr.r(), &qtb.rows(0, n).into_owned());
    }
    svd_solve(a, b)
}

fn svd_solve(a: DMatrix<f64>, b: &DMatrix<f64>) -> Result<DMatrix<f64>, String> {
    let svd = a.svd(true, true);
    let largest = svd.singular_values.iter().copied().fold(0.0, f64::max);
    if !(largest > 0.0) {
        return Err(format!(
            "the system matrix is zero or not finite (no sample constrains the free control points; largest singular value {largest})"
        ));
    }
    svd.solve(b, largest * SINGULAR_RELATIVE)
        .map_err(|e| e.to_string())
}

/// The row systems are banded (a sample touches the q + 1 control points of its span): below
/// this fraction of nonzero columns per row the banded Givens QR ([`BandedQr`]) is used.
const BANDED_FRACTION: f64 = 0.5;

/// Factors A X = B by the banded Givens QR when every row's nonzeros fit a window of at most
/// `BANDED_FRACTION` of the columns; `None` when A is not banded enough.
pub fn banded_factor(a: &DMatrixView<f64>, b: &DMatrixView<f64>) -> Option<BandedQr> {
    let (m, n) = a.shape();
    // row r of A is column r of Aᵀ: contiguous, so the scans and the gathers run in order
    let at = a.transpose();
    let bands: Vec<Option<(usize, usize)>> = (0..m)
        .map(|r| {
            let row = at.column(r);
            let row = row.as_slice();
            let first = row.iter().position(|&v| v != 0.0)?;
            let last = row.iter().rposition(|&v| v != 0.0)?;
            Some((first, last + 1 - first))
        })
        .collect();
    let width = bands.iter().flatten().map(|&(_, w)| w).max().unwrap_or(1);
    if n == 0 || width as f64 > BANDED_FRACTION * n as f64 {
        return None;
    }
    let mut qr = BandedQr::new(n, width, b.ncols());
    let mut rhs = vec![0.0; b.ncols()];
    for (r, band) in bands.iter().enumerate() {
        for (c, v) in rhs.iter_mut().enumerate() {
            *v = b[(r, c)];
        }
        let (first, len) = band.unwrap_or((0, 0));
        let row = at.column(r);
        qr.add_row(first, &row.as_slice()[first..first + len], &rhs)
            .ok()?;
    }
    Some(qr)
}

/// Solves a banded factor whose R is well-conditioned enough for back substitution (the same
/// pivot criterion as the dense QR path), `None` otherwise.
pub fn banded_solve(qr: &BandedQr) -> Option<DMatrix<f64>> {
    banded_solve_with(qr, SINGULAR_RELATIVE.sqrt())
}

/// [`banded_solve`] with a given relative pivot threshold (for systems known to have full
/// rank, e.g. with a positive-weight regularizing block, [`SINGULAR_RELATIVE`] itself).
pub fn banded_solve_with(qr: &BandedQr, relative_pivot: f64) -> Option<DMatrix<f64>> {
    let x = qr.solve(relative_pivot).ok()?;
    let k = x.len() / qr.unknowns().max(1);
    Some(DMatrix::from_row_slice(qr.unknowns(), k, &x))
}

/// Least-squares solution of A X = B: QR when A has full column rank (banded Givens QR when A
/// is banded, else dense Householder), else the SVD minimum-norm solution.
pub fn solve_least_squares(a: DMatrix<f64>, b: &DMatrix<f64>) -> Result<DMatrix<f64>, String> {
    if let Some(x) = banded_factor(&a.as_view(), &b.as_view())
        .as_ref()
        .and_then(banded_solve)
    {
        return Ok(x);
    }
    if a.nrows() >= a.ncols() && a.ncols() > 0 {
        let n = a.ncols();
        let qr = a.clone().qr();
        let r = qr.r();
        let diag: Vec<f64> = (0..n).map(|i| r[(i, i)].abs()).collect();
        let largest = diag.iter().copied().fold(0.0, f64::max);
        let smallest = diag.iter().copied().fold(f64::INFINITY, f64::min);
        let mut qtb = b.clone();
        qr.q_tr_mul(&mut qtb);
        let qtb = qtb.rows(0, n).into_owned();
        if largest > 0.0
            && smallest > largest * SINGULAR_RELATIVE.sqrt()
            && let Some(x) = r.solve_upper_triangular(&qtb)
        {
            return Ok(x);
        }
        // rank-deficient: the minimum-norm solution from the same factor (what
        // `solve_min_norm` computes for a tall A, without factoring A a second time)
        if a.nrows() > n {
            return svd_solve(r, &qtb);
        }
    }
    solve_min_norm(a, b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn qr_solves_consistent_system_exactly() {
        let a = DMatrix::from_row_slice(4, 2, &[1.0, 0.0, 1.0, 1.0, 1.0, 2.0, 1.0, 3.0]);
        let x_true = DMatrix::from_row_slice(2, 1, &[0.5, -2.0]);
        let b = &a * &x_true;
        let x = solve_least_squares(a, &b).unwrap();
        assert!((x - x_true).norm() < 1e-14);
    }

    #[test]
    fn tall_rank_deficient_gives_minimum_norm() {
        // x0 + x1 = 2 four times (tall, rank 1): the QR-reduced path gives (1, 1) as well
        let a = DMatrix::from_row_slice(4, 2, &[1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0]);
        let b = DMatrix::from_row_slice(4, 1, &[2.0, 2.0, 2.0, 2.0]);
        let x = solve_min_norm(a, &b).unwrap();
        assert!(
            (x[0] - 1.0).abs() < 1e-12 && (x[1] - 1.0).abs() < 1e-12,
            "{x}"
        );
    }

    #[test]
    fn rank_deficient_gives_minimum_norm() {
        // x0 + x1 = 2 (twice): the minimum-norm solution is (1, 1)
        let a = DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0]);
        let b = DMatrix::from_row_slice(2, 1, &[2.0, 2.0]);
        let x = solve_least_squares(a, &b).unwrap();
        assert!(
            (x[0] - 1.0).abs() < 1e-12 && (x[1] - 1.0).abs() < 1e-12,
            "{x}"
        );
    }
}
