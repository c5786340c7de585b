//! The first stage of an n-sided corner group ([SV] §3.4): the n quads of a central split are
//! faired together as one triangle mesh (Kobbelt discrete fairing, with wings sampled from the
//! masters) and refitted with their internal curves shared exactly (nside-discrete); the
//! framework then runs the per-quad continuity and fairing steps.
//!
//! Models give the quads in cyclic order but in any parametrization. Each quad is brought into
//! nside-discrete's convention by reversing u and/or v (so that the common centre is at
//! (u, v) = (1, 1)) and transposing when needed (so that side u1 is the internal curve shared with
//! the next quad); the result is mapped back with the inverse transforms, so the model's links
//! stay valid. The neighbour across outer side k (side v0 in the convention) is the master
//! whose side lies on it, found geometrically ([`ON_SIDE`] × the quad size).

use nside_discrete::{Neighbour, NsidedParams, NsidedReport, fair_corner};
use nurbs_core::{BSplineSurface, Direction, Point3, Side};

use crate::model::{CornerGroup, Model};

/// Two points closer than this fraction of the quad size are the same point (shared corners,
/// sides lying on each other).
pub const ON_SIDE: f64 = 1e-6;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Orient {
    reverse_u: bool,
    reverse_v: bool,
    transpose: bool,
}

fn apply(s: &BSplineSurface, o: Orient) -> nurbs_core::Result<BSplineSurface> {
    let mut t = s.clone();
    if o.reverse_u {
        t = t.reversed(Direction::U)?;
    }
    if o.reverse_v {
        t = t.reversed(Direction::V)?;
    }
    if o.transpose {
        t = t.transposed()?;
    }
    Ok(t)
}

fn undo(s: &BSplineSurface, o: Orient) -> nurbs_core::Result<BSplineSurface> {
    let mut t = s.clone();
    if o.transpose {
        t = t.transposed()?;
    }
    if o.reverse_v {
        t = t.reversed(Direction::V)?;
    }
    if o.reverse_u {
        t = t.reversed(Direction::U)?;
    }
    Ok(t)
}

fn corners(s: &BSplineSurface) -> [(Point3, (bool, bool)); 4] {
    let ((a, b), (c, d)) = (s.domain_u(), s.domain_v());
    [
        (s.point(a, c), (false, false)),
        (s.point(b, c), (true, false)),
        (s.point(a, d), (false, true)),
        (s.point(b, d), (true, true)),
    ]
}

fn side_mid(s: &BSplineSurface, side: Side) -> Point3 {
    let (a, b) = side.along_domain(s);
    let (u, v) = side.params(s, 0.5 * (a + b));
    s.point(u, v)
}

fn near(p: &Point3, q: &Point3, tol: f64) -> bool {
    (p - q).norm() <= tol
}

/// Fairs corner group `group` of `model` as one mesh and refits it; `current` holds the
/// masters as faired so far. Returns the new quads (in the model's parametrization, in group
/// order) and nside-discrete's report.
pub fn fair_group(
    model: &Model,
    current: &Model,
    group: &CornerGroup,
) -> Result<(Vec<BSplineSurface>, NsidedReport), String> {
    let quads: Vec<&BSplineSurface> = group
        .patches
        .iter()
        .map(|&k| &current.surfaces[k].surface)
        .collect();
    let n = quads.len();
    if n < 3 {
        return Err(format!(
            "corner group {} has {n} patches; an n-sided corner needs at least 3",
            group.name
        ));
    }
    let size = quads.iter().map(|q| q.size()).fold(0.0, f64::max);
    let tol = ON_SIDE * size;
    // the centre: the corner common to every quad
    let centre = corners(quads[0])
        .into_iter()
        .map(|(p, _)| p)
        .find(|p| {
            quads
                .iter()
                .all(|q| corners(q).iter().any(|(c, _)| near(c, p, tol)))
        })
        .ok_or_else(|| {
            format!(
                "corner group {}: the patches do not share a common centre point",
                group.name
            )
        })?;
    let mut orients = Vec::with_capacity(n);
    let mut oriented = Vec::with_capacity(n);
    for (k, q) in quads.iter().enumerate() {
        let (_, (at_u1, at_v1)) = corners(q)
            .into_iter()
            .find(|(c, _)| near(c, &centre, tol))
            .ok_or_else(|| format!("corner group {}: patch {k} misses the centre", group.name))?;
        let mut o = Orient {
            reverse_u: !at_u1,
            reverse_v: !at_v1,
            transpose: false,
        };
        let t = apply(q, o).map_err(|e| e.to_string())?;
        let next = quads[(k + 1) % n];
        let shares = |side: Side| {
            let m = side_mid(&t, side);
            Side::ALL.iter().any(|&s| near(&side_mid(next, s), &m, tol))
        };
        if shares(Side::U1) {
        } else if shares(Side::V1) {
            o.transpose = true;
        } else {
            return Err(format!(
                "corner group {}: patch {k} shares no internal curve with patch {}",
                group.name,
                (k + 1) % n
            ));
        }
        oriented.push(apply(q, o).map_err(|e| e.to_string())?);
        orients.push(o);
    }
    // neighbours: the master whose side lies on outer side v0 of each oriented quad
    let mut neighbours: Vec<Option<Neighbour>> = Vec::with_capacity(n);
    for (k, t) in oriented.iter().enumerate() {
        let slave = group.patches[k];
        let m = side_mid(t, Side::V0);
        let found = model
            .links
            .iter()
            .filter(|l| l.slave == slave && !group.patches.contains(&l.master))
            .find_map(|l| {
                let master = &current.surfaces[l.master].surface;
                Side::ALL
                    .into_iter()
                    .find(|&s| {
                        near(&side_mid(master, s), &side_mid(t, Side::V0), tol) || {
                            // the master side may be the whole boundary curve: its midpoint is
                            // then the corner V_{k+1}-side half's end, so test containment
                            let (a, b) = s.along_domain(master);
                            let (u, v) = s.params(master, a + 0.25 * (b - a));
                            let (u2, v2) = s.params(master, a + 0.75 * (b - a));
                            near(&master.point(u, v), &m, tol)
                                || near(&master.point(u2, v2), &m, tol)
                        }
                    })
                    .map(|side| Neighbour {
                        surface: master,
                        side,
                    })
            });
        neighbours.push(found);
    }
    let (faired, report) = fair_corner(&oriented, &neighbours, &NsidedParams::default())
        .map_err(|e| format!("corner group {}: {e}", group.name))?;
    let back = faired
        .iter()
        .zip(&orients)
        .map(|(s, &o)| undo(s, o))
        .collect::<nurbs_core::Result<Vec<_>>>()
        .map_err(|e| e.to_string())?;
    Ok((back, report))
}
