//! Central split of an n-sided hole into n bicubic quads (\[SV\] §3.4, Fig. 2).
//!
//! Input: n = 3…8 boundary curves c_0 … c_{n−1} in cyclic order, c_k ending where c_{k+1} starts.
//! Each curve is split at its parametric midpoint t_k = (a_k + b_k)/2 into two halves (exact
//! extraction, i.e. knot insertion), giving the side midpoints M_k = c_k(t_k) and the corners
//! V_k = c_k(a_k) (= c_{k−1}(b_{k−1})).
//!
//! * Centre: C = C₀ + (1/n) Σ_k (L_k/2)·(d_k·n̂)/(d_k·ê_k) n̂, with C₀ = (1/n) Σ M_k, n̂ the unit
//!   normal of the loop (Newell's formula), ê_k = (C₀ − M_k)/L_k, L_k = |C₀ − M_k| and d_k the
//!   inward cross-boundary direction at M_k. The lift is the apex height of a parabola leaving
//!   M_k along d_k and reaching C₀'s foot with zero slope; without tangent data d_k lies in the
//!   plane of ê_k and the side, so a planar loop stays planar.
//! * Internal curve I_k from M_k to C: the cubic Bézier with P₀ = M_k, P₁ = M_k + (ℓ_k/3) d_k,
//!   P₂ = C − (ℓ_k/3) τ_k, P₃ = C (ℓ_k = |C − M_k|, τ_k the unit direction of C − M_k in the plane
//!   ⊥ n̂, so all internal curves share the tangent plane ⊥ n̂ at C), refined to its knot vector.
//! * Quad interior: the bicubic Coons patch of its four sides, which in B-spline form is the net
//!   P_ij = R^v_ij + R^u_ij − B_ij with the ruled nets R^v_ij = (1 − ξ_j) A_i + ξ_j B_i (sides
//!   v = 0, 1), R^u_ij = (1 − ξ_i) D_j + ξ_i E_j (sides u = 0, 1) and the bilinear corner net B,
//!   ξ the Greville abscissae (a linear function has the Greville abscissae as coefficients).
//!   The side rows are then copied from the side curves, so they are bit-identical to them.
//!
//! # Orientation convention
//! Quad k (corner V_k, between curves c_{k−1} and c_k), parameters (u, v) ∈ [0, 1]²:
//! * `Side::V0` (v = 0, column j = 0): first half of c_k, u from V_k to M_k (outer);
//! * `Side::U0` (u = 0, row i = 0): second half of c_{k−1} reversed, v from V_k to M_{k−1} (outer);
//! * `Side::U1` (u = 1, row i = n_u − 1): internal curve I_k, v from M_k to C;
//! * `Side::V1` (v = 1, column j = n_v − 1): internal curve I_{k−1}, u from M_{k−1} to C.
//!
//! So S_k(0, 0) = V_k, S_k(1, 0) = M_k, S_k(0, 1) = M_{k−1}, S_k(1, 1) = C, and internal curve I_k
//! is side `U1` of quad k and side `V1` of quad k + 1 (indices mod n) with the same direction and
//! parametrization: the knot vector in v of quad k equals the one in u of quad k + 1, and the
//! control row i = n_u − 1 of quad k is bit-identical to the column j = n_v − 1 of quad k + 1.
//! All normals S_u × S_v point to the side from which the boundary loop runs counter-clockwise.
//!
//! # Knot vectors
//! All quads are bicubic on [0, 1]². Internal curve I_k carries the union (maximum multiplicity)
//! of the knots of the two boundary halves parallel to it: the reversed second half of c_{k−1}
//! (opposite in quad k) and the first half of c_{k+1} (opposite in quad k + 1), each mapped
//! affinely to [0, 1] and raised to degree 3; spans are halved (largest first) until there are
//! at least `min_spans`, so the quads have interior freedom for fairing (\[SV\] §3.2 step 1).
//!
//! # Tolerance
//! Curves must close the loop within `closure_tolerance` × loop size (bounding-box diagonal of
//! the control points). Corners are then snapped: V_k takes the start point of c_k exactly, so
//! the boundary rows equal the curve halves except for that snap (reported as the closure gap).

