//! Sampling a central split into one triangle mesh for discrete fairing (\[SV\] §3.4, Fig. 3).
//!
//! Quad k is sampled on the grid u_a × v_b of its knot vectors' span samples (`samples_per_span`
//! per span plus the end), so every knot span holds data for the refit. Each grid cell
//! (a, b)–(a+1, b+1) gives the triangles [(a,b), (a+1,b), (a+1,b+1)] and [(a,b), (a+1,b+1),
//! (a,b+1)], counter-clockwise about S_u × S_v. Vertices are welded, not duplicated: the samples
//! of internal curve I_k (side `U1` of quad k, side `V1` of quad k + 1, same parameters because
//! the knot vectors agree) and the centre exist once.
//!
//! Wings: for a side k with a neighbour N (a surface and its `Side` that touches boundary curve
//! c_k), `wing_rows` rows of N are added beyond the boundary. Each boundary vertex p is projected
//! onto N's side curve (parameter t), and row r takes N at the side parameter t and the cross
//! parameter moved inward by r·h(t), h(t) = s / |∂N/∂cross(t)|, s the mean boundary edge length
//! of side k: the rows are about one boundary spacing apart, so the fixed rings carry N's
//! tangent plane (and curvature) into the umbrella² stencils next to the boundary.

use nurbs_core::{
    BSplineSurface, Direction, Point3, ProjectionParams, Side, TriMesh, Vector3, project_to_curve,
};

use crate::error::{NsideError, Result};
use crate::split::{MAX_SIDES, MIN_SIDES};

/// Distance between rows that must coincide (shared internal curves, corners), relative to the
/// size of the quads: rounding of one evaluation, far below any modelling tolerance.
pub const SHARED_ROW_REL: f64 = 1e-9;

/// A neighbour surface across one side of the n-sided hole.
#[derive(Debug, Clone, Copy)]
pub struct Neighbour<'a> {
    /// the surface
    pub surface: &'a BSplineSurface,
    /// its side that lies on the hole's boundary curve
    pub side: Side,
}

/// Settings of the sampling.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SamplingParams {
    /// Samples per knot span of each quad direction. Default 8: with the default 4 spans this
    /// gives 33 × 33 samples per quad; with 4 the normals along the boundary of a paraboloid
    /// hole deviate up to 0.24° from the neighbours' (0.08° with 8, tests/nsided.rs).
    pub samples_per_span: usize,
    /// Rows sampled from each neighbour beyond the boundary. Default 2: the umbrella² stencil of
    /// a vertex next to the boundary reaches two rings out (\[K97\] §3).
    pub wing_rows: usize,
}

impl Default for SamplingParams {
    fn default() -> Self {
        Self {
            samples_per_span: 8,
            wing_rows: 2,
        }
    }
}

/// Where a mesh vertex comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum VertexOrigin {
    /// a sample of quad `quad` at (u, v) (welded vertices name their owner: for internal curve
    /// I_k quad k, for the centre quad 0)
    Quad {
        /// quad index
        quad: usize,
        /// parameter u
        u: f64,
        /// parameter v
        v: f64,
    },
    /// a sample of the neighbour across side `side`, `row` ≥ 1 rows beyond the boundary, at the
    /// neighbour's parameters (u, v)
    Wing {
        /// side (boundary curve) index
        side: usize,
        /// row counted from the boundary
        row: usize,
        /// neighbour parameter u
        u: f64,
        /// neighbour parameter v
        v: f64,
    },
}

/// The sample grid of one quad: parameters and the mesh vertex of every sample.
#[derive(Debug, Clone, PartialEq)]
pub struct QuadGrid {
    /// sample parameters in u
    pub us: Vec<f64>,
    /// sample parameters in v
    pub vs: Vec<f64>,
    /// mesh vertex of sample (a, b) at index a · vs.len() + b
    pub vertices: Vec<usize>,
}

