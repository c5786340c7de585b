//! Least-squares fitting of curves and surfaces to points with given parameters and knots
//! (\[NB\] §9.4), with fixed control points and optional smoothing.
//!
//! Unknowns are the free control points x_f (a [`ControlMask`] or a flag per curve point); fixed
//! ones keep the template's values x_c. With the collocation matrix A (rows = samples) and the
//! bending stiffness K (curves ∫|C''|², G²²; surfaces the thin-plate
//! K = U²²⊗V⁰⁰ + 2U¹¹⊗V¹¹ + U⁰⁰⊗V²²), the normal equations are
//! (A_fᵀA_f + λK_ff) x_f = A_fᵀ(b − A_c x_c) − λK_fc x_c,
//! one right-hand side per coordinate, solved by a sparse Cholesky factorization.
//!
//! # Deviation from the paper
//! \[NB\] solves the normal equations densely; the matrix is sparse (bandwidth ~ p·n_v), so a
//! sparse Cholesky is used. Normal equations square the condition number; the pivot check below
//! turns near-singular systems into an error instead of a silently wrong fit.
//!
//! # Tolerance
//! The system is reported singular when a Cholesky pivot squared falls below
//! [`SINGULAR_PIVOT_REL`] times the largest (a relative measure, independent of units).

use nalgebra::DMatrix;
use nalgebra_sparse::factorization::CscCholesky;
use nalgebra_sparse::{CooMatrix, CscMatrix};

use crate::Point3;
use crate::basis::BasisEvaluator;
use crate::curve::BSplineCurve;
use crate::error::{Error, Result};
use crate::frames::ControlMask;
use crate::gram::{ThinPlateGram, gram_matrix};
use crate::surface::BSplineSurface;

/// Relative size (pivot² / largest pivot²) below which the normal matrix counts as singular.
pub const SINGULAR_PIVOT_REL: f64 = 1e-14;

/// Settings of a least-squares fit.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FitParams {
    /// λ, weight of the bending energy added to the squared distances (units: the energy is in
    /// length²/parameter², so λ is in parameter²; 0 = pure least squares, the default).
    pub smoothing: f64,
}

/// How well a fit matches its data.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FitReport {
    /// largest distance between a data point and the fitted point at its parameters
    pub max_error: f64,
    /// root mean square of those distances
    pub rms_error: f64,
    /// number of unknown control points
    pub free_points: usize,
    /// number of data points
    pub samples: usize,
}

/// One fitting problem in index form: rows of (control index, basis value) per sample.
struct Problem<'a> {
    fixed_values: &'a [Point3],
    free: &'a [bool],
    rows: Vec<Vec<(usize, f64)>>,
    targets: &'a [Point3],
    stiffness: Vec<(usize, usize, f64)>,
    smoothing: f64,
    name: &'a dyn Fn(usize) -> String,
}

fn check_points(points: &[Point3], what: &'static str) -> Result<()> {
    if let Some(k) = points
        .iter()
        .position(|p| !p.coords.iter().all(|c| c.is_finite()))
    {
        return Err(Error::Format {
            detail: format!("{what} {k} is not finite"),
        });
    }
    Ok(())
}

fn check_smoothing(fit: &FitParams) -> Result<()> {
    if !(fit.smoothing.is_finite() && fit.smoothing >= 0.0) {
        return Err(Error::Format {
            detail: format!("smoothing weight {} must be finite and ≥ 0", fit.smoothing),
        });
    }
    Ok(())
}

/// Solves the masked least-squares problem; returns all control points.
fn solve(problem: &Problem<'_>) -> Result<Vec<Point3>> {
    let n = problem.free.len();
    let mut col = vec![usize::MAX; n];
    let mut nf = 0;
    for (k, &f) in problem.free.iter().enumerate() {
        if f {
            col[k] = nf;
            nf += 1;
        }
    }
    let mut out = problem.fixed_values.to_vec();
    if nf == 0 {
        return Ok(out);
    }
    let (mut coo, mut rhs, covered) = problem.data_equations(&col, nf);
    if problem.smoothing == 0.0
        && let Some(ck) = covered.iter().position(|&c| !c)
    {
        let k = col.iter().position(|&c| c == ck).unwrap_or(0);
        return Err(Error::SingularSystem {
            reason: format!(
                "control point {} has no data point in its support (a knot span without data)",
                (problem.name)(k)
            ),
        });
    }
    if problem.smoothing > 0.0 {
        problem.add_smoothing(&col, &mut coo, &mut rhs);
    }
    let chol = problem.factor(&coo, &col)?;
    let x = chol.solve(&rhs);
    for (k, &ck) in col.iter().enumerate() {
        if ck != usize::MAX {
            out[k] = Point3::new(x[(ck, 0)], x[(ck, 1)], x[(ck, 2)]);
        }
    }
    Ok(out)
}

