//! The joint polish of a slave's frames: every condition of every linked side (\[SV\] §4: the gap,
//! the normal and the normal curvature across each side) solved at once over rows 0..=r of all
//! the sides, by damped Gauss–Newton (Levenberg–Marquardt, \[NW\] §10.3).
//!
//! The staged steps decide a side's rows level by level and side by side: at a corner of two
//! sides the first three points of one side's row 2 are rows 0 and 1 of the other side, fixed
//! by its C0 and G1 steps before any G2 row is solved, and the shared twist is the mean of two
//! candidates. Where the two masters' curvatures change quickly near the corner, what the C0 and
//! G1 steps left there is not what the other side's G2 condition needs, and the G2 rows ring
//! along both sides (on a kernel's vertex blend between a plane and three fillets the relative
//! curvature figure stayed near 1.8 however fine the knots). Solved together, the corner block
//! takes the positions that satisfy both sides' conditions at once; away from the corners the
//! solution is the staged one (one side's rows alone were exact there).
//!
//! Each residual is a condition divided by its tolerance — the gap by the G0 tolerance, the
//! normals' difference n_s × n_m (the sine of the angle the measure reports; at a point without
//! a normal, the tilts of the derivatives there) by the G1 angle, the curvature difference by the G2
//! relative tolerance times the master's curvature (not below the measure's flatness cut-off)
//! — so that one unit is one tolerance whatever the condition. The masters' feet are found once
//! (the moves are a fraction of the tolerances, far below the masters' curvature radii).
//! With the weights fixed the slave's derivatives are linear in its control points
//! ([`nurbs_core::surface_basis`], exact); the residuals' derivatives with respect to those
//! derivative vectors are central differences. The normal equations are sparse (a point reaches
//! the samples of its basis function's support only) and solved by sparse Cholesky.
//!
//! # Tolerance
//! [`JOINT_ITERATIONS`], [`JOINT_SPAN_SAMPLES`], [`JOINT_GOAL`]: see each.

use std::collections::BTreeMap;

use nurbs_core::surface_basis::{SurfaceBasis, SurfaceBasisEvaluator};
use nurbs_core::{
    BSplineSurface, Continuity, Direction, Point3, Side, SurfaceDerivatives, Vector3,
};

use crate::error::Result;
use crate::link::SideLink;
use crate::measure::{DEFAULT_SAMPLES, FLAT_RADIUS_FACTOR, is_collapsed};
use crate::params::ConnectParams;
use crate::rows::row_of;
use crate::sampling::in_zones;
use crate::slave::degenerate_corner_blocks;

mod normal;
mod weights;

use weights::Round;

/// Most Gauss–Newton iterations of one polish: a bound of work. On kernel vertex blends (four
/// G2 sides, nets up to 37 × 59) the worst residual fell by about a factor of ten every four
/// iterations at first and by 1–3 % an iteration after twenty; the eighty after those bring a
/// residual down by another factor of 5–10 (e^(−80·0.02) ≈ 0.2, e^(−80·0.03) ≈ 0.09), what a
/// blend left at a few times its goal by the first twenty needs. An iteration costs one
/// numeric factorization per damping tried (the ordering and symbolic factor are found once).
pub const JOINT_ITERATIONS: usize = 100;

