//! Discrete thin-plate fairing of a triangle mesh (\[K97\] §3, \[SV\] §3.4).
//!
//! The umbrella operator U(p_i) = (1/n_i) Σ_{j ∈ N(i)} p_j − p_i is a discrete Laplacian; the
//! discrete thin-plate energy is E = Σ_{i interior} |U(p_i)|². Minimizing E over the free
//! vertices (the others fixed) gives the normal equations
//! A_fᵀ A_f x_f = −A_fᵀ A_c x_c,
//! where A is the umbrella matrix (one row per interior vertex) split into free and fixed columns:
//! a sparse symmetric positive definite system, solved once for the three coordinates with a
//! sparse Cholesky (nurbs-core `sparse`, fill-reducing ordering). Its solution satisfies the
//! umbrella² condition U²(p) = 0 at free vertices surrounded by regular rows, so quadratic
//! surfaces sampled on regular lattices are reproduced exactly.
//!
//! Weights: [`UmbrellaWeights::Uniform`] is Kobbelt's umbrella, w_ij = 1/n_i; it depends on the
//! mesh connectivity only, so its solution follows the sampling's parametrization.
//! [`UmbrellaWeights::MeanValue`] takes Floater's mean-value weights
//! w_ij ∝ (tan(α_{j−1}/2) + tan(α_j/2)) / |q_j − q_i| (α_j the angle at q_i between q_j and q_{j+1})
//! from a layout q of the same mesh (normally a flat embedding, see [`fair_mesh_with_layout`]);
//! they are positive and reproduce linear functions of the layout, so irregular vertices (the
//! valence-2n centre of an n-sided corner, the corners of its quads) do not bend the result.
//!
//! # Deviation from the paper
//! \[K97\] also offers a local quadratic fit per vertex for the energy; the umbrella form is used
//! here for every vertex, so low valences (3, 4) need no special case and never make a local fit
//! singular.

use std::time::Instant;

use nalgebra::DMatrix;
use nurbs_core::sparse::{FillOrdering, SparseSpd, SpdSolver};
use nurbs_core::{Point3, TriMesh, Vector3};

use crate::error::{NsideError, Result};
use crate::topology::{MeshTopology, ring_distance};

/// How the umbrella operator weighs the neighbours of a vertex.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UmbrellaWeights {
    /// 1/n_i for every neighbour (\[K97\]), the default
    #[default]
    Uniform,
    /// Floater's mean-value weights of the layout (linear precision in the layout)
    MeanValue,
    /// The cotangent Laplace operator of the layout with lumped (barycentric) areas A_i: row
    /// (L p)_i = Σ_j ½(cot α_ij + cot β_ij)(p_j − p_i) scaled by 1/√A_i, so that the energy is
    /// the finite-element thin-plate energy Σ_i (1/A_i)|(L p)_i|² and, L being symmetric with
    /// zero row sums, quadratics of a flat layout are reproduced away from the boundary
    Cotangent,
}

/// Settings of the discrete fairing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscreteFairingParams {
    /// Rings fixed beyond the boundary (the boundary, ring 0, is always fixed). Default 2: the
    /// seed's setting, which carries the neighbours' tangent planes and curvature into the hole.
    pub fixed_rings: usize,
    /// Sparse solver. Default: faer with nested dissection along coordinate cuts of the layout
    /// (on the 10k-vertex benchmark cap faster than AMD; AMD has less fill on the 100k one).
    pub solver: SpdSolver,
    /// Umbrella weights. Default uniform (\[K97\]).
    pub weights: UmbrellaWeights,
    /// Weight of a data term w Σ |p − p₀|² over the free vertices, relative to the mean diagonal
    /// of the fairing system LᵀL (unit-free). Default 0: pure discrete fairing, as \[K97\]. A
    /// positive weight keeps the faired mesh near its input (a caller with a deviation
    /// tolerance raises it until the moves fit).
    pub data_weight: f64,
}

