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
//! # Deviation from the paper
//! [K97] also offers a local quadratic fit per vertex for the energy; the umbrella form is used
//! here for every vertex, so low valences (3, 4) need no special case and never make a local fit
//! singular.

use std::time::Instant;

use nalgebra::DMatrix;
use nurbs_core::sparse::{SparseSpd, SpdSolver};
use nurbs_core::{Point3, TriMesh};

use crate::error::{NsideError, Result};
use crate::topology::{MeshTopology, ring_distance};

/// Settings of the discrete fairing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscreteFairingParams {
    /// Rings fixed beyond the boundary (the boundary, ring 0, is always fixed). Default 2: the
    /// seed's setting, which carries the neighbours' tangent planes and curvature into the hole.
    pub fixed_rings: usize,
    /// Sparse solver. Default: faer with AMD ordering (see docs/benchmarks.md).
    pub solver: SpdSolver,
}

impl Default for DiscreteFairingParams {
    fn default() -> Self {
        Self {
            fixed_rings: 2,
            solver: SpdSolver::DEFAULT,
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
    /// Σ |U(p_i)|² before
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

/// Fairs `mesh`: the boundary, `params.fixed_rings` rings inside it and the vertices flagged in
/// `extra_fixed` keep their positions; all others minimize the umbrella² energy.
pub fn fair_mesh(
    mesh: &TriMesh,
    extra_fixed: &[usize],
    params: &DiscreteFairingParams,
) -> Result<(TriMesh, DiscreteFairingReport)> {
    let start = Instant::now();
    let topology = MeshTopology::new(mesh)?;
    let n = mesh.positions.len();
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
    let energy_before = umbrella_energy(&mesh.positions, &topology);
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
            let w = 1.0 / ring.len() as f64;
            row.extend(ring.iter().map(|&j| (j, w)));
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
    let energy_after = umbrella_energy(&out.positions, &topology);
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
