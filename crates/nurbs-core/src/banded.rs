//! Least squares for banded systems by Givens QR, row by row.
//!
//! Spline least-squares systems are banded: a sample row touches only the p + 1 basis functions
//! of its knot span (times the coordinates per control point), so every row of A has its
//! nonzeros in one window [s, s + w) of the columns. Givens rotations merge such a row into an
//! upper-triangular R whose row i has its nonzeros in [i, i + w) (no fill beyond the window):
//! O(w²) per row instead of O(n²), and R is kept in n × w storage (Golub–Van Loan §5.2.5,
//! "fast Givens for banded problems"; Lawson–Hanson ch. 27, sequential banded accumulation).
//!
//! min |A x − b| is then R x = Qᵀb by back substitution. Without column pivoting the QR is not
//! rank-revealing; [`BandedQr::solve`] refuses (an error naming the column) when a diagonal of R
//! falls below a relative threshold, so that callers can fall back to a rank-revealing dense
//! method (e.g. the SVD minimum-norm solution).

use crate::error::{Error, Result};

/// Upper-triangular banded factor R and Qᵀb of a least-squares system, accumulated row by row.
#[derive(Debug, Clone)]
pub struct BandedQr {
    n: usize,
    width: usize,
    rhs_cols: usize,
    /// row i holds R(i, i..i + width)
    r: Vec<f64>,
    /// row i holds (Qᵀb)(i, ..)
    qtb: Vec<f64>,
    filled: Vec<bool>,
    /// squared residual norm per right-hand side (rows rotated to zero)
    residual2: Vec<f64>,
    scratch: Vec<f64>,
    scratch_rhs: Vec<f64>,
}

impl BandedQr {
    /// An empty factorization of a system with `n` unknowns, at most `width` consecutive
    /// nonzeros per row, and `rhs_cols` right-hand sides.
    pub fn new(n: usize, width: usize, rhs_cols: usize) -> Self {
        let width = width.clamp(1, n.max(1));
        Self {
            n,
            width,
            rhs_cols,
            r: vec![0.0; n * width],
            qtb: vec![0.0; n * rhs_cols],
            filled: vec![false; n],
            residual2: vec![0.0; rhs_cols],
            scratch: vec![0.0; 2 * width],
            scratch_rhs: vec![0.0; rhs_cols],
        }
    }

    /// Number of unknowns.
    pub fn unknowns(&self) -> usize {
        self.n
    }

    /// Largest number of consecutive nonzeros per row this factorization accepts.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Adds the equation Σ_t `values[t] x[start + t]` = rhs (one value per right-hand side).
    ///
    /// # Errors
    /// [`Error::BandOverflow`] when the row does not fit the window (`values.len()` > width or
    /// past the last unknown), [`Error::LengthMismatch`] when `rhs` has the wrong length.
    pub fn add_row(&mut self, start: usize, values: &[f64], rhs: &[f64]) -> Result<()> {
        if values.len() > self.width || start + values.len() > self.n {
            return Err(Error::BandOverflow {
                start,
                len: values.len(),
                width: self.width,
                unknowns: self.n,
            });
        }
        if rhs.len() != self.rhs_cols {
            return Err(Error::LengthMismatch {
                what: "banded row right-hand sides vs the system's",
                left: rhs.len(),
                right: self.rhs_cols,
            });
        }
        let w = self.width;
        let mut x = std::mem::take(&mut self.scratch);
        let mut y = std::mem::take(&mut self.scratch_rhs);
        // the row's live window is x[off..off + w]; everything past it is zero, so moving the
        // window right is a change of `off`, and the buffer (2w long) is rebased only when the
        // window would run past its end
        x.fill(0.0);
        x[..values.len()].copy_from_slice(values);
        y.copy_from_slice(rhs);
        let mut col = start;
        let mut off = 0;
        loop {
            // skip leading zeros (the window moves right)
            let lead = x[off..off + w].iter().position(|&v| v != 0.0);
            let Some(lead) = lead else {
                for (acc, v) in self.residual2.iter_mut().zip(&y) {
                    *acc += v * v;
                }
                break;
            };
            if lead > 0 {
                off += lead;
                col += lead;
                if off > w {
                    // the part past the buffer's end is zero by the invariant
                    let kept = 2 * w - off;
                    x.copy_within(off.., 0);
                    x[kept..].fill(0.0);
                    off = 0;
                }
            }
            if col >= self.n {
                break;
            }
            let live = &mut x[off..off + w];
            let row = &mut self.r[col * w..(col + 1) * w];
            let row_rhs = &mut self.qtb[col * self.rhs_cols..(col + 1) * self.rhs_cols];
            if !self.filled[col] {
                row.copy_from_slice(live);
                row_rhs.copy_from_slice(&y);
                self.filled[col] = true;
                break;
            }
            rotate(row, row_rhs, live, &mut y);
        }
        self.scratch = x;
        self.scratch_rhs = y;
        Ok(())
    }

