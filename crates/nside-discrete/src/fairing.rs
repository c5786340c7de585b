//! Discrete thin-plate fairing of a triangle mesh ([K97] §3, [SV] §3.4).
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
//! [K97] also offers a local quadratic fit per vertex for the energy; the umbrella form is used
//! here for every vertex, so low valences (3, 4) need no special case and never make a local fit
//! singular.

use std::time::Instant;

use nalgebra::DMatrix;
use nurbs_core::sparse::{SparseSpd, SpdSolver};
use nurbs_core::{Point3, TriMesh, Vector3};

use crate::error::{NsideError, Result};
use crate::topology::{MeshTopology, ring_distance};

/// How the umbrella operator weighs the neighbours of a vertex.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UmbrellaWeights {
    /// 1/n_i for every neighbour ([K97]), the default
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
    /// Sparse solver. Default: faer with AMD ordering (see docs/benchmarks.md).
    pub solver: SpdSolver,
    /// Umbrella weights. Default uniform ([K97]).
    pub weights: UmbrellaWeights,
}

impl Default for DiscreteFairingParams {
    fn default() -> Self {
        Self {
            fixed_rings: 2,
            solver: SpdSolver::DEFAULT,
            weights: UmbrellaWeights::Uniform,
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
    let dist = ring_distance(&topology);
    let mut fixed: Vec<bool> = dist.iter().map(|&d| d <= params.fixed_rings).collect();
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
    let mut col = vec![usize::MAX; n];
    let mut nf = 0;
    for v in 0..n {
        if !fixed[v] {
            col[v] = nf;
            nf += 1;
        }
    }
    let energy = |positions: &[Point3]| match params.weights {
        UmbrellaWeights::Uniform => umbrella_energy(positions, &topology),
        UmbrellaWeights::MeanValue | UmbrellaWeights::Cotangent => {
            let mut row = Vec::with_capacity(16);
            let mut e = 0.0;
            for (i, ring) in topology.rings.iter().enumerate() {
                if topology.boundary[i] || ring.is_empty() {
                    continue;
                }
                row.clear();
                row.push((i, -1.0));
                if params.weights == UmbrellaWeights::MeanValue {
                    mean_value_row(layout, i, ring, &mut row);
                } else {
                    cotangent_row(layout, i, ring, &mut row);
                }
                let u = row.iter().fold(Vector3::zeros(), |acc, &(j, w)| {
                    acc + w * positions[j].coords
                });
                e += u.norm_squared();
            }
            e
        }
    };
    let energy_before = energy(&mesh.positions);
    let mut out = mesh.clone();
    if nf > 0 {
        let mut triplets = Vec::with_capacity(nf * 20);
        let mut rhs = DMatrix::<f64>::zeros(nf, 3);
        let mut row: Vec<(usize, f64)> = Vec::with_capacity(16);
        for (i, ring) in topology.rings.iter().enumerate() {
            if topology.boundary[i] || ring.is_empty() {
                continue;
            }
            row.clear();
            row.push((i, -1.0));
            match params.weights {
                UmbrellaWeights::Uniform => {
                    let w = 1.0 / ring.len() as f64;
                    row.extend(ring.iter().map(|&j| (j, w)));
                }
                UmbrellaWeights::MeanValue => mean_value_row(layout, i, ring, &mut row),
                UmbrellaWeights::Cotangent => cotangent_row(layout, i, ring, &mut row),
            }
            let mut fixed_part = nurbs_core::Vector3::zeros();
            for &(v, wv) in &row {
                if col[v] == usize::MAX {
                    fixed_part += wv * mesh.positions[v].coords;
                }
            }
            for &(a, wa) in &row {
                let ca = col[a];
                if ca == usize::MAX {
                    continue;
                }
                for c in 0..3 {
                    rhs[(ca, c)] -= wa * fixed_part[c];
                }
                for &(b, wb) in &row {
                    if col[b] != usize::MAX {
                        triplets.push((ca, col[b], wa * wb));
                    }
                }
            }
        }
        let system = SparseSpd::from_triplets(nf, &triplets)?;
        let x = system.solve(&rhs, params.solver)?;
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