use nurbs_core::{BSplineCurve, BSplineSurface, KnotVector, Point3, Vector3};

use crate::error::{NsideError, Result};

/// Fewest sides of an n-sided patch.
pub(crate) const MIN_SIDES: usize = 3;
/// Most sides of an n-sided patch supported.
pub(crate) const MAX_SIDES: usize = 8;
/// Degree of the quads in both directions.
pub(crate) const QUAD_DEGREE: usize = 3;
/// Smallest cosine between the inward direction d_k and the chord ê_k used in the centre lift;
/// directions closer to perpendicular than ~84° are clamped so the lift stays bounded.
const MIN_LIFT_COSINE: f64 = 0.1;
/// Boundary polygon points per boundary curve for the self-intersection test.
const LOOP_SAMPLES_PER_CURVE: usize = 48;
/// Enclosed area (relative to size²) below which the loop counts as degenerate.
const DEGENERATE_AREA_REL: f64 = 1e-12;
/// Length (relative to the loop size) below which a direction counts as zero.
const ZERO_LENGTH_REL: f64 = 1e-14;

/// Settings of the central split.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CentralSplitParams {
    /// Largest end-to-start gap between consecutive curves, relative to the loop size. Default
    /// 1e-7: curves taken from one model meet to rounding, 1e-7 still admits single-precision
    /// exchange data.
    pub closure_tolerance: f64,
    /// Fewest knot spans of each quad direction. Default 4: two interior rows on each side of the
    /// frames that \[SV\] §3.2 fixes (positional, tangential, curvature) stay free.
    pub min_spans: usize,
}

impl Default for CentralSplitParams {
    fn default() -> Self {
        Self {
            closure_tolerance: 1e-7,
            min_spans: 4,
        }
    }
}

/// What the central split built.
#[derive(Debug, Clone, PartialEq)]
pub struct CentralSplitReport {
    /// largest end-to-start gap between consecutive curves (model units), closed by snapping
    pub closure_gap: f64,
    /// the centre point C
    pub centre: Point3,
    /// side midpoints M_k
    pub midpoints: Vec<Point3>,
    /// unit normal of the boundary loop (Newell), the orientation of the quads
    pub loop_normal: Vector3,
}

/// Validates the loop and builds the n quads of the central split (see the module docs for the
/// construction and the orientation convention). `cross_tangents[k]`, when given, is a direction
/// across side k at its midpoint pointing into the hole (e.g. minus the neighbour's
/// cross-boundary derivative); its component along the side is ignored.
pub fn central_split(
    boundaries: &[BSplineCurve],
    cross_tangents: Option<&[Option<Vector3>]>,
    params: &CentralSplitParams,
) -> Result<(Vec<BSplineSurface>, CentralSplitReport)> {
    check_split_input(boundaries, cross_tangents, params)?;
    let n = boundaries.len();
    let all: Vec<Point3> = boundaries
        .iter()
        .flat_map(|c| c.control_points().iter().copied())
        .collect();
    let size = nurbs_core::homogeneous::bounding_diagonal(&all);
    let closure_gap = closure_gap(boundaries, params.closure_tolerance * size)?;
    let loop_normal = check_loop(boundaries, size)?;
    let mut halves = Halves::new(boundaries)?;
    let midpoints = &halves.midpoints;
    let c0 = Point3::from(midpoints.iter().map(|m| m.coords).sum::<Vector3>() / n as f64);
    let zero = ZERO_LENGTH_REL * size.max(f64::MIN_POSITIVE);
    let inward = halves.inward(c0, cross_tangents, loop_normal, zero);
    let mut lift = Vector3::zeros();
    for k in 0..n {
        let chord = c0 - midpoints[k];
        let l = chord.norm();
        let Some(e) = chord.try_normalize(zero) else {
            continue;
        };
        let cosine = inward[k].dot(&e).max(MIN_LIFT_COSINE);
        lift += 0.5 * l * inward[k].dot(&loop_normal) / cosine * loop_normal;
    }
    let centre = c0 + lift / n as f64;
    halves.snap();
    let internal_knots = halves.internal_knots(params.min_spans);
    let frame = CentreFrame {
        centre,
        loop_normal,
        zero,
    };
    let mut internal = Vec::with_capacity(n);
    for k in 0..n {
        let m = halves.midpoints[k];
        internal.push(frame.internal_curve(m, inward[k], &internal_knots[k])?);
    }
    let mut quads = Vec::with_capacity(n);
    for k in 0..n {
        let prev = (k + n - 1) % n;
        let v0 = refine_to(&halves.first[k], &internal_knots[prev], k)?;
        let u0 = refine_to(&halves.second_rev[prev], &internal_knots[k], k)?;
        quads.push(coons(&v0, &internal[prev], &u0, &internal[k])?);
    }
    Ok((
        quads,
        CentralSplitReport {
            closure_gap,
            centre,
            midpoints: halves.midpoints,
            loop_normal,
        },
    ))
}

