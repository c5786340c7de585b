//! Least-squares solves of the overdetermined row systems of [SV] §4.
//!
//! # Deviation from the paper
//! The paper solves A x = b through the normal equations AᵀA x = Aᵀb. We use Householder QR when
//! A has full column rank (condition squared by the normal equations is avoided), and the SVD
//! with a relative cut-off otherwise, which returns the minimum-norm least-squares solution: the
//! smallest control point movement among all best fits.
//!
//! # Tolerance
//! [`SINGULAR_RELATIVE`]: singular values (or |R_ii| of the QR) below this fraction of the largest
//! are treated as zero.

use nalgebra::DMatrix;

/// Relative cut-off of singular values (and QR pivots): ~1e4 rounding units, well above the
/// noise of the sampled coefficients, well below any real direction of the system.
pub const SINGULAR_RELATIVE: f64 = 1e-12;

/// Minimum-norm least-squares solution of A X = B by a complete orthogonal decomposition:
/// column-pivoted QR A P = Q [R11 R12; 0 ≈0] reveals the rank r (|R_ii| above the cut-off), then
/// the minimum-norm solution of [R11 R12] z = (QᵀB)_{1..r} comes from the QR of its transpose,
/// [R11 R12]ᵀ = Q₂ R₂: z = Q₂ R₂⁻ᵀ (QᵀB)_{1..r}, and X = P z. Same solution as the SVD with the
/// same cut-off, at the cost of two QR factorizations.
pub fn solve_min_norm(a: DMatrix<f64>, b: &DMatrix<f64>) -> Result<DMatrix<f64>, String> {
    let (m, n) = a.shape();
    if m == 0 || n == 0 {
        return Err(format!("empty system ({m} × {n})"));
    }
    let qr = a.col_piv_qr();
    let r = qr.r();
    let k = m.min(n);
    let largest = r[(0, 0)].abs();
    if !(largest > 0.0 && largest.is_finite()) {
        return Err(format!(
            "the system matrix is zero or not finite (no sample constrains the free control points; largest pivot {largest})"
        ));
    }
    let rank = (0..k)
        .take_while(|&i| r[(i, i)].abs() > largest * SINGULAR_RELATIVE)
        .count();
    let mut qtb = b.clone();
    qr.q_tr_mul(&mut qtb);
    let c = qtb.rows(0, rank).into_owned();
    let t = r.rows(0, rank).transpose();
    let qr2 = t.qr();
    let r2 = qr2.r();
    let y = r2
        .transpose()
        .solve_lower_triangular(&c)
        .ok_or_else(|| "triangular factor is singular".to_string())?;
    let mut z = qr2.q() * y;
    qr.p().inv_permute_rows(&mut z);
    Ok(z)
}

/// Least-squares solution of A X = B: QR when A has full column rank, else the SVD minimum-norm
/// solution.
pub fn solve_least_squares(a: DMatrix<f64>, b: &DMatrix<f64>) -> Result<DMatrix<f64>, String> {
    if a.nrows() >= a.ncols() && a.ncols() > 0 {
        let n = a.ncols();
        let qr = a.clone().qr();
        let r = qr.r();
        let diag: Vec<f64> = (0..n).map(|i| r[(i, i)].abs()).collect();
        let largest = diag.iter().copied().fold(0.0, f64::max);
        let smallest = diag.iter().copied().fold(f64::INFINITY, f64::min);
        if largest > 0.0 && smallest > largest * SINGULAR_RELATIVE.sqrt() {
            let mut qtb = b.clone();
            qr.q_tr_mul(&mut qtb);
            if let Some(x) = r.solve_upper_triangular(&qtb.rows(0, n).into_owned()) {
                return Ok(x);
            }
        }
    }
    solve_min_norm(a, b)
}

/// Minimum-norm solution by the SVD (reference for the tests).
#[cfg(test)]
fn svd_solve(a: DMatrix<f64>, b: &DMatrix<f64>) -> Result<DMatrix<f64>, String> {
    let svd = a.svd(true, true);
    let largest = svd.singular_values.iter().copied().fold(0.0, f64::max);
    svd.solve(b, largest * SINGULAR_RELATIVE)
        .map_err(|e| e.to_string())
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
    fn complete_orthogonal_decomposition_matches_the_svd() {
        // a 40 × 12 system of rank 7 with a consistent and an inconsistent right-hand side
        let left = DMatrix::from_fn(40, 7, |i, j| {
            ((i * 7 + j * 3) % 11) as f64 - 5.0 + (i as f64 * 0.37 + j as f64).sin()
        });
        let right = DMatrix::from_fn(7, 12, |i, j| {
            ((i * 5 + j * 2) % 7) as f64 - 3.0 + (j as f64 * 0.61 - i as f64).cos()
        });
        let a = &left * &right;
        let b = DMatrix::from_fn(40, 2, |i, j| (i as f64 * 0.3 + j as f64).sin());
        let x = solve_min_norm(a.clone(), &b).unwrap();
        let reference = svd_solve(a, &b).unwrap();
        assert!(
            (&x - &reference).norm() < 1e-9 * reference.norm(),
            "{x} vs {reference}"
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
