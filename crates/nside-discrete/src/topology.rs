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
        let Some(wedges) = Wedges::new(mesh) else {
            // something is wrong: find the first offending face the slow, exact way
            return Err(face_error(mesh));
        };
        // a directed edge a→b is the first vertex of a wedge of a; it is a boundary edge when
        // no wedge of b starts at a
        let mut boundary = vec![false; n];
        for a in 0..n {
            for &(b, _) in wedges.of(a) {
                if !wedges.of(b).iter().any(|&(c, _)| c == a) {
                    boundary[a] = true;
                    boundary[b] = true;
                }
            }
        }
        let rings = (0..n).map(|v| ordered_ring(wedges.of(v))).collect();
        Ok(Self { rings, boundary })
    }
}

/// The wedges (next, previous) of every vertex in face order, as compressed rows: vertex v of
/// face f = [v, b, c] (up to rotation) has the wedge (b, c).
struct Wedges {
    start: Vec<usize>,
    wedge: Vec<(usize, usize)>,
}

impl Wedges {
    /// None when a face is out of range, repeats a vertex or a directed edge is used twice.
    fn new(mesh: &TriMesh) -> Option<Self> {
        let n = mesh.positions.len();
        let mut start = vec![0usize; n + 1];
        for f in &mesh.faces {
            if f.iter().any(|&v| v >= n) || f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
                return None;
            }
            for &v in f {
                start[v + 1] += 1;
            }
        }
        for v in 0..n {
            start[v + 1] += start[v];
        }
        let mut next = start.clone();
        let mut wedge = vec![(0, 0); start[n]];
        for f in &mesh.faces {
            for k in 0..3 {
                let v = f[k];
                wedge[next[v]] = (f[(k + 1) % 3], f[(k + 2) % 3]);
                next[v] += 1;
            }
        }
        let w = Self { start, wedge };
        // a directed edge v→b used twice is a repeated first vertex among the wedges of v
        let mut scratch = Vec::new();
        for v in 0..n {
            let ws = w.of(v);
            if ws.len() <= 32 {
                for (k, &(b, _)) in ws.iter().enumerate() {
                    if ws[..k].iter().any(|&(c, _)| c == b) {
                        return None;
                    }
                }
            } else {
                scratch.clear();
                scratch.extend(ws.iter().map(|&(b, _)| b));
                scratch.sort_unstable();
                if scratch.windows(2).any(|p| p[0] == p[1]) {
                    return None;
                }
            }
        }
        Some(w)
    }

    fn of(&self, v: usize) -> &[(usize, usize)] {
        &self.wedge[self.start[v]..self.start[v + 1]]
    }
}

/// The neighbours of a vertex in order from its wedges, as `TriMesh::one_rings` orders them:
/// from the wedge whose first vertex ends no other wedge (a boundary vertex), else the first.
fn ordered_ring(w: &[(usize, usize)]) -> Vec<usize> {
    if w.is_empty() {
        return Vec::new();
    }
    let start = w
        .iter()
        .position(|&(b, _)| !w.iter().any(|&(_, c)| c == b))
        .unwrap_or(0);
    let mut ring = Vec::with_capacity(w.len() + 1);
    ring.push(w[start].0);
    // at most 64 wedges are tracked in a bit set, more in a vector
    let mut used_small = 0u64;
    let mut used_big = if w.len() > 64 {
        vec![false; w.len()]
    } else {
        Vec::new()
    };
    let is_used = |k: usize, small: u64, big: &[bool]| {
        if big.is_empty() {
            small & (1 << k) != 0
        } else {
            big[k]
        }
    };
    let mut cur = start;
    loop {
        if used_big.is_empty() {
            used_small |= 1 << cur;
        } else {
            used_big[cur] = true;
        }
        let c = w[cur].1;
        match w
            .iter()
            .enumerate()
            .position(|(k, &(b, _))| b == c && !is_used(k, used_small, &used_big))
        {
            Some(k) => {
                ring.push(c);
                cur = k;
            }
            None => {
                if c != ring[0] {
                    ring.push(c);
                }
                break;
            }
        }
    }
    ring
}

/// The error of the first bad face in face order (the exact check, run once something is wrong).
fn face_error(mesh: &TriMesh) -> NsideError {
    let n = mesh.positions.len();
    let mut edges: HashMap<(usize, usize), usize> = HashMap::with_capacity(mesh.faces.len() * 3);
    for (face, f) in mesh.faces.iter().enumerate() {
        if f.iter().any(|&v| v >= n) {
            return NsideError::BadFace {
                face,
                detail: format!("vertex index out of range ({n} vertices)"),
            };
        }
        if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
            return NsideError::BadFace {
                face,
                detail: "repeats a vertex".into(),
            };
        }
        for k in 0..3 {
            let e = (f[k], f[(k + 1) % 3]);
            if let Some(other) = edges.insert(e, face) {
                return NsideError::NotManifold {
                    detail: format!(
                        "directed edge {}→{} is used by faces {other} and {face} (non-manifold or inconsistently oriented)",
                        e.0, e.1
                    ),
                };
            }
        }
    }
    // not reached: the fast check fails on exactly these cases
    NsideError::NotManifold {
        detail: "inconsistent faces".into(),
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
