//! The master's spline space along a join, carried into the slave (knot transfer).
//!
//! Rows 0, 1 and 2 of a slave side are splines in the along parameter t; C0, G1 and G2 ask them
//! to reproduce the master's boundary curve, its cross-boundary tangent field and its curvature
//! along the join (\[SV\] §4). When the master has knots along the join — the lead-in knots a
//! faired fillet received, the knots a trimmed master carries — its boundary data are splines with
//! breakpoints there, and a slave without breakpoints at the same places can only approximate
//! them: knot insertion by bisection of failing spans ([`crate::slave`]) then needs many rounds
//! and dozens of knots and still leaves a residual next to each master knot. Making the spline
//! spaces compatible first is what CAD systems do before matching two edges (\[NB\] §5.3, knot
//! refinement; \[SV\] §3.2 step 1): the slave's along degree is raised to the master's (up to
//! [`LEAD_IN_DEGREE`]) and every interior master knot inside the
//! join is inserted at the slave parameter whose side point projects onto it.
//!
//! Both operations are exact (homogeneous coordinates for rational slaves): the shape does not
//! change, only the freedom. Where the two parametrisations along the join are affinely related
//! (a fillet and its vertex blend cut from one rolling ball) the spaces then agree exactly;
//! otherwise the knots sit where the master's curvature changes and the refinement of
//! [`crate::slave::set_step`] handles the rest.
//!
//! # Tolerance
//! [`TRANSFER_SAMPLES`] samples locate the master knots along the side; each is then found to
//! [`TRANSFER_PARAMETER_RELATIVE`] of the master domain by safeguarded secant steps. Master
//! knots within [`TRANSFER_MERGE_RELATIVE`] of the join's ends are not carried over, and a mapped
//! knot within [`TRANSFER_MERGE_SPAN`] of its span from a slave knot counts as that knot —
//! except next to an end of the side whose neighbour carries no frame (a pole, an unlinked
//! side), where a master's ramp knots all arrive (`spread`).

use nurbs_core::{BSplineSurface, Continuity, Direction, ProjectionParams, Side};

use crate::error::Result;
use crate::knots::new_knots;
use crate::lead_in::LEAD_IN_DEGREE;
use crate::link::SideLink;
use crate::measure::is_collapsed;
use crate::sampling::MasterTracker;

/// Samples along a side used to bracket the master knots (a bracket per 1/64 of the side: the
/// foot parameter is monotone along a join, so any bracket count works; more only saves secant
/// steps).
pub const TRANSFER_SAMPLES: usize = 65;

/// A mapped knot is accurate when its foot parameter is within this fraction of the master's
/// domain of the master knot (far below any knot spacing the refinement creates, whose spans are
/// halved at most a few times).
pub const TRANSFER_PARAMETER_RELATIVE: f64 = 1e-12;

/// Secant steps per mapped knot (regula falsi with the Illinois rule converges superlinearly; a
/// bracket of 1/64 of the side reaches 1e-12 in a handful).
pub(crate) const TRANSFER_STEPS: usize = 40;

/// A master knot inside the join must be this fraction of the master domain away from the ends
/// of the join's foot range to be transferred (the join's own end is a slave knot already).
pub const TRANSFER_MERGE_RELATIVE: f64 = 1e-6;

/// A mapped knot within this fraction of its slave span from a slave knot is that knot. Two
/// parametrisations of one circle (a fillet's arc and its vertex blend's) differ by a few 1e-4
/// of the domain, so the knots a fillet's lead-in and the blend's own lead-in place at "the
/// same" width land that close: inserting both would leave a span of 1e-4 of its neighbours,
/// whose basis function the row solves cannot weigh (its least-squares column is 10⁴ smaller),
/// for a breakpoint the neighbouring knot already provides to within a tenth of a span — where
/// the degree-p pieces meeting there still reproduce the master's within the refinement's reach.
pub const TRANSFER_MERGE_SPAN: f64 = 0.1;

/// What [`with_master_knots`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TransferReport {
    /// degree elevation (u, v)
    pub degree_elevation: (usize, usize),
    /// knots inserted
    pub knots_inserted: usize,
}