/// Bad input unless there are 3…8 polynomial boundaries of degree ≤ 3, one cross tangent
/// entry per side when given, and a finite closure tolerance ≥ 0.
fn check_split_input(
    boundaries: &[BSplineCurve],
    cross_tangents: Option<&[Option<Vector3>]>,
    params: &CentralSplitParams,
) -> Result<()> {
    let n = boundaries.len();
    if !(MIN_SIDES..=MAX_SIDES).contains(&n) {
        return Err(NsideError::SideCount {
            count: n,
            min: MIN_SIDES,
            max: MAX_SIDES,
        });
    }
    if let Some(t) = cross_tangents
        && t.len() != n
    {
        return Err(NsideError::CountMismatch {
            what: "cross tangents per side",
            expected: n,
            got: t.len(),
        });
    }
    if !(params.closure_tolerance >= 0.0) || !params.closure_tolerance.is_finite() {
        return Err(NsideError::BadParam {
            name: "closure_tolerance",
            value: params.closure_tolerance,
            detail: "must be finite and ≥ 0",
        });
    }
    for (curve, c) in boundaries.iter().enumerate() {
        if c.is_rational() {
            return Err(NsideError::UnsupportedCurve {
                curve,
                detail: "rational curves cannot be held exactly by polynomial quads".into(),
            });
        }
        if c.degree() > QUAD_DEGREE {
            return Err(NsideError::UnsupportedCurve {
                curve,
                detail: format!("degree {} is above the quads' degree 3", c.degree()),
            });
        }
    }
    Ok(())
}

/// The largest end-to-start gap between consecutive boundaries; an open loop error where one
/// exceeds `tolerance` (model units).
fn closure_gap(boundaries: &[BSplineCurve], tolerance: f64) -> Result<f64> {
    let n = boundaries.len();
    let mut closure_gap: f64 = 0.0;
    for k in 0..n {
        let next = (k + 1) % n;
        let end = boundaries[k].point(boundaries[k].domain().1);
        let start = boundaries[next].point(boundaries[next].domain().0);
        let gap = (end - start).norm();
        if !(gap <= tolerance) {
            return Err(NsideError::OpenLoop {
                curve: k,
                next,
                gap,
                tolerance,
            });
        }
        closure_gap = closure_gap.max(gap);
    }
    Ok(closure_gap)
}

/// The boundary curves split at their parametric midpoints, as cubics on [0, 1].
struct Halves {
    /// first[k] runs V_k → M_k
    first: Vec<BSplineCurve>,
    /// second_rev[k] runs V_{k+1} → M_k
    second_rev: Vec<BSplineCurve>,
    /// M_k
    midpoints: Vec<Point3>,
    /// c_k′ at the midpoint
    tangents: Vec<Vector3>,
}

