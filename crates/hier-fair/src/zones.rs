//! Vertex zones: where the masters of two G2 sides of a slave disagree in curvature at their
//! common corner beyond what one surface can meet there (\[SV\] §3.3, the corner compatibility of
//! two sides one order up from the twist), G2 is set and judged on the rest of each side and
//! relaxed within a short stretch next to that corner ([`g_continuity::SideLink::g2_zones`]);
//! the stretch's curvature figures are reported apart, as the vertex figures.
//!
//! At a corner shared by sides A and B, both G1, G2 to B's master means the slave's second
//! fundamental form equals that master's at every point of B, the corner included (linkage
//! curve theorem, \[SV\] §2); so in A's cross direction d the slave's normal curvature there is
//! κ_B(d), and A's G2 asks κ_A(d). With the relative measure of `g_continuity::measure` and its
//! tolerance ρ, the best one surface can do at that point is the mean of the two, which meets
//! both only when |κ_A − κ_B| ≤ 2ρ·max(|κ_A|, |κ_B|) or both are below the flatness cut-off.
//! The zones are a function of the model alone — the masters at the slave's corners — so the
//! framework's steps, its reports and `check` judge a link on the same samples.

use g_continuity::{SideLink, Tolerances};
use nurbs_core::{BSplineSurface, Continuity, Direction, Side};

use crate::model::Model;

/// The flatness cut-off of the measure for `slave`: curvatures below it count as zero.
pub fn flat_curvature(slave: &BSplineSurface) -> f64 {
    1.0 / (g_continuity::measure::FLAT_RADIUS_FACTOR * slave.size())
}

/// The normal curvatures of the masters of `link` and `other` (adjacent sides) at the corner `t`
/// of `link`'s side, both in the slave's cross direction of `link` there and signed with
/// respect to the first master's normal. `None` where a normal is undefined.
pub fn masters_at_corner(
    slave: &BSplineSurface,
    link: &SideLink<'_>,
    other: &SideLink<'_>,
    t: f64,
) -> Option<(f64, f64)> {
    let params = nurbs_core::ProjectionParams::default();
    let (u, v) = link.side.params(slave, t);
    let d = slave.derivatives(u, v);
    let dir = match link.side.cross_direction() {
        Direction::U => d.du,
        Direction::V => d.dv,
    };
    let curvature = |master: &BSplineSurface| {
        let f = nurbs_core::project_to_surface(master, &d.point, &params);
        let dm = master.derivatives(f.u, f.v);
        Some((dm.normal_curvature(&dir)?, dm.normal()?))
    };
    let (k1, n1) = curvature(link.master)?;
    let (k2, n2) = curvature(other.master)?;
    Some((k1, if n1.dot(&n2) < 0.0 { -k2 } else { k2 }))
}

/// Length of a vertex zone, as a fraction of its side's along-side domain: 1/20. Where the
/// masters of two G2 sides disagree at their corner beyond what one surface can meet (module
/// doc), G2 is set and judged on the rest of each side and relaxed within this stretch next to
/// the corner ([`g_continuity::SideLink::g2_zones`]). Its length is set by what decides G2: the
/// measure's K = 101 samples put five of them in a zone, so the zone is more than a sample next
/// to the vertex, and the slave's knots inside it ([`g_continuity::slave::ZONE_KNOTS`]) let the
/// curvature turn from one master's to the other's there while everything beyond is free of
/// the corner's frame.
pub const VERTEX_ZONE: f64 = 0.05;

/// A corner where the masters of two G2 sides disagree ([`conflicted_ends`]): the neighbouring
/// side through it, and the normal curvatures of this side's master and of the neighbour's
/// there, in this side's cross direction (1/model unit, signed with respect to this master's
/// normal).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CornerConflict {
    /// the slave's side that meets this one at the corner
    pub neighbour: Side,
    /// this side's master's normal curvature there
    pub kappa: f64,
    /// the neighbouring side's master's
    pub kappa_other: f64,
}