/// The slave with its along spline space made compatible with each master's along the join
/// where the master has knots inside the join: along degree raised to the master's (never above
/// `max(current, LEAD_IN_DEGREE)`; a join without master knots is one polynomial piece, which
/// the refinement approximates without changing the slave's representation), and the
/// master's interior knots inserted at the slave parameters whose side points project onto them
/// (as simple knots: a multiple master knot is mostly the joint of the arcs of a rational conic,
/// a parametric joint of a smooth surface that the slave need not copy). A direction that would
/// exceed `max_control_points` gets no knots from that link. Collapsed sides are skipped, and so
/// is every direction whose `single_piece` flag (u, v) is false: a slave that came with knots of
/// its own along the join has been fitted or refined for it already (a refitted corner group, a
/// fitted patch) and keeps its spline space, refined only where the tolerances are missed —
/// carrying over the refinement knots its masters received at their own corners added up to 18
/// knots per side to the five-sided group's quads and missed a link there. A single polynomial
/// piece (a kernel's vertex blend) cannot follow any breakpoint of its master. The shape is
/// unchanged.
pub fn with_master_knots(
    slave: &BSplineSurface,
    links: &[SideLink],
    single_piece: [bool; 2],
    max_control_points: usize,
    projection: ProjectionParams,
) -> Result<(BSplineSurface, TransferReport)> {
    let mut s = slave.clone();
    let mut report = TransferReport::default();
    for link in links {
        let piece = match link.side.along_direction() {
            Direction::U => single_piece[0],
            Direction::V => single_piece[1],
        };
        if !piece || is_collapsed(&s, link.side) {
            continue;
        }
        let mut tracker = MasterTracker::new(link.master, projection);
        let Some(along) = master_along(&s, link, &mut tracker) else {
            continue;
        };
        let dir = link.side.along_direction();
        let degree = match dir {
            Direction::U => s.degree_u(),
            Direction::V => s.degree_v(),
        };
        let want = along.degree.min(degree.max(LEAD_IN_DEGREE));
        if want > degree {
            s = s.elevate_degree(dir, want - degree)?;
            match dir {
                Direction::U => report.degree_elevation.0 += want - degree,
                Direction::V => report.degree_elevation.1 += want - degree,
            }
        }
        let xs = slave_params(&s, link, &along, &mut tracker);
        let kv = match dir {
            Direction::U => s.knots_u(),
            Direction::V => s.knots_v(),
        };
        let xs = new_knots(
            &s,
            dir,
            &spread(kv.knots(), &xs, free_ends(&s, link, links)),
        );
        let count = match dir {
            Direction::U => s.num_u(),
            Direction::V => s.num_v(),
        };
        if xs.is_empty() || count + xs.len() > max_control_points {
            continue;
        }
        s = s.refine(dir, &xs)?;
        report.knots_inserted += xs.len();
    }
    Ok((s, report))
}

/// The values of `xs` (ascending, master knots mapped onto the side) that are farther than
/// [`TRANSFER_MERGE_SPAN`] of their span from every knot of `knots` and from the value kept
/// before them — except in the first or last span where that end of the side is `free` (its
/// neighbouring side carries no frame: collapsed to a pole, or unlinked): there the domain's
/// end is no breakpoint to merge with, and every value a tenth of the master's own spacing
/// (the distance to the nearest other value of `xs`) away from the span's inner knot stays.
/// Next to a linked neighbour they would crowd that side's first cross spans, where its G1 and
/// G2 rows lie, into a few thousandths of the side; with them (and without the merge with the
/// value kept before) a metre part lost six G2 links (docs/benchmarks.md), so there they merge
/// as elsewhere.
fn spread(knots: &[f64], xs: &[f64], free: [bool; 2]) -> Vec<f64> {
    let (Some(&first), Some(&last)) = (knots.first(), knots.last()) else {
        return Vec::new();
    };
    let mut kept: Vec<f64> = Vec::new();
    for (i, &x) in xs.iter().enumerate() {
        let hi = knots.partition_point(|&k| k <= x);
        if hi == 0 || hi == knots.len() {
            continue;
        }
        let (a, b) = (knots[hi - 1], knots[hi]);
        let at_free_start = a == first && free[0];
        let at_free_end = b == last && free[1];
        let keep = if at_free_start || at_free_end {
            let before = i.checked_sub(1).map_or(f64::INFINITY, |j| x - xs[j]);
            let after = xs.get(i + 1).map_or(f64::INFINITY, |&y| y - x);
            let near = TRANSFER_MERGE_SPAN * (b - a).min(before).min(after);
            (at_free_start || x - a > near) && (at_free_end || b - x > near)
        } else {
            let near = TRANSFER_MERGE_SPAN * (b - a);
            let prev = kept.last().copied().unwrap_or(f64::NEG_INFINITY);
            x - a > near && b - x > near && x - prev > near
        };
        if keep {
            kept.push(x);
        }
    }
    kept
}

