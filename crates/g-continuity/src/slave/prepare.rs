//! Making a slave ready for its rows to move (\[SV\] §3.2 step 1): clamped, weights that are all
//! equal dropped, the degree raised across each linked side (G_r needs degree ≥ r) and along it
//! (knots inserted there later must not become creases), the curvature lead-in of G2 sides, the
//! master's knots carried in, and control rows enough for the frames of two opposite sides. The
//! shape is unchanged (rational slaves stay rational).

use nurbs_core::{BSplineSurface, Direction, Side};

use super::status::{level, levels_of};
use super::{ConnectReport, SideLink, check_links};
use crate::error::Result;
use crate::params::ConnectParams;

/// Makes a slave ready for the staged framework (\[SV\] §3.2 step 1): clamped, of sufficient
/// degree and with enough control rows for the frames of all its `links`, with the curvature
/// lead-in of [`ConnectParams::lead_in`] at its G2 sides. The shape is unchanged (rational
/// slaves stay rational).
pub fn prepare_slave(
    slave: &BSplineSurface,
    links: &[SideLink],
    params: &ConnectParams,
) -> Result<(BSplineSurface, ConnectReport)> {
    check_links(links)?;
    let mut report = ConnectReport::default();
    let s = prepare(slave, links, params, &mut report)?;
    Ok((s, report))
}

/// Makes the slave clamped, of sufficient degree and with enough control rows. A rational slave
/// stays rational with its weights (the row equations take them, [`crate::sampling::SideBasis`]);
/// only weights that are all equal are dropped, which is exact.
pub(super) fn prepare(
    slave: &BSplineSurface,
    links: &[SideLink],
    params: &ConnectParams,
    report: &mut ConnectReport,
) -> Result<BSplineSurface> {
    let mut s = drop_equal_weights(slave.clamped()?, report)?;
    s = raise_cross_degrees(s, links, report)?;
    s = raise_along_degrees(s, links, report)?;
    if let Some(width) = params.lead_in {
        s = add_lead_in(s, links, width, report)?;
    }
    if params.transfer_knots {
        s = add_master_knots(s, slave, links, params, report)?;
    }
    s = add_zone_knots(s, links, report)?;
    add_control_rows(s, links, report)
}

/// Distinct knots a vertex zone holds ([`SideLink::g2_zones`]), at 1/3, 2/3 and the whole of
/// its length from its corner (where the slave has none there yet): the frame of the
/// neighbouring side at that corner is its first three control columns, whose B-spline support
/// ends at the third distinct knot from the corner, so with three knots inside the zone the G2
/// rows beyond it move points the corner's frame does not hold — G2 can be met on the rest of
/// the side whatever the corner asks.
pub const ZONE_KNOTS: usize = 3;

/// `s` with [`ZONE_KNOTS`] knots inside each vertex zone of `links`.
fn add_zone_knots(
    mut s: BSplineSurface,
    links: &[SideLink],
    report: &mut ConnectReport,
) -> Result<BSplineSurface> {
    for l in links.iter().filter(|l| l.g2_zones.iter().any(|&z| z > 0.0)) {
        let dir = l.side.along_direction();
        let (a, b) = l.domain(&s);
        let mut xs = Vec::new();
        for k in 1..=ZONE_KNOTS {
            let f = k as f64 / ZONE_KNOTS as f64;
            if l.g2_zones[0] > 0.0 {
                xs.push(a + f * l.g2_zones[0]);
            }
            if l.g2_zones[1] > 0.0 {
                xs.push(b - f * l.g2_zones[1]);
            }
        }
        let knots = crate::knots::new_breakpoints(&s, dir, &xs);
        if !knots.is_empty() {
            s = s.refine(dir, &knots)?;
            report.knots_inserted += knots.len();
        }
    }
    Ok(s)
}

/// The degree of `s` in direction `dir`.
fn degree_in(s: &BSplineSurface, dir: Direction) -> usize {
    match dir {
        Direction::U => s.degree_u(),
        Direction::V => s.degree_v(),
    }
}

impl ConnectReport {
    /// Counts a degree elevation by `by` in direction `dir`.
    fn count_elevation(&mut self, dir: Direction, by: usize) {
        match dir {
            Direction::U => self.degree_elevation.0 += by,
            Direction::V => self.degree_elevation.1 += by,
        }
    }

