//! The trimmed region: mesh checks, the outer boundary loop, its best-fit plane and the discrete
//! geodesic curvature of the loop.
//!
//! The region must be a connected, orientable triangle manifold with boundary (\[VV18\] §"Algorithm
//! for automatic labeling": "manifold-with-boundary, orientable, possibly multiply connected").
//! Boundary loops run in face orientation, so the outer loop is counter-clockwise seen from the
//! side the face normals point to and the region lies on its left.
//!
//! Discrete geodesic curvature: at a boundary vertex i with interior angle α_i = Σ (angles of the
//! faces at i), the turning angle is τ_i = π − α_i, the integral of κ_g over the dual boundary
//! arc (Gauss–Bonnet). τ > 0 is a convex (left) turn, τ < 0 a concave one. It is intrinsic, so it
//! holds on curved regions, where the angle of a projection would not.
//!
//! The best-fit plane (principal axes of the vertices, normal oriented with the faces) gives 2D
//! coordinates for the constructions of the labeling (extensions, virtual corners) and the SVG
//! drawing. The outer loop is the loop enclosing the largest area in that plane.
//!
//! # Tolerance
//! A face counts as degenerate when its area is below [`DEGENERATE_AREA_REL`] × D², D the
//! bounding-box diagonal of the mesh (relative, so independent of units).

use std::collections::HashMap;

use nalgebra::{Matrix3, SymmetricEigen, Vector2};
use nurbs_core::{Point3, TriMesh, Vector3};

use crate::error::{LabelError, Result};

/// Face area (relative to the squared bounding-box diagonal) below which a triangle is
/// degenerate: 1e-14 is ~100 rounding units of an area computed from coordinates of size D, far
/// below any real triangle (a 10⁶-face mesh has faces of ~1e-6 D²).
pub const DEGENERATE_AREA_REL: f64 = 1e-14;

/// A 2D point or vector in the best-fit plane.
pub type Point2 = Vector2<f64>;

/// The best-fit plane of the region: origin (centroid), orthonormal axes, normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneFrame {
    /// centroid of the used vertices
    pub origin: Point3,
    /// first principal axis (largest spread)
    pub e1: Vector3,
    /// second axis, normal × e1
    pub e2: Vector3,
    /// unit normal, on the side the faces point to on average
    pub normal: Vector3,
}

impl PlaneFrame {
    /// Coordinates of `p` in the plane.
    pub fn project(&self, p: &Point3) -> Point2 {
        let d = p - self.origin;
        Point2::new(d.dot(&self.e1), d.dot(&self.e2))
    }
    /// Direction `d` in the plane (not normalized).
    pub fn project_dir(&self, d: &Vector3) -> Point2 {
        Point2::new(d.dot(&self.e1), d.dot(&self.e2))
    }
}

/// A validated region with its outer boundary loop.
#[derive(Debug, Clone)]
pub struct Region<'a> {
    /// the mesh
    pub mesh: &'a TriMesh,
    /// outer loop vertex indices, counter-clockwise (region on the left)
    pub outer: Vec<usize>,
    /// the other boundary loops (holes)
    pub holes: Vec<Vec<usize>>,
    /// best-fit plane
    pub frame: PlaneFrame,
    /// bounding-box diagonal of the used vertices (length units)
    pub size: f64,
    /// τ at each position of `outer` (radians)
    pub turning: Vec<f64>,
    /// `outer` in plane coordinates
    pub outer_2d: Vec<Point2>,
    /// cumulative arc length along `outer`, `outer.len() + 1` entries (closing edge last)
    pub arc: Vec<f64>,
    /// position of each vertex in `outer` (usize::MAX when not on it)
    pub loop_position: Vec<usize>,
    /// which vertices are used by a face
    pub used: Vec<bool>,
}

fn find(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

/// Signed area of a closed 2D polygon (positive when counter-clockwise).
pub fn signed_area(poly: &[Point2]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            a.x * b.y - b.x * a.y
        })
        .sum::<f64>()
        / 2.0
}

