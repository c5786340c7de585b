//! Vertex conflicts in the report, and the contact lines of a slave's corners: where two G2
//! links meet at a corner whose masters disagree in curvature beyond what one surface can meet
//! there (\[SV\] §3.3; [`crate::zones`] has the condition and the vertex zones that relax G2 next
//! to such a corner), the phrase that names a missed link's corner and the conflict problems of
//! the zones; where the masters touch along a line through the corner, the direction the
//! slave's boundary leaves it in.

use g_continuity::{LinkMeasure, SideLink};
use nurbs_core::{BSplineSurface, Continuity, Direction, Side};

use super::{Job, LinkFair, Problem, ProblemKind, report};
use crate::model::Model;
use crate::zones::{conflicted_ends, flat_curvature, masters_at_corner};

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
            .filter(|x| !x.in_zone)
            .filter_map(|x| Some((x.kappa_slave? - x.kappa_master?).abs()))
            .fold(0.0, f64::max);
        let (a, b) = link.side.along_domain(slave);
        let (start, end) = link.side.neighbours();
        let flat = flat_curvature(slave);
        let mut found: Option<(f64, f64, f64, Side, usize)> = None;
        // a corner with a vertex zone is relaxed there already ([`crate::zones`])
        for (e, (t, neighbour)) in [(a, start), (b, end)].into_iter().enumerate() {
            if link.g2_zones[e] > 0.0 {
                continue;
            }
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
    /// G0 tolerance of that boundary (the gap at which a link counts as met). A B-master that
    /// is the next part of the slave's own ring gives none ([`across_a_seam`]).
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
            let k = a.side.index();
            let (t0, t1) = a.side.along_domain(me);
            let (start, end) = a.side.neighbours();
            for (e, (t, adj)) in [(t0, start), (t1, end)].into_iter().enumerate() {
                let Some((kb, _)) = g2(adj) else {
                    continue;
                };
                let b_master = self.model.links[*kb].master;
                if across_a_seam(self.model, self.surface, b_master) {
                    continue;
                }
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

/// Whether `master` is a part of `slave`'s own ring, linked to it across their seam
/// ([`super::seams`]): a master of the slave's own role outside any corner group they share
/// (the quads of an n-sided corner are linked to each other too, and there the rule is meant).
/// Its contact line with the common master continues the slave's own boundary, so turning the
/// slave's boundary onto it (the contact-line rule, [`Job::contact_lines`]) would only fold the
/// seam's own mismatch into the boundary's first span: on a metre part's fillet ring that made
/// two parts peak at 46–48× their input's curvature, which they no longer do
/// (docs/benchmarks.md).
fn across_a_seam(model: &Model, slave: usize, master: usize) -> bool {
    let one_group = model
        .corners
        .iter()
        .any(|g| g.patches.contains(&slave) && g.patches.contains(&master));
    model.surfaces[master].role == model.surfaces[slave].role && !one_group
}

/// The named conflicts of the vertex zones ([`crate::zones`]) on `out` (the faired model with
/// its links' parts `ranges`): for every link of `links` that has a zone, its length along the
/// side, the corner and the two masters' normal curvatures there, and what the zone reads.
pub(super) fn zone_problems(
    out: &Model,
    ranges: &[Option<(f64, f64)>],
    links: &[LinkFair],
    rho: f64,
) -> Vec<Problem> {
    let mut problems = Vec::new();
    for l in links.iter().filter(|l| l.target >= Continuity::G2) {
        let Some(m) = &l.after else { continue };
        let conflicts = crate::zones::link_conflicts(out, ranges, l.link, rho);
        for (zone, conflict) in m.vertex_zones.iter().zip(conflicts) {
            let Some(c) = conflict.filter(|_| *zone > 0.0) else {
                continue;
            };
            let slave = out.links[l.link].slave;
            let other = out
                .links_of_slave(slave)
                .into_iter()
                .find(|&i| out.links[i].side == c.neighbour)
                .map_or_else(|| c.neighbour.name().to_string(), |i| out.link_label(i));
            problems.push(Problem {
                kind: ProblemKind::Conflict,
                surface: out.surfaces[slave].name.clone(),
                link: Some(out.link_label(l.link)),
                message: format!(
                    "G2 relaxed within {} at its corner with {} ({other}), {}: there the two masters differ in normal curvature across this side by {:.3e} (1/length unit, {:.3e} against {:.3e}), and no surface is G2 to both at that point; the zone reads {:.3e} relative",
                    report::length(*zone),
                    c.neighbour.name(),
                    if l.met { "met along the rest of the side" } else { "the rest of the side as measured" },
                    (c.kappa - c.kappa_other).abs(),
                    c.kappa,
                    c.kappa_other,
                    m.vertex_g2_rel.unwrap_or(0.0),
                ),
                amount: Some(*zone),
            });
        }
    }
    problems
}

/// Whether some corner of `slave` joins two G2 links whose masters disagree beyond what the
/// relative tolerance `rho` lets one surface meet at that point ([`conflicted_ends`]). The
/// slave can still meet both where the disagreement is small, by bending its boundary off its
/// own master near the corner within the gap and angle tolerances (the corner curvature
/// equation of `g_continuity::rows`); what it rules out is that the width of a curvature
/// lead-in decides, so no narrower one is tried.
pub(super) fn incompatible_corner(
    links: &[SideLink<'_>],
    slave: &BSplineSurface,
    rho: f64,
) -> bool {
    conflicted_ends(links, slave, rho)
        .iter()
        .flatten()
        .any(Option::is_some)
}

#[cfg(test)]
mod tests {
    use g_continuity::SideLink;
    use nurbs_core::shapes::{arc, extrude_curve, plane_patch};
    use nurbs_core::{BSplineSurface, Continuity, Point3, Side, Vector3};

    use super::{across_a_seam, incompatible_corner};

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
            g2_zones: [0.0; 2],
        };
        incompatible_corner(&[link(Side::U0, a), link(Side::V0, b)], &slave, 5e-3)
    }

    #[test]
    fn a_master_of_the_slave_s_own_role_is_across_a_seam() {
        let square = |role: &str, x: f64| {
            serde_json::json!({"name": format!("{role}{x}"), "role": role, "surface": {
                "degree_u": 1, "degree_v": 1, "control_points":
                [[[x, 0, 0], [x, 1, 0]], [[x + 1.0, 0, 0], [x + 1.0, 1, 0]]]}})
        };
        let json = serde_json::json!({"surfaces": [
            square("primary", 0.0), square("connecting", 1.0), square("connecting", 2.0),
            square("corner", 3.0), square("corner", 4.0), square("corner", 5.0)],
            "corners": [{"name": "hole", "patches": ["corner4", "corner5"]}]});
        let model = crate::model::Model::from_json(&json.to_string()).unwrap();
        // a fillet part on the next part of its ring; a vertex blend on a fillet; a fillet on
        // its plane; a quad of an n-sided corner on its neighbour quad; a vertex blend on a
        // corner patch outside its group
        assert!(across_a_seam(&model, 1, 2));
        assert!(!across_a_seam(&model, 3, 2));
        assert!(!across_a_seam(&model, 1, 0));
        assert!(!across_a_seam(&model, 4, 5));
        assert!(across_a_seam(&model, 3, 4));
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