impl Halves {
    /// Splits every boundary at its parametric midpoint.
    fn new(boundaries: &[BSplineCurve]) -> Result<Self> {
        let n = boundaries.len();
        let mut halves = Self {
            first: Vec::with_capacity(n),
            second_rev: Vec::with_capacity(n),
            midpoints: Vec::with_capacity(n),
            tangents: Vec::with_capacity(n),
        };
        for (k, c) in boundaries.iter().enumerate() {
            let (a, b) = c.domain();
            let tm = 0.5 * (a + b);
            halves.first.push(unit_cubic(c, a, tm, false, k)?);
            halves.second_rev.push(unit_cubic(c, tm, b, true, k)?);
            let d = c.derivatives(tm, 1);
            halves.midpoints.push(Point3::from(d.d[0]));
            halves.tangents.push(d.d[1]);
        }
        Ok(halves)
    }

    /// The inward directions d_k at the midpoints, ⊥ the side tangent: from `cross_tangents`
    /// where given and not along the side, else towards `c0`, turned to point towards `c0`.
    fn inward(
        &self,
        c0: Point3,
        cross_tangents: Option<&[Option<Vector3>]>,
        loop_normal: Vector3,
        zero: f64,
    ) -> Vec<Vector3> {
        let n = self.midpoints.len();
        let mut inward = Vec::with_capacity(n);
        for k in 0..n {
            let t = self.tangents[k]
                .try_normalize(0.0)
                .unwrap_or_else(Vector3::zeros);
            let chord = c0 - self.midpoints[k];
            let given = cross_tangents.and_then(|ct| ct[k]);
            let raw = given.unwrap_or(chord);
            let mut d = raw - raw.dot(&t) * t;
            if d.norm() <= zero {
                d = chord - chord.dot(&t) * t;
            }
            let mut d = d.try_normalize(0.0).unwrap_or_else(|| {
                chord
                    .try_normalize(0.0)
                    .unwrap_or_else(|| loop_normal.cross(&t))
            });
            if d.dot(&chord) < 0.0 {
                d = -d;
            }
            inward.push(d);
        }
        inward
    }

    /// Snaps the halves: V_k = start of c_k; M_k shared bit-exactly by both halves.
    fn snap(&mut self) {
        let n = self.midpoints.len();
        for k in 0..n {
            let prev = (k + n - 1) % n;
            let vk = self.first[k].control_points()[0];
            set_first(&mut self.second_rev[prev], vk);
            let mk = self.midpoints[k];
            set_last(&mut self.first[k], mk);
            set_last(&mut self.second_rev[k], mk);
        }
    }

    /// The interior knots of every internal curve I_k: those of the reversed second half of
    /// c_{k−1} and the first half of c_{k+1} (parallel to it), with at least `min_spans` spans.
    fn internal_knots(&self, min_spans: usize) -> Vec<Vec<f64>> {
        let n = self.midpoints.len();
        let mut internal_knots = Vec::with_capacity(n);
        for k in 0..n {
            let prev = (k + n - 1) % n;
            let next = (k + 1) % n;
            let mut knots = merge_interior(self.second_rev[prev].knots(), self.first[next].knots());
            ensure_spans(&mut knots, min_spans);
            internal_knots.push(knots);
        }
        internal_knots
    }
}

/// The centre C with the loop normal n̂ that the internal curves' end tangents are ⊥ to.
struct CentreFrame {
    centre: Point3,
    loop_normal: Vector3,
    /// length below which a direction counts as zero (model units)
    zero: f64,
}

impl CentreFrame {
    /// The internal curve from the midpoint `m` (leaving along `inward`) to C, refined by the
    /// interior knots `knots`, with its ends exactly M and C.
    fn internal_curve(&self, m: Point3, inward: Vector3, knots: &[f64]) -> Result<BSplineCurve> {
        let (centre, loop_normal, zero) = (self.centre, self.loop_normal, self.zero);
        let chord = centre - m;
        let l = chord.norm();
        let flat = chord - chord.dot(&loop_normal) * loop_normal;
        let tau = flat
            .try_normalize(zero)
            .or_else(|| chord.try_normalize(zero))
            .unwrap_or(inward);
        let pts = vec![m, m + inward * (l / 3.0), centre - tau * (l / 3.0), centre];
        let bez = BSplineCurve::new(KnotVector::bezier(QUAD_DEGREE)?, pts, None)?;
        let mut curve = bez.refine(knots)?;
        set_first(&mut curve, m);
        set_last(&mut curve, centre);
        Ok(curve)
    }
}

