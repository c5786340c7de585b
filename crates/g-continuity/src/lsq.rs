//! Least-squares solves of the overdetermined row systems of \[SV\] §4.
//!
//! # Deviation from the paper
//! The paper solves A x = b through the normal equations AᵀA x = Aᵀb. We use Householder QR when
//! A has full column rank (condition squared by the normal equations is avoided), and otherwise a
//! complete orthogonal decomposition (column-pivoted QR, then a QR of the rank rows) with a
//! relative cut-off, which returns the minimum-norm least-squares solution: the smallest control
//! point movement among all best fits (the SVD's solution, at a fraction of its work: 8 % less
//! CPU on the lofted block, docs/benchmarks.md). The row systems are banded (a sample touches
//! the q + 1 control points of its span), so they first go through nurbs-core's banded Givens QR
//! ([`BandedQr`]), O(rows × width²) instead of O(rows × columns²); a rank-deficient one is then
//! solved from that factor's square R, never by factoring the tall A a second time.
//!
//! # Tolerance
//! [`SINGULAR_RELATIVE`]: pivots |R_ii| of the QR below this fraction of the largest are treated
//! as zero.

use nalgebra::{DMatrix, DMatrixView};
use nurbs_core::BandedQr;

/// Relative cut-off of singular values (and QR pivots): ~1e4 rounding units, well above the
/// noise of the sampled coefficients, well below any real direction of the system.
pub const SINGULAR_RELATIVE: f64 = 1e-12;

/// Why a least-squares solve of this module failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// The system matrix is zero or not finite: nothing constrains the unknowns.
    #[error(
        "the system matrix is zero or not finite (no sample constrains the free control points; largest {measure} {largest})"
    )]
    ZeroSystem {
        /// what was measured: "pivot" (the QR's) or "singular value" (the SVD's)
        measure: &'static str,
        /// the largest pivot or singular value found
        largest: f64,
    },
    /// The triangular factor of the complete orthogonal decomposition could not be inverted.
    #[error("singular triangular factor")]
    SingularTriangular,
    /// The SVD refused the solve (the reference solve the tests compare against).
    #[error("{detail}")]
    Svd {
        /// the SVD's reason
        detail: &'static str,
    },
    /// An error of the kernel's banded QR (a row that does not fit its band).
    #[error(transparent)]
    Core(#[from] nurbs_core::Error),
}

/// Minimum-norm least-squares solution of A X = B by a complete orthogonal decomposition. A tall
/// A is first reduced by QR (A = QR, so min |AX − B| and min |RX − QᵀB| have the same
/// solutions, and the same minimum-norm one): the decomposition then works on the small square R.
pub fn solve_min_norm(a: DMatrix<f64>, b: &DMatrix<f64>) -> Result<DMatrix<f64>, SolveError> {
    let (m, n) = a.shape();
    if m > n && n > 0 {
        let qr = a.qr();
        let mut qtb = b.clone();
        qr.q_tr_mul(&mut qtb);
        return cod_solve(qr.r(), &qtb.rows(0, n).into_owned());
    }
    cod_solve(a, b)
}

/// Minimum-norm least-squares solution of a square (or wide) A X = B by a complete orthogonal
/// decomposition: column-pivoted QR, A P = Q [R₁; 0] with R₁ the r rows of the numerical rank
/// (|R_ii| above [`SINGULAR_RELATIVE`] × |R_00|), then R₁ᵀ = Z T, so that X = P Z T⁻ᵀ (QᵀB)₁…ᵣ.
/// The same solution as the SVD's where both find the same rank, for a fraction of its work.
fn cod_solve(a: DMatrix<f64>, b: &DMatrix<f64>) -> Result<DMatrix<f64>, SolveError> {
    let n = a.ncols();
    let qr = a.col_piv_qr();
    let r = qr.r();
    // no row or no column: nothing constrains the unknowns (an error, as a zero matrix)
    let largest = if r.nrows() > 0 && n > 0 {
        r[(0, 0)].abs()
    } else {
        0.0
    };
    if !(largest > 0.0) {
        return Err(SolveError::ZeroSystem {
            measure: "pivot",
            largest,
        });
    }
    let rank = (0..r.nrows().min(n))
        .take_while(|&i| r[(i, i)].abs() > largest * SINGULAR_RELATIVE)
        .count();
    let mut qtb = b.clone();
    qr.q_tr_mul(&mut qtb);
    let c = qtb.rows(0, rank).into_owned();
    // R₁ᵀ = Z T (thin QR of the n × r matrix); R₁ y = c ⇔ Tᵀ (Zᵀ y) = c
    let lq = r.rows(0, rank).transpose().qr();
    let t = lq.r();
    let w = t
        .transpose()
        .solve_lower_triangular(&c)
        .ok_or(SolveError::SingularTriangular)?;
    let mut y = lq.q() * w;
    qr.p().inv_permute_rows(&mut y);
    Ok(y)
}