impl Default for DiscreteFairingParams {
    fn default() -> Self {
        Self {
            fixed_rings: 2,
            solver: SpdSolver::Faer(FillOrdering::NestedDissection),
            weights: UmbrellaWeights::Uniform,
            data_weight: 0.0,
        }
    }
}

/// What a discrete fairing run achieved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscreteFairingReport {
    /// vertices of the mesh
    pub vertices: usize,
    /// vertices that moved freely
    pub free_vertices: usize,
    /// Σ |U(p_i)|² before (with the weights used)
    pub energy_before: f64,
    /// Σ |U(p_i)|² after
    pub energy_after: f64,
    /// largest vertex displacement (model units)
    pub max_move: f64,
    /// wall-clock seconds
    pub seconds: f64,
}

/// Umbrella energy Σ |U(p_i)|² over the vertices with a closed one-ring.
pub fn umbrella_energy(positions: &[Point3], topology: &MeshTopology) -> f64 {
    let mut e = 0.0;
    for (i, ring) in topology.rings.iter().enumerate() {
        if topology.boundary[i] || ring.is_empty() {
            continue;
        }
        let mean = ring.iter().fold(nurbs_core::Vector3::zeros(), |acc, &j| {
            acc + positions[j].coords
        }) / ring.len() as f64;
        e += (mean - positions[i].coords).norm_squared();
    }
    e
}

/// Appends the normalized mean-value weights of the closed ring `ring` of `i` in `layout` to
/// `row`; falls back to uniform weights when the ring is degenerate (a zero edge or weight sum).
fn mean_value_row(layout: &[Point3], i: usize, ring: &[usize], row: &mut Vec<(usize, f64)>) {
    let m = ring.len();
    let start = row.len();
    let c = layout[i];
    // tan(α/2) = |a × b| / (|a||b| + a·b)
    let half_tan = |a: usize, b: usize| {
        let (x, y) = (layout[a] - c, layout[b] - c);
        let den = x.norm() * y.norm() + x.dot(&y);
        if den > 0.0 {
            x.cross(&y).norm() / den
        } else {
            f64::INFINITY
        }
    };
    let mut sum = 0.0;
    for k in 0..m {
        let (prev, j, next) = (ring[(k + m - 1) % m], ring[k], ring[(k + 1) % m]);
        let w = (half_tan(prev, j) + half_tan(j, next)) / (layout[j] - c).norm();
        sum += w;
        row.push((j, w));
    }
    if sum.is_finite() && sum > 0.0 {
        for e in &mut row[start..] {
            e.1 /= sum;
        }
    } else {
        row.truncate(start);
        let w = 1.0 / m as f64;
        row.extend(ring.iter().map(|&j| (j, w)));
    }
}

/// Replaces `row` (which holds (i, −1)) by the cotangent row of the closed ring of `i` in
/// `layout`, scaled by 1/√A_i; falls back to the uniform row when the ring has no area.
fn cotangent_row(layout: &[Point3], i: usize, ring: &[usize], row: &mut Vec<(usize, f64)>) {
    let m = ring.len();
    let c = layout[i];
    // cot of the angle at o between a and b
    let cot = |o: Point3, a: Point3, b: Point3| {
        let (x, y) = (a - o, b - o);
        x.dot(&y) / x.cross(&y).norm()
    };
    let mut area = 0.0;
    let mut sum = 0.0;
    let start = row.len();
    for k in 0..m {
        let (prev, j, next) = (
            layout[ring[(k + m - 1) % m]],
            layout[ring[k]],
            layout[ring[(k + 1) % m]],
        );
        area += (j - c).cross(&(next - c)).norm() / 6.0;
        let w = 0.5 * (cot(prev, c, j) + cot(next, c, j));
        sum += w;
        row.push((ring[k], w));
    }
    let scale = 1.0 / area.sqrt();
    if sum.is_finite() && area > 0.0 && scale.is_finite() {
        row[start - 1].1 = -sum * scale;
        for e in &mut row[start..] {
            e.1 *= scale;
        }
    } else {
        row.truncate(start);
        let w = 1.0 / m as f64;
        row.extend(ring.iter().map(|&j| (j, w)));
    }
}

