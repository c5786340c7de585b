//! The jump of the p-th derivative at a simple knot, and the control point that removes it.
//!
//! A degree-p B-spline is C^{p−1} at a simple knot t_c; removing the knot and reinserting it
//! (\[SV\] §5.1, \[FS\]; \[HK\] for general order) yields a curve that is C^p there.
//! The polygons for which t_c is removable are exactly those with zero jump
//! J = x^{(p)}(t_c⁺) − x^{(p)}(t_c⁻) = Σ_i β_i P_i, β_i = N_i^{(p)}(t_c⁺) − N_i^{(p)}(t_c⁻),
//! i = c − p − 1 … c (p + 2 points). Hence:
//! - exact single-point solve: P_j ← −Σ_{i≠j} β_i P_i / β_j (remove, then reinsert with only P_j
//!   free);
//! - least squares: the nearest removable polygon, P_i ← P_i − β_i J / Σ β_k² (the orthogonal
//!   projection that remove-in-least-squares + reinsert performs).
//!
//! Point j is faired at the knot in the middle of its stencil, c = j + ⌈(p + 1)/2⌉ (for cubics
//! c = j + 2, the choice of the algorithm notes). The β come from nurbs-core's
//! [`BasisEvaluator`]; [`cubic_closed_form`] is Farin's formula, kept as a cross-check.
//!
//! # Tolerance
//! |β_j| below [`PIVOT_REL`] × max |β_i| counts as zero: P_j does not influence the jump.

use nurbs_core::{BasisEvaluator, KnotVector, Point3, Vector3};

/// Relative size of β_j (against the largest β of the knot) below which P_j cannot remove the
/// jump.
pub const PIVOT_REL: f64 = 1e-12;

/// The jump functionals of one knot vector, one per control point that has a central simple
/// knot.
#[derive(Debug, Clone, PartialEq)]
pub struct KnotJumps {
    degree: usize,
    /// per point j: index of the first point of its stencil, or usize::MAX when j has none
    first: Vec<usize>,
    /// per point j: β of its stencil, p + 2 values (zeros when none)
    beta: Vec<f64>,
    /// per point j: position of j inside its stencil
    offset: usize,
}

impl KnotJumps {
    /// The jump functionals of `knots` (clamped, as every nurbs-core curve).
    pub fn new(knots: &KnotVector) -> Self {
        let p = knots.degree();
        let n = knots.num_basis();
        let t = knots.knots();
        let width = p + 2;
        // the stencil of knot c is c − p − 1 … c; j = c − ⌈(p+1)/2⌉ sits at position p + 1 − ⌈(p+1)/2⌉
        let half = (p + 2) / 2;
        let offset = p + 1 - half;
        let mut first = vec![usize::MAX; n];
        let mut beta = vec![0.0; n * width];
        let mut eval = BasisEvaluator::new(p);
        let mut left = vec![0.0; (p + 1) * (p + 1)];
        let mut right = vec![0.0; (p + 1) * (p + 1)];
        for j in 0..n {
            let c = j + half;
            // interior simple knot: p + 1 ≤ c ≤ n − 1, neighbours strictly apart
            if c < p + 1 || c > n.saturating_sub(1) || !(t[c - 1] < t[c] && t[c] < t[c + 1]) {
                continue;
            }
            eval.derivatives(t, c - 1, t[c], p, &mut left);
            eval.derivatives(t, c, t[c], p, &mut right);
            let b = &mut beta[j * width..(j + 1) * width];
            // left span c − 1: functions c − 1 − p + r = stencil position r
            // right span c: functions c − p + r = stencil position r + 1
            for r in 0..=p {
                b[r] -= left[p * (p + 1) + r];
                b[r + 1] += right[p * (p + 1) + r];
            }
            first[j] = c - p - 1;
        }
        Self {
            degree: p,
            first,
            beta,
            offset,
        }
    }

    /// Degree of the knot vector.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The stencil of point j: its first point and β (p + 2 values), `None` when j has no central
    /// simple knot.
    #[inline]
    pub fn stencil(&self, j: usize) -> Option<(usize, &[f64])> {
        let width = self.degree + 2;
        (self.first.get(j).copied().unwrap_or(usize::MAX) != usize::MAX)
            .then(|| (self.first[j], &self.beta[j * width..(j + 1) * width]))
    }

    /// The jump J = Σ β_i P_i at the central knot of point j (points read through `at`).
    #[inline]
    pub fn jump(&self, j: usize, at: impl Fn(usize) -> Point3) -> Option<Vector3> {
        let (first, b) = self.stencil(j)?;
        Some(
            b.iter()
                .enumerate()
                .fold(Vector3::zeros(), |acc, (k, &bk)| {
                    acc + bk * at(first + k).coords
                }),
        )
    }

    /// The exact single-point solve: the position of P_j that makes the jump vanish.
    #[inline]
    pub fn target(&self, j: usize, at: impl Fn(usize) -> Point3) -> Option<Point3> {
        let (first, b) = self.stencil(j)?;
        let bj = b[self.offset];
        let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if !(bj.abs() > PIVOT_REL * scale) {
            return None;
        }
        let mut acc = Vector3::zeros();
        for (k, &bk) in b.iter().enumerate() {
            if k != self.offset {
                acc += bk * at(first + k).coords;
            }
        }
        Some(Point3::from(-acc / bj))
    }
}

/// Farin's cubic closed form for P_j (knot c = j + 2 removed and reinserted), with t the full
/// knot vector: L = [(t_{c+1}−t_{c−3})P_{j−1} − (t_{c+1}−t_c)P_{j−2}] / (t_c−t_{c−3}),
/// R = [(t_{c+3}−t_{c−1})P_{j+1} − (t_c−t_{c−1})P_{j+2}] / (t_{c+3}−t_c),
/// P_j = [(t_{c+2}−t_c)L + (t_c−t_{c−2})R] / (t_{c+2}−t_{c−2}). `None` where a span is empty or j has
/// no such knot.
pub fn cubic_closed_form(t: &[f64], p: &[Point3], j: usize) -> Option<Point3> {
    let c = j + 2;
    if j < 2 || j + 2 >= p.len() || c + 3 >= t.len() {
        return None;
    }
    let (d_l, d_r, d_m) = (t[c] - t[c - 3], t[c + 3] - t[c], t[c + 2] - t[c - 2]);
    if !(d_l > 0.0 && d_r > 0.0 && d_m > 0.0) {
        return None;
    }
    let l = ((t[c + 1] - t[c - 3]) * p[j - 1].coords - (t[c + 1] - t[c]) * p[j - 2].coords) / d_l;
    let r = ((t[c + 3] - t[c - 1]) * p[j + 1].coords - (t[c] - t[c - 1]) * p[j + 2].coords) / d_r;
    Some(Point3::from(
        ((t[c + 2] - t[c]) * l + (t[c] - t[c - 2]) * r) / d_m,
    ))
}