/// The minimum-norm solution by the SVD (the reference [`cod_solve`] is tested against).
#[cfg(test)]
fn svd_solve(a: DMatrix<f64>, b: &DMatrix<f64>) -> Result<DMatrix<f64>, SolveError> {
    let svd = a.svd(true, true);
    let largest = svd.singular_values.iter().copied().fold(0.0, f64::max);
    if !(largest > 0.0) {
        return Err(SolveError::ZeroSystem {
            measure: "singular value",
            largest,
        });
    }
    svd.solve(b, largest * SINGULAR_RELATIVE)
        .map_err(|detail| SolveError::Svd { detail })
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

/// The upper-triangular R of a banded factor as a dense n × n matrix.
pub(crate) fn dense_r(f: &BandedQr) -> DMatrix<f64> {
    let n = f.unknowns();
    let mut r = DMatrix::zeros(n, n);
    for (i, row, _) in f.rows() {
        for (t, v) in row.iter().enumerate().take(n - i) {
            r[(i, i + t)] = *v;
        }
    }
    r
}

/// Qᵀb of a banded factor as a dense n × k matrix (k right-hand sides).
pub(crate) fn dense_qtb(f: &BandedQr) -> DMatrix<f64> {
    let n = f.unknowns();
    // one squared residual per right-hand side, rows filled or not
    let k = f.residual_squared().len();
    let mut c = DMatrix::zeros(n, k);
    for (i, _, rhs) in f.rows() {
        for (j, v) in rhs.iter().enumerate() {
            c[(i, j)] = *v;
        }
    }
    c
}

/// Least-squares solution of A X = B: QR when A has full column rank (banded Givens QR when A
/// is banded, else dense Householder), else the SVD minimum-norm solution.
pub fn solve_least_squares(a: DMatrix<f64>, b: &DMatrix<f64>) -> Result<DMatrix<f64>, SolveError> {
    if let Some(f) = banded_factor(&a.as_view(), &b.as_view()) {
        if let Some(x) = banded_solve(&f) {
            return Ok(x);
        }
        // rank-deficient: the minimum-norm solution from the banded factor's square R (the
        // same solutions as A's, without a second, dense factorization of the tall A)
        return cod_solve(dense_r(&f), &dense_qtb(&f));
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
            return cod_solve(r, &qtb);
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
    fn cod_matches_svd_on_rank_deficient_systems() {
        // a 12 × 12 system of rank 7 (A = U V with U 12 × 7, V 7 × 12), two right-hand sides
        let mut seed = 7u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64) / (1u64 << 53) as f64 - 0.5
        };
        let u = DMatrix::from_fn(12, 7, |_, _| rnd());
        let v = DMatrix::from_fn(7, 12, |_, _| rnd());
        let a = &u * &v;
        let b = DMatrix::from_fn(12, 2, |_, _| rnd());
        let by_svd = svd_solve(a.clone(), &b).unwrap();
        let by_cod = cod_solve(a, &b).unwrap();
        assert!(
            (&by_svd - &by_cod).norm() < 1e-9 * by_svd.norm(),
            "{by_svd} {by_cod}"
        );
    }

    #[test]
    fn an_empty_or_zero_system_is_an_error() {
        let b = DMatrix::zeros(0, 1);
        assert!(solve_min_norm(DMatrix::zeros(0, 2), &b).is_err());
        let b = DMatrix::zeros(2, 1);
        assert!(solve_min_norm(DMatrix::zeros(2, 2), &b).is_err());
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