/// Rounds of reweighting after the first least-squares solve (Lawson's update,
/// `weights::lawson`): the least-squares optimum can leave a few samples beyond their
/// tolerance while the sum of squares is small — next to a degenerate corner of a vertex blend,
/// where two sides meet tangentially and the normal turns fast, one side's angle stayed at 2.2
/// tolerances while the polish met the other three sides. Each round multiplies the weight of
/// every residual group by how far it is beyond [`JOINT_GOAL`], as Lawson's algorithm does
/// towards a minimax fit, and starts from the last round's state. The rounds run only after a
/// first round that met more links than its start (it is converging towards the tolerances;
/// where it met none more, as on blends whose rows ring at a corner, reweighting never met one
/// on the kernel models), continue only while each round's worst residual falls below that of
/// the best round so far, and share one round's
/// iterations ([`JOINT_ITERATIONS`] / 3 each: the polish at most doubles its work). Where none
/// of those rounds beat the first (each stopped as its worst residual rose: too short to solve
/// its reweighted problem, which Lawson's update assumes solved), they run once more from the
/// first round's state with [`JOINT_ITERATIONS`] each (the polish then at most quintuples its
/// work): a variable-radius box's blend by default met its last side in the third such round
/// (313 iterations), while where the short rounds did lower the worst residual, longer ones only
/// continued a slow descent (300 iterations, no link more; docs/benchmarks.md). The round
/// meeting the most links (then with the smallest worst residual) is kept, so the rounds only
/// help. Three: the variable-radius boxes' blends needed one to three.
pub const JOINT_REWEIGHTS: usize = 3;

/// Samples inside each knot span along a side, besides the measure's uniform samples
/// ([`DEFAULT_SAMPLES`]): near a corner the knots may lie a hundredth of a percent of the side
/// apart, where uniform samples see nothing, and a span's basis functions must be pinned by
/// samples inside it. Each span along a side brings one more function per row, three new
/// points; two samples of six residuals each over-determine them. (Four per span, tried first
/// on the lofted block's blends, took 23 to 40 iterations where two took 17 to 19 and met the
/// same links or more: more samples between the same points only weight the spans' interiors
/// against the measure's samples.)
pub const JOINT_SPAN_SAMPLES: usize = 2;

/// The polish stops once every residual is within this share of its tolerance: the feet are
/// found once and the samples are not every point of the side, so a result just inside the
/// tolerances at the samples could measure just outside them; half leaves room for both.
pub const JOINT_GOAL: f64 = 0.5;

/// The Levenberg–Marquardt damping the first iteration starts from, relative to the diagonal of
/// the normal equations (\[NW\] §10.3: a step between Gauss–Newton and a short gradient step);
/// divided by [`DAMPING_DOWN`] after an accepted step, multiplied by [`DAMPING_UP`] after a
/// rejected one, and the polish ends when it passes [`DAMPING_MAX`] (no step lowers the cost).
const DAMPING_START: f64 = 1e-3;
/// See [`DAMPING_START`].
const DAMPING_DOWN: f64 = 3.0;
/// See [`DAMPING_START`].
const DAMPING_UP: f64 = 4.0;
/// See [`DAMPING_START`].
const DAMPING_MAX: f64 = 1e8;

/// Relative step of the central differences of a residual with respect to the slave's
/// derivative vectors: the residuals are smooth (rational in those vectors), so the error is
/// of order h² ≈ 1e-12 against rounding of order 1e-16/h ≈ 1e-10 — both far below the
/// tolerance units the residuals are measured in.
const DIFF_STEP: f64 = 1e-6;

/// Residuals per sample: the gap (three), the normals' difference (two), the normal-curvature
/// difference across the side.
const RES: usize = 6;

/// What [`polish_joint`] did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JointReport {
    /// Gauss–Newton iterations accepted
    pub iterations: usize,
    /// the largest residual before (in tolerance units, at the polish's samples)
    pub worst_before: f64,
    /// the largest residual after
    pub worst_after: f64,
    /// largest control-point move (model units)
    pub max_move: f64,
}

/// One sample of a side with its master's foot, found once.
struct Sample {
    link: usize,
    u: f64,
    v: f64,
    foot: Point3,
    dm: SurfaceDerivatives,
    /// the master's fundamental forms at the foot (`None` where it has no normal)
    ff: Option<nurbs_core::FundamentalForms>,
    nm: Vector3,
    /// an orthonormal pair spanning the master's tangent plane at the foot
    t1: Vector3,
    t2: Vector3,
    /// inside a vertex zone of its link ([`SideLink::g2_zones`]): no G2 residual
    zoned: bool,
}