/// Fairs `mesh`: the boundary, `params.fixed_rings` rings inside it and the vertices flagged in
/// `extra_fixed` keep their positions; all others minimize the umbrella² energy.
pub fn fair_mesh(
    mesh: &TriMesh,
    extra_fixed: &[usize],
    params: &DiscreteFairingParams,
) -> Result<(TriMesh, DiscreteFairingReport)> {
    fair_mesh_with_layout(mesh, &mesh.positions, extra_fixed, params)
}

/// Data weights [`fair_mesh_within`] tries: from [`WITHIN_FIRST_WEIGHT`] up by factors of 10,
/// at most [`WITHIN_MAX_STEPS`] times, then [`WITHIN_BISECTIONS`] halvings of the last bracket
/// in log scale (each a factor of about √10 … 1.2 in the weight).
pub const WITHIN_FIRST_WEIGHT: f64 = 1e-6;
/// See [`WITHIN_FIRST_WEIGHT`]: 20 decades reach a weight of 10¹⁴, at which every free vertex
/// moves by 10⁻¹⁴ of what pure fairing moves it.
pub const WITHIN_MAX_STEPS: usize = 20;
/// See [`WITHIN_FIRST_WEIGHT`]: 6 halvings of a decade in log scale narrow it to a factor 1.04.
pub const WITHIN_BISECTIONS: usize = 6;

/// [`fair_mesh`] with no vertex moving more than `tolerance`: pure fairing where its moves fit,
/// else the smallest data weight ([`DiscreteFairingParams::data_weight`], searched as
/// [`WITHIN_FIRST_WEIGHT`] says) whose moves do — the fairest mesh within the tolerance.
/// Returns the mesh, its report and the weight used.
pub fn fair_mesh_within(
    mesh: &TriMesh,
    extra_fixed: &[usize],
    params: &DiscreteFairingParams,
    tolerance: f64,
) -> Result<(TriMesh, DiscreteFairingReport, f64)> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(NsideError::BadParam {
            name: "tolerance",
            value: tolerance,
            detail: "a finite distance > 0",
        });
    }
    let run = |w: f64| {
        fair_mesh(
            mesh,
            extra_fixed,
            &DiscreteFairingParams {
                data_weight: w,
                ..*params
            },
        )
    };
    let (m, r) = run(params.data_weight)?;
    if r.max_move <= tolerance {
        return Ok((m, r, params.data_weight));
    }
    // bracket: `low` moves too much, `high` fits
    let mut low = params.data_weight;
    let mut w = params.data_weight.max(WITHIN_FIRST_WEIGHT);
    let mut fit = None;
    for _ in 0..WITHIN_MAX_STEPS {
        let (m, r) = run(w)?;
        if r.max_move <= tolerance {
            fit = Some((m, r, w));
            break;
        }
        low = w;
        w *= 10.0;
    }
    let Some(mut best) = fit else {
        // no weight up to 10¹⁴ fits (a tolerance below round-off): the mesh as it was
        let (_, mut r) = run(0.0)?;
        r.energy_after = r.energy_before;
        r.max_move = 0.0;
        return Ok((mesh.clone(), r, f64::INFINITY));
    };
    for _ in 0..WITHIN_BISECTIONS {
        if low <= 0.0 {
            break;
        }
        let mid = (low * best.2).sqrt();
        let (m, r) = run(mid)?;
        if r.max_move <= tolerance {
            best = (m, r, mid);
        } else {
            low = mid;
        }
    }
    Ok(best)
}

