//! Mesh topology for discrete fairing: manifold check, boundary flags, one-rings and the ring
//! distance of every vertex from the boundary (ring 0 = the boundary itself).

use std::collections::{HashMap, VecDeque};

use nurbs_core::TriMesh;

use crate::error::{NsideError, Result};

/// Checked topology of a triangle mesh region.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshTopology {
    /// ordered neighbours of every vertex
    pub rings: Vec<Vec<usize>>,
    /// whether a vertex lies on a boundary edge
    pub boundary: Vec<bool>,
}

impl MeshTopology {
    /// Checks that every face names three distinct existing vertices, every edge has at most
    /// two faces (consistently oriented), and coordinates are finite.
    pub fn new(mesh: &TriMesh) -> Result<Self> {
        let n = mesh.positions.len();
        if let Some(index) = mesh
            .positions
            .iter()
            .position(|p| !p.coords.iter().all(|c| c.is_finite()))
        {
            return Err(NsideError::NonFinite { index });
        }
        let mut edges: HashMap<(usize, usize), usize> =
            HashMap::with_capacity(mesh.faces.len() * 3);
        for (face, f) in mesh.faces.iter().enumerate() {
            if f.iter().any(|&v| v >= n) {
                return Err(NsideError::BadFace {
                    face,
                    detail: format!("vertex index out of range ({n} vertices)"),
                });
            }
            if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
                return Err(NsideError::BadFace {
                    face,
                    detail: "repeats a vertex".into(),
                });
            }
            for k in 0..3 {
                let e = (f[k], f[(k + 1) % 3]);
                if let Some(other) = edges.insert(e, face) {
                    return Err(NsideError::NotManifold {
                        detail: format!(
                            "directed edge {}→{} is used by faces {other} and {face} (non-manifold or inconsistently oriented)",
                            e.0, e.1
                        ),
                    });
                }
            }
        }
        let mut boundary = vec![false; n];
        for &(a, b) in edges.keys() {
            if !edges.contains_key(&(b, a)) {
                boundary[a] = true;
                boundary[b] = true;
            }
        }
        let rings = mesh.one_rings();
        Ok(Self { rings, boundary })
    }
}

/// Ring distance of every vertex from the boundary (0 on the boundary, `usize::MAX` for vertices
/// not connected to it).
pub fn ring_distance(topology: &MeshTopology) -> Vec<usize> {
    let n = topology.rings.len();
    let mut dist = vec![usize::MAX; n];
    let mut queue = VecDeque::new();
    for v in 0..n {
        if topology.boundary[v] {
            dist[v] = 0;
            queue.push_back(v);
        }
    }
    while let Some(v) = queue.pop_front() {
        for &w in &topology.rings[v] {
            if dist[w] == usize::MAX {
                dist[w] = dist[v] + 1;
                queue.push_back(w);
            }
        }
    }
    dist
}