/// Where the masters of G2 sides meeting at a corner of `slave` disagree there beyond what the
/// relative tolerance `rho` lets one surface meet at that point ([module doc](self)), per link of
/// `links` and end of its side (start, end): in that link's cross direction, against the master
/// of the neighbouring side at that end. Links over part of a side, collapsed sides and targets
/// below G2 have no such end.
pub fn conflicted_ends(
    links: &[SideLink<'_>],
    slave: &BSplineSurface,
    rho: f64,
) -> Vec<[Option<CornerConflict>; 2]> {
    let flat = flat_curvature(slave);
    let g2 = |side: Side| {
        links.iter().find(|l| {
            l.side == side
                && l.target >= Continuity::G2
                && l.range.is_none()
                && !g_continuity::measure::is_collapsed(slave, side)
        })
    };
    links
        .iter()
        .map(|l| {
            let Some(link) = g2(l.side).filter(|x| std::ptr::eq(*x, l)) else {
                return [None; 2];
            };
            let (a, b) = link.side.along_domain(slave);
            let (start, end) = link.side.neighbours();
            [(a, start), (b, end)].map(|(t, neighbour)| {
                let other = g2(neighbour)?;
                let (k1, k2) = masters_at_corner(slave, link, other, t)?;
                let big = k1.abs().max(k2.abs());
                (big > flat && (k1 - k2).abs() > 2.0 * rho * big).then_some(CornerConflict {
                    neighbour,
                    kappa: k1,
                    kappa_other: k2,
                })
            })
        })
        .collect()
}

/// Samples of a side's boundary for its length (the polyline through them; a zone's length
/// needs two digits, and 33 points take a quarter circle's to 1e-4).
const LENGTH_SAMPLES: usize = 33;

/// The length of `side` of `slave` (polyline through [`LENGTH_SAMPLES`] points).
fn side_length(slave: &BSplineSurface, side: Side) -> f64 {
    let (a, b) = side.along_domain(slave);
    let points: Vec<nurbs_core::Point3> = (0..LENGTH_SAMPLES)
        .map(|i| {
            let t = a + (b - a) * i as f64 / (LENGTH_SAMPLES - 1) as f64;
            let (u, v) = side.params(slave, t);
            slave.point(u, v)
        })
        .collect();
    points.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}

/// Whether the disagreement `c` at a corner of a side of length `length` needs a vertex zone:
/// where the boundary can instead bend off its own master within the gap and angle tolerances
/// `tol` over the zone's length L, the continuity steps meet both masters at the corner without
/// one (a curvature change Δκ over L costs an angle Δκ L and a gap Δκ L²/2: the corner
/// curvature equation of `g_continuity::rows`, with which the kernel's lofted blocks meet
/// every link at corners whose masters differ by 9 %).
pub fn needs_zone(c: &CornerConflict, length: f64, tol: &Tolerances) -> bool {
    let dk = (c.kappa - c.kappa_other).abs();
    let l = VERTEX_ZONE * length;
    dk * l > tol.g1_deg.to_radians() || 0.5 * dk * l * l > tol.g0
}

/// `links` with their vertex zones set ([`VERTEX_ZONE`] of the side at each conflicted end,
/// [`conflicted_ends`], that the boundary cannot bend to within the tolerances `tol`,
/// [`needs_zone`]).
pub fn with_vertex_zones<'a>(
    mut links: Vec<SideLink<'a>>,
    slave: &BSplineSurface,
    tol: &Tolerances,
) -> Vec<SideLink<'a>> {
    let ends = conflicted_ends(&links, slave, tol.g2_rel);
    for (l, e) in links.iter_mut().zip(ends) {
        if e.iter().all(Option::is_none) {
            continue;
        }
        let (a, b) = l.side.along_domain(slave);
        let length = side_length(slave, l.side);
        l.g2_zones = e.map(|c| {
            if c.is_some_and(|c| needs_zone(&c, length, tol)) {
                VERTEX_ZONE * (b - a)
            } else {
                0.0
            }
        });
    }
    links
}

/// The links of the slave of link `k` of `model` (each over its part `ranges[i]` where given)
/// and the position of `k` among them.
fn slave_links<'m>(
    model: &'m Model,
    ranges: &[Option<(f64, f64)>],
    k: usize,
) -> (Vec<SideLink<'m>>, Option<usize>) {
    let ks = model.links_of_slave(model.links[k].slave);
    let links = ks
        .iter()
        .map(|&i| {
            let l = &model.links[i];
            SideLink {
                side: l.side,
                master: &model.surfaces[l.master].surface,
                target: l.continuity,
                range: ranges.get(i).copied().flatten(),
                g2_zones: [0.0; 2],
            }
        })
        .collect();
    (links, ks.iter().position(|&i| i == k))
}

/// The conflicted corners of link `k` of `model` at the start and end of its side
/// ([`conflicted_ends`] over the links of its slave).
pub fn link_conflicts(
    model: &Model,
    ranges: &[Option<(f64, f64)>],
    k: usize,
    rho: f64,
) -> [Option<CornerConflict>; 2] {
    let (links, at) = slave_links(model, ranges, k);
    let slave = &model.surfaces[model.links[k].slave].surface;
    at.map_or([None; 2], |p| conflicted_ends(&links, slave, rho)[p])
}

/// The vertex zones of link `k` of `model` ([`with_vertex_zones`] over the links of its slave),
/// in the along-side parameter.
pub fn link_zones(
    model: &Model,
    ranges: &[Option<(f64, f64)>],
    k: usize,
    tol: &Tolerances,
) -> [f64; 2] {
    let (links, at) = slave_links(model, ranges, k);
    let slave = &model.surfaces[model.links[k].slave].surface;
    at.map_or([0.0; 2], |p| {
        with_vertex_zones(links, slave, tol)[p].g2_zones
    })
}