/// The tolerance units of the residuals.
#[derive(Clone, Copy)]
struct Units {
    g0: f64,
    g1: f64,
    g2: f64,
    flat: f64,
}

/// The slave derivative vectors a residual depends on, in the order of [`SurfaceBasis`]'s
/// fields.
const FIELDS: usize = 6;

fn field(d: &mut SurfaceDerivatives, f: usize) -> &mut Vector3 {
    match f {
        0 => &mut d.point.coords,
        1 => &mut d.du,
        2 => &mut d.dv,
        3 => &mut d.duu,
        4 => &mut d.duv,
        _ => &mut d.dvv,
    }
}

/// The residuals of sample `sm` of a side `side` with target `target` at the slave derivatives
/// `ds`, in tolerance units.
fn residuals(
    ds: &SurfaceDerivatives,
    sm: &Sample,
    side: Side,
    target: Continuity,
    units: Units,
) -> [f64; RES] {
    let mut out = [0.0; RES];
    let gap = ds.point - sm.foot;
    for k in 0..3 {
        out[k] = gap[k] / units.g0;
    }
    if target < Continuity::G1 {
        return out;
    }
    let (e, along, second) = match side.cross_direction() {
        Direction::U => (ds.du, ds.dv, ds.duu),
        Direction::V => (ds.dv, ds.du, ds.dvv),
    };
    let le = e.norm();
    match ds.normal() {
        // the normals' difference, n_s × n_m (in the master's tangent plane, of length sin θ,
        // θ the angle the measure reports), in the plane's two directions
        Some(ns) => {
            let ns = if sm.nm.dot(&ns) < 0.0 { -ns } else { ns };
            let c = ns.cross(&sm.nm);
            out[3] = c.dot(&sm.t1) / units.g1;
            out[4] = c.dot(&sm.t2) / units.g1;
        }
        // no normal (a degenerate point): the tilts of the derivatives that exist
        None => {
            let la = along.norm();
            if le > 0.0 {
                out[3] = sm.nm.dot(&e) / le / units.g1;
            }
            if la > 0.0 {
                out[4] = sm.nm.dot(&along) / la / units.g1;
            }
        }
    }
    if target < Continuity::G2 || sm.zoned {
        return out;
    }
    let km = sm.ff.and_then(|ff| sm.dm.normal_curvature_with(&ff, &e));
    if let (Some(ns), Some(km)) = (ds.normal(), km) {
        let km = if sm.nm.dot(&ns) < 0.0 { -km } else { km };
        let ks = second.dot(&ns) / (le * le);
        out[5] = (ks - km) / (units.g2 * km.abs().max(units.flat));
    }
    out
}

