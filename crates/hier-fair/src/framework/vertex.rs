//! Vertex conflicts: corners of a slave where two G2 links meet and their masters disagree in
//! curvature, so that no surface is G2 to both there ([SV] §3.3, the corner compatibility of two
//! sides, one order up from the twist).
//!
//! At a corner shared by sides A and B, both G1, G2 to B's master means the slave's second
//! fundamental form equals that master's at every point of B, the corner included (linkage curve
//! theorem, [SV] §2); so in A's cross direction d the slave's normal curvature there is κ_B(d),
//! and A's G2 asks κ_A(d). With the relative measure of `g_continuity::measure` and its
//! tolerance ρ, the best the slave can do at that point with its boundary on A's master is the
//! mean of the two, which meets both only when |κ_A − κ_B| ≤ 2ρ·max(|κ_A|, |κ_B|) or both are
//! below the flatness cut-off; beyond that only a boundary bent off its master near the corner
//! meets both (a curvature change Δκ over a length L costs a gap Δκ L²/2 and an angle Δκ L), which
//! the gap and angle tolerances allow for small Δκ only.

use super::*;

/// The flatness cut-off of the measure for `slave`: curvatures below it count as zero.
fn flat_curvature(slave: &BSplineSurface) -> f64 {
    1.0 / (g_continuity::measure::FLAT_RADIUS_FACTOR * slave.size())
}

