//! Refitting the quads of a central split to a faired mesh (\[SV\] §3.4: "using the faired
//! n-sided mesh, we refit the quadrilateral surfaces, and fix the internal subdividing curves").
//!
//! 1. Internal curves first, as curves: I_k (side `U1` of quad k, knots in v) is fitted by least
//!    squares ([`nurbs_core::fit_curve`]) to the faired samples along it, with P₀ = M_k kept and the
//!    last point set to the faired centre C.
//! 2. Centre tangent plane: the plane through C whose normal n_c minimizes Σ_k ((P^k_{m−1} − C)·n_c)²
//!    (smallest eigenvector of the 3 × 3 scatter matrix, oriented like the quads) receives the
//!    second-to-last points P^k_{m−1}, so the end tangents of all internal curves are coplanar and
//!    the n quads share one normal at C.
//! 3. Each quad is fitted ([`nurbs_core::fit_surface`]) to the faired samples of its grid with the
//!    positional frame fixed: its outer rows keep the boundary halves, its rows on I_k and I_{k−1}
//!    are the curves of step 1, copied, so the shared rows are bit-identical.
//!
//! 4. Cross rows: the rows next to the internal curves (the cross-derivative functions that the
//!    later G1 step starts from) come from two independent fits, which disagree most near the
//!    centre, where the mesh has its valence-2n vertex. They are made consistent in the manner
//!    of \[SV\] §4.1: along I_k the common normal n(t) is the mean of both quads' normals, and each
//!    quad moves the inner points Q_j next to its two internal sides by the minimum-norm
//!    least-squares displacements w_j = β_j n(g_j) (along the common normal at the point's
//!    Greville abscissa g_j: the paper's fixed directions) with
//!    Σ_j N_j(t) (R_j − Q_j − w_j)·n(t) = 0 at
//!    [`ANGLE_SAMPLES`] parameters per side (R_j the curve's points; the cross derivative is a
//!    positive multiple of Σ_j N_j(t)(R_j − Q_j), so the constraint puts it in the plane ⊥ n(t)).
//!    Points of the other frames (next to the outer boundary, on the other internal curve) stay;
//!    the twist next to the centre belongs to both internal sides and takes both constraints.
//!
//! [`RefitReport::max_internal_angle_deg`] is the largest angle between the normals of quads k
//! and k + 1 along I_k, and [`RefitReport::max_boundary_angle_deg`] the largest angle between a
//! quad's normal and its neighbour's along the outer boundary.
//!
//! # Deviation from the paper
//! The paper leaves the refit unspecified; fitting the internal curves once and copying them is
//! what makes them shared exactly rather than within the fit error.

use nalgebra::{Matrix3, SymmetricEigen};
use nurbs_core::{
    BSplineCurve, BSplineSurface, ControlMask, FitParams, Frame, Point3, Side, Vector3, fit_curve,
    fit_surface,
};

use crate::error::{NsideError, Result};
use crate::sampling::{Neighbour, SampledCorner, neighbour_params, side_params};

/// Samples per internal curve or boundary half at which the normal angles are measured.
pub const ANGLE_SAMPLES: usize = 65;
/// |S_u × S_v| (relative to the squared size of the control net) below which a surface normal
/// counts as undefined and the sample is skipped in the angle measurements.
const SINGULAR_NORMAL_REL: f64 = 1e-20;

/// What the refit achieved.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RefitReport {
    /// largest distance between a faired sample and its quad at the sample's parameters (model
    /// units)
    pub max_error: f64,
    /// root mean square of those distances
    pub rms_error: f64,
    /// largest distance of a faired sample from its fitted internal curve (before the centre
    /// plane adjustment)
    pub curve_max_error: f64,
    /// largest move of a second-to-last internal control point onto the centre tangent plane
    pub centre_plane_move: f64,
    /// largest move of a control point next to an internal curve by the cross-row alignment
    pub cross_row_move: f64,
    /// largest angle (degrees) between the normals of adjacent quads along internal curves
    pub max_internal_angle_deg: f64,
    /// largest angle (degrees) between the lines of the quad and neighbour normals along the
    /// sides that have a neighbour (`None` when none has)
    pub max_boundary_angle_deg: Option<f64>,
}