/// The part of `c` over [a, b] mapped affinely to [0, 1] (reversed when asked), degree 3.
fn unit_cubic(
    c: &BSplineCurve,
    a: f64,
    b: f64,
    reverse: bool,
    curve: usize,
) -> Result<BSplineCurve> {
    let part = c.extract(a, b)?;
    let p = part.degree();
    let kv = part.knots().knots();
    let m = kv.len();
    let mut knots: Vec<f64> = kv
        .iter()
        .enumerate()
        .map(|(i, &t)| {
            if i <= p {
                0.0
            } else if i + p + 1 >= m {
                1.0
            } else {
                (t - a) / (b - a)
            }
        })
        .collect();
    let mut points = part.control_points().to_vec();
    if reverse {
        knots = knots.iter().rev().map(|&t| 1.0 - t).collect();
        // 1 − 1 and 1 − 0 are exact
        points.reverse();
    }
    let unit = BSplineCurve::new(KnotVector::new(p, knots)?, points, None)?;
    let out = if p < QUAD_DEGREE {
        unit.elevate_degree(QUAD_DEGREE - p)?
    } else {
        unit
    };
    if out.degree() != QUAD_DEGREE {
        return Err(NsideError::UnsupportedCurve {
            curve,
            detail: format!("degree elevation gave degree {}", out.degree()),
        });
    }
    Ok(out)
}

fn set_first(c: &mut BSplineCurve, p: Point3) {
    c.control_points_mut()[0] = p;
}

fn set_last(c: &mut BSplineCurve, p: Point3) {
    let pts = c.control_points_mut();
    let last = pts.len() - 1;
    pts[last] = p;
}

/// Two knots on [0, 1] closer than this are one knot in [`merge_interior`]: the halves of
/// two sides are mapped to [0, 1] affinely, and a knot both carry (a side's midpoint knot, one
/// reversed) comes out of the two maps a rounding apart (0.4 and 0.3999999999999999); kept
/// apart they would make a span of 1e-16, a double knot in effect, which a later knot removal
/// cannot take out.
const SAME_KNOT: f64 = 1e-10;

/// Interior knots (with multiplicity) of the union of two cubic knot vectors on [0, 1]; knots
/// within [`SAME_KNOT`] of one another count as one (the first vector's value is kept).
fn merge_interior(a: &KnotVector, b: &KnotVector) -> Vec<f64> {
    let mut all: Vec<(f64, usize)> = a.interior_knots();
    for (t, m) in b.interior_knots() {
        match all.iter_mut().find(|(s, _)| (*s - t).abs() <= SAME_KNOT) {
            Some(entry) => entry.1 = entry.1.max(m),
            None => all.push((t, m)),
        }
    }
    all.sort_by(|x, y| x.0.total_cmp(&y.0));
    all.iter()
        .flat_map(|&(t, m)| std::iter::repeat_n(t, m))
        .collect()
}

/// Halves the largest span until [0, 1] with `interior` has at least `min_spans` spans.
fn ensure_spans(interior: &mut Vec<f64>, min_spans: usize) {
    loop {
        let mut bounds = vec![0.0];
        for &t in interior.iter() {
            if t != *bounds.last().unwrap_or(&0.0) {
                bounds.push(t);
            }
        }
        bounds.push(1.0);
        if bounds.len() > min_spans {
            return;
        }
        let (i, _) = bounds
            .windows(2)
            .enumerate()
            .map(|(i, w)| (i, w[1] - w[0]))
            .fold(
                (0, f64::NEG_INFINITY),
                |best, x| if x.1 > best.1 { x } else { best },
            );
        interior.push(0.5 * (bounds[i] + bounds[i + 1]));
        interior.sort_by(f64::total_cmp);
    }
}