/// Whether the start and the end of `link`'s side are free for [`spread`]: the neighbouring
/// side there is collapsed in `s` or has no link of at least G1 in `links`.
fn free_ends(s: &BSplineSurface, link: &SideLink, links: &[SideLink]) -> [bool; 2] {
    let (start, end) = link.side.neighbours();
    let free = |side: Side| {
        is_collapsed(s, side)
            || !links
                .iter()
                .any(|l| l.side == side && l.target >= Continuity::G1)
    };
    [free(start), free(end)]
}

/// The master's knots along one join.
struct MasterAlong {
    /// master direction that runs along the join
    dir: Direction,
    /// its degree
    degree: usize,
    /// the side samples: (slave parameter, master foot parameter in `dir`), ascending in the first
    samples: Vec<(f64, f64)>,
    /// interior master knots strictly inside the join's foot range (distinct values)
    knots: Vec<f64>,
}

/// Projects samples of the slave side onto the master and finds which master direction runs
/// along the join (the one whose foot parameter sweeps the larger share of its domain) and its
/// knots inside the join. `None` when the foot parameter is not monotone (the side runs back and
/// forth over the master: no one-to-one knot map) or the join has no master knot.
fn master_along(
    slave: &BSplineSurface,
    link: &SideLink,
    tracker: &mut MasterTracker,
) -> Option<MasterAlong> {
    let master = link.master;
    let ts = crate::sampling::uniform_part_params(slave, link.side, link.range, TRANSFER_SAMPLES)
        .ok()?;
    let mut feet = Vec::with_capacity(ts.len());
    for t in ts {
        let (u, v) = link.side.params(slave, t);
        let f = tracker.project(&slave.point(u, v));
        feet.push((t, f.u, f.v));
    }
    let (u0, u1) = master.domain_u();
    let (v0, v1) = master.domain_v();
    let sweep = |i: usize| {
        let (lo, hi) = feet
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), f| {
                let x = if i == 0 { f.1 } else { f.2 };
                (lo.min(x), hi.max(x))
            });
        (hi - lo, lo, hi)
    };
    let (su, ulo, uhi) = sweep(0);
    let (sv, vlo, vhi) = sweep(1);
    let (dir, lo, hi, width) = if su / (u1 - u0) >= sv / (v1 - v0) {
        (Direction::U, ulo, uhi, u1 - u0)
    } else {
        (Direction::V, vlo, vhi, v1 - v0)
    };
    let samples: Vec<(f64, f64)> = feet
        .iter()
        .map(|f| (f.0, if dir == Direction::U { f.1 } else { f.2 }))
        .collect();
    let increasing = samples.windows(2).all(|w| w[1].1 >= w[0].1);
    let decreasing = samples.windows(2).all(|w| w[1].1 <= w[0].1);
    if !(increasing || decreasing) {
        return None;
    }
    let kv = match dir {
        Direction::U => master.knots_u(),
        Direction::V => master.knots_v(),
    };
    let margin = TRANSFER_MERGE_RELATIVE * width;
    let knots: Vec<f64> = kv
        .interior_knots()
        .into_iter()
        .map(|(k, _)| k)
        .filter(|&k| k > lo + margin && k < hi - margin)
        .collect();
    if knots.is_empty() {
        return None;
    }
    Some(MasterAlong {
        dir,
        degree: kv.degree(),
        samples,
        knots,
    })
}