impl Problem<'_> {
    /// The data part A_fᵀA_f, A_fᵀ(b − A_c x_c) of the normal equations over the `nf` free
    /// points (`col`: column of each point, `usize::MAX` when fixed), and whether each free
    /// point has a sample in its support.
    fn data_equations(
        &self,
        col: &[usize],
        nf: usize,
    ) -> (CooMatrix<f64>, DMatrix<f64>, Vec<bool>) {
        let mut coo = CooMatrix::new(nf, nf);
        let mut rhs = DMatrix::<f64>::zeros(nf, 3);
        let mut covered = vec![false; nf];
        for (row, target) in self.rows.iter().zip(self.targets) {
            let mut residual = target.coords;
            for &(k, b) in row {
                if col[k] == usize::MAX {
                    residual -= b * self.fixed_values[k].coords;
                }
            }
            for &(k, b) in row {
                let ck = col[k];
                if ck == usize::MAX {
                    continue;
                }
                covered[ck] |= b != 0.0;
                for c in 0..3 {
                    rhs[(ck, c)] += b * residual[c];
                }
                for &(l, b2) in row {
                    if col[l] != usize::MAX {
                        coo.push(ck, col[l], b * b2);
                    }
                }
            }
        }
        (coo, rhs, covered)
    }

    /// Adds the smoothing part λK_ff to `coo` and −λK_fc x_c to `rhs`.
    fn add_smoothing(&self, col: &[usize], coo: &mut CooMatrix<f64>, rhs: &mut DMatrix<f64>) {
        let lambda = self.smoothing;
        for &(a, b, value) in &self.stiffness {
            let (ca, cb) = (col[a], col[b]);
            if ca == usize::MAX {
                continue;
            }
            if cb == usize::MAX {
                for c in 0..3 {
                    rhs[(ca, c)] -= lambda * value * self.fixed_values[b].coords[c];
                }
            } else {
                coo.push(ca, cb, lambda * value);
            }
        }
    }

    /// The Cholesky factor of the normal matrix `coo`; singular when it is not positive
    /// definite or a pivot squared falls below [`SINGULAR_PIVOT_REL`] × the largest (the error
    /// names the point, `col` its column).
    fn factor(&self, coo: &CooMatrix<f64>, col: &[usize]) -> Result<CscCholesky<f64>> {
        let csc = CscMatrix::from(coo);
        let chol = CscCholesky::factor(&csc).map_err(|e| Error::SingularSystem {
            reason: format!("normal matrix is not positive definite ({e:?})"),
        })?;
        let l = chol.l();
        let diag: Vec<f64> = (0..l.ncols())
            .map(|j| l.col(j).values().first().copied().unwrap_or(0.0))
            .collect();
        let dmax = diag.iter().fold(0.0f64, |m, d| m.max(d * d));
        if let Some(j) = diag
            .iter()
            .position(|d| !(d * d > SINGULAR_PIVOT_REL * dmax))
        {
            let k = col.iter().position(|&c| c == j).unwrap_or(0);
            return Err(Error::SingularSystem {
                reason: format!(
                    "control point {} is not determined by the data (pivot ratio below {SINGULAR_PIVOT_REL:e})",
                    (self.name)(k)
                ),
            });
        }
        Ok(chol)
    }
}

fn report(errors: impl Iterator<Item = f64>, free_points: usize) -> FitReport {
    let (mut max, mut sum, mut count) = (0.0f64, 0.0, 0usize);
    for e in errors {
        max = max.max(e);
        sum += e * e;
        count += 1;
    }
    FitReport {
        max_error: max,
        rms_error: if count > 0 {
            (sum / count as f64).sqrt()
        } else {
            0.0
        },
        free_points,
        samples: count,
    }
}