/// The points that move: rows 0..=r of every whole linked side (r the row of its target), less
/// the points on the boundary of a side no whole link covers (an unlinked, partially linked or
/// collapsed side keeps its boundary), rows 0 and 1 of a side the settings keep
/// ([`SetParams::kept_sides`]: shared with a surface no link covers), the blocks of degenerate
/// corners, and at a corner the C0 rows turned onto a contact line
/// ([`SetParams::contact_lines`]) the corner and the row's second point: the direction the
/// boundary leaves the corner in is a condition of third order that no residual here carries,
/// and next to a corner the knots may be hundredths of a millimetre apart, so that a move far
/// inside the G0 tolerance would turn it by degrees. Returns each control index's column block.
///
/// [`SetParams::contact_lines`]: crate::SetParams::contact_lines
/// [`SetParams::kept_sides`]: crate::SetParams::kept_sides
fn unknowns(
    slave: &BSplineSurface,
    links: &[SideLink],
    params: &ConnectParams,
) -> BTreeMap<(usize, usize), usize> {
    let (nu, nv) = (slave.num_u(), slave.num_v());
    let whole = |s: Side| {
        links
            .iter()
            .any(|l| l.side == s && l.range.is_none() && !is_collapsed(slave, s))
    };
    let mut kept: Vec<(usize, usize)> = degenerate_corner_blocks(slave);
    for (k, s) in Side::ALL.into_iter().enumerate() {
        if !whole(s) {
            kept.extend(s.row(0, nu, nv));
        }
        // a side shared with a surface no link covers keeps its tangential frame
        if params.set.kept_sides[k] {
            kept.extend(s.row(0, nu, nv));
            kept.extend(s.row(1, nu, nv));
        }
    }
    for (k, s) in Side::ALL.into_iter().enumerate().filter(|&(_, s)| whole(s)) {
        let row = s.row(0, nu, nv);
        let m = row.len();
        for (e, ends) in [[0, 1], [m - 1, m.saturating_sub(2)]]
            .into_iter()
            .enumerate()
        {
            if params.set.contact_lines[k][e].is_some() {
                kept.extend(ends.map(|c| row[c]));
            }
        }
    }
    let mut columns = BTreeMap::new();
    for l in links.iter().filter(|l| whole(l.side)) {
        for k in 0..=row_of(l.target) {
            for ij in l.side.row(k, nu, nv) {
                if !kept.contains(&ij) && !columns.contains_key(&ij) {
                    let c = columns.len();
                    columns.insert(ij, c);
                }
            }
        }
    }
    columns
}

/// The samples of every link: the measure's uniform ones over its part and
/// [`JOINT_SPAN_SAMPLES`] inside every knot span along it, with the master's foot.
fn samples(slave: &BSplineSurface, links: &[SideLink], params: &ConnectParams) -> Vec<Sample> {
    let mut out = Vec::new();
    for (li, l) in links.iter().enumerate() {
        if is_collapsed(slave, l.side) {
            continue;
        }
        let (a, b) = l.domain(slave);
        let mut ts: Vec<f64> = (0..DEFAULT_SAMPLES)
            .map(|q| a + (b - a) * q as f64 / (DEFAULT_SAMPLES - 1) as f64)
            .collect();
        let kv = crate::sampling::along_knots(slave, l.side);
        let mut breaks: Vec<f64> = kv.knots().to_vec();
        breaks.dedup();
        for w in breaks.windows(2) {
            for q in 0..JOINT_SPAN_SAMPLES {
                let t = w[0] + (w[1] - w[0]) * (q as f64 + 0.5) / JOINT_SPAN_SAMPLES as f64;
                if t > a && t < b {
                    ts.push(t);
                }
            }
        }
        let points: Vec<Point3> = ts
            .iter()
            .map(|&t| {
                let (u, v) = l.side.params(slave, t);
                slave.point(u, v)
            })
            .collect();
        let feet = crate::memo::project_side(l.master, params.measure.projection, &points);
        for (&t, foot) in ts.iter().zip(feet) {
            let dm = l.master.derivatives(foot.u, foot.v);
            let Some(nm) = dm.normal() else { continue };
            let Some(t1) = (dm.du - nm * nm.dot(&dm.du)).try_normalize(f64::MIN_POSITIVE) else {
                continue;
            };
            let t2 = nm.cross(&t1);
            let (u, v) = l.side.params(slave, t);
            out.push(Sample {
                link: li,
                u,
                v,
                foot: dm.point,
                ff: dm.fundamental_forms(),
                dm,
                nm,
                t1,
                t2,
                zoned: in_zones(t, (a, b), l.g2_zones),
            });
        }
    }
    out
}

/// Least damping: below it the damped diagonal differs from the undamped by rounding only.
const DAMPING_MIN: f64 = 1e-12;