/// The normal curvatures of the masters of `link` and `other` (adjacent sides) at the corner `t`
/// of `link`'s side, both in the slave's cross direction of `link` there and signed with
/// respect to the first master's normal. `None` where a normal is undefined.
fn masters_at_corner(
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

impl Job<'_> {
    /// Whether, at a corner of a missed G2 link's side where the neighbouring side is G2 too,
    /// the two masters disagree: their normal curvatures in the slave's cross direction at the
    /// corner point differ, so that no surface can be G2 to both at that point (two fillets of
    /// different radii meeting at a vertex blend's corner). The larger disagreement of the two
    /// corners is named when it accounts for at least half of the slave's largest miss along
    /// the side (wherever that lies: a corner conflict spreads over the spans next to the
    /// corner) and is above the flatness cut-off of the measure. Returns the phrase for the
    /// report.
    pub(super) fn vertex_conflict(
        &self,
        labelled: &[(usize, SideLink<'_>)],
        link: SideLink<'_>,
        slave: &BSplineSurface,
        m: &LinkMeasure,
    ) -> Option<String> {
        // the largest absolute difference (the relative figure peaks where both curvatures are
        // near the flatness cut-off)
        let worst = m
            .detail
            .iter()
            .filter_map(|x| Some((x.kappa_slave? - x.kappa_master?).abs()))
            .fold(0.0, f64::max);
        let (a, b) = link.side.along_domain(slave);
        let (start, end) = link.side.neighbours();
        let flat = flat_curvature(slave);
        let mut found: Option<(f64, f64, f64, Side, usize)> = None;
        for (t, neighbour) in [(a, start), (b, end)] {
            let Some((k, other)) = labelled
                .iter()
                .find(|(_, l)| l.side == neighbour && l.target >= Continuity::G2)
            else {
                continue;
            };
            let Some((k1, k2)) = masters_at_corner(slave, &link, other, t) else {
                continue;
            };
            let diff = (k1 - k2).abs();
            if found.is_none_or(|f| diff > f.0) {
                found = Some((diff, k1, k2, neighbour, *k));
            }
        }
        let (diff, k1, k2, neighbour, k) = found?;
        (diff >= 0.5 * worst && diff > flat).then(|| {
            format!(
                "; at its corner with {} ({}), the two masters differ in normal curvature across this side by {diff:.3e} (1/length unit, {k1:.3e} against {k2:.3e}): no surface is G2 to both at that point",
                neighbour.name(),
                self.model.link_label(k)
            )
        })
    }
}

impl Job<'_> {
    /// The contact lines that leave this surface's G2 corners ([`SetParams::contact_lines`]):
    /// at a corner of two G2 sides A and B whose B-master is linked G2 to the A-master
    /// along a side of its own that passes through the corner — a fillet on the plane its
    /// vertex blend also touches — the direction of that side's boundary curve there, the line
    /// along which the two masters touch and agree in curvature (a G1 join of the two masters
    /// leaves their curvatures apart along it, and then no slope of the slave's curvature
    /// matches both: no line is given). The corner passes through it when it lies within the
    /// G0 tolerance of that boundary (the gap at which a link counts as met).
    ///
    /// [`SetParams::contact_lines`]: g_continuity::SetParams::contact_lines
    pub(super) fn contact_lines(&self) -> [[Option<[f64; 3]>; 2]; 4] {
        let mut out = [[None; 2]; 4];
        let me = self.start;
        let links = self.links();
        let g2 = |side: Side| {
            links.iter().find(|(_, l)| {
                l.side == side
                    && l.target >= Continuity::G2
                    && l.range.is_none()
                    && !g_continuity::measure::is_collapsed(me, side)
            })
        };
        let params = nurbs_core::ProjectionParams::default();
        for (ka, a) in links.iter().filter_map(|(_, l)| g2(l.side)) {
            let a_master = self.model.links[*ka].master;
            let k = Side::ALL.iter().position(|&s| s == a.side).unwrap_or(0);
            let (t0, t1) = a.side.along_domain(me);
            let (start, end) = a.side.neighbours();
            for (e, (t, adj)) in [(t0, start), (t1, end)].into_iter().enumerate() {
                let Some((kb, _)) = g2(adj) else {
                    continue;
                };
                let b_master = self.model.links[*kb].master;
                let mb = &self.current.surfaces[b_master].surface;
                let (u, v) = a.side.params(me, t);
                let corner = me.point(u, v);
                let foot = nurbs_core::project_to_surface(mb, &corner, &params);
                for contact in self.model.links.iter().filter(|x| {
                    x.slave == b_master && x.master == a_master && x.continuity >= Continuity::G2
                }) {
                    // the boundary point of that side at the foot's along parameter
                    let in_u = contact.side.along_direction() == Direction::U;
                    let (bu, bv) = contact.side.params(mb, if in_u { foot.u } else { foot.v });
                    let d = mb.derivatives(bu, bv);
                    if (d.point - corner).norm() > self.model.tolerances.g0 {
                        continue;
                    }
                    let line = if in_u { d.du } else { d.dv };
                    out[k][e] = Some([line.x, line.y, line.z]);
                }
            }
        }
        out
    }
}

/// Whether some corner of `slave` joins two G2 links whose masters disagree beyond what the
/// relative tolerance `rho` lets one surface meet at that point (module doc), in either side's
/// cross direction. The slave can still meet both where the disagreement is small, by bending
/// its boundary off its own master near the corner within the gap and angle tolerances (the
/// corner curvature equation of `g_continuity::rows`); what it rules out is that the width of
/// a curvature lead-in decides, so no narrower one is tried.
pub(super) fn incompatible_corner(
    links: &[SideLink<'_>],
    slave: &BSplineSurface,
    rho: f64,
) -> bool {
    let flat = flat_curvature(slave);
    let g2 = |side: Side| {
        links.iter().find(|l| {
            l.side == side
                && l.target >= Continuity::G2
                && l.range.is_none()
                && !g_continuity::measure::is_collapsed(slave, side)
        })
    };
    links.iter().filter_map(|l| g2(l.side)).any(|link| {
        let (a, b) = link.side.along_domain(slave);
        let (start, end) = link.side.neighbours();
        [(a, start), (b, end)].into_iter().any(|(t, neighbour)| {
            g2(neighbour)
                .and_then(|other| masters_at_corner(slave, link, other, t))
                .is_some_and(|(k1, k2)| {
                    let big = k1.abs().max(k2.abs());
                    big > flat && (k1 - k2).abs() > 2.0 * rho * big
                })
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs_core::shapes::{arc, extrude_curve, plane_patch};
    use nurbs_core::{Point3, Vector3};

    /// The plane z = 0 over [−2, 2]².
    fn ground() -> BSplineSurface {
        plane_patch(
            Point3::origin(),
            Vector3::x(),
            Vector3::y(),
            (-2.0, 2.0),
            (-2.0, 2.0),
        )
        .unwrap()
    }

    /// A cylinder of radius `r` touching z = 0 along the y axis: normal curvature 1/r in x, 0 in
    /// y at the origin.
    fn roller(r: f64) -> BSplineSurface {
        let c = arc(
            Point3::new(0.0, 0.0, r),
            -Vector3::z(),
            Vector3::x(),
            r,
            -0.5,
            0.5,
        )
        .unwrap();
        extrude_curve(&c, Vector3::y(), (-2.0, 2.0)).unwrap()
    }

    /// The unit square in z = 0 with G2 links on u0 and v0 (corner at the origin) to `a`, `b`.
    fn corner_of(a: &BSplineSurface, b: &BSplineSurface) -> bool {
        let slave = plane_patch(
            Point3::origin(),
            Vector3::x(),
            Vector3::y(),
            (0.0, 1.0),
            (0.0, 1.0),
        )
        .unwrap();
        let link = |side, master| SideLink {
            side,
            master,
            target: Continuity::G2,
            range: None,
        };
        incompatible_corner(&[link(Side::U0, a), link(Side::V0, b)], &slave, 5e-3)
    }

    #[test]
    fn masters_of_different_curvature_at_a_corner_rule_g2_out() {
        let (plane, cylinder) = (ground(), roller(5.0));
        assert!(corner_of(&plane, &cylinder));
        assert!(corner_of(&cylinder, &plane));
        // the same curvature on both sides, or curvatures below the flatness cut-off, are no
        // conflict
        assert!(!corner_of(&plane, &plane));
        assert!(!corner_of(&cylinder, &cylinder));
        assert!(!corner_of(&plane, &roller(1e5)));
    }
}