/// Like [`fair_mesh`], with the [`UmbrellaWeights::MeanValue`] weights (when chosen) taken from
/// `layout`, positions of the same vertices (e.g. the mesh projected onto a plane).
pub fn fair_mesh_with_layout(
    mesh: &TriMesh,
    layout: &[Point3],
    extra_fixed: &[usize],
    params: &DiscreteFairingParams,
) -> Result<(TriMesh, DiscreteFairingReport)> {
    let start = Instant::now();
    let topology = MeshTopology::new(mesh)?;
    let n = mesh.positions.len();
    check_layout(layout, n)?;
    let fixed = fixed_vertices(&topology, params.fixed_rings, extra_fixed)?;
    let mut col = vec![usize::MAX; n];
    let mut nf = 0;
    for v in 0..n {
        if !fixed[v] {
            col[v] = nf;
            nf += 1;
        }
    }
    let rows = UmbrellaRows::new(&topology, layout, params.weights);
    let energy = |positions: &[Point3]| match params.weights {
        UmbrellaWeights::Uniform => umbrella_energy(positions, &topology),
        UmbrellaWeights::MeanValue | UmbrellaWeights::Cotangent => rows.energy(positions),
    };
    let energy_before = energy(&mesh.positions);
    let mut out = mesh.clone();
    if nf > 0 {
        let (system, rhs) = normal_equations(&mesh.positions, &col, nf, &rows, params.data_weight)?;
        let x = solve_free(&system, &rhs, layout, &col, params.solver)?;
        for v in 0..n {
            if col[v] != usize::MAX {
                let k = col[v];
                out.positions[v] = Point3::new(x[(k, 0)], x[(k, 1)], x[(k, 2)]);
            }
        }
    }
    let max_move = nurbs_core::fairing::max_displacement(&mesh.positions, &out.positions);
    out.normals.clear();
    out.fill_missing_normals();
    let energy_after = energy(&out.positions);
    Ok((
        out,
        DiscreteFairingReport {
            vertices: n,
            free_vertices: nf,
            energy_before,
            energy_after,
            max_move,
            seconds: start.elapsed().as_secs_f64(),
        },
    ))
}

/// Bad input unless `layout` holds `n` finite positions.
fn check_layout(layout: &[Point3], n: usize) -> Result<()> {
    if layout.len() != n {
        return Err(NsideError::CountMismatch {
            what: "layout positions",
            expected: n,
            got: layout.len(),
        });
    }
    if let Some(index) = layout
        .iter()
        .position(|p| !p.coords.iter().all(|c| c.is_finite()))
    {
        return Err(NsideError::NonFinite { index });
    }
    Ok(())
}

/// The vertices that keep their positions: within `fixed_rings` rings of the boundary and
/// `extra_fixed`; bad input when an index is out of range or nothing is fixed.
fn fixed_vertices(
    topology: &MeshTopology,
    fixed_rings: usize,
    extra_fixed: &[usize],
) -> Result<Vec<bool>> {
    let dist = ring_distance(topology);
    let n = dist.len();
    let mut fixed: Vec<bool> = dist.iter().map(|&d| d <= fixed_rings).collect();
    for &index in extra_fixed {
        if index >= n {
            return Err(NsideError::FixedIndex { index, count: n });
        }
        fixed[index] = true;
    }
    // vertices cut off from any boundary stay where they are unless something else is fixed
    if !fixed.iter().any(|&f| f) {
        return Err(NsideError::NothingFixed);
    }
    Ok(fixed)
}

/// The umbrella rows, one per vertex with a closed one-ring, in compressed form: entry k of
/// row r is vertex `vertex[k]` with weight `weight[k]` (the vertex itself first).
struct UmbrellaRows {
    /// row r holds entries start[r]..start[r + 1]
    start: Vec<usize>,
    vertex: Vec<usize>,
    weight: Vec<f64>,
}