/// The polish's least-squares problem: the samples, the moving points and the units.
struct Problem<'a> {
    links: &'a [SideLink<'a>],
    samples: Vec<Sample>,
    /// the moving points in column order
    points: Vec<(usize, usize)>,
    /// per sample, the moving points its basis reaches with their values and derivatives
    /// ([`sample_basis`]: they depend on the knots and weights only, so they are found once)
    basis: Vec<Vec<(usize, [f64; FIELDS])>>,
    units: Units,
    /// per sample and residual its weight in the cost (`Problem::reweight`; 1 in the first
    /// round)
    weights: Vec<f64>,
}

/// The value and derivatives of basis function `q` of `sb`, in the order of [`field`].
fn coefficients(sb: &SurfaceBasis, q: usize) -> [f64; FIELDS] {
    [
        sb.value[q],
        sb.du[q],
        sb.dv[q],
        sb.duu[q],
        sb.duv[q],
        sb.dvv[q],
    ]
}

fn cost(r: &[f64]) -> f64 {
    r.iter().map(|x| x * x).sum()
}

fn worst(r: &[f64]) -> f64 {
    r.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// The derivative fields besides the point that [`residuals`] reads for a sample of a side
/// `side` with target `target` (`zoned`: inside a vertex zone, no G2 residual): S_u and S_v
/// (the normal) from G1 on, and the second derivative across the side (S_uu on a u side, S_vv
/// on a v side) at G2. S_uv enters no residual.
fn residual_fields(side: Side, target: Continuity, zoned: bool) -> &'static [usize] {
    if target < Continuity::G1 {
        &[]
    } else if target < Continuity::G2 || zoned {
        &[1, 2]
    } else {
        match side.cross_direction() {
            Direction::U => &[1, 2, 3],
            Direction::V => &[1, 2, 5],
        }
    }
}

impl Problem<'_> {
    /// Every sample's residuals on `s`, in sample order, with the slave's derivatives there
    /// (the normal equations of an accepted state reuse them).
    fn residual(&self, s: &BSplineSurface) -> (Vec<f64>, Vec<SurfaceDerivatives>) {
        let mut eval = s.evaluator();
        let mut r = Vec::with_capacity(self.samples.len() * RES);
        let mut derivatives = Vec::with_capacity(self.samples.len());
        for sm in &self.samples {
            let l = &self.links[sm.link];
            let ds = eval.derivatives(sm.u, sm.v);
            let w = &self.weights[r.len()..r.len() + RES];
            let res = residuals(&ds, sm, l.side, l.target, self.units);
            r.extend(res.iter().zip(w).map(|(x, w)| x * w));
            derivatives.push(ds);
        }
        (r, derivatives)
    }

    /// The derivatives of one sample's residuals with respect to each coordinate of each slave
    /// derivative vector ([`FIELDS`]), by central differences ([`DIFF_STEP`]), for the fields
    /// the residuals read ([`residual_fields`]): the others' differences are exactly zero and
    /// are not taken. The point enters the gap alone, whose difference is taken on its own.
    fn gradient(&self, ds: &SurfaceDerivatives, sm: &Sample) -> [[[f64; RES]; 3]; FIELDS] {
        let l = &self.links[sm.link];
        let mut g = [[[0.0; RES]; 3]; FIELDS];
        let scale = ds.du.norm().max(ds.dv.norm());
        let step = |base: &SurfaceDerivatives, f: usize| {
            let mut base = *base;
            DIFF_STEP * field(&mut base, f).norm().max(scale).max(f64::MIN_POSITIVE)
        };
        // the gap, (S − foot)/g0, is the only residual the point enters
        let h = step(ds, 0);
        for (d, gd) in g[0].iter_mut().enumerate() {
            let (plus, minus) = (ds.point[d] + h, ds.point[d] - h);
            gd[d] = ((plus - sm.foot[d]) / self.units.g0 - (minus - sm.foot[d]) / self.units.g0)
                / (2.0 * h);
        }
        for &f in residual_fields(l.side, l.target, sm.zoned) {
            let h = step(ds, f);
            for (d, gd) in g[f].iter_mut().enumerate() {
                let (mut plus, mut minus) = (*ds, *ds);
                field(&mut plus, f)[d] += h;
                field(&mut minus, f)[d] -= h;
                let rp = residuals(&plus, sm, l.side, l.target, self.units);
                let rm = residuals(&minus, sm, l.side, l.target, self.units);
                for q in 0..RES {
                    gd[q] = (rp[q] - rm[q]) / (2.0 * h);
                }
            }
        }
        g
    }

    /// One sample's Jacobian (sample `k`, slave derivatives `ds`): per moving point its basis
    /// reaches, its column block and the rows of its three coordinates — the chain of
    /// [`Self::gradient`] and the basis functions' derivatives (a point moved by δ moves S_kl
    /// by R_ij,kl δ).
    fn jacobian(&self, k: usize, ds: &SurfaceDerivatives, out: &mut Vec<(usize, [[f64; RES]; 3])>) {
        let g = self.gradient(ds, &self.samples[k]);
        let w = &self.weights[RES * k..RES * (k + 1)];
        out.clear();
        for &(c, coef) in &self.basis[k] {
            let mut rows = [[0.0; RES]; 3];
            for (d, row) in rows.iter_mut().enumerate() {
                for (f, &cf) in coef.iter().enumerate() {
                    for (x, gq) in row.iter_mut().zip(g[f][d]) {
                        *x += cf * gq;
                    }
                }
                for (x, wq) in row.iter_mut().zip(w) {
                    *x *= wq;
                }
            }
            out.push((c, rows));
        }
    }

    /// `s` with every moving point displaced by its block of `dx`.
    fn apply(&self, s: &BSplineSurface, dx: &[f64]) -> BSplineSurface {
        let mut out = s.clone();
        for (c, &(i, j)) in self.points.iter().enumerate() {
            let idx = out.index(i, j);
            out.control_points_mut()[idx] += Vector3::new(dx[3 * c], dx[3 * c + 1], dx[3 * c + 2]);
        }
        out
    }
}

