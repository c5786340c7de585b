//! Measuring the numerical continuity of a link: a slave side on its master (\[SV\] §1.2, §4).
//!
//! At K samples t_k along the slave side (both ends included), with slave point S_k and master
//! point M_k = the closest point of the master (projection; the master may be trimmed):
//! - G0: the gap |S_k − M_k|;
//! - G1: the angle between the unit normals, atan2(|n_s × σ n_m|, n_s · σ n_m) in degrees, where
//!   σ = ±1 is the relative orientation of the two surfaces along the join (that of the majority
//!   of the samples): the figure does not depend on how either surface is oriented, but a normal
//!   that turns over along the join — next to a pole, a degenerate corner — shows as ≈ 180°;
//! - G2: the normal curvatures in the slave's cross-boundary direction d = S_u (u sides) or S_v
//!   (v sides): κ_s = II_s(d, d)/I_s(d, d) and κ_m = II_m(d, d)/I_m(d, d) of the master in the same
//!   3D direction (its tangential part), signed with respect to n_s (κ_m flips with σ);
//!   g2_abs = |κ_s − κ_m| and g2_rel = |κ_s − κ_m| / max(|κ_s|, |κ_m|), taken as 0 when both are
//!   below the flatness cut-off (the measure of CATIA's connect checker, model-format.md).
//!   Normal curvature is even in d, so the direction of d (into the slave) needs no sign fix.
//!
//! By the linkage curve theorem (Pegna–Wolter, \[SV\] §2) equal normal curvature in one
//! non-tangent direction along a G1 join means G2.
//!
//! # The checker's figures: across the boundary, vertices apart
//! The same pass also computes the figures an industry connect checker reports, and only
//! reports them: nothing is decided on them.
//! - [`LinkMeasure::g2_rel_across`], [`LinkMeasure::g2_abs_across`]: the same relative and
//!   absolute differences of the normal curvatures taken in the true cross-boundary direction
//!   d = n_s × T, T the slave side's tangent (S_v on u sides, S_u on v sides) — the plane normal
//!   to the boundary that CATIA's connect checker and Open CASCADE's continuity analysis
//!   measure in ([`cross_boundary_direction`]) — over the interior samples, every sample but
//!   the two ends;
//! - [`LinkMeasure::vertex_g1_deg`], [`LinkMeasure::vertex_g2_rel`]: the normal angle and the
//!   relative curvature difference (across, too) of the two end samples, the side's vertices,
//!   where the side meets the neighbouring side and its master, whose curvature may disagree
//!   with this master's (two fillets of different radii at a corner blend) so that no surface
//!   can be G2 to both there; a checker reports an edge's end points apart from its interior.
//!
//! Why both: the parametric figure ([`LinkMeasure::g2_rel`], d = S_u or S_v, every sample) is the
//! one the framework's row systems set (the G2 row of a sample prescribes the slave's curvature row
//! along its cross derivative) and the one every decision is taken on ([`LinkMeasure::meets`],
//! [`LinkMeasure::excess`]: refinement, the joint polish, which links are met). Along a G1 join the
//! two directions agree wherever S_u is perpendicular to the boundary, and an exactly G2 join reads
//! ≈ 0 both ways (linkage curve theorem); they differ where the parametrization is skewed — next to
//! a corner whose sides meet at a small angle, S_u runs almost along the boundary, and the
//! curvature along it is nearly the boundary's own, which both surfaces share by G1 whatever their
//! curvature across (a jump across shows in κ(S_u) only by sin² of the angle between S_u and T) —
//! and where the master is nearly straight across the boundary, so that a small absolute difference
//! is a large relative one. Measured on a kernel's lofted block (faired by default, K = 101, g2
//! tolerance 0.005): all 25 G2 links meet the parametric figure, while 13 read above 0.005 across,
//! every one of them a side of the four corner patches (C11, C12, C16, C17), whose cross
//! derivatives run 3–20° off the perpendicular to the side and whose masters are nearly straight
//! across (curvature radii of thousands of units on patches of size 6–7.5, the flatness cut-off a
//! radius of 1000 sizes): C11.v0 → F14 reads 0.0012 parametric and 1.50 across (κ across −1.5e-4
//! against 3.1e-4, of opposite sign, while along S_u both read −2.31e-3, the shared along-boundary
//! part), C12.v1 → F15 0.0039 against 1.44, C16.v0 → F18 0.0050 against 1.03, and C11.u0 → P13 (a
//! plane) 0 against 1 (the slave's curvature along S_u 2e-7, below the cut-off, across 3.5e-4,
//! above it). The vertex figures of the same corners reach 0.86 (C11.v0) and 1.8 (C12.u1 → F04).
//! The variable-radius box shows three such links (one corner patch), the three-radii corner one;
//! the other kernel models none.
//!
//! Samples where a normal is undefined (poles, degenerate points) are counted, not measured; a
//! side whose boundary is a single point is reported as collapsed with no G1/G2 value.
//!
//! # Tolerance
//! [`COLLAPSED_SIDE_RELATIVE`]: a side is collapsed when its control row spans less than this
//! times the slave size. [`FLAT_RADIUS_FACTOR`]: the default flatness cut-off is a curvature
//! radius of this many slave sizes.