impl<'a> Region<'a> {
    /// Validates `mesh` and extracts its outer loop. Errors name the offending face, edge or
    /// vertex: [`LabelError::NonFiniteVertex`], [`LabelError::FaceIndexOutOfRange`],
    /// [`LabelError::DegenerateTriangle`], [`LabelError::NonManifoldEdge`],
    /// [`LabelError::NonOrientable`], [`LabelError::NonManifoldVertex`],
    /// [`LabelError::NoBoundary`], [`LabelError::Disconnected`], [`LabelError::EmptyMesh`].
    pub fn new(mesh: &'a TriMesh) -> Result<Self> {
        let used = used_vertices(mesh)?;
        let nv = mesh.positions.len();
        let (mut lo, mut hi) = (Vector3::repeat(f64::MAX), Vector3::repeat(f64::MIN));
        for (p, _) in mesh.positions.iter().zip(&used).filter(|(_, u)| **u) {
            lo = lo.inf(&p.coords);
            hi = hi.sup(&p.coords);
        }
        let size = (hi - lo).norm();
        check_face_areas(mesh, DEGENERATE_AREA_REL * size * size)?;
        check_manifold(mesh)?;
        check_connected(mesh, &used)?;
        let frame = best_fit_plane(mesh, &used);
        let (outer, holes) = outer_loop(mesh, &frame)?;
        let turning = turning_angles(mesh, &outer);
        let outer_2d: Vec<Point2> = outer
            .iter()
            .map(|&v| frame.project(&mesh.positions[v]))
            .collect();
        let n = outer.len();
        let mut arc = Vec::with_capacity(n + 1);
        arc.push(0.0);
        for i in 0..n {
            let d = (mesh.positions[outer[(i + 1) % n]] - mesh.positions[outer[i]]).norm();
            arc.push(arc[i] + d);
        }
        let mut loop_position = vec![usize::MAX; nv];
        for (i, &v) in outer.iter().enumerate() {
            loop_position[v] = i;
        }
        Ok(Self {
            mesh,
            outer,
            holes,
            frame,
            size,
            turning,
            outer_2d,
            arc,
            loop_position,
            used,
        })
    }

    /// Number of vertices of the outer loop.
    pub fn loop_len(&self) -> usize {
        self.outer.len()
    }

    /// Perimeter of the outer loop.
    pub fn perimeter(&self) -> f64 {
        self.arc[self.outer.len()]
    }

    /// Position of the 3D point of outer-loop position `i` (taken modulo the loop length).
    pub fn loop_point(&self, i: usize) -> Point3 {
        self.mesh.positions[self.outer[i % self.outer.len()]]
    }

    /// Winding number of the outer loop around `q` (plane coordinates): non-zero inside.
    pub fn winding(&self, q: &Point2) -> i32 {
        let poly = &self.outer_2d;
        let n = poly.len();
        let mut w = 0;
        for i in 0..n {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            let cross = (b - a).perp(&(q - a));
            if a.y <= q.y {
                if b.y > q.y && cross > 0.0 {
                    w += 1;
                }
            } else if b.y <= q.y && cross < 0.0 {
                w -= 1;
            }
        }
        w
    }

    /// Distance in the plane from `q` to the outer loop polyline.
    pub fn distance_to_loop(&self, q: &Point2) -> f64 {
        let poly = &self.outer_2d;
        let n = poly.len();
        (0..n)
            .map(|i| {
                let (a, b) = (poly[i], poly[(i + 1) % n]);
                let ab = b - a;
                let t =
                    ((q - a).dot(&ab) / ab.norm_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
                (a + ab * t - q).norm()
            })
            .fold(f64::INFINITY, f64::min)
    }
}

/// Which vertices a face uses; errors for an empty mesh, a non-finite vertex or a face index
/// out of range.
fn used_vertices(mesh: &TriMesh) -> Result<Vec<bool>> {
    if mesh.faces.is_empty() {
        return Err(LabelError::EmptyMesh);
    }
    let nv = mesh.positions.len();
    if let Some(vertex) = mesh
        .positions
        .iter()
        .position(|p| !p.coords.iter().all(|c| c.is_finite()))
    {
        return Err(LabelError::NonFiniteVertex { vertex });
    }
    let mut used = vec![false; nv];
    for (face, f) in mesh.faces.iter().enumerate() {
        for &vertex in f {
            if vertex >= nv {
                return Err(LabelError::FaceIndexOutOfRange {
                    face,
                    vertex,
                    count: nv,
                });
            }
            used[vertex] = true;
        }
    }
    Ok(used)
}

/// The first face whose area is not above `threshold` (model units²) is an error.
fn check_face_areas(mesh: &TriMesh, threshold: f64) -> Result<()> {
    for (face, f) in mesh.faces.iter().enumerate() {
        let area = if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
            0.0
        } else {
            0.5 * mesh.face_normal_area(f).norm()
        };
        if !(area > threshold) {
            return Err(LabelError::DegenerateTriangle {
                face,
                area,
                threshold,
            });
        }
    }
    Ok(())
}