/// Per sample, the moving points (`column`: per control index its column block) whose basis
/// function reaches it — some value or derivative up to order 2 not zero (at a clamped
/// boundary the functions of rows beyond 2 vanish exactly with their derivatives) — with those
/// values and derivatives ([`coefficients`]).
fn sample_basis(
    slave: &BSplineSurface,
    samples: &[Sample],
    column: &[Option<usize>],
) -> Vec<Vec<(usize, [f64; FIELDS])>> {
    let mut basis_eval = SurfaceBasisEvaluator::new(slave);
    let mut sb = SurfaceBasis::new(slave);
    samples
        .iter()
        .map(|sm| {
            basis_eval.eval(sm.u, sm.v, &mut sb);
            (0..sb.len())
                .filter_map(|q| {
                    let (i, j) = sb.control_index(q);
                    let c = column[slave.index(i, j)]?;
                    let coef = coefficients(&sb, q);
                    coef.iter().any(|&x| x != 0.0).then_some((c, coef))
                })
                .collect()
        })
        .collect()
}

impl<'a> Problem<'a> {
    /// The problem of `slave` and `links`: the moving points ([`unknowns`]), the samples
    /// ([`samples`]) and the tolerance units of `params`; an error for a tolerance that is not
    /// positive and finite.
    fn new(
        slave: &BSplineSurface,
        links: &'a [SideLink<'a>],
        params: &ConnectParams,
    ) -> Result<Self> {
        let t = params.tolerances;
        let flat = params
            .measure
            .flat_curvature
            .unwrap_or(1.0 / (FLAT_RADIUS_FACTOR * slave.size().max(f64::MIN_POSITIVE)));
        for (name, value) in [("g0", t.g0), ("g1_deg", t.g1_deg), ("g2_rel", t.g2_rel)] {
            if !(value > 0.0 && value.is_finite()) {
                return Err(crate::Error::InvalidParameter {
                    name,
                    value,
                    reason: "a tolerance of the joint polish must be positive and finite",
                });
            }
        }
        let columns = unknowns(slave, links, params);
        let mut column = vec![None; slave.control_points().len()];
        let mut points = vec![(0, 0); columns.len()];
        for (&(i, j), &c) in &columns {
            column[slave.index(i, j)] = Some(c);
            points[c] = (i, j);
        }
        let samples = samples(slave, links, params);
        let basis = sample_basis(slave, &samples, &column);
        let weights = vec![1.0; RES * samples.len()];
        Ok(Problem {
            links,
            samples,
            weights,
            basis,
            points,
            units: Units {
                g0: t.g0,
                g1: t.g1_deg.to_radians(),
                g2: t.g2_rel,
                flat: flat.max(f64::MIN_POSITIVE),
            },
        })
    }

    /// Whether every link of `s` meets its target by the measure of `params`.
    fn all_met(&self, s: &BSplineSurface, params: &ConnectParams) -> bool {
        let t = params.tolerances;
        self.links.iter().all(|l| {
            l.measure(s, &params.measure)
                .is_ok_and(|m| m.meets(l.target, t.g0, t.g1_deg, t.g2_rel))
        })
    }
}