/// The slave parameters along the side whose foot points on the master have the master knots
/// as their parameter in `along.dir` (regula falsi, Illinois rule, inside the sample bracket).
fn slave_params(
    slave: &BSplineSurface,
    link: &SideLink,
    along: &MasterAlong,
    tracker: &mut MasterTracker,
) -> Vec<f64> {
    let master = link.master;
    let (m0, m1) = match along.dir {
        Direction::U => master.domain_u(),
        Direction::V => master.domain_v(),
    };
    let accuracy = TRANSFER_PARAMETER_RELATIVE * (m1 - m0);
    // the first knot's bracket may lie anywhere along the side: start from a global projection
    tracker.reset();
    let mut foot = |t: f64| {
        let (u, v) = link.side.params(slave, t);
        let f = tracker.project(&slave.point(u, v));
        if along.dir == Direction::U { f.u } else { f.v }
    };
    let mut out = Vec::with_capacity(along.knots.len());
    for &knot in &along.knots {
        let Some(w) = along
            .samples
            .windows(2)
            .find(|w| (w[0].1 - knot) * (w[1].1 - knot) <= 0.0)
        else {
            continue;
        };
        let (mut ta, mut fa) = (w[0].0, w[0].1 - knot);
        let (mut tb, mut fb) = (w[1].0, w[1].1 - knot);
        let mut t = ta;
        let mut side = 0i8;
        for _ in 0..TRANSFER_STEPS {
            if fa.abs() <= accuracy {
                t = ta;
                break;
            }
            if fb.abs() <= accuracy {
                t = tb;
                break;
            }
            t = if fb != fa {
                (ta * fb - tb * fa) / (fb - fa)
            } else {
                0.5 * (ta + tb)
            };
            let ft = foot(t) - knot;
            if ft.abs() <= accuracy {
                break;
            }
            if ft * fb > 0.0 {
                tb = t;
                fb = ft;
                if side == 1 {
                    fa *= 0.5;
                }
                side = 1;
            } else {
                ta = t;
                fa = ft;
                if side == -1 {
                    fb *= 0.5;
                }
                side = -1;
            }
        }
        out.push(t);
    }
    out.sort_by(f64::total_cmp);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs_core::{KnotVector, Point3};

    /// A flat strip (z = 0) of degree `degree_u` in u and 1 in v, x = u (control points at the
    /// Greville abscissae), y ∈ [y0, y0 + 1].
    fn strip_at(knots_u: Vec<f64>, degree_u: usize, y0: f64) -> BSplineSurface {
        let ku = KnotVector::new(degree_u, knots_u).unwrap();
        let n = ku.num_basis();
        let k = ku.knots().to_vec();
        let kv = KnotVector::bezier(1).unwrap();
        let pts = (0..n)
            .flat_map(|i| {
                let x = k[i + 1..=i + degree_u].iter().sum::<f64>() / degree_u as f64;
                (0..2).map(move |j| Point3::new(x, y0 + j as f64, 0.0))
            })
            .collect();
        BSplineSurface::new(ku, kv, pts, None).unwrap()
    }

    /// A quadratic Bézier strip in u (control abscissae `xs`), linear in v, y ∈ [1, 2], z = 0:
    /// its side v0 lies on the side v1 of a [`strip`].
    fn quadratic_strip(xs: [f64; 3]) -> BSplineSurface {
        BSplineSurface::new(
            KnotVector::bezier(2).unwrap(),
            KnotVector::bezier(1).unwrap(),
            (0..3)
                .flat_map(|i| (0..2).map(move |j| Point3::new(xs[i], 1.0 + j as f64, 0.0)))
                .collect(),
            None,
        )
        .unwrap()
    }

    /// A link of the whole `side` onto `master`, without vertex zones.
    fn link(side: Side, master: &BSplineSurface, target: Continuity) -> SideLink<'_> {
        SideLink {
            side,
            master,
            target,
            range: None,
            g2_zones: [0.0; 2],
        }
    }

    fn strip(knots_u: Vec<f64>, degree_u: usize) -> BSplineSurface {
        strip_at(knots_u, degree_u, 0.0)
    }

    #[test]
    fn master_knots_arrive_at_the_projected_slave_parameters() {
        // master: x = u on [0, 1] with knots at 0.3 and 0.8, quintic along; slave: a quadratic
        // strip y ∈ [1, 2] with x = u, its side v0 on the master's side v1: the knots map
        // identically
        let master = strip(
            vec![
                0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.3, 0.8, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0,
            ],
            5,
        );
        let slave = quadratic_strip([0.0, 0.5, 1.0]);
        let links = [link(Side::V0, &master, Continuity::G1)];
        let (s, report) =
            with_master_knots(&slave, &links, [true; 2], 1024, ProjectionParams::default())
                .unwrap();
        assert_eq!(s.degree_u(), 5, "raised to the master's degree");
        assert_eq!(report.degree_elevation, (3, 0));
        assert_eq!(report.knots_inserted, 2);
        let inner: Vec<f64> = s.knots_u().interior_knots().iter().map(|k| k.0).collect();
        assert_eq!(inner.len(), 2);
        assert!((inner[0] - 0.3).abs() < 1e-10, "{inner:?}");
        assert!((inner[1] - 0.8).abs() < 1e-10, "{inner:?}");
        // the shape is unchanged
        for i in 0..=10 {
            let u = i as f64 / 10.0;
            assert!((s.point(u, 0.5) - slave.point(u, 0.5)).norm() < 1e-12);
        }
    }

    #[test]
    fn a_reparametrised_side_gets_the_knots_where_its_points_project() {
        // the slave runs over x ∈ [0, 1] with x = t² (control points 0, 0, 1 in a quadratic
        // Bézier: x(t) = t²), so master knot 0.25 lands at t = 0.5 and 0.64 at t = 0.8
        let master = strip(vec![0.0, 0.0, 0.0, 0.0, 0.25, 0.64, 1.0, 1.0, 1.0, 1.0], 3);
        let slave = quadratic_strip([0.0, 0.0, 1.0]);
        let links = [link(Side::V0, &master, Continuity::G0)];
        let (s, _) =
            with_master_knots(&slave, &links, [true; 2], 1024, ProjectionParams::default())
                .unwrap();
        let inner: Vec<f64> = s.knots_u().interior_knots().iter().map(|k| k.0).collect();
        assert_eq!(inner.len(), 2, "{inner:?}");
        assert!((inner[0] - 0.5).abs() < 1e-9, "{inner:?}");
        assert!((inner[1] - 0.8).abs() < 1e-9, "{inner:?}");
        assert_eq!(s.degree_u(), 3);
    }

    #[test]
    fn the_control_point_cap_is_kept() {
        let master = strip(
            vec![0.0, 0.0, 0.0, 0.0, 0.25, 0.5, 0.75, 1.0, 1.0, 1.0, 1.0],
            3,
        );
        let shifted = strip_at(vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0], 3, 1.0);
        let links = [link(Side::V0, &master, Continuity::G1)];
        let (s, report) =
            with_master_knots(&shifted, &links, [true; 2], 5, ProjectionParams::default()).unwrap();
        assert_eq!(report.knots_inserted, 0);
        assert_eq!(s.num_u(), 4);
    }

    #[test]
    fn ramp_knots_next_to_free_ends_all_arrive() {
        // a master with three ramp knots within 1.2 % of each end of the join (a fillet's
        // one-hump section) and one in the middle; the slave is one quadratic span whose other
        // sides carry no link: every knot is a breakpoint it lacks, however close to an end
        let ramp = [0.004, 0.008, 0.012, 0.5, 0.988, 0.992, 0.996];
        let mut knots = vec![0.0; 4];
        knots.extend(ramp);
        knots.extend([1.0; 4]);
        let master = strip(knots, 3);
        let slave = quadratic_strip([0.0, 0.5, 1.0]);
        let links = [link(Side::V0, &master, Continuity::G2)];
        let (s, report) =
            with_master_knots(&slave, &links, [true; 2], 1024, ProjectionParams::default())
                .unwrap();
        assert_eq!(report.knots_inserted, ramp.len());
        let inner: Vec<f64> = s.knots_u().interior_knots().iter().map(|k| k.0).collect();
        for (got, want) in inner.iter().zip(ramp) {
            assert!((got - want).abs() < 1e-10, "{inner:?}");
        }
    }

    #[test]
    fn ramp_knots_merge_next_to_a_linked_neighbour_and_arrive_next_to_a_free_one() {
        // span (0.3, 1): an isolated knot within a tenth of it from 0.3 is 0.3; next to the end
        // 0, a ramp 0.005 apart merges with the end and with each other where that end's
        // neighbour is linked, and arrives whole where it is free
        let knots = [0.0, 0.0, 0.0, 0.3, 1.0, 1.0, 1.0];
        let xs = [0.005, 0.01, 0.015, 0.301, 0.6];
        assert_eq!(spread(&knots, &xs, [false; 2]), vec![0.6]);
        assert_eq!(
            spread(&knots, &xs, [true, false]),
            vec![0.005, 0.01, 0.015, 0.6]
        );
        // the last span, free at the end
        assert_eq!(
            spread(&knots, &[0.7, 0.99, 0.995], [false, true]),
            vec![0.7, 0.99, 0.995]
        );
    }

    #[test]
    fn a_free_end_is_a_collapsed_or_unlinked_neighbour() {
        let master = strip(vec![0.0, 0.0, 1.0, 1.0], 1);
        let slave = quadratic_strip([0.0, 0.5, 1.0]);
        let links = [
            link(Side::V0, &master, Continuity::G2),
            link(Side::U0, &master, Continuity::G2),
            link(Side::U1, &master, Continuity::G0),
        ];
        // V0 runs along u: its start meets U0 (linked G2), its end U1 (only G0: no frame)
        assert_eq!(free_ends(&slave, &links[0], &links), [false, true]);
    }
}