    /// The stored rows of R (index, R(i, i..i + width), (Qᵀb)(i, ..)), for stacking this factor
    /// into another system: min |A x − b|² = |R x − Qᵀb|² + const.
    pub fn rows(&self) -> impl Iterator<Item = (usize, &[f64], &[f64])> {
        let w = self.width;
        let k = self.rhs_cols;
        (0..self.n).filter(|&i| self.filled[i]).map(move |i| {
            (
                i,
                &self.r[i * w..(i + 1) * w],
                &self.qtb[i * k..(i + 1) * k],
            )
        })
    }

    /// Squared residual norm |A x − b|² of the least-squares solution, per right-hand side.
    pub fn residual_squared(&self) -> &[f64] {
        &self.residual2
    }

    /// The least-squares solution (row-major: x[i * rhs_cols + c]).
    ///
    /// # Errors
    /// [`Error::SingularSystem`] naming the first column whose diagonal |R_ii| is at most
    /// `relative_tol` × the largest diagonal (or whose row never received an equation).
    pub fn solve(&self, relative_tol: f64) -> Result<Vec<f64>> {
        let (n, w, k) = (self.n, self.width, self.rhs_cols);
        let largest = (0..n).map(|i| self.r[i * w].abs()).fold(0.0f64, f64::max);
        if let Some(i) =
            (0..n).find(|&i| !self.filled[i] || !(self.r[i * w].abs() > relative_tol * largest))
        {
            return Err(Error::SingularSystem {
                reason: format!(
                    "banded least squares: column {i} of {n} is not determined (|R_ii| = {:.3e}, largest {largest:.3e})",
                    self.r[i * w].abs()
                ),
            });
        }
        let mut x = vec![0.0; n * k];
        for i in (0..n).rev() {
            let row = &self.r[i * w..(i + 1) * w];
            for c in 0..k {
                let mut acc = self.qtb[i * k + c];
                for t in 1..w.min(n - i) {
                    acc -= row[t] * x[(i + t) * k + c];
                }
                x[i * k + c] = acc / row[0];
            }
        }
        Ok(x)
    }
}