/// A sampled corner: the mesh and what every vertex is.
#[derive(Debug, Clone, PartialEq)]
pub struct SampledCorner {
    /// the welded triangle mesh (quads and wings)
    pub mesh: TriMesh,
    /// origin of every mesh vertex
    pub origins: Vec<VertexOrigin>,
    /// vertices that must stay fixed: the boundary of the n-sided patch and all wing vertices
    pub fixed: Vec<bool>,
    /// vertices on the boundary of the n-sided patch (the outer quad sides)
    pub patch_boundary: Vec<bool>,
    /// the sample grid of every quad
    pub grids: Vec<QuadGrid>,
    /// the mesh vertex of the centre
    pub centre: usize,
    /// boundary vertices of every side k in loop order, V_k … M_k … V_{k+1}
    pub side_chains: Vec<Vec<usize>>,
    /// unit normal of the boundary loop (Newell's formula over the side chains)
    pub loop_normal: Vector3,
}

impl SampledCorner {
    /// The mesh projected onto the plane through its centroid perpendicular to the loop normal:
    /// the flat layout from which [`crate::UmbrellaWeights::MeanValue`] weights are taken.
    pub fn flat_layout(&self) -> Vec<Point3> {
        let pts = &self.mesh.positions;
        let c = pts.iter().map(|p| p.coords).sum::<Vector3>() / pts.len().max(1) as f64;
        let n = self.loop_normal;
        pts.iter().map(|p| p - (p.coords - c).dot(&n) * n).collect()
    }
}

/// Checks that `quads` form a central split in the convention of [`crate::split`]: 3…8 quads,
/// knot vectors in v of quad k equal to those in u of quad k + 1, shared rows and corners equal
/// within [`SHARED_ROW_REL`] × size.
pub fn check_quads(quads: &[BSplineSurface]) -> Result<()> {
    let n = quads.len();
    if !(MIN_SIDES..=MAX_SIDES).contains(&n) {
        return Err(NsideError::SideCount {
            count: n,
            min: MIN_SIDES,
            max: MAX_SIDES,
        });
    }
    let size = quads.iter().map(|q| q.size()).fold(0.0, f64::max);
    let tol = SHARED_ROW_REL * size;
    for k in 0..n {
        let q = &quads[k];
        if q.is_rational() {
            return Err(NsideError::BadQuad {
                quad: k,
                detail: "rational quads are not supported".into(),
            });
        }
        let next = &quads[(k + 1) % n];
        if q.knots_v() != next.knots_u() {
            return Err(NsideError::BadQuad {
                quad: k,
                detail: format!(
                    "its v knot vector differs from the u knot vector of quad {}",
                    (k + 1) % n
                ),
            });
        }
        let (nu, nv) = (q.num_u(), q.num_v());
        let nv_next = next.num_v();
        for j in 0..nv {
            let d = (q.control_point(nu - 1, j) - next.control_point(j, nv_next - 1)).norm();
            if !(d <= tol) {
                return Err(NsideError::BadQuad {
                    quad: k,
                    detail: format!(
                        "internal row u1[{j}] is {d} away from row v1[{j}] of quad {}",
                        (k + 1) % n
                    ),
                });
            }
        }
        let centre = quads[0].control_point(quads[0].num_u() - 1, quads[0].num_v() - 1);
        let d = (q.control_point(nu - 1, nv - 1) - centre).norm();
        if !(d <= tol) {
            return Err(NsideError::BadQuad {
                quad: k,
                detail: format!("its corner (1, 1) is {d} away from the centre of quad 0"),
            });
        }
        let vnext = next.control_point(0, 0);
        let end = next.control_point(0, nv_next - 1);
        let d = (q.control_point(nu - 1, 0) - end).norm();
        if !(d <= tol) || !vnext.coords.iter().all(|c| c.is_finite()) {
            return Err(NsideError::BadQuad {
                quad: k,
                detail: format!(
                    "its corner (1, 0) is {d} away from corner (0, 1) of quad {}",
                    (k + 1) % n
                ),
            });
        }
    }
    Ok(())
}