use nurbs_core::{BSplineSurface, Direction, ProjectionParams, Side, SurfaceDerivatives, Vector3};

use crate::error::{Error, Result};
use crate::sampling::uniform_part_params;

/// A side whose control row spans less than this fraction of the slave size is a point (the
/// kernel's value, one for the workspace).
pub use nurbs_core::mesh::COLLAPSED_SIDE_RELATIVE;

/// Default flatness cut-off: curvatures below 1/(FLAT_RADIUS_FACTOR × slave size) count as zero
/// (a radius a thousand times the part is flat for every practical reflection line).
pub const FLAT_RADIUS_FACTOR: f64 = 1e3;

/// Default number of samples per side (K = 101: a sample every 1 % of the side).
pub const DEFAULT_SAMPLES: usize = 101;

/// Settings of a measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasureParams {
    /// Samples along the side, both ends included (default [`DEFAULT_SAMPLES`]).
    pub samples: usize,
    /// Curvature (1/model unit) below which a normal curvature counts as zero for g2_rel;
    /// `None`: 1/([`FLAT_RADIUS_FACTOR`] × slave size).
    pub flat_curvature: Option<f64>,
    /// Projection onto the master (kernel defaults).
    pub projection: ProjectionParams,
}

impl Default for MeasureParams {
    fn default() -> Self {
        Self {
            samples: DEFAULT_SAMPLES,
            flat_curvature: None,
            projection: ProjectionParams::default(),
        }
    }
}

/// One sample of a measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleMeasure {
    /// parameter along the slave side
    pub t: f64,
    /// master parameters (u, v) of the foot point
    pub master_params: (f64, f64),
    /// gap |S − M| (model units)
    pub gap: f64,
    /// normal angle in degrees, `None` where a normal is undefined
    pub angle_deg: Option<f64>,
    /// slave normal curvature in the cross direction (1/unit), signed w.r.t. the slave normal
    pub kappa_slave: Option<f64>,
    /// master normal curvature in the same direction, signed w.r.t. the slave normal
    pub kappa_master: Option<f64>,
    /// slave normal curvature in the true cross-boundary direction n_s × T
    /// ([`cross_boundary_direction`]; 1/unit), signed w.r.t. the slave normal; reported only
    pub kappa_slave_across: Option<f64>,
    /// master normal curvature in the direction n_s × T, signed w.r.t. the slave normal;
    /// reported only
    pub kappa_master_across: Option<f64>,
    /// inside a vertex zone of the link ([`crate::SideLink::g2_zones`]): its curvatures count
    /// with the vertex figures, and no decision takes them
    pub in_zone: bool,
}