/// `c` refined to the knot vector [0⁴, interior, 1⁴] (which must contain its knots).
fn refine_to(c: &BSplineCurve, interior: &[f64], quad: usize) -> Result<BSplineCurve> {
    let mut have = c.knots().interior_knots();
    let mut insert = Vec::new();
    for &t in interior {
        match have.iter_mut().find(|(s, m)| *s == t && *m > 0) {
            Some(entry) => entry.1 -= 1,
            None => insert.push(t),
        }
    }
    if have.iter().any(|&(_, m)| m > 0) {
        return Err(NsideError::BadQuad {
            quad,
            detail: "boundary half has knots outside the merged knot vector".into(),
        });
    }
    let first = c.control_points()[0];
    let last = *c.control_points().last().unwrap_or(&first);
    let mut out = if insert.is_empty() {
        c.clone()
    } else {
        c.refine(&insert)?
    };
    set_first(&mut out, first);
    set_last(&mut out, last);
    Ok(out)
}

/// Bicubic Coons net from the sides v = 0 (`a`, in u), v = 1 (`b`, in u), u = 0 (`d`, in v) and
/// u = 1 (`e`, in v); the side rows are copied exactly.
fn coons(
    a: &BSplineCurve,
    b: &BSplineCurve,
    d: &BSplineCurve,
    e: &BSplineCurve,
) -> Result<BSplineSurface> {
    let ku = a.knots().clone();
    let kv = d.knots().clone();
    let (nu, nv) = (ku.num_basis(), kv.num_basis());
    let (gu, gv) = (ku.greville(), kv.greville());
    let (pa, pb, pd, pe) = (
        a.control_points(),
        b.control_points(),
        d.control_points(),
        e.control_points(),
    );
    let (c00, c10, c01, c11) = (
        pa[0].coords,
        pa[nu - 1].coords,
        pb[0].coords,
        pb[nu - 1].coords,
    );
    let mut net = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            let (x, y) = (gu[i], gv[j]);
            let rv = (1.0 - y) * pa[i].coords + y * pb[i].coords;
            let ru = (1.0 - x) * pd[j].coords + x * pe[j].coords;
            let bl = (1.0 - x) * (1.0 - y) * c00
                + x * (1.0 - y) * c10
                + (1.0 - x) * y * c01
                + x * y * c11;
            net.push(Point3::from(rv + ru - bl));
        }
    }
    for i in 0..nu {
        net[i * nv] = pa[i];
        net[i * nv + nv - 1] = pb[i];
    }
    for j in 0..nv {
        net[j] = pd[j];
        net[(nu - 1) * nv + j] = pe[j];
    }
    Ok(BSplineSurface::new(ku, kv, net, None)?)
}

/// Whether the closed segments a0a1 and b0b1 share a point (crossing, touching or overlapping).
fn segments_meet(a0: [f64; 2], a1: [f64; 2], b0: [f64; 2], b1: [f64; 2]) -> bool {
    let orient = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        let v = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        if v > 0.0 {
            1
        } else if v < 0.0 {
            -1
        } else {
            0
        }
    };
    // c lies on the segment ab, given that the three are collinear
    let on = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        c[0] >= a[0].min(b[0])
            && c[0] <= a[0].max(b[0])
            && c[1] >= a[1].min(b[1])
            && c[1] <= a[1].max(b[1])
    };
    let (o1, o2) = (orient(a0, a1, b0), orient(a0, a1, b1));
    let (o3, o4) = (orient(b0, b1, a0), orient(b0, b1, a1));
    if o1 * o2 < 0 && o3 * o4 < 0 {
        return true;
    }
    (o1 == 0 && on(a0, a1, b0))
        || (o2 == 0 && on(a0, a1, b1))
        || (o3 == 0 && on(b0, b1, a0))
        || (o4 == 0 && on(b0, b1, a1))
}