/// Polishes the frames of `slave` (prepared, its staged continuity set) towards every link's
/// target at once: damped Gauss–Newton over rows 0..=r of every whole linked side (module
/// docs), no control point moving more than `max_move` from where it is in `slave` (a step
/// that would is rejected like one that raises the cost: the damping grows and the step
/// shrinks — a trust region on the moves; with R_ij ≥ 0 and Σ R_ij = 1 the surface then moves
/// at most `max_move` too), until every residual is within [`JOINT_GOAL`] of its tolerance or
/// every link meets its target by the measure of `params`, no step is accepted, or
/// [`JOINT_ITERATIONS`]; then, where links are still missed, in reweighted rounds
/// ([`JOINT_REWEIGHTS`]). Each accepted step lowers the sum of squared (weighted) residuals,
/// in tolerance units, at the polish's samples; whether the result is better for the model is
/// the caller's to judge. A `max_move` that is not positive is an error.
pub fn polish_joint(
    slave: &BSplineSurface,
    links: &[SideLink],
    params: &ConnectParams,
    max_move: f64,
) -> Result<(BSplineSurface, JointReport)> {
    crate::slave::check_links(links)?;
    crate::slave::check_rows(slave, links)?;
    if !(max_move > 0.0) {
        return Err(crate::Error::InvalidParameter {
            name: "max_move",
            value: max_move,
            reason: "the joint polish's move bound must be positive",
        });
    }
    let mut problem = Problem::new(slave, links, params)?;
    let (r, ds) = problem.residual(slave);
    let mut report = JointReport {
        worst_before: worst(&r),
        ..JointReport::default()
    };
    let mut lm = normal::Lm {
        pattern: problem.pattern(),
        symbolic: None,
        s: slave.clone(),
        r,
        ds,
        offset: vec![0.0; 3 * problem.points.len()],
    };
    report.iterations += problem.least_squares(&mut lm, JOINT_ITERATIONS, max_move, params)?;
    let unweighted = problem.unweighted(&lm.r);
    let w = worst(&unweighted);
    let (s, r) = if w <= JOINT_GOAL {
        (lm.s, lm.r)
    } else {
        let met = problem.met(&lm.s, params);
        let mut best = Round {
            met,
            worst: w,
            s: lm.s.clone(),
            r: unweighted.clone(),
        };
        report.iterations += problem.reweighted(
            &mut lm,
            (met, w, &unweighted),
            slave,
            max_move,
            params,
            &mut best,
        )?;
        (best.s, best.r)
    };
    report.worst_after = worst(&r);
    report.max_move = s
        .control_points()
        .iter()
        .zip(slave.control_points())
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max);
    Ok((s, report))
}

#[cfg(test)]
mod tests;