/// Continuity of one link: the worst sample of each measure.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkMeasure {
    /// the slave side
    pub side: Side,
    /// number of samples
    pub samples: usize,
    /// true when the slave side is a single point (no G1/G2 there)
    pub collapsed: bool,
    /// largest gap (model units)
    pub g0: f64,
    /// parameter of the largest gap
    pub worst_g0_t: f64,
    /// largest normal angle (degrees); `None` when no sample has both normals
    pub g1_deg: Option<f64>,
    /// parameter of the largest angle
    pub worst_g1_t: Option<f64>,
    /// largest relative curvature difference; `None` when no sample has both curvatures
    pub g2_rel: Option<f64>,
    /// largest absolute curvature difference (1/unit)
    pub g2_abs: Option<f64>,
    /// parameter of the largest relative difference
    pub worst_g2_t: Option<f64>,
    /// largest relative curvature difference in the true cross-boundary direction n_s × T over
    /// the interior samples (all but the two ends), the checker's figure (module doc); `None`
    /// when no interior sample has both curvatures. Reported only: decisions take [`Self::g2_rel`]
    pub g2_rel_across: Option<f64>,
    /// largest absolute curvature difference in the direction n_s × T over the interior
    /// samples (1/unit); reported only
    pub g2_abs_across: Option<f64>,
    /// parameter of the largest interior relative difference across
    pub worst_g2_across_t: Option<f64>,
    /// larger normal angle of the two end samples, the side's vertices, and of the samples of
    /// its vertex zones (degrees); `None` when none has both normals; reported only
    pub vertex_g1_deg: Option<f64>,
    /// larger relative curvature difference in the direction n_s × T of the two end samples and
    /// of the samples of the vertex zones; `None` when none has both curvatures; reported only
    pub vertex_g2_rel: Option<f64>,
    /// lengths along the side (model units, the polyline through the samples) of the vertex
    /// zones at its start and end ([`crate::SideLink::g2_zones`]; 0: none), whose curvature
    /// figures count with [`Self::vertex_g2_rel`]
    pub vertex_zones: [f64; 2],
    /// samples where a normal (slave or master) is undefined
    pub undefined_normals: usize,
    /// samples where a normal curvature is undefined
    pub undefined_curvatures: usize,
    /// the samples themselves
    pub detail: Vec<SampleMeasure>,
}

impl LinkMeasure {
    /// The worst of its measures relative to its tolerance, up to `target` (G0: gap; G1: plus
    /// angle; G2: plus relative curvature): ≤ 1 where the link meets them. Undefined values
    /// (collapsed sides, poles) count as 0.
    pub fn excess(&self, target: nurbs_core::Continuity, g0: f64, g1_deg: f64, g2_rel: f64) -> f64 {
        use nurbs_core::Continuity::*;
        let mut e = self.g0 / g0;
        if target >= G1 {
            e = e.max(self.g1_deg.unwrap_or(0.0) / g1_deg);
        }
        if target >= G2 {
            e = e.max(self.g2_rel.unwrap_or(0.0) / g2_rel);
        }
        e
    }

    /// Whether the link meets the tolerances up to `target` (G0: gap; G1: plus angle; G2: plus
    /// relative curvature). Undefined values (collapsed sides, poles) do not count against it.
    pub fn meets(&self, target: nurbs_core::Continuity, g0: f64, g1_deg: f64, g2_rel: f64) -> bool {
        use nurbs_core::Continuity::*;
        let ok0 = self.g0 <= g0;
        let ok1 = self.g1_deg.is_none_or(|a| a <= g1_deg);
        let ok2 = self.g2_rel.is_none_or(|r| r <= g2_rel);
        match target {
            G0 => ok0,
            G1 => ok0 && ok1,
            G2 => ok0 && ok1 && ok2,
        }
    }
}

/// Spread of the control row of `side` (largest distance from its first point).
pub fn side_extent(slave: &BSplineSurface, side: Side) -> f64 {
    let row = side.row(0, slave.num_u(), slave.num_v());
    let first = slave.control_point(row[0].0, row[0].1);
    row.iter()
        .map(|&(i, j)| (slave.control_point(i, j) - first).norm())
        .fold(0.0, f64::max)
}

/// Whether `side` of `slave` is collapsed to a point.
pub fn is_collapsed(slave: &BSplineSurface, side: Side) -> bool {
    side_extent(slave, side) <= COLLAPSED_SIDE_RELATIVE * slave.size()
}

/// The slave's parametric cross-boundary derivative on `side` (S_u on u sides, S_v on v sides).
pub(crate) fn cross_derivative(d: &SurfaceDerivatives, side: Side) -> Vector3 {
    match side.cross_direction() {
        Direction::U => d.du,
        Direction::V => d.dv,
    }
}

/// The true cross-boundary direction of `side` at the slave point `d`: n_s × T, T the side's
/// tangent (S_v on u sides, S_u on v sides), scaled as the part of the cross derivative e
/// (S_u, S_v) perpendicular to T, d = e − (e·T/|T|²) T — which lies in the tangent plane and is
/// perpendicular to T, so parallel to n_s × T (normal curvature is even in d and does not depend
/// on its length). `None` where the normal is undefined (poles, degenerate points; a vanishing
/// T — a collapsed side — is one) or d vanishes.
pub fn cross_boundary_direction(d: &SurfaceDerivatives, side: Side) -> Option<Vector3> {
    d.normal()?;
    let (e, t) = match side.cross_direction() {
        Direction::U => (d.du, d.dv),
        Direction::V => (d.dv, d.du),
    };
    let tt = t.norm_squared();
    if !(tt > 0.0) {
        return None;
    }
    let dir = e - t * (e.dot(&t) / tt);
    (dir.norm_squared() > 0.0).then_some(dir)
}