/// Refits `quads` to the faired `positions` of `sampled` (the mesh made by
/// [`crate::sample_quads`] from these quads) as described in the module docs; `neighbours`
/// only serve the boundary angle measurement.
pub fn refit_quads(
    quads: &[BSplineSurface],
    sampled: &SampledCorner,
    positions: &[Point3],
    neighbours: &[Option<Neighbour<'_>>],
) -> Result<(Vec<BSplineSurface>, RefitReport)> {
    check_refit_input(quads, sampled, positions, neighbours)?;
    let fit = FitParams::default();
    let centre = positions[sampled.centre];
    let mut report = RefitReport::default();
    // 1. internal curves
    let (mut curves, curve_max_error) =
        fit_internal_curves(quads, sampled, positions, centre, &fit)?;
    report.curve_max_error = curve_max_error;
    // 2. centre tangent plane
    report.centre_plane_move = onto_centre_plane(&mut curves, centre);
    // 3. quads with the positional frame fixed
    let mut out = Vec::with_capacity(quads.len());
    for (k, q) in quads.iter().enumerate() {
        out.push(fit_quad(q, k, &curves, sampled, positions, &fit)?);
    }
    // 4. cross rows
    report.cross_row_move = align_cross_rows(&mut out);
    (report.max_error, report.rms_error) = sample_errors(&out, sampled, positions);
    report.max_internal_angle_deg = internal_angle_deg(&out);
    report.max_boundary_angle_deg = boundary_angle_deg(&out, neighbours)?;
    Ok((out, report))
}

/// Bad input unless there is one sample grid and one neighbour entry per quad and `positions`
/// are finite and as many as the mesh's vertices.
fn check_refit_input(
    quads: &[BSplineSurface],
    sampled: &SampledCorner,
    positions: &[Point3],
    neighbours: &[Option<Neighbour<'_>>],
) -> Result<()> {
    let n = quads.len();
    if sampled.grids.len() != n {
        return Err(NsideError::CountMismatch {
            what: "sample grids per quad",
            expected: n,
            got: sampled.grids.len(),
        });
    }
    if neighbours.len() != n {
        return Err(NsideError::CountMismatch {
            what: "neighbours per side",
            expected: n,
            got: neighbours.len(),
        });
    }
    if positions.len() != sampled.mesh.positions.len() {
        return Err(NsideError::CountMismatch {
            what: "faired positions",
            expected: sampled.mesh.positions.len(),
            got: positions.len(),
        });
    }
    if let Some(index) = positions
        .iter()
        .position(|p| !p.coords.iter().all(|c| c.is_finite()))
    {
        return Err(NsideError::NonFinite { index });
    }
    Ok(())
}

/// Step 1: each internal curve I_k fitted to the faired samples along side U1 of quad k, from
/// M_k to `centre`; with the largest fit error.
fn fit_internal_curves(
    quads: &[BSplineSurface],
    sampled: &SampledCorner,
    positions: &[Point3],
    centre: Point3,
    fit: &FitParams,
) -> Result<(Vec<BSplineCurve>, f64)> {
    let mut curves = Vec::with_capacity(quads.len());
    let mut max_error: f64 = 0.0;
    for (k, q) in quads.iter().enumerate() {
        let (nu, nv) = (q.num_u(), q.num_v());
        let mut pts: Vec<Point3> = (0..nv).map(|j| q.control_point(nu - 1, j)).collect();
        pts[nv - 1] = centre;
        let template = BSplineCurve::new(q.knots_v().clone(), pts, None)?;
        let mut free = vec![true; nv];
        free[0] = false;
        free[nv - 1] = false;
        let g = &sampled.grids[k];
        let mv = g.vs.len();
        let a = g.us.len() - 1;
        let data: Vec<Point3> = (0..mv).map(|b| positions[g.vertices[a * mv + b]]).collect();
        let (curve, rep) = fit_curve(&template, &free, &g.vs, &data, fit)?;
        max_error = max_error.max(rep.max_error);
        curves.push(curve);
    }
    Ok((curves, max_error))
}

/// Step 2: moves the second-to-last point of every curve onto the plane through `centre` that
/// fits them best; returns the largest move.
fn onto_centre_plane(curves: &mut [BSplineCurve], centre: Point3) -> f64 {
    let mut scatter = Matrix3::zeros();
    for c in curves.iter() {
        let p = c.control_points();
        let d = p[p.len() - 2] - centre;
        scatter += d * d.transpose();
    }
    let eig = SymmetricEigen::new(scatter);
    let imin = eig.eigenvalues.imin();
    let n_c: Vector3 = eig.eigenvectors.column(imin).into_owned();
    let mut worst: f64 = 0.0;
    for c in curves.iter_mut() {
        let pts = c.control_points_mut();
        let m = pts.len();
        let d = pts[m - 2] - centre;
        let off = d.dot(&n_c);
        worst = worst.max(off.abs());
        pts[m - 2] -= off * n_c;
    }
    worst
}

/// Step 3: quad k fitted to its faired samples with its positional frame fixed: the outer
/// rows as they are, the rows on I_k and I_{k−1} copied from `curves`.
fn fit_quad(
    q: &BSplineSurface,
    k: usize,
    curves: &[BSplineCurve],
    sampled: &SampledCorner,
    positions: &[Point3],
    fit: &FitParams,
) -> Result<BSplineSurface> {
    let n = curves.len();
    let prev = (k + n - 1) % n;
    let (nu, nv) = (q.num_u(), q.num_v());
    let mut net = q.control_points().to_vec();
    for (j, p) in curves[k].control_points().iter().enumerate() {
        net[(nu - 1) * nv + j] = *p;
    }
    for (i, p) in curves[prev].control_points().iter().enumerate() {
        net[i * nv + nv - 1] = *p;
    }
    let template = BSplineSurface::new(q.knots_u().clone(), q.knots_v().clone(), net, None)?;
    let mask = ControlMask::with_boundary_frame(&template, Frame::Positional);
    let g = &sampled.grids[k];
    let mv = g.vs.len();
    let mut params = Vec::with_capacity(g.vertices.len());
    let mut data = Vec::with_capacity(g.vertices.len());
    for (a, &u) in g.us.iter().enumerate() {
        for (b, &v) in g.vs.iter().enumerate() {
            params.push((u, v));
            data.push(positions[g.vertices[a * mv + b]]);
        }
    }
    let (surface, _) = fit_surface(&template, &mask, &params, &data, fit)?;
    Ok(surface)
}

/// The largest and the root mean square distance between the faired samples and their quads
/// at the samples' parameters.
fn sample_errors(
    quads: &[BSplineSurface],
    sampled: &SampledCorner,
    positions: &[Point3],
) -> (f64, f64) {
    let (mut sum2, mut count, mut max_error) = (0.0, 0usize, 0.0f64);
    for (k, q) in quads.iter().enumerate() {
        let g = &sampled.grids[k];
        let mv = g.vs.len();
        let mut eval = q.evaluator();
        for (a, &u) in g.us.iter().enumerate() {
            for (b, &v) in g.vs.iter().enumerate() {
                let d = (eval.point(u, v) - positions[g.vertices[a * mv + b]]).norm();
                max_error = max_error.max(d);
                sum2 += d * d;
                count += 1;
            }
        }
    }
    (max_error, (sum2 / count.max(1) as f64).sqrt())
}

/// Singular values below this fraction of the largest count as zero in the minimum-norm
/// least-squares solve of the cross-row alignment (rounding of the assembled matrix).
const ALIGN_RCOND: f64 = 1e-10;

/// The common normal n(t) along a curve at [`ANGLE_SAMPLES`] parameters t (where defined).
type CommonNormals = Vec<(f64, Vector3)>;

/// Step 4 of the module docs; returns the largest move.
fn align_cross_rows(quads: &mut [BSplineSurface]) -> f64 {
    let n = quads.len();
    // common normals along every internal curve I_k, from the fits before alignment
    let normals: Vec<CommonNormals> = (0..n)
        .map(|k| common_normals(&quads[k], &quads[(k + 1) % n]))
        .collect();
    let mut worst: f64 = 0.0;
    for k in 0..n {
        let prev = (k + n - 1) % n;
        worst = worst.max(align_quad(&mut quads[k], &normals[k], &normals[prev]));
    }
    worst
}

/// The mean unit normal of quad `q` along its side U1 and quad `r` along its side V1 (the
/// internal curve they share), at [`ANGLE_SAMPLES`] parameters.
fn common_normals(q: &BSplineSurface, r: &BSplineSurface) -> CommonNormals {
    (0..ANGLE_SAMPLES)
        .filter_map(|s| {
            let t = s as f64 / (ANGLE_SAMPLES - 1) as f64;
            let (a, b) = (unit_normal(q, 1.0, t)?, unit_normal(r, t, 1.0)?);
            // quads of opposite orientation (a caller's patches need not agree): their
            // normals are the same line; the mean of a and −a would be noise
            let b = if a.dot(&b) < 0.0 { -b } else { b };
            Some((t, (a + b).try_normalize(0.0)?))
        })
        .collect()
}

/// Moves the inner points of `q` next to its sides U1 (common normals `along_v`) and V1
/// (`along_u`) by the minimum-norm least-squares displacements along the common normal;
/// returns the largest move (0 when the solve fails and nothing moves).
fn align_quad(q: &mut BSplineSurface, along_v: &CommonNormals, along_u: &CommonNormals) -> f64 {
    let (nu, nv) = (q.num_u(), q.num_v());
    // unknowns: inner points next to U1 (nu−2, 2..=nv−2) and V1 (2..=nu−2, nv−2); the
    // twists (nu−2, 1) and (1, nv−2) belong to the outer sides' tangential frames
    let mut unknowns: Vec<(usize, usize)> = (2..nv - 1).map(|j| (nu - 2, j)).collect();
    unknowns.extend((2..nu - 2).map(|i| (i, nv - 2)));
    let rows = cross_rows(q, &unknowns, along_v, along_u);
    // each inner point moves along the common normal at its Greville abscissa only: with
    // free 3D moves the tangential components enter only through the variation of n(t)
    // (singular values ~1e-3 of the largest), and a least-squares solve fits the rows'
    // inconsistencies with them — millimetre moves on the five-sided fixture
    let directions: Vec<Vector3> = unknowns
        .iter()
        .map(|&(i, j)| {
            let (kv, index, list) = if i == nu - 2 {
                (q.knots_v(), j, along_v)
            } else {
                (q.knots_u(), i, along_u)
            };
            let p = kv.degree();
            let g = kv.knots()[index + 1..=index + p].iter().sum::<f64>() / p as f64;
            list.iter()
                .min_by(|x, y| (x.0 - g).abs().total_cmp(&(y.0 - g).abs()))
                .map_or_else(Vector3::zeros, |&(_, n)| n)
        })
        .collect();
    let mut a = nalgebra::DMatrix::<f64>::zeros(rows.len(), unknowns.len());
    let mut b = nalgebra::DVector::<f64>::zeros(rows.len());
    for (r, (coeffs, rhs)) in rows.iter().enumerate() {
        for &(c, v) in coeffs {
            a[(r, c)] += v.dot(&directions[c]);
        }
        b[r] = *rhs;
    }
    // moving the inner point Q by β d changes (R − Q)·n by −β d·n: A β = b
    let svd = a.svd(true, true);
    let eps = ALIGN_RCOND * svd.singular_values.max();
    let Ok(beta) = svd.solve(&b, eps) else {
        return 0.0;
    };
    let mut worst: f64 = 0.0;
    let pts = q.control_points_mut();
    for (c, &(i, j)) in unknowns.iter().enumerate() {
        let d = directions[c] * beta[c];
        if d.iter().all(|x| x.is_finite()) {
            pts[i * nv + j] += d;
            worst = worst.max(d.norm());
        }
    }
    worst
}

/// The constraints Σ_j N_j(t) (R_j − Q_j − w_j)·n(t) = 0 along side U1 (at `along_v`'s
/// samples) and side V1 (`along_u`) of `q`, as (the unknowns' coefficient vectors, indexed
/// into `unknowns`; Σ_j N_j(t) (R_j − Q_j)·n(t)).
fn cross_rows(
    q: &BSplineSurface,
    unknowns: &[(usize, usize)],
    along_v: &CommonNormals,
    along_u: &CommonNormals,
) -> Vec<(Vec<(usize, Vector3)>, f64)> {
    let (nu, nv) = (q.num_u(), q.num_v());
    let col = |i: usize, j: usize| unknowns.iter().position(|&x| x == (i, j));
    let mut rows: Vec<(Vec<(usize, Vector3)>, f64)> = Vec::new();
    // side U1 (u = 1, along v, curve I_k) and side V1 (v = 1, along u, curve I_{k−1})
    for (side_v1, list) in [(false, along_v), (true, along_u)] {
        let kv = if side_v1 { q.knots_u() } else { q.knots_v() };
        let p = kv.degree();
        let mut basis = nurbs_core::BasisEvaluator::new(p);
        let mut vals = vec![0.0; p + 1];
        for &(t, normal) in list {
            let span = kv.span(t);
            basis.values(kv.knots(), span, t, &mut vals);
            let mut coeffs = Vec::with_capacity(p + 1);
            let mut rhs = 0.0;
            for a in 0..=p {
                let idx = span - p + a;
                let (on, inner) = if side_v1 {
                    ((idx, nv - 1), (idx, nv - 2))
                } else {
                    ((nu - 1, idx), (nu - 2, idx))
                };
                let d = q.control_point(on.0, on.1) - q.control_point(inner.0, inner.1);
                rhs += vals[a] * d.dot(&normal);
                if let Some(c) = col(inner.0, inner.1) {
                    coeffs.push((c, vals[a] * normal));
                }
            }
            rows.push((coeffs, rhs));
        }
    }
    rows
}

/// Unit normal S_u × S_v of `s` at (u, v), `None` where it is singular.
fn unit_normal(s: &BSplineSurface, u: f64, v: f64) -> Option<Vector3> {
    let d = s.derivatives(u, v);
    let c = d.du.cross(&d.dv);
    let size = s.size();
    if c.norm() <= SINGULAR_NORMAL_REL * size * size {
        return None;
    }
    Some(c / c.norm())
}

fn angle_deg(a: &Vector3, b: &Vector3) -> f64 {
    // atan2 keeps accuracy for tiny angles where acos loses it
    a.cross(b).norm().atan2(a.dot(b)).to_degrees()
}

/// Largest angle (degrees) between the normals of quads k (side `U1`) and k + 1 (side `V1`)
/// along every internal curve I_k, at [`ANGLE_SAMPLES`] parameters.
pub fn internal_angle_deg(quads: &[BSplineSurface]) -> f64 {
    let n = quads.len();
    let mut worst: f64 = 0.0;
    for k in 0..n {
        let (q, r) = (&quads[k], &quads[(k + 1) % n]);
        let (a, b) = q.domain_v();
        let u1 = q.domain_u().1;
        let v1 = r.domain_v().1;
        for s in 0..ANGLE_SAMPLES {
            let t = a + (b - a) * s as f64 / (ANGLE_SAMPLES - 1) as f64;
            if let (Some(n1), Some(n2)) = (unit_normal(q, u1, t), unit_normal(r, t, v1)) {
                worst = worst.max(angle_deg(&n1, &n2));
            }
        }
    }
    worst
}

/// Largest angle (degrees) between the normal lines of the quads and their neighbours along the
/// outer sides that have one: side k is quad k's `V0` side and quad k + 1's `U0` side.
pub fn boundary_angle_deg(
    quads: &[BSplineSurface],
    neighbours: &[Option<Neighbour<'_>>],
) -> Result<Option<f64>> {
    let n = quads.len();
    let mut worst: Option<f64> = None;
    for (k, nb) in neighbours.iter().enumerate() {
        let Some(nb) = nb else { continue };
        let next = (k + 1) % n;
        let mut samples = Vec::with_capacity(2 * ANGLE_SAMPLES);
        for s in 0..ANGLE_SAMPLES {
            let t = s as f64 / (ANGLE_SAMPLES - 1) as f64;
            let q = &quads[k];
            let (a, b) = q.domain_u();
            samples.push((k, Side::V0, a + (b - a) * t));
            let r = &quads[next];
            let (a, b) = r.domain_v();
            samples.push((next, Side::U0, a + (b - a) * t));
        }
        let points: Vec<Point3> = samples
            .iter()
            .map(|&(q, side, t)| {
                let (u, v) = side.params(&quads[q], t);
                quads[q].point(u, v)
            })
            .collect();
        let ts = side_params(nb, points.into_iter())?;
        for (&(q, side, t), &tn) in samples.iter().zip(&ts) {
            let (u, v) = side.params(&quads[q], t);
            let (nu, nv) = neighbour_params(nb, tn, 0.0);
            if let (Some(n1), Some(n2)) = (
                unit_normal(&quads[q], u, v),
                unit_normal(nb.surface, nu, nv),
            ) {
                let n2 = if n1.dot(&n2) < 0.0 { -n2 } else { n2 };
                let a = angle_deg(&n1, &n2);
                worst = Some(worst.map_or(a, |w: f64| w.max(a)));
            }
        }
    }
    Ok(worst)
}