/// Samples the quads of a central split (and the wings of the neighbours given per side,
/// `neighbours.len()` = number of quads) into one welded triangle mesh.
pub fn sample_quads(
    quads: &[BSplineSurface],
    neighbours: &[Option<Neighbour<'_>>],
    params: &SamplingParams,
) -> Result<SampledCorner> {
    check_quads(quads)?;
    let n = quads.len();
    if neighbours.len() != n {
        return Err(NsideError::CountMismatch {
            what: "neighbours per side",
            expected: n,
            got: neighbours.len(),
        });
    }
    if params.samples_per_span == 0 {
        return Err(NsideError::BadParam {
            name: "samples_per_span",
            value: 0.0,
            detail: "must be at least 1",
        });
    }
    let (mut positions, mut origins, mut grids) = sample_grids(quads, params.samples_per_span);
    let centre = positions.len();
    let q0 = &quads[0];
    let (u1, v1) = (q0.domain_u().1, q0.domain_v().1);
    positions.push(q0.point(u1, v1));
    origins.push(VertexOrigin::Quad {
        quad: 0,
        u: u1,
        v: v1,
    });
    weld_internal_curves(&mut grids, centre);
    let mut faces = grid_faces(&grids);
    let side_chains = side_chains(&grids);
    let mut patch_boundary = vec![false; positions.len()];
    for &v in side_chains.iter().flatten() {
        patch_boundary[v] = true;
    }
    let loop_normal = newell_normal(&positions, &side_chains);
    let mut fixed = patch_boundary.clone();
    for (k, nb) in neighbours.iter().enumerate() {
        let Some(nb) = nb else { continue };
        add_wing(
            k,
            nb,
            &side_chains[k],
            params.wing_rows,
            &mut positions,
            &mut origins,
            &mut fixed,
            &mut faces,
        )?;
    }
    let mut mesh = TriMesh {
        positions,
        normals: Vec::new(),
        faces,
    };
    mesh.fill_missing_normals();
    patch_boundary.resize(mesh.positions.len(), false);
    Ok(SampledCorner {
        mesh,
        origins,
        fixed,
        patch_boundary,
        grids,
        centre,
        side_chains,
        loop_normal,
    })
}

/// Each quad's own vertices, `samples_per_span` per knot span: every sample (a, b) but those of
/// its V1 row (the U1 column, internal curve I_k, included; the centre not), with their origins
/// and the quads' grids (V1 rows left unset).
fn sample_grids(
    quads: &[BSplineSurface],
    samples_per_span: usize,
) -> (Vec<Point3>, Vec<VertexOrigin>, Vec<QuadGrid>) {
    let mut positions: Vec<Point3> = Vec::new();
    let mut origins = Vec::new();
    let mut grids: Vec<QuadGrid> = Vec::with_capacity(quads.len());
    for (k, q) in quads.iter().enumerate() {
        let us = q.knots_u().span_samples(samples_per_span);
        let vs = q.knots_v().span_samples(samples_per_span);
        let (mu, mv) = (us.len(), vs.len());
        let mut vertices = vec![usize::MAX; mu * mv];
        let mut eval = q.evaluator();
        for a in 0..mu {
            for b in 0..mv - 1 {
                vertices[a * mv + b] = positions.len();
                positions.push(eval.point(us[a], vs[b]));
                origins.push(VertexOrigin::Quad {
                    quad: k,
                    u: us[a],
                    v: vs[b],
                });
            }
        }
        grids.push(QuadGrid { us, vs, vertices });
    }
    (positions, origins, grids)
}

/// Sets the V1 row of quad k to the vertices of the U1 column of quad k − 1, ending at
/// `centre`.
fn weld_internal_curves(grids: &mut [QuadGrid], centre: usize) {
    let n = grids.len();
    for k in 0..n {
        let prev = (k + n - 1) % n;
        let (mu, mv) = (grids[k].us.len(), grids[k].vs.len());
        let pmv = grids[prev].vs.len();
        for a in 0..mu {
            grids[k].vertices[a * mv + mv - 1] = if a + 1 == mu {
                centre
            } else {
                grids[prev].vertices[(grids[prev].us.len() - 1) * pmv + a]
            };
        }
    }
}

/// Two triangles per cell of every grid.
fn grid_faces(grids: &[QuadGrid]) -> Vec<[usize; 3]> {
    let mut faces = Vec::new();
    for g in grids {
        let mv = g.vs.len();
        for a in 0..g.us.len() - 1 {
            for b in 0..mv - 1 {
                let p00 = g.vertices[a * mv + b];
                let p10 = g.vertices[(a + 1) * mv + b];
                let p11 = g.vertices[(a + 1) * mv + b + 1];
                let p01 = g.vertices[a * mv + b + 1];
                faces.push([p00, p10, p11]);
                faces.push([p00, p11, p01]);
            }
        }
    }
    faces
}

/// The boundary vertices of every side k in loop order: quad k's V0 row (V_k → M_k), then quad
/// k + 1's U0 column backwards (M_k → V_{k+1}).
fn side_chains(grids: &[QuadGrid]) -> Vec<Vec<usize>> {
    let n = grids.len();
    let mut side_chains = Vec::with_capacity(n);
    for k in 0..n {
        let next = (k + 1) % n;
        let g = &grids[k];
        let mv = g.vs.len();
        let mut chain: Vec<usize> = (0..g.us.len()).map(|a| g.vertices[a * mv]).collect();
        let h = &grids[next];
        chain.extend((0..h.vs.len() - 1).rev().map(|b| h.vertices[b]));
        side_chains.push(chain);
    }
    side_chains
}

/// The unit normal of the boundary loop by Newell's formula (+z when it vanishes).
fn newell_normal(positions: &[Point3], side_chains: &[Vec<usize>]) -> Vector3 {
    let mut newell = Vector3::zeros();
    for chain in side_chains {
        for w in chain.windows(2) {
            newell += positions[w[0]].coords.cross(&positions[w[1]].coords);
        }
    }
    newell.try_normalize(0.0).unwrap_or_else(Vector3::z)
}

/// Parameters of neighbour `nb` at the side parameter `t` moved `offset` (parameter units)
/// inward across its side.
pub(crate) fn neighbour_params(nb: &Neighbour<'_>, t: f64, offset: f64) -> (f64, f64) {
    let s = nb.surface;
    let (u, v) = nb.side.params(s, t);
    let (u, v) = match nb.side {
        Side::U0 => (u + offset, v),
        Side::U1 => (u - offset, v),
        Side::V0 => (u, v + offset),
        Side::V1 => (u, v - offset),
    };
    (s.knots_u().clamp_param(u), s.knots_v().clamp_param(v))
}

/// Side parameters of the points of `chain` on the side curve of `nb`.
pub(crate) fn side_params(
    nb: &Neighbour<'_>,
    points: impl Iterator<Item = Point3>,
) -> Result<Vec<f64>> {
    let s = nb.surface;
    let curve = s.isocurve(nb.side.cross_direction(), nb.side.boundary_param(s))?;
    let proj = ProjectionParams::default();
    Ok(points
        .map(|p| project_to_curve(&curve, &p, &proj).t)
        .collect())
}

fn add_wing(
    side: usize,
    nb: &Neighbour<'_>,
    chain: &[usize],
    rows: usize,
    positions: &mut Vec<Point3>,
    origins: &mut Vec<VertexOrigin>,
    fixed: &mut Vec<bool>,
    faces: &mut Vec<[usize; 3]>,
) -> Result<()> {
    if rows == 0 {
        return Ok(());
    }
    let spacing = chain
        .windows(2)
        .map(|w| (positions[w[1]] - positions[w[0]]).norm())
        .sum::<f64>()
        / (chain.len() - 1) as f64;
    let ts = side_params(nb, chain.iter().map(|&v| positions[v]))?;
    let mut eval = nb.surface.evaluator();
    let mut lower: Vec<usize> = chain.to_vec();
    for row in 1..=rows {
        let mut upper = Vec::with_capacity(chain.len());
        for &t in &ts {
            let (u0, v0) = neighbour_params(nb, t, 0.0);
            let d = eval.derivatives(u0, v0);
            let speed = match nb.side.cross_direction() {
                Direction::U => d.du.norm(),
                Direction::V => d.dv.norm(),
            };
            if !(speed > 0.0) || !speed.is_finite() {
                return Err(NsideError::BadQuad {
                    quad: side,
                    detail: format!("neighbour has no cross-boundary derivative at t = {t}"),
                });
            }
            let (u, v) = neighbour_params(nb, t, row as f64 * spacing / speed);
            upper.push(positions.len());
            positions.push(eval.point(u, v));
            origins.push(VertexOrigin::Wing { side, row, u, v });
            fixed.push(true);
        }
        for i in 0..chain.len() - 1 {
            faces.push([lower[i + 1], lower[i], upper[i]]);
            faces.push([lower[i + 1], upper[i], upper[i + 1]]);
        }
        lower = upper;
    }
    Ok(())
}
