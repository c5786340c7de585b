//! Sparse symmetric positive definite systems A X = B: assembly from triplets and a sparse
//! Cholesky factorization, shared by the fitting, energy and discrete-fairing crates.
//!
//! Two back ends: nalgebra-sparse's `CscCholesky` (no reordering: fill follows the given
//! numbering) and faer's sparse Cholesky (feature `faer`, on by default) with an optional AMD
//! fill-reducing ordering. `docs/benchmarks.md` records which is faster on which problem.

use nalgebra::DMatrix;

use crate::error::{Error, Result};

/// Which sparse Cholesky to use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpdSolver {
    /// nalgebra-sparse, natural order
    NalgebraSparse,
    /// faer, with the ordering given
    #[cfg(feature = "faer")]
    Faer(FillOrdering),
}

/// Fill-reducing ordering of the faer back end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FillOrdering {
    /// keep the caller's numbering (good when it is already banded)
    Natural,
    /// approximate minimum degree
    Amd,
    /// nested dissection from coordinates of the unknowns ([`SparseSpd::nested_dissection`]),
    /// for callers that have them (discrete fairing: the mesh vertices) and pass the order to
    /// [`SparseSpd::solve_ordered`]; [`SparseSpd::solve`], which has no coordinates, takes AMD
    NestedDissection,
}

impl SpdSolver {
    /// faer with AMD where available, otherwise nalgebra-sparse.
    pub const DEFAULT: SpdSolver = {
        #[cfg(feature = "faer")]
        {
            SpdSolver::Faer(FillOrdering::Amd)
        }
        #[cfg(not(feature = "faer"))]
        {
            SpdSolver::NalgebraSparse
        }
    };
}

/// A symmetric matrix in compressed sparse columns, both triangles, rows sorted per column.
#[derive(Debug, Clone, PartialEq)]
pub struct SparseSpd {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    values: Vec<f64>,
}

impl SparseSpd {
    /// Assembles an n × n matrix from (row, column, value) triplets; duplicates are summed. The
    /// caller supplies both (i, j) and (j, i) for off-diagonal entries.
    pub fn from_triplets(n: usize, triplets: &[(usize, usize, f64)]) -> Result<Self> {
        let mut count = vec![0usize; n + 1];
        for &(i, j, v) in triplets {
            if i >= n || j >= n {
                return Err(Error::ControlNetShape {
                    detail: format!("sparse entry ({i}, {j}) outside a {n}×{n} matrix"),
                });
            }
            if !v.is_finite() {
                return Err(Error::SingularSystem {
                    reason: format!("entry ({i}, {j}) is {v}"),
                });
            }
            count[j + 1] += 1;
        }
        for j in 0..n {
            count[j + 1] += count[j];
        }
        let mut rows = vec![0usize; triplets.len()];
        let mut vals = vec![0.0; triplets.len()];
        let mut next = count.clone();
        for &(i, j, v) in triplets {
            rows[next[j]] = i;
            vals[next[j]] = v;
            next[j] += 1;
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(triplets.len());
        let mut values = Vec::with_capacity(triplets.len());
        col_ptr.push(0);
        let mut order: Vec<usize> = Vec::new();
        for j in 0..n {
            order.clear();
            order.extend(count[j]..count[j + 1]);
            order.sort_by_key(|&k| rows[k]);
            for &k in &order {
                if row_idx.len() > col_ptr[j] && *row_idx.last().expect("non-empty") == rows[k] {
                    *values.last_mut().expect("non-empty") += vals[k];
                } else {
                    row_idx.push(rows[k]);
                    values.push(vals[k]);
                }
            }
            col_ptr.push(row_idx.len());
        }
        Ok(Self {
            n,
            col_ptr,
            row_idx,
            values,
        })
    }

    /// Takes a matrix already in compressed sparse columns (both triangles, rows strictly
    /// increasing within each column), as assemblers that know their pattern build it.
    pub fn from_csc(
        n: usize,
        col_ptr: Vec<usize>,
        row_idx: Vec<usize>,
        values: Vec<f64>,
    ) -> Result<Self> {
        let bad = |detail: String| Error::ControlNetShape {
            detail: format!("sparse matrix: {detail}"),
        };
        if col_ptr.len() != n + 1
            || col_ptr[0] != 0
            || col_ptr[n] != row_idx.len()
            || row_idx.len() != values.len()
        {
            return Err(bad(format!(
                "{} column pointers, {} rows, {} values for n = {n}",
                col_ptr.len(),
                row_idx.len(),
                values.len()
            )));
        }
        for j in 0..n {
            if col_ptr[j] > col_ptr[j + 1] {
                return Err(bad(format!("column pointers decrease at column {j}")));
            }
            let rows = &row_idx[col_ptr[j]..col_ptr[j + 1]];
            if rows.iter().any(|&r| r >= n) || rows.windows(2).any(|w| w[0] >= w[1]) {
                return Err(bad(format!(
                    "rows of column {j} are out of range or not increasing"
                )));
            }
        }
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(Error::SingularSystem {
                reason: format!("entry {k} is {}", values[k]),
            });
        }
        Ok(Self {
            n,
            col_ptr,
            row_idx,
            values,
        })
    }