/// Measures the link of `side` of `slave` on `master`: the master comes first, then the slave
/// whose side is measured.
///
/// Prefer [`SideLink::measure`](crate::SideLink::measure): a [`SideLink`](crate::SideLink)
/// names the slave's side and its master, and the slave is passed alone, so the two surfaces
/// cannot be swapped. This function stays for callers without a link at hand and gives the
/// same figures; swapped, it would measure the master's side against the slave instead.
///
/// ```
/// use g_continuity::{MeasureParams, SideLink, measure_link};
/// use nurbs_core::{Continuity, Point3, Side, Vector3, shapes::plane_patch};
/// // a flat master over x ∈ [0, 1] and a slave over x ∈ [1, 2] bent up by 10° at x = 1
/// let master = plane_patch(Point3::origin(), Vector3::x(), Vector3::y(), (0.0, 1.0), (0.0, 1.0))
///     .unwrap();
/// let (c, s) = (10f64.to_radians().cos(), 10f64.to_radians().sin());
/// let slave = plane_patch(Point3::new(1.0, 0.0, 0.0), Vector3::new(c, 0.0, s), Vector3::y(),
///     (0.0, 1.0), (0.0, 1.0)).unwrap();
/// let params = MeasureParams::default();
/// // preferred: the link names the slave's side and the master; the slave is passed alone
/// let link = SideLink { side: Side::U0, master: &master, target: Continuity::G1, range: None, g2_zones: [0.0; 2] };
/// let named = link.measure(&slave, &params).unwrap();
/// assert!(named.g0 < 1e-12 && (named.g1_deg.unwrap() - 10.0).abs() < 1e-6);
/// // the same figures, master first
/// assert_eq!(measure_link(&master, &slave, Side::U0, &params).unwrap(), named);
/// // swapped, the master's side u = 0 (at x = 0) is measured: a gap of about one unit
/// assert!(measure_link(&slave, &master, Side::U0, &params).unwrap().g0 > 0.9);
/// ```
pub fn measure_link(
    master: &BSplineSurface,
    slave: &BSplineSurface,
    side: Side,
    params: &MeasureParams,
) -> Result<LinkMeasure> {
    measure_link_on(master, slave, side, None, params)
}

/// [`measure_link`] over the part `range` of the side (an along-side parameter interval,
/// clipped to the side's domain; `None`: the whole side).
pub fn measure_link_on(
    master: &BSplineSurface,
    slave: &BSplineSurface,
    side: Side,
    range: Option<(f64, f64)>,
    params: &MeasureParams,
) -> Result<LinkMeasure> {
    measure_link_zoned(master, slave, side, range, [0.0; 2], params)
}

/// [`measure_link_on`] with vertex zones ([`crate::SideLink::g2_zones`]): the samples inside a
/// zone count as vertex samples — their curvature differences go to the vertex figures, not to
/// [`LinkMeasure::g2_rel`], [`LinkMeasure::g2_abs`] or the figures across — while their gap and
/// normal angle count as everywhere.
pub fn measure_link_zoned(
    master: &BSplineSurface,
    slave: &BSplineSurface,
    side: Side,
    range: Option<(f64, f64)>,
    zones: [f64; 2],
    params: &MeasureParams,
) -> Result<LinkMeasure> {
    let ts = uniform_part_params(slave, side, range, params.samples)?;
    let domain = crate::sampling::side_part(slave, side, range);
    let flat = flat_cut_off(slave, params)?;
    let collapsed = is_collapsed(slave, side);
    let mut m = LinkMeasure::unmeasured(side, &ts, collapsed);
    let pairs = measure_gaps(&mut m, master, slave, &ts, params.projection);
    let orientation = if collapsed {
        1.0
    } else {
        relative_orientation(&pairs)
    };
    let zoned = |t: f64| crate::sampling::in_zones(t, domain, zones);
    measure_normals(&mut m, &pairs, orientation, flat, &zoned);
    m.vertex_zones = zone_lengths(slave, side, domain, zones, &ts);
    Ok(m)
}