    /// Counts the knots inserted and the degree elevation (u, v) of a preparation step.
    fn count_added(&mut self, knots_inserted: usize, degree_elevation: (usize, usize)) {
        self.knots_inserted += knots_inserted;
        self.degree_elevation.0 += degree_elevation.0;
        self.degree_elevation.1 += degree_elevation.1;
    }
}

/// `s` without its weights when they are all equal (exact), else `s` itself.
fn drop_equal_weights(mut s: BSplineSurface, report: &mut ConnectReport) -> Result<BSplineSurface> {
    if let Some(w) = s.weights()
        && w.iter().all(|&x| x == w[0])
    {
        s = BSplineSurface::new(
            s.knots_u().clone(),
            s.knots_v().clone(),
            s.control_points().to_vec(),
            None,
        )?;
        report.made_polynomial = true;
    }
    Ok(s)
}

/// `s` with the degree across each linked side raised to the row its target sets (G_r: r).
fn raise_cross_degrees(
    mut s: BSplineSurface,
    links: &[SideLink],
    report: &mut ConnectReport,
) -> Result<BSplineSurface> {
    for dir in [Direction::U, Direction::V] {
        let need_degree = links
            .iter()
            .filter(|l| l.side.cross_direction() == dir)
            .map(|l| level(l.target))
            .max()
            .unwrap_or(0);
        let degree = degree_in(&s, dir);
        if need_degree > degree {
            s = s.elevate_degree(dir, need_degree - degree)?;
            report.count_elevation(dir, need_degree - degree);
        }
    }
    Ok(s)
}

/// `s` with the degree along each linked side raised to nurbs-core's `SMOOTH_JOIN_DEGREE`.
/// The refinement rounds insert knots along the linked sides (the master's knots too): a
/// low-degree along direction (a plane's, a cylinder's axis) is raised first, so that those
/// knots do not become creases once the rows move.
fn raise_along_degrees(
    mut s: BSplineSurface,
    links: &[SideLink],
    report: &mut ConnectReport,
) -> Result<BSplineSurface> {
    for l in links {
        let dir = l.side.along_direction();
        let degree = degree_in(&s, dir);
        if degree < nurbs_core::ops::SMOOTH_JOIN_DEGREE {
            s = s.with_smooth_joins(dir)?;
            report.count_elevation(dir, nurbs_core::ops::SMOOTH_JOIN_DEGREE - degree);
        }
    }
    Ok(s)
}

/// `s` with the curvature lead-in of `width` at its G2 sides ([`crate::lead_in`]).
fn add_lead_in(
    s: BSplineSurface,
    links: &[SideLink],
    width: f64,
    report: &mut ConnectReport,
) -> Result<BSplineSurface> {
    let (more, lead) = crate::lead_in::with_lead_in(&s, links, width)?;
    report.count_added(lead.knots_inserted, lead.degree_elevation);
    Ok(more)
}

/// `s` with each master's knots and degree carried in along the join where `slave` (the input)
/// is a single polynomial piece along it ([`crate::transfer`]).
fn add_master_knots(
    s: BSplineSurface,
    slave: &BSplineSurface,
    links: &[SideLink],
    params: &ConnectParams,
    report: &mut ConnectReport,
) -> Result<BSplineSurface> {
    let single_piece = [
        slave.knots_u().interior_knots().is_empty(),
        slave.knots_v().interior_knots().is_empty(),
    ];
    let (more, moved) = crate::transfer::with_master_knots(
        &s,
        links,
        single_piece,
        params.max_control_points,
        params.measure.projection,
    )?;
    report.count_added(moved.knots_inserted, moved.degree_elevation);
    Ok(more)
}

/// `s` with knots across where it has too few control rows for the frames of its two opposite
/// sides (row r + 1 of each G_r side, one row of an unlinked side).
fn add_control_rows(
    mut s: BSplineSurface,
    links: &[SideLink],
    report: &mut ConnectReport,
) -> Result<BSplineSurface> {
    let levels = levels_of(links);
    for (dir, a, b) in [
        (Direction::U, Side::U0, Side::U1),
        (Direction::V, Side::V0, Side::V1),
    ] {
        let need = levels[a.index()].map_or(1, |l| l + 1) + levels[b.index()].map_or(1, |l| l + 1);
        let (more, inserted) = s.with_smooth_control_count(dir, need)?;
        s = more;
        report.knots_inserted += inserted;
    }
    Ok(s)
}