/// Newell normal of the sampled loop, degeneracy and self-intersection checks.
fn check_loop(boundaries: &[BSplineCurve], size: f64) -> Result<Vector3> {
    let m = LOOP_SAMPLES_PER_CURVE;
    let mut pts = Vec::with_capacity(boundaries.len() * m);
    let mut tags = Vec::with_capacity(boundaries.len() * m);
    for (k, c) in boundaries.iter().enumerate() {
        let (a, b) = c.domain();
        for s in 0..m {
            let t = a + (b - a) * s as f64 / m as f64;
            pts.push(c.point(t));
            tags.push((k, t));
        }
    }
    let count = pts.len();
    let mut newell = Vector3::zeros();
    for i in 0..count {
        newell += pts[i].coords.cross(&pts[(i + 1) % count].coords);
    }
    // the plane of the test: Newell's normal, or for a loop without area (a bow tie) the
    // smallest principal direction of the points
    let normal = newell.try_normalize(0.0).unwrap_or_else(|| {
        let c = pts.iter().map(|p| p.coords).sum::<Vector3>() / count as f64;
        let scatter = pts.iter().fold(nalgebra::Matrix3::zeros(), |m, p| {
            m + (p.coords - c) * (p.coords - c).transpose()
        });
        let e = nalgebra::SymmetricEigen::new(scatter);
        e.eigenvectors.column(e.eigenvalues.imin()).into_owned()
    });
    let ex = normal
        .cross(&Vector3::x())
        .try_normalize(1e-3)
        .unwrap_or_else(|| normal.cross(&Vector3::y()).normalize());
    let ey = normal.cross(&ex);
    let flat: Vec<[f64; 2]> = pts
        .iter()
        .map(|p| [p.coords.dot(&ex), p.coords.dot(&ey)])
        .collect();
    for i in 0..count {
        let (a0, a1) = (flat[i], flat[(i + 1) % count]);
        for j in i + 2..count {
            if (j + 1) % count == i {
                continue;
            }
            let (b0, b1) = (flat[j], flat[(j + 1) % count]);
            if segments_meet(a0, a1, b0, b1) {
                return Err(NsideError::SelfIntersecting {
                    curve_a: tags[i].0,
                    t_a: tags[i].1,
                    curve_b: tags[j].0,
                    t_b: tags[j].1,
                });
            }
        }
    }
    let area = 0.5 * newell.norm();
    if !(area > DEGENERATE_AREA_REL * size * size) {
        return Err(NsideError::DegenerateLoop { area, size });
    }
    Ok(normal)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_are_halved_until_enough() {
        let mut k = vec![0.5];
        ensure_spans(&mut k, 4);
        assert_eq!(k, vec![0.25, 0.5, 0.75]);
        let mut none = Vec::new();
        ensure_spans(&mut none, 1);
        assert!(none.is_empty());
    }

    #[test]
    fn merge_keeps_largest_multiplicity() {
        let a = KnotVector::new(3, vec![0., 0., 0., 0., 0.5, 0.5, 1., 1., 1., 1.]).unwrap();
        let b = KnotVector::new(3, vec![0., 0., 0., 0., 0.25, 0.5, 1., 1., 1., 1.]).unwrap();
        assert_eq!(merge_interior(&a, &b), vec![0.25, 0.5, 0.5]);
    }

    /// A knot that two side halves carry a rounding apart is one knot, not a 1e-16 span.
    #[test]
    fn merge_takes_knots_a_rounding_apart_as_one() {
        let a = KnotVector::new(3, vec![0., 0., 0., 0., 0.4, 0.8, 1., 1., 1., 1.]).unwrap();
        let b = KnotVector::new(
            3,
            vec![0., 0., 0., 0., 0.3999999999999999, 0.8, 1., 1., 1., 1.],
        )
        .unwrap();
        assert_eq!(merge_interior(&a, &b), vec![0.4, 0.8]);
    }

    #[test]
    fn greville_of_bezier_is_uniform() {
        let g = KnotVector::bezier(3).unwrap().greville();
        assert_eq!(g, vec![0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0]);
    }
}