    /// Dimension n.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Stored entries (both triangles).
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// y = A x for one column.
    pub fn mul_vec(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n];
        for j in 0..self.n {
            for k in self.col_ptr[j]..self.col_ptr[j + 1] {
                y[self.row_idx[k]] += self.values[k] * x[j];
            }
        }
        y
    }

    /// The matrix with every diagonal entry a_ii of its pattern replaced by f(a_ii) (a damped
    /// system from its undamped one, without assembling again).
    pub fn map_diagonal(&self, f: impl Fn(f64) -> f64) -> SparseSpd {
        let mut out = self.clone();
        for c in 0..self.n {
            for k in self.col_ptr[c]..self.col_ptr[c + 1] {
                if self.row_idx[k] == c {
                    out.values[k] = f(self.values[k]);
                }
            }
        }
        out
    }

    /// Solves A X = B by sparse Cholesky; a matrix that is not positive definite is
    /// [`Error::SingularSystem`].
    pub fn solve(&self, rhs: &DMatrix<f64>, solver: SpdSolver) -> Result<DMatrix<f64>> {
        if rhs.nrows() != self.n {
            return Err(Error::LengthMismatch {
                what: "right-hand side rows vs matrix size",
                left: rhs.nrows(),
                right: self.n,
            });
        }
        match solver {
            SpdSolver::NalgebraSparse => {
                let csc = nalgebra_sparse::CscMatrix::try_from_csc_data(
                    self.n,
                    self.n,
                    self.col_ptr.clone(),
                    self.row_idx.clone(),
                    self.values.clone(),
                )
                .map_err(|e| Error::SingularSystem {
                    reason: format!("bad sparse structure: {e}"),
                })?;
                let chol =
                    nalgebra_sparse::factorization::CscCholesky::factor(&csc).map_err(|e| {
                        Error::SingularSystem {
                            reason: format!("matrix is not positive definite ({e:?})"),
                        }
                    })?;
                Ok(chol.solve(rhs))
            }
            #[cfg(feature = "faer")]
            SpdSolver::Faer(ordering) => self.solve_faer(rhs, ordering, None),
        }
    }

    /// Solves A X = B by faer's sparse Cholesky with the elimination order given (old indices
    /// in elimination order, e.g. from [`SparseSpd::nested_dissection`]).
    #[cfg(feature = "faer")]
    pub fn solve_ordered(&self, rhs: &DMatrix<f64>, order: &[usize]) -> Result<DMatrix<f64>> {
        if rhs.nrows() != self.n {
            return Err(Error::LengthMismatch {
                what: "right-hand side rows vs matrix size",
                left: rhs.nrows(),
                right: self.n,
            });
        }
        let mut inverse = vec![usize::MAX; self.n];
        if order.len() == self.n {
            for (k, &v) in order.iter().enumerate() {
                if v < self.n {
                    inverse[v] = k;
                }
            }
        }
        if inverse.contains(&usize::MAX) {
            return Err(Error::ControlNetShape {
                detail: format!("elimination order is not a permutation of 0..{}", self.n),
            });
        }
        self.solve_faer(rhs, FillOrdering::Natural, Some((order, &inverse)))
    }

    #[cfg(feature = "faer")]
    fn solve_faer(
        &self,
        rhs: &DMatrix<f64>,
        ordering: FillOrdering,
        custom: Option<(&[usize], &[usize])>,
    ) -> Result<DMatrix<f64>> {
        let (col_ptr, row_idx, values) = self.upper();
        let symbolic = symbolic_cholesky(self.n, &col_ptr, &row_idx, ordering, custom)?;
        numeric_solve(&symbolic, (&col_ptr, &row_idx, &values), rhs)
    }

    /// The upper triangle (rows ≤ column, a prefix of every sorted column) in compressed
    /// columns: faer's input.
    #[cfg(feature = "faer")]
    fn upper(&self) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
        let n = self.n;
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(self.row_idx.len() / 2 + n);
        let mut values = Vec::with_capacity(self.row_idx.len() / 2 + n);
        col_ptr.push(0);
        for c in 0..n {
            for k in self.col_ptr[c]..self.col_ptr[c + 1] {
                if self.row_idx[k] <= c {
                    row_idx.push(self.row_idx[k]);
                    values.push(self.values[k]);
                }
            }
            col_ptr.push(row_idx.len());
        }
        (col_ptr, row_idx, values)
    }
}

