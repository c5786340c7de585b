//! A small triangle mesh: tessellation of surfaces, boundary loops, one-rings, OBJ output.
//!
//! Faces are counter-clockwise seen from the side the normal points to. A surface is tessellated
//! on a parameter grid into two triangles per cell, oriented with S_u × S_v; the grid points of a
//! collapsed side (a pole) are merged into one vertex so that the mesh stays manifold.

use std::io::Write;

use crate::surface::BSplineSurface;
use crate::{Point3, Vector3};

/// Relative distance (against the surface size) under which the points of a side count as one
/// point: a side collapsed to a pole evaluates to the same point up to rounding, and a kernel
/// writes its control row to 10–16 digits. The one value of the workspace (g-continuity's
/// collapsed-side test uses it too).
pub const COLLAPSED_SIDE_RELATIVE: f64 = 1e-9;

/// An indexed triangle mesh.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TriMesh {
    /// vertex positions
    pub positions: Vec<Point3>,
    /// unit vertex normals (same length as positions; may be empty)
    pub normals: Vec<Vector3>,
    /// triangles as vertex indices, counter-clockwise
    pub faces: Vec<[usize; 3]>,
}

impl TriMesh {
    /// Tessellates `surface` on a uniform `nu × nv` parameter grid (both ≥ 2).
    pub fn from_surface(surface: &BSplineSurface, nu: usize, nv: usize) -> Self {
        let (nu, nv) = (nu.max(2), nv.max(2));
        let us = surface.knots_u().uniform_params(nu);
        let vs = surface.knots_v().uniform_params(nv);
        let ders = surface.eval_grid_derivatives(&us, &vs);
        let tol = COLLAPSED_SIDE_RELATIVE * surface.size();
        let grid = |a: usize, b: usize| a * nv + b;
        // vertex id of each grid point, merging collapsed sides
        let mut id: Vec<usize> = (0..nu * nv).collect();
        let collapsed = |cells: &[usize]| {
            cells
                .iter()
                .all(|&k| (ders[k].point - ders[cells[0]].point).norm() <= tol)
        };
        let sides: [Vec<usize>; 4] = [
            (0..nv).map(|b| grid(0, b)).collect(),
            (0..nv).map(|b| grid(nu - 1, b)).collect(),
            (0..nu).map(|a| grid(a, 0)).collect(),
            (0..nu).map(|a| grid(a, nv - 1)).collect(),
        ];
        for cells in &sides {
            if collapsed(cells) {
                let root = cells.iter().map(|&k| id[k]).min().unwrap_or(cells[0]);
                for &k in cells {
                    id[k] = root;
                }
            }
        }
        // compact the ids
        let mut remap = vec![usize::MAX; nu * nv];
        let mut positions = Vec::new();
        let mut normals = Vec::new();
        for k in 0..nu * nv {
            let root = id[k];
            if remap[root] == usize::MAX {
                remap[root] = positions.len();
                positions.push(ders[root].point);
                normals.push(ders[root].normal().unwrap_or_else(Vector3::zeros));
            }
        }
        let vid = |a: usize, b: usize| remap[id[grid(a, b)]];
        let mut faces = Vec::with_capacity(2 * (nu - 1) * (nv - 1));
        for a in 0..nu - 1 {
            for b in 0..nv - 1 {
                let (p00, p10, p11, p01) =
                    (vid(a, b), vid(a + 1, b), vid(a + 1, b + 1), vid(a, b + 1));
                for f in [[p00, p10, p11], [p00, p11, p01]] {
                    if f[0] != f[1] && f[1] != f[2] && f[0] != f[2] {
                        faces.push(f);
                    }
                }
            }
        }
        let mut mesh = Self {
            positions,
            normals,
            faces,
        };
        mesh.fill_missing_normals();
        mesh
    }

    /// Replaces zero normals (singular surface points) by the area-weighted face normals around.
    pub fn fill_missing_normals(&mut self) {
        if self.normals.len() != self.positions.len() {
            self.normals = vec![Vector3::zeros(); self.positions.len()];
        }
        let mut acc = vec![Vector3::zeros(); self.positions.len()];
        for f in &self.faces {
            let n = self.face_normal_area(f);
            for &v in f {
                acc[v] += n;
            }
        }
        for (n, a) in self.normals.iter_mut().zip(acc) {
            if n.norm_squared() == 0.0 {
                *n = a.try_normalize(0.0).unwrap_or_else(Vector3::zeros);
            }
        }
    }

    /// (b − a) × (c − a): twice the area times the unit normal of a face.
    pub fn face_normal_area(&self, f: &[usize; 3]) -> Vector3 {
        let (a, b, c) = (
            self.positions[f[0]],
            self.positions[f[1]],
            self.positions[f[2]],
        );
        (b - a).cross(&(c - a))
    }