/// The lengths of the vertex zones `zones` (along-side parameter lengths at the start and end of
/// `domain`) on `slave`'s `side`: the polyline through the zone's end points and the samples
/// `ts` inside it.
fn zone_lengths(
    slave: &BSplineSurface,
    side: Side,
    (a, b): (f64, f64),
    zones: [f64; 2],
    ts: &[f64],
) -> [f64; 2] {
    let length = |from: f64, to: f64| {
        let mut params = vec![from];
        params.extend(ts.iter().copied().filter(|&t| t > from && t < to));
        params.push(to);
        let points: Vec<nurbs_core::Point3> = params
            .iter()
            .map(|&t| {
                let (u, v) = side.params(slave, t);
                slave.point(u, v)
            })
            .collect();
        points.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
    };
    [
        if zones[0] > 0.0 {
            length(a, (a + zones[0]).min(b))
        } else {
            0.0
        },
        if zones[1] > 0.0 {
            length((b - zones[1]).max(a), b)
        } else {
            0.0
        },
    ]
}

/// The flatness cut-off of a measurement: [`MeasureParams::flat_curvature`], or the curvature
/// of a radius of [`FLAT_RADIUS_FACTOR`] slave sizes; an error unless ≥ 0.
fn flat_cut_off(slave: &BSplineSurface, params: &MeasureParams) -> Result<f64> {
    let flat = params
        .flat_curvature
        .unwrap_or(1.0 / (FLAT_RADIUS_FACTOR * slave.size().max(f64::MIN_POSITIVE)));
    if !(flat >= 0.0) {
        return Err(Error::InvalidParameter {
            name: "flat_curvature",
            value: flat,
            reason: "must be ≥ 0",
        });
    }
    Ok(flat)
}

impl LinkMeasure {
    /// The measure of `side` at the parameters `ts` before any sample is taken: no gap, no
    /// angle, no curvature difference, no details.
    fn unmeasured(side: Side, ts: &[f64], collapsed: bool) -> Self {
        Self {
            side,
            samples: ts.len(),
            collapsed,
            g0: 0.0,
            worst_g0_t: ts[0],
            g1_deg: None,
            worst_g1_t: None,
            g2_rel: None,
            g2_abs: None,
            worst_g2_t: None,
            g2_rel_across: None,
            g2_abs_across: None,
            worst_g2_across_t: None,
            vertex_g1_deg: None,
            vertex_g2_rel: None,
            vertex_zones: [0.0; 2],
            undefined_normals: 0,
            undefined_curvatures: 0,
            detail: Vec::with_capacity(ts.len()),
        }
    }
}

/// The first pass of a measurement: at every parameter of `ts` the slave's point and its foot
/// on the master, the gap recorded in `m` (largest gap and a sample each); returns the slave's
/// and the master's derivatives there, in order.
fn measure_gaps(
    m: &mut LinkMeasure,
    master: &BSplineSurface,
    slave: &BSplineSurface,
    ts: &[f64],
    projection: ProjectionParams,
) -> Vec<(SurfaceDerivatives, SurfaceDerivatives)> {
    let mut slave_eval = slave.evaluator();
    let mut master_eval = master.evaluator();
    let slave_points: Vec<SurfaceDerivatives> = ts
        .iter()
        .map(|&t| {
            let (u, v) = m.side.params(slave, t);
            slave_eval.derivatives(u, v)
        })
        .collect();
    let points: Vec<nurbs_core::Point3> = slave_points.iter().map(|d| d.point).collect();
    let feet = crate::memo::project_side(master, projection, &points);
    let mut pairs = Vec::with_capacity(ts.len());
    for ((&t, ds), proj) in ts.iter().zip(slave_points).zip(feet) {
        let dm = master_eval.derivatives(proj.u, proj.v);
        if proj.distance > m.g0 {
            m.g0 = proj.distance;
            m.worst_g0_t = t;
        }
        m.detail.push(SampleMeasure {
            t,
            master_params: (proj.u, proj.v),
            gap: proj.distance,
            angle_deg: None,
            kappa_slave: None,
            kappa_master: None,
            kappa_slave_across: None,
            kappa_master_across: None,
            in_zone: false,
        });
        pairs.push((ds, dm));
    }
    pairs
}

/// The relative orientation σ = ±1 of the two normals along the join: that of the majority of
/// the samples (weighted by |n_s · n_m|), so that a normal turned over next to a pole or a
/// degenerate corner shows as an angle near 180° instead of being folded back to 0°.
fn relative_orientation(pairs: &[(SurfaceDerivatives, SurfaceDerivatives)]) -> f64 {
    let sum: f64 = pairs
        .iter()
        .filter_map(|(ds, dm)| ds.normal().zip(dm.normal()))
        .map(|(ns, nm)| ns.dot(&nm))
        .sum();
    if sum < 0.0 { -1.0 } else { 1.0 }
}