/// A sparse Cholesky's symbolic part — the fill-reducing order and the factor's structure —
/// found once for a sparsity pattern and reused for every matrix of that pattern (a damped
/// Gauss–Newton method solves one system of the same pattern per damping it tries). Solving
/// with it gives the same result, bit for bit, as [`SparseSpd::solve`] with the same ordering:
/// the ordering depends on the pattern only.
#[cfg(feature = "faer")]
#[derive(Debug)]
pub struct SpdSymbolic {
    n: usize,
    /// the full pattern (both triangles) of the matrices it serves
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// its upper triangle, faer's input
    upper_col_ptr: Vec<usize>,
    upper_row_idx: Vec<usize>,
    symbolic: faer::sparse::linalg::cholesky::SymbolicCholesky<usize>,
}

#[cfg(feature = "faer")]
impl SpdSymbolic {
    /// The symbolic factorization of `a`'s pattern with `ordering` ([`FillOrdering::NestedDissection`]
    /// takes AMD, as [`SparseSpd::solve`] does).
    pub fn new(a: &SparseSpd, ordering: FillOrdering) -> Result<Self> {
        let (upper_col_ptr, upper_row_idx, _) = a.upper();
        let symbolic = symbolic_cholesky(a.n, &upper_col_ptr, &upper_row_idx, ordering, None)?;
        Ok(Self {
            n: a.n,
            col_ptr: a.col_ptr.clone(),
            row_idx: a.row_idx.clone(),
            upper_col_ptr,
            upper_row_idx,
            symbolic,
        })
    }

    /// Whether `a` has the pattern this was made for.
    pub fn fits(&self, a: &SparseSpd) -> bool {
        a.n == self.n && a.col_ptr == self.col_ptr && a.row_idx == self.row_idx
    }

    /// Solves A X = B for a matrix of this pattern; another pattern is
    /// [`Error::ControlNetShape`], a matrix that is not positive definite
    /// [`Error::SingularSystem`].
    pub fn solve(&self, a: &SparseSpd, rhs: &DMatrix<f64>) -> Result<DMatrix<f64>> {
        if !self.fits(a) {
            return Err(Error::ControlNetShape {
                detail: "the matrix's sparsity pattern is not the factorization's".to_string(),
            });
        }
        if rhs.nrows() != self.n {
            return Err(Error::LengthMismatch {
                what: "right-hand side rows vs matrix size",
                left: rhs.nrows(),
                right: self.n,
            });
        }
        let (_, _, values) = a.upper();
        numeric_solve(
            &self.symbolic,
            (&self.upper_col_ptr, &self.upper_row_idx, &values),
            rhs,
        )
    }
}

/// faer's symbolic Cholesky of the upper-triangle pattern (`col_ptr`, `row_idx`).
#[cfg(feature = "faer")]
fn symbolic_cholesky(
    n: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
    ordering: FillOrdering,
    custom: Option<(&[usize], &[usize])>,
) -> Result<faer::sparse::linalg::cholesky::SymbolicCholesky<usize>> {
    use faer::sparse::SymbolicSparseColMatRef;
    use faer::sparse::linalg::cholesky::{SymmetricOrdering, factorize_symbolic_cholesky};
    let pattern = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
    let order = match (custom, ordering) {
        (Some((fwd, inv)), _) => {
            SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(fwd, inv, n))
        }
        (None, FillOrdering::Natural) => SymmetricOrdering::Identity,
        (None, FillOrdering::Amd | FillOrdering::NestedDissection) => SymmetricOrdering::Amd,
    };
    factorize_symbolic_cholesky(pattern, faer::Side::Upper, order, Default::default()).map_err(
        |e| Error::SingularSystem {
            reason: format!("symbolic factorization: {e:?}"),
        },
    )
}