/// Errors for an edge of more than two faces, an edge used twice in one direction, a vertex
/// with more than one outgoing boundary edge, or no boundary at all.
fn check_manifold(mesh: &TriMesh) -> Result<()> {
    // edges: undirected use count and directed duplicates
    let mut undirected: HashMap<(usize, usize), usize> = HashMap::new();
    let mut directed: HashMap<(usize, usize), usize> = HashMap::new();
    for f in &mesh.faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            *undirected.entry((a.min(b), a.max(b))).or_default() += 1;
            *directed.entry((a, b)).or_default() += 1;
        }
    }
    let mut bad: Vec<_> = undirected.iter().filter(|(_, c)| **c > 2).collect();
    bad.sort();
    if let Some(&(&(a, b), &faces)) = bad.first() {
        return Err(LabelError::NonManifoldEdge { a, b, faces });
    }
    let mut twice: Vec<_> = directed.iter().filter(|(_, c)| **c > 1).collect();
    twice.sort();
    if let Some(&(&(a, b), _)) = twice.first() {
        return Err(LabelError::NonOrientable { a, b });
    }
    let mut out_degree = vec![0usize; mesh.positions.len()];
    for &(a, b) in directed.keys() {
        if !directed.contains_key(&(b, a)) {
            out_degree[a] += 1;
        }
    }
    if let Some(vertex) = out_degree.iter().position(|&d| d > 1) {
        return Err(LabelError::NonManifoldVertex {
            vertex,
            boundary_edges: out_degree[vertex],
        });
    }
    if out_degree.iter().all(|&d| d == 0) {
        return Err(LabelError::NoBoundary);
    }
    Ok(())
}

/// An error when the `used` vertices fall into more than one component through the faces.
fn check_connected(mesh: &TriMesh, used: &[bool]) -> Result<()> {
    let nv = mesh.positions.len();
    let mut parent: Vec<usize> = (0..nv).collect();
    for f in &mesh.faces {
        let r0 = find(&mut parent, f[0]);
        for &v in &f[1..] {
            let r = find(&mut parent, v);
            parent[r] = r0;
        }
    }
    let mut roots: Vec<usize> = (0..nv)
        .filter(|&v| used[v])
        .map(|v| find(&mut parent, v))
        .collect();
    roots.sort_unstable();
    roots.dedup();
    if roots.len() > 1 {
        return Err(LabelError::Disconnected {
            components: roots.len(),
        });
    }
    Ok(())
}

/// The boundary loop enclosing the largest area in the plane of `frame`, and the others.
fn outer_loop(mesh: &TriMesh, frame: &PlaneFrame) -> Result<(Vec<usize>, Vec<Vec<usize>>)> {
    let mut loops = mesh.boundary_loops();
    let areas: Vec<f64> = loops
        .iter()
        .map(|l| {
            let poly: Vec<Point2> = l
                .iter()
                .map(|&v| frame.project(&mesh.positions[v]))
                .collect();
            signed_area(&poly).abs()
        })
        .collect();
    let best = (0..loops.len())
        .max_by(|&a, &b| areas[a].total_cmp(&areas[b]).then(b.cmp(&a)))
        .ok_or(LabelError::NoBoundary)?;
    let outer = loops.swap_remove(best);
    Ok((outer, loops))
}

/// The turning angle τ = π − α at every vertex of `outer`, α the sum of its faces' angles.
fn turning_angles(mesh: &TriMesh, outer: &[usize]) -> Vec<f64> {
    let mut angle_sum = vec![0.0; mesh.positions.len()];
    for f in &mesh.faces {
        for k in 0..3 {
            let p = mesh.positions[f[k]];
            let a = mesh.positions[f[(k + 1) % 3]] - p;
            let b = mesh.positions[f[(k + 2) % 3]] - p;
            angle_sum[f[k]] += a.angle(&b);
        }
    }
    outer
        .iter()
        .map(|&v| std::f64::consts::PI - angle_sum[v])
        .collect()
}

/// Principal axes of the used vertices; the normal is turned to agree with the faces.
fn best_fit_plane(mesh: &TriMesh, used: &[bool]) -> PlaneFrame {
    let pts: Vec<&Point3> = mesh
        .positions
        .iter()
        .zip(used)
        .filter(|(_, u)| **u)
        .map(|(p, _)| p)
        .collect();
    let count = pts.len().max(1) as f64;
    let c = pts.iter().fold(Vector3::zeros(), |s, p| s + p.coords) / count;
    let mut cov = Matrix3::zeros();
    for p in &pts {
        let d = p.coords - c;
        cov += d * d.transpose();
    }
    let eig = SymmetricEigen::new(cov);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let e1: Vector3 = eig.eigenvectors.column(order[0]).into_owned();
    let mut normal: Vector3 = eig.eigenvectors.column(order[2]).into_owned();
    let face_sum = mesh
        .faces
        .iter()
        .fold(Vector3::zeros(), |s, f| s + mesh.face_normal_area(f));
    if face_sum.dot(&normal) < 0.0 {
        normal = -normal;
    }
    let e2 = normal.cross(&e1);
    PlaneFrame {
        origin: Point3::from(c),
        e1,
        e2,
        normal,
    }
}