impl UmbrellaRows {
    /// The rows of `topology` with `weights` (mean-value and cotangent ones from `layout`).
    fn new(topology: &MeshTopology, layout: &[Point3], weights: UmbrellaWeights) -> Self {
        let n = topology.rings.len();
        let mut rows = Self {
            start: Vec::with_capacity(n + 1),
            vertex: Vec::with_capacity(7 * n),
            weight: Vec::with_capacity(7 * n),
        };
        rows.start.push(0);
        let mut row: Vec<(usize, f64)> = Vec::with_capacity(16);
        for (i, ring) in topology.rings.iter().enumerate() {
            if topology.boundary[i] || ring.is_empty() {
                continue;
            }
            row.clear();
            row.push((i, -1.0));
            match weights {
                UmbrellaWeights::Uniform => {
                    let w = 1.0 / ring.len() as f64;
                    row.extend(ring.iter().map(|&j| (j, w)));
                }
                UmbrellaWeights::MeanValue => mean_value_row(layout, i, ring, &mut row),
                UmbrellaWeights::Cotangent => cotangent_row(layout, i, ring, &mut row),
            }
            for &(j, w) in &row {
                rows.vertex.push(j);
                rows.weight.push(w);
            }
            rows.start.push(rows.vertex.len());
        }
        rows
    }

    /// Number of rows.
    fn len(&self) -> usize {
        self.start.len() - 1
    }

    /// Σ_r |row r · positions|².
    fn energy(&self, positions: &[Point3]) -> f64 {
        (0..self.len())
            .map(|r| {
                (self.start[r]..self.start[r + 1])
                    .fold(Vector3::zeros(), |acc, k| {
                        acc + self.weight[k] * positions[self.vertex[k]].coords
                    })
                    .norm_squared()
            })
            .sum()
    }
}

/// Solves `system` for the free vertices (`col` their columns) with `solver`; faer's nested
/// dissection takes its cuts from the free vertices' `layout` positions.
fn solve_free(
    system: &SparseSpd,
    rhs: &DMatrix<f64>,
    layout: &[Point3],
    col: &[usize],
    solver: SpdSolver,
) -> Result<DMatrix<f64>> {
    Ok(
        if solver == SpdSolver::Faer(FillOrdering::NestedDissection) {
            let mut coords = vec![[0.0; 3]; rhs.nrows()];
            for (v, &c) in col.iter().enumerate() {
                if c != usize::MAX {
                    let p = layout[v];
                    coords[c] = [p.x, p.y, p.z];
                }
            }
            let order = system.nested_dissection(&coords)?;
            system.solve_ordered(rhs, &order)?
        } else {
            system.solve(rhs, solver)?
        },
    )
}

/// The umbrella rows restricted to the free vertices, and their transpose.
struct FreeRows {
    /// row r holds entries start[r]..start[r + 1] of `entry`
    start: Vec<usize>,
    /// (free column, weight)
    entry: Vec<(usize, f64)>,
    /// Σ w p over each row's fixed vertices
    fixed_part: Vec<Vector3>,
    /// free vertex c is held by entries t_start[c]..t_start[c + 1] of `t_entry`
    t_start: Vec<usize>,
    /// (row, weight), in row order per free vertex
    t_entry: Vec<(usize, f64)>,
}

impl FreeRows {
    /// Splits `rows` at `positions` into free entries (`col`: free column of each vertex,
    /// `usize::MAX` when fixed; `nf` free) and fixed parts; rows without a free entry are
    /// dropped.
    fn new(rows: &UmbrellaRows, positions: &[Point3], col: &[usize], nf: usize) -> Self {
        let mut start = Vec::with_capacity(rows.len() + 1);
        let mut entry: Vec<(usize, f64)> = Vec::with_capacity(rows.vertex.len());
        let mut fixed_part = Vec::with_capacity(rows.len());
        start.push(0);
        // the free entries transposed: how many rows hold each free vertex
        let mut t_start = vec![0usize; nf + 1];
        for r in 0..rows.len() {
            let mut fixed = Vector3::zeros();
            let before = entry.len();
            for k in rows.start[r]..rows.start[r + 1] {
                let (v, w) = (rows.vertex[k], rows.weight[k]);
                let c = col[v];
                if c == usize::MAX {
                    fixed += w * positions[v].coords;
                } else {
                    entry.push((c, w));
                    t_start[c + 1] += 1;
                }
            }
            if entry.len() > before {
                start.push(entry.len());
                fixed_part.push(fixed);
            }
        }
        for c in 0..nf {
            t_start[c + 1] += t_start[c];
        }
        // the rows holding each free vertex, in row order, with its weight there
        let mut next = t_start[..nf].to_vec();
        let mut t_entry: Vec<(usize, f64)> = vec![(0, 0.0); t_start[nf]];
        for r in 0..start.len() - 1 {
            for &(c, w) in &entry[start[r]..start[r + 1]] {
                t_entry[next[c]] = (r, w);
                next[c] += 1;
            }
        }
        Self {
            start,
            entry,
            fixed_part,
            t_start,
            t_entry,
        }
    }