/// The numeric Cholesky of the upper triangle `upper` on `symbolic`, and A X = B solved with it.
#[cfg(feature = "faer")]
fn numeric_solve(
    symbolic: &faer::sparse::linalg::cholesky::SymbolicCholesky<usize>,
    (col_ptr, row_idx, values): (&[usize], &[usize], &[f64]),
    rhs: &DMatrix<f64>,
) -> Result<DMatrix<f64>> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
    let fail = |what: &str, e: String| Error::SingularSystem {
        reason: format!("{what}: {e}"),
    };
    let n = rhs.nrows();
    let pattern = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
    let upper = SparseColMatRef::new(pattern, values);
    let par = faer::Par::Seq;
    let mut factor = vec![0.0; symbolic.len_val()];
    let mut buffer =
        MemBuffer::try_new(symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()))
            .map_err(|e| fail("memory", format!("{e:?}")))?;
    let llt = symbolic
        .factorize_numeric_llt::<f64>(
            &mut factor,
            upper,
            faer::Side::Upper,
            Default::default(),
            par,
            MemStack::new(&mut buffer),
            Default::default(),
        )
        .map_err(|e| fail("matrix is not positive definite", format!("{e:?}")))?;
    let mut b = faer::Mat::<f64>::from_fn(n, rhs.ncols(), |i, j| rhs[(i, j)]);
    let mut buffer = MemBuffer::try_new(symbolic.solve_in_place_scratch::<f64>(rhs.ncols(), par))
        .map_err(|e| fail("memory", format!("{e:?}")))?;
    llt.solve_in_place_with_conj(faer::Conj::No, b.as_mut(), par, MemStack::new(&mut buffer));
    Ok(DMatrix::from_fn(n, rhs.ncols(), |i, j| b[(i, j)]))
}

/// Subsets of at most this many unknowns are not dissected further.
const ND_LEAF: usize = 64;

impl SparseSpd {
    /// Nested-dissection elimination order (old indices in elimination order) from coordinates
    /// of the unknowns (e.g. mesh vertices): each subset is cut at the median of the coordinate
    /// axis that gives the smallest separator, the unknowns of the lower half coupled to the
    /// upper half (in the matrix graph), ordered after both halves (recursively). Straight cuts keep the
    /// separators short on surface meshes; subsets of ≤ 64 unknowns keep the caller's order.
    pub fn nested_dissection(&self, coords: &[[f64; 3]]) -> Result<Vec<usize>> {
        if coords.len() != self.n {
            return Err(Error::LengthMismatch {
                what: "coordinates vs matrix size",
                left: coords.len(),
                right: self.n,
            });
        }
        enum Task {
            Split(Vec<usize>),
            Emit(Vec<usize>),
        }
        let n = self.n;
        let mut order = Vec::with_capacity(n);
        let mut dissection = Dissection {
            matrix: self,
            coords,
            side: vec![usize::MAX; n],
            splits: 0,
        };
        let mut tasks = vec![Task::Split((0..n).collect())];
        while let Some(task) = tasks.pop() {
            let mut set = match task {
                Task::Emit(set) => {
                    order.extend(set);
                    continue;
                }
                Task::Split(set) => set,
            };
            if set.len() <= ND_LEAF {
                set.sort_unstable();
                order.extend(set);
                continue;
            }
            let (a, sep, b) = dissection.split(set);
            tasks.push(Task::Emit(sep));
            tasks.push(Task::Split(b));
            tasks.push(Task::Split(a));
        }
        Ok(order)
    }
}

/// The state of one nested dissection: which cut last put each unknown in an upper half.
struct Dissection<'a> {
    matrix: &'a SparseSpd,
    coords: &'a [[f64; 3]],
    /// side[v]: the cut (numbered by `splits`) that put v in its upper half
    side: Vec<usize>,
    /// cuts made so far
    splits: usize,
}