    /// Boundary loops: chains of edges used by one face only, each in face orientation.
    pub fn boundary_loops(&self) -> Vec<Vec<usize>> {
        use std::collections::{BTreeMap, HashSet};
        let mut directed: HashSet<(usize, usize)> = HashSet::new();
        for f in &self.faces {
            for k in 0..3 {
                directed.insert((f[k], f[(k + 1) % 3]));
            }
        }
        let mut next: BTreeMap<usize, usize> = BTreeMap::new();
        for &(a, b) in &directed {
            if !directed.contains(&(b, a)) {
                next.insert(a, b);
            }
        }
        let mut loops = Vec::new();
        while let Some((&start, _)) = next.iter().next() {
            let mut lp = vec![start];
            let mut cur = next.remove(&start).unwrap_or(start);
            while cur != start {
                lp.push(cur);
                match next.remove(&cur) {
                    Some(n) => cur = n,
                    None => break,
                }
            }
            loops.push(lp);
        }
        loops
    }

    /// The neighbours of every vertex in rotational order (counter-clockwise around the
    /// normal); for boundary vertices the ring starts and ends on the boundary.
    pub fn one_rings(&self) -> Vec<Vec<usize>> {
        let n = self.positions.len();
        let mut wedges: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
        for f in &self.faces {
            for k in 0..3 {
                wedges[f[k]].push((f[(k + 1) % 3], f[(k + 2) % 3]));
            }
        }
        wedges
            .into_iter()
            .map(|w| {
                if w.is_empty() {
                    return Vec::new();
                }
                // start at a wedge whose first vertex ends no other wedge (boundary), else anywhere
                let start = w
                    .iter()
                    .position(|&(b, _)| !w.iter().any(|&(_, c)| c == b))
                    .unwrap_or(0);
                let mut ring = vec![w[start].0];
                let mut used = vec![false; w.len()];
                let mut cur = start;
                loop {
                    used[cur] = true;
                    let c = w[cur].1;
                    match w
                        .iter()
                        .enumerate()
                        .position(|(k, &(b, _))| !used[k] && b == c)
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
            })
            .collect()
    }

    /// Parses Wavefront OBJ text: `v` records in order (so vertex indices stay those of the
    /// file, 0-based here), `f` records with 1-based or negative indices (`a`, `a/t`, `a/t/n`,
    /// `a//n`), polygons split into fans. Other records are ignored.
    pub fn from_obj_str(text: &str) -> crate::Result<Self> {
        let err = |line: usize, detail: String| crate::Error::Format {
            detail: format!("OBJ line {line}: {detail}"),
        };
        let mut mesh = TriMesh::default();
        let mut polygon: Vec<usize> = Vec::with_capacity(8);
        for (k, raw) in text.lines().enumerate() {
            let line = k + 1;
            let mut it = raw.split_whitespace();
            match it.next() {
                Some("v") => {
                    let mut c = [0.0; 3];
                    for slot in &mut c {
                        let field = it
                            .next()
                            .ok_or_else(|| err(line, "a vertex needs three coordinates".into()))?;
                        *slot = field
                            .parse::<f64>()
                            .ok()
                            .filter(|x| x.is_finite())
                            .ok_or_else(|| {
                                err(line, format!("{field:?} is not a finite number"))
                            })?;
                        if slot.abs() > crate::MAX_COORDINATE {
                            return Err(err(
                                line,
                                format!(
                                    "coordinate {field} is beyond the bound of {:e}",
                                    crate::MAX_COORDINATE
                                ),
                            ));
                        }
                    }
                    mesh.positions.push(Point3::new(c[0], c[1], c[2]));
                }
                Some("f") => {
                    polygon.clear();
                    for field in it {
                        let first = field.split('/').next().unwrap_or("");
                        let index: i64 = first
                            .parse()
                            .map_err(|_| err(line, format!("{field:?} is not a vertex index")))?;
                        let n = mesh.positions.len() as i64;
                        let resolved = if index > 0 { index - 1 } else { n + index };
                        if index == 0 || resolved < 0 || resolved >= n {
                            return Err(err(
                                line,
                                format!(
                                    "vertex index {index} is out of range ({n} vertices so far)"
                                ),
                            ));
                        }
                        polygon.push(resolved as usize);
                    }
                    if polygon.len() < 3 {
                        return Err(err(
                            line,
                            format!("a face needs at least 3 vertices, got {}", polygon.len()),
                        ));
                    }
                    for j in 1..polygon.len() - 1 {
                        mesh.faces.push([polygon[0], polygon[j], polygon[j + 1]]);
                    }
                }
                _ => {}
            }
        }
        Ok(mesh)
    }

    /// Writes the mesh as Wavefront OBJ (positions, normals when present, 1-based faces).
    pub fn write_obj(&self, out: &mut impl Write) -> std::io::Result<()> {
        for p in &self.positions {
            writeln!(out, "v {} {} {}", p.x, p.y, p.z)?;
        }
        let with_normals = self.normals.len() == self.positions.len();
        if with_normals {
            for n in &self.normals {
                writeln!(out, "vn {} {} {}", n.x, n.y, n.z)?;
            }
        }
        for f in &self.faces {
            if with_normals {
                writeln!(
                    out,
                    "f {0}//{0} {1}//{1} {2}//{2}",
                    f[0] + 1,
                    f[1] + 1,
                    f[2] + 1
                )?;
            } else {
                writeln!(out, "f {} {} {}", f[0] + 1, f[1] + 1, f[2] + 1)?;
            }
        }
        Ok(())
    }
}