/// The relative and absolute difference of two normal curvatures, the relative one 0 where
/// both are below `flat`.
fn curvature_difference(ks: f64, km: f64, flat: f64) -> (f64, f64) {
    let abs = (ks - km).abs();
    let big = ks.abs().max(km.abs());
    let rel = if big < flat { 0.0 } else { abs / big };
    (rel, abs)
}

impl LinkMeasure {
    /// Records the relative and absolute curvature difference across the boundary `(rel, abs)`
    /// of the sample at `t`: with the vertex figure where the sample is a `vertex` (an end or in
    /// a vertex zone), else with the interior's figures across.
    fn record_across(&mut self, t: f64, vertex: bool, (rel, abs): (f64, f64)) {
        if vertex {
            if self.vertex_g2_rel.is_none_or(|r| rel > r) {
                self.vertex_g2_rel = Some(rel);
            }
            return;
        }
        if self.g2_abs_across.is_none_or(|a| abs > a) {
            self.g2_abs_across = Some(abs);
        }
        if self.g2_rel_across.is_none_or(|r| rel > r) {
            self.g2_rel_across = Some(rel);
            self.worst_g2_across_t = Some(t);
        }
    }
}

/// The second pass of a measurement: the normal angle and the normal curvatures of every
/// sample of `m` from its derivatives `pairs`, the master's normal turned by `orientation`,
/// curvatures below `flat` counting as zero in the relative difference; the checker's figures
/// (across the boundary, the vertices apart) from the same derivatives.
fn measure_normals(
    m: &mut LinkMeasure,
    pairs: &[(SurfaceDerivatives, SurfaceDerivatives)],
    orientation: f64,
    flat: f64,
    zoned: &dyn Fn(f64) -> bool,
) {
    let (side, collapsed) = (m.side, m.collapsed);
    let last = pairs.len().saturating_sub(1);
    let mut detail = std::mem::take(&mut m.detail);
    for (k, ((ds, dm), sample)) in pairs.iter().zip(detail.iter_mut()).enumerate() {
        let t = sample.t;
        let in_zone = zoned(t);
        sample.in_zone = in_zone;
        let vertex = k == 0 || k == last || in_zone;
        let normals = if collapsed {
            None
        } else {
            ds.normal().zip(dm.normal())
        };
        match normals {
            None => {
                m.undefined_normals += 1;
                if !collapsed {
                    m.undefined_curvatures += 1;
                }
            }
            Some((ns, nm)) => {
                let nm = nm * orientation;
                let angle = ns.cross(&nm).norm().atan2(ns.dot(&nm)).to_degrees();
                sample.angle_deg = Some(angle);
                if m.g1_deg.is_none_or(|a| angle > a) {
                    m.g1_deg = Some(angle);
                    m.worst_g1_t = Some(t);
                }
                if vertex && m.vertex_g1_deg.is_none_or(|a| angle > a) {
                    m.vertex_g1_deg = Some(angle);
                }
                let across = cross_boundary_direction(ds, side)
                    .and_then(|d| ds.normal_curvature(&d).zip(dm.normal_curvature(&d)));
                if let Some((ks, km)) = across {
                    let km = km * orientation;
                    sample.kappa_slave_across = Some(ks);
                    sample.kappa_master_across = Some(km);
                    m.record_across(t, vertex, curvature_difference(ks, km, flat));
                }
                let dir = cross_derivative(ds, side);
                match (ds.normal_curvature(&dir), dm.normal_curvature(&dir)) {
                    (Some(ks), Some(km)) => {
                        let km = km * orientation;
                        sample.kappa_slave = Some(ks);
                        sample.kappa_master = Some(km);
                        let (rel, abs) = curvature_difference(ks, km, flat);
                        if in_zone {
                            continue;
                        }
                        if m.g2_abs.is_none_or(|a| abs > a) {
                            m.g2_abs = Some(abs);
                        }
                        if m.g2_rel.is_none_or(|r| rel > r) {
                            m.g2_rel = Some(rel);
                            m.worst_g2_t = Some(t);
                        }
                    }
                    _ => m.undefined_curvatures += 1,
                }
            }
        }
    }
    m.detail = detail;
}

#[cfg(test)]
mod tests;