impl Dissection<'_> {
    /// Cuts `set` along the axis (of three) with the smallest separator — on a curved surface
    /// the longest axis may cut it obliquely — into the lower half without the separator, the
    /// separator (the lower unknowns coupled to the upper half) and the upper half.
    fn split(&mut self, mut set: Vec<usize>) -> (Vec<usize>, Vec<usize>, Vec<usize>) {
        let mut best: Option<(usize, usize)> = None;
        let mut half = 0;
        for axis in 0..3 {
            half = self.cut(&mut set, axis);
            let sep = set[..half]
                .iter()
                .filter(|&&v| self.touches_upper(v))
                .count();
            if best.is_none_or(|(_, s)| sep < s) {
                best = Some((axis, sep));
            }
        }
        let (axis, _) = best.expect("three axes tried");
        if axis != 2 {
            // the last axis tried is in place; redo the best one
            half = self.cut(&mut set, axis);
        }
        let (mut a, mut sep) = (Vec::with_capacity(half), Vec::new());
        for &v in &set[..half] {
            if self.touches_upper(v) {
                sep.push(v);
            } else {
                a.push(v);
            }
        }
        let b = set[half..].to_vec();
        (a, sep, b)
    }

    /// Cuts `set` at its median along `axis` ([`median_cut`]) and marks its upper part as the
    /// upper half of a new cut; returns the size of the lower part.
    fn cut(&mut self, set: &mut [usize], axis: usize) -> usize {
        let half = median_cut(set, self.coords, axis);
        self.splits += 1;
        for &v in &set[half..] {
            self.side[v] = self.splits;
        }
        half
    }

    /// Whether unknown v is coupled (in the matrix graph) to the upper half of the last cut.
    fn touches_upper(&self, v: usize) -> bool {
        let m = self.matrix;
        m.row_idx[m.col_ptr[v]..m.col_ptr[v + 1]]
            .iter()
            .any(|&w| self.side[w] == self.splits)
    }
}

/// Cuts `set` at the median of `coords` along `axis`, all unknowns with the median coordinate
/// on one side (a grid line split between both would widen the separator); returns the size
/// of the lower part.
fn median_cut(set: &mut [usize], coords: &[[f64; 3]], axis: usize) -> usize {
    let half = set.len() / 2;
    let key = |v: usize| coords[v][axis];
    set.select_nth_unstable_by(half, |&a, &b| key(a).total_cmp(&key(b)));
    let m = key(set[half]);
    let (lower, upper) = set.split_at_mut(half);
    let below = partition(lower, |v| key(v).total_cmp(&m).is_lt());
    let equal_up = partition(upper, |v| key(v).total_cmp(&m).is_eq());
    [below, half + equal_up]
        .into_iter()
        .filter(|&k| k > 0 && k < set.len())
        .min_by_key(|&k| k.abs_diff(half))
        .unwrap_or(half)
}