/// The Givens rotation that zeroes the first entry of the new row (`x`, right-hand sides `y`)
/// against the stored row `row` (right-hand sides `row_rhs`) of the same leading column.
fn rotate(row: &mut [f64], row_rhs: &mut [f64], x: &mut [f64], y: &mut [f64]) {
    let (a, b) = (row[0], x[0]);
    // √(a² + b²) without libm's hypot (5× slower); hypot only when a² + b² overflows
    let h = match (a * a + b * b).sqrt() {
        h if h.is_finite() && h > 0.0 => h,
        _ => a.hypot(b),
    };
    let (c, s) = (a / h, b / h);
    for (rt, xt) in row.iter_mut().zip(x.iter_mut()) {
        let (p, q) = (*rt, *xt);
        *rt = c * p + s * q;
        *xt = c * q - s * p;
    }
    for (rt, yt) in row_rhs.iter_mut().zip(y.iter_mut()) {
        let (p, q) = (*rt, *yt);
        *rt = c * p + s * q;
        *yt = c * q - s * p;
    }
    x[0] = 0.0;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::rng;
    use nalgebra::DMatrix;
    use rand::Rng;

    /// A random banded system (width w) against nalgebra's dense QR least squares.
    #[test]
    fn matches_dense_least_squares() {
        let mut r = rng(11);
        // the last case: rows with runs of zeros inside the band, so that one row's window
        // moves right by more than its width (the scratch buffer is rebased)
        for (n, w, m, k, sparse) in [
            (30, 4, 80, 1, false),
            (45, 12, 200, 3, false),
            (12, 12, 40, 2, false),
            (7, 1, 20, 1, false),
            (60, 9, 400, 2, true),
        ] {
            let mut a = DMatrix::<f64>::zeros(m, n);
            let mut b = DMatrix::<f64>::zeros(m, k);
            let mut qr = BandedQr::new(n, w, k);
            for row in 0..m {
                // rows cover every column (row % (n − w + 1) walks the windows), some shorter
                let start = (row * 7 + row / 3) % (n - w + 1);
                let len = if row % 5 == 0 { w.div_ceil(2) } else { w };
                let mut vals: Vec<f64> = (0..len).map(|_| r.random_range(-1.0..1.0)).collect();
                if sparse {
                    for (t, v) in vals.iter_mut().enumerate() {
                        if t > 0 && t + 1 < len && r.random_range(0.0..1.0) < 0.6 {
                            *v = 0.0;
                        }
                    }
                }
                let rhs: Vec<f64> = (0..k).map(|_| r.random_range(-1.0..1.0)).collect();
                for (t, v) in vals.iter().enumerate() {
                    a[(row, start + t)] = *v;
                }
                for (c, v) in rhs.iter().enumerate() {
                    b[(row, c)] = *v;
                }
                qr.add_row(start, &vals, &rhs).unwrap();
            }
            let x = qr.solve(1e-12).unwrap();
            let dense = a.clone().qr();
            let mut qtb = b.clone();
            dense.q_tr_mul(&mut qtb);
            let xd = dense
                .r()
                .solve_upper_triangular(&qtb.rows(0, n).into_owned())
                .unwrap();
            for i in 0..n {
                for c in 0..k {
                    let (got, want) = (x[i * k + c], xd[(i, c)]);
                    assert!(
                        (got - want).abs() <= 1e-10 * (1.0 + want.abs()),
                        "n {n} w {w}: x[{i},{c}] {got} vs {want}"
                    );
                }
            }
            // the accumulated residual is that of the solution
            let xm = DMatrix::from_row_slice(n, k, &x);
            let res = &a * &xm - &b;
            for c in 0..k {
                let want = res.column(c).norm_squared();
                let got = qr.residual_squared()[c];
                assert!((got - want).abs() <= 1e-9 * (1.0 + want), "{got} vs {want}");
            }
        }
    }

    /// Stacking the rows of a factor into a new one gives the same solution as the whole system.
    #[test]
    fn stacked_factor_rows_give_the_same_solution() {
        let mut r = rng(5);
        let (n, w) = (20, 6);
        let mut whole = BandedQr::new(n, w, 1);
        let mut part = BandedQr::new(n, w, 1);
        let mut rest = Vec::new();
        for row in 0..90 {
            let start = row % (n - w + 1);
            let vals: Vec<f64> = (0..w).map(|_| r.random_range(-1.0..1.0)).collect();
            let rhs = [r.random_range(-1.0..1.0)];
            whole.add_row(start, &vals, &rhs).unwrap();
            if row % 2 == 0 {
                part.add_row(start, &vals, &rhs).unwrap();
            } else {
                rest.push((start, vals, rhs));
            }
        }
        let mut stacked = BandedQr::new(n, w, 1);
        for (i, row, rhs) in part.rows() {
            stacked.add_row(i, &row[..w.min(n - i)], rhs).unwrap();
        }
        for (start, vals, rhs) in &rest {
            stacked.add_row(*start, vals, rhs).unwrap();
        }
        let (a, b) = (whole.solve(1e-12).unwrap(), stacked.solve(1e-12).unwrap());
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() < 1e-11, "{x} vs {y}");
        }
    }

    #[test]
    fn undetermined_column_and_bad_rows_are_errors() {
        let mut qr = BandedQr::new(3, 2, 1);
        qr.add_row(0, &[1.0, 1.0], &[1.0]).unwrap();
        qr.add_row(0, &[1.0, 1.0], &[1.0]).unwrap();
        assert!(matches!(qr.solve(1e-12), Err(Error::SingularSystem { .. })));
        assert!(matches!(
            qr.add_row(2, &[1.0, 1.0], &[0.0]),
            Err(Error::BandOverflow { start: 2, .. })
        ));
        assert!(matches!(
            qr.add_row(0, &[1.0, 1.0, 1.0], &[0.0]),
            Err(Error::BandOverflow { len: 3, .. })
        ));
        assert!(matches!(
            qr.add_row(0, &[1.0], &[0.0, 1.0]),
            Err(Error::LengthMismatch { .. })
        ));
    }
}