/// Fits a polynomial surface with the knots and degrees of `template` to `points` sampled at
/// `params`; control points that `mask` fixes keep the template's values.
pub fn fit_surface(
    template: &BSplineSurface,
    mask: &ControlMask,
    params: &[(f64, f64)],
    points: &[Point3],
    fit: &FitParams,
) -> Result<(BSplineSurface, FitReport)> {
    if template.is_rational() {
        return Err(Error::RationalNotSupported {
            operation: "least-squares surface fitting",
        });
    }
    mask.check_shape(template)?;
    if params.len() != points.len() {
        return Err(Error::LengthMismatch {
            what: "fit parameters vs points",
            left: params.len(),
            right: points.len(),
        });
    }
    check_points(points, "data point")?;
    check_smoothing(fit)?;
    let (ku, kv) = (template.knots_u(), template.knots_v());
    let (p, q, nv) = (template.degree_u(), template.degree_v(), template.num_v());
    let (mut bu, mut bv) = (BasisEvaluator::new(p), BasisEvaluator::new(q));
    let (mut nu_vals, mut nv_vals) = (vec![0.0; p + 1], vec![0.0; q + 1]);
    let mut rows = Vec::with_capacity(params.len());
    for &(u, v) in params {
        ku.check_param(u)?;
        kv.check_param(v)?;
        let (su, sv) = (ku.span(u), kv.span(v));
        bu.values(ku.knots(), su, u, &mut nu_vals);
        bv.values(kv.knots(), sv, v, &mut nv_vals);
        let mut row = Vec::with_capacity((p + 1) * (q + 1));
        for a in 0..=p {
            for b in 0..=q {
                row.push(((su - p + a) * nv + sv - q + b, nu_vals[a] * nv_vals[b]));
            }
        }
        rows.push(row);
    }
    let mut stiffness = Vec::new();
    if fit.smoothing > 0.0 {
        let gram = ThinPlateGram::new(ku, kv)?;
        let nu = template.num_u();
        for i in 0..nu {
            for j in 0..nv {
                for k in i.saturating_sub(p)..(i + p + 1).min(nu) {
                    for l in j.saturating_sub(q)..(j + q + 1).min(nv) {
                        stiffness.push((i * nv + j, k * nv + l, gram.stiffness((i, j), (k, l))));
                    }
                }
            }
        }
    }
    let name = move |k: usize| format!("[{}][{}]", k / nv, k % nv);
    let problem = Problem {
        fixed_values: template.control_points(),
        free: mask.as_slice(),
        rows,
        targets: points,
        stiffness,
        smoothing: fit.smoothing,
        name: &name,
    };
    let solved = solve(&problem)?;
    let surface = BSplineSurface::new(ku.clone(), kv.clone(), solved, None)?;
    let mut eval = surface.evaluator();
    let rep = report(
        params
            .iter()
            .zip(points)
            .map(|(&(u, v), x)| (eval.point(u, v) - x).norm()),
        mask.free_count(),
    );
    Ok((surface, rep))
}

/// Fits a polynomial curve with the knots and degree of `template` to `points` at `params`;
/// control points with `free[k] == false` keep the template's values.
pub fn fit_curve(
    template: &BSplineCurve,
    free: &[bool],
    params: &[f64],
    points: &[Point3],
    fit: &FitParams,
) -> Result<(BSplineCurve, FitReport)> {
    if template.is_rational() {
        return Err(Error::RationalNotSupported {
            operation: "least-squares curve fitting",
        });
    }
    if free.len() != template.control_points().len() {
        return Err(Error::LengthMismatch {
            what: "free flags vs control points",
            left: free.len(),
            right: template.control_points().len(),
        });
    }
    if params.len() != points.len() {
        return Err(Error::LengthMismatch {
            what: "fit parameters vs points",
            left: params.len(),
            right: points.len(),
        });
    }
    check_points(points, "data point")?;
    check_smoothing(fit)?;
    let kv = template.knots();
    let p = kv.degree();
    let mut basis = BasisEvaluator::new(p);
    let mut vals = vec![0.0; p + 1];
    let mut rows = Vec::with_capacity(params.len());
    for &t in params {
        kv.check_param(t)?;
        let s = kv.span(t);
        basis.values(kv.knots(), s, t, &mut vals);
        rows.push((0..=p).map(|a| (s - p + a, vals[a])).collect());
    }
    let mut stiffness = Vec::new();
    if fit.smoothing > 0.0 {
        let g = gram_matrix(kv, 2, 2)?;
        let n = kv.num_basis();
        for i in 0..n {
            for k in i.saturating_sub(p)..(i + p + 1).min(n) {
                stiffness.push((i, k, g.get(i, k)));
            }
        }
    }
    let name = |k: usize| format!("[{k}]");
    let problem = Problem {
        fixed_values: template.control_points(),
        free,
        rows,
        targets: points,
        stiffness,
        smoothing: fit.smoothing,
        name: &name,
    };
    let solved = solve(&problem)?;
    let curve = BSplineCurve::new(kv.clone(), solved, None)?;
    let rep = report(
        params
            .iter()
            .zip(points)
            .map(|(&t, x)| (curve.point(t) - x).norm()),
        free.iter().filter(|&&f| f).count(),
    );
    Ok((curve, rep))
}