    /// The free entries of row r.
    fn row(&self, r: usize) -> &[(usize, f64)] {
        &self.entry[self.start[r]..self.start[r + 1]]
    }
}

/// The normal equations A_fᵀ A_f x_f = −A_fᵀ A_c x_c of the umbrella rows (see the module
/// documentation), assembled column by column straight into compressed sparse columns: column a
/// of A_fᵀ A_f is Σ_r w_ra · (row r restricted to the free vertices) over the rows r holding a,
/// accumulated in row order (the order a triplet assembly would sum them in).
fn normal_equations(
    positions: &[Point3],
    col: &[usize],
    nf: usize,
    rows: &UmbrellaRows,
    data_weight: f64,
) -> Result<(SparseSpd, DMatrix<f64>)> {
    let free = FreeRows::new(rows, positions, col, nf);
    // the data term: w = data_weight × mean diagonal of LᵀL on every free vertex
    let mut vertex_of = vec![0usize; nf];
    for (v, &c) in col.iter().enumerate() {
        if c != usize::MAX {
            vertex_of[c] = v;
        }
    }
    let data = if data_weight > 0.0 && nf > 0 {
        let diagonal: f64 = free.entry.iter().map(|&(_, w)| w * w).sum();
        data_weight * diagonal / nf as f64
    } else {
        0.0
    };
    let mut rhs = vec![0.0; 3 * nf];
    let mut col_ptr = Vec::with_capacity(nf + 1);
    let mut row_idx = Vec::with_capacity(20 * nf);
    let mut values = Vec::with_capacity(20 * nf);
    col_ptr.push(0);
    // dense accumulator of the current column; mark[b] == a when entry b is in its pattern
    let mut acc = vec![0.0; nf];
    let mut mark = vec![usize::MAX; nf];
    let mut pattern: Vec<usize> = Vec::with_capacity(64);
    for a in 0..nf {
        pattern.clear();
        let mut b_a = Vector3::zeros();
        for &(r, wa) in &free.t_entry[free.t_start[a]..free.t_start[a + 1]] {
            b_a -= wa * free.fixed_part[r];
            for &(b, wb) in free.row(r) {
                if mark[b] != a {
                    mark[b] = a;
                    acc[b] = 0.0;
                    pattern.push(b);
                }
                acc[b] += wa * wb;
            }
        }
        if data > 0.0 {
            if mark[a] != a {
                mark[a] = a;
                acc[a] = 0.0;
                pattern.push(a);
            }
            acc[a] += data;
            b_a += data * positions[vertex_of[a]].coords;
        }
        rhs[a] = b_a.x;
        rhs[nf + a] = b_a.y;
        rhs[2 * nf + a] = b_a.z;
        pattern.sort_unstable();
        row_idx.extend_from_slice(&pattern);
        values.extend(pattern.iter().map(|&b| acc[b]));
        col_ptr.push(row_idx.len());
    }
    Ok((
        SparseSpd::from_csc(nf, col_ptr, row_idx, values)?,
        DMatrix::from_vec(nf, 3, rhs),
    ))
}