/// Moves the entries satisfying `pred` to the front of `items` (in no particular order) and
/// returns their count.
fn partition(items: &mut [usize], pred: impl Fn(usize) -> bool) -> usize {
    let mut k = 0;
    for i in 0..items.len() {
        if pred(items[i]) {
            items.swap(i, k);
            k += 1;
        }
    }
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    fn laplacian_1d(n: usize) -> SparseSpd {
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 2.0));
            if i + 1 < n {
                t.push((i, i + 1, -1.0));
                t.push((i + 1, i, -1.0));
            }
        }
        SparseSpd::from_triplets(n, &t).unwrap()
    }

    #[test]
    fn solvers_agree_and_solve() {
        let a = laplacian_1d(50);
        let rhs = DMatrix::from_fn(50, 2, |i, j| (i + j) as f64);
        let mut solvers = vec![SpdSolver::NalgebraSparse];
        #[cfg(feature = "faer")]
        solvers.extend([
            SpdSolver::Faer(FillOrdering::Natural),
            SpdSolver::Faer(FillOrdering::Amd),
            SpdSolver::Faer(FillOrdering::NestedDissection),
        ]);
        for s in solvers {
            let x = a.solve(&rhs, s).unwrap();
            for c in 0..2 {
                let col: Vec<f64> = x.column(c).iter().copied().collect();
                let y = a.mul_vec(&col);
                for i in 0..50 {
                    assert!((y[i] - rhs[(i, c)]).abs() < 1e-9, "{s:?}");
                }
            }
        }
    }

    /// One symbolic factorization serves every matrix of its pattern, with the results of a
    /// fresh solve bit for bit; another pattern is refused; `map_diagonal` keeps the pattern.
    #[cfg(feature = "faer")]
    #[test]
    fn a_symbolic_factorization_is_reused_for_its_pattern() {
        let n = 40;
        let rhs = DMatrix::from_fn(n, 1, |i, _| (i as f64 * 0.37).sin());
        let shifted = |shift: f64| {
            let mut t = Vec::new();
            for i in 0..n {
                t.push((i, i, 2.0 + shift + 0.01 * i as f64));
                for j in [i + 1, i + 7].into_iter().filter(|&j| j < n) {
                    t.push((i, j, -0.5));
                    t.push((j, i, -0.5));
                }
            }
            SparseSpd::from_triplets(n, &t).unwrap()
        };
        let first = shifted(0.0);
        let symbolic = SpdSymbolic::new(&first, FillOrdering::Amd).unwrap();
        for shift in [0.0, 0.3, 5.0] {
            let a = shifted(shift);
            assert!(symbolic.fits(&a));
            let fresh = a.solve(&rhs, SpdSolver::Faer(FillOrdering::Amd)).unwrap();
            assert_eq!(symbolic.solve(&a, &rhs).unwrap(), fresh, "shift {shift}");
        }
        // the damped matrix from the undamped one, without assembling again
        assert_eq!(first.map_diagonal(|v| v + 0.3), shifted(0.3));
        let other = laplacian_1d(n);
        assert!(!symbolic.fits(&other));
        assert!(matches!(
            symbolic.solve(&other, &rhs),
            Err(Error::ControlNetShape { .. })
        ));
        // not positive definite: an error, not a panic
        assert!(matches!(
            symbolic.solve(&shifted(-10.0), &rhs),
            Err(Error::SingularSystem { .. })
        ));
    }

    #[cfg(feature = "faer")]
    #[test]
    fn nested_dissection_orders_and_solves() {
        // the 5-point Laplacian of a 30 × 30 grid (Dirichlet), unknowns numbered row by row
        let m = 30;
        let n = m * m;
        let mut t = Vec::new();
        for a in 0..m {
            for b in 0..m {
                let i = a * m + b;
                t.push((i, i, 4.0));
                for (da, db) in [(1, 0), (0, 1)] {
                    if a + da < m && b + db < m {
                        let j = (a + da) * m + b + db;
                        t.extend([(i, j, -1.0), (j, i, -1.0)]);
                    }
                }
            }
        }
        let a = SparseSpd::from_triplets(n, &t).unwrap();
        let coords: Vec<[f64; 3]> = (0..n)
            .map(|i| [(i / m) as f64, (i % m) as f64, 0.0])
            .collect();
        let order = a.nested_dissection(&coords).unwrap();
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n).collect::<Vec<_>>());
        let rhs = DMatrix::from_fn(n, 3, |i, j| ((i * 7 + j) % 11) as f64);
        let x = a.solve_ordered(&rhs, &order).unwrap();
        let y = a.solve(&rhs, SpdSolver::Faer(FillOrdering::Amd)).unwrap();
        assert!((x - y).amax() < 1e-9);
        assert!(a.nested_dissection(&coords[1..]).is_err());
        assert!(a.solve_ordered(&rhs, &order[1..]).is_err());
    }

    #[test]
    fn singular_is_an_error() {
        // the Neumann Laplacian (constant null space)
        let mut t = vec![(0, 0, 1.0), (1, 1, 1.0), (0, 1, -1.0), (1, 0, -1.0)];
        t.push((1, 1, 0.0));
        let a = SparseSpd::from_triplets(2, &t).unwrap();
        let rhs = DMatrix::from_element(2, 1, 1.0);
        assert!(matches!(
            a.solve(&rhs, SpdSolver::NalgebraSparse),
            Err(Error::SingularSystem { .. })
        ));
        #[cfg(feature = "faer")]
        assert!(matches!(
            a.solve(&rhs, SpdSolver::Faer(FillOrdering::Amd)),
            Err(Error::SingularSystem { .. })
        ));
    }
}
