//! The first stage of an n-sided corner group (\[SV\] §3.4): the n quads of a central split are
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

/// How a quad is turned into nside-discrete's convention (applied in this order).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Orient {
    reverse_u: bool,
    reverse_v: bool,
    transpose: bool,
}

/// `s` turned by `o`.
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

/// `s` turned back by `o` (the inverse of [`apply`]).
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

/// The four corner points of `s`, each with whether it is at u = u1 and at v = v1.
fn corners(s: &BSplineSurface) -> [(Point3, (bool, bool)); 4] {
    let ((a, b), (c, d)) = (s.domain_u(), s.domain_v());
    [
        (s.point(a, c), (false, false)),
        (s.point(b, c), (true, false)),
        (s.point(a, d), (false, true)),
        (s.point(b, d), (true, true)),
    ]
}

/// The point of `s` at the middle of `side`.
fn side_mid(s: &BSplineSurface, side: Side) -> Point3 {
    let (a, b) = side.along_domain(s);
    let (u, v) = side.params(s, 0.5 * (a + b));
    s.point(u, v)
}

/// Whether `p` and `q` are within `tol` of each other.
fn near(p: &Point3, q: &Point3, tol: f64) -> bool {
    (p - q).norm() <= tol
}

/// Why a corner group could not be faired as one mesh (the framework then fairs its patches one
/// by one and says so with this text).
#[derive(Debug, thiserror::Error)]
pub enum CornerGroupError {
    /// fewer than three patches
    #[error("corner group {group} has {patches} patches; an n-sided corner needs at least 3")]
    TooFew {
        /// the group's name
        group: String,
        /// its patches
        patches: usize,
    },
    /// no corner point common to all patches
    #[error("corner group {group}: the patches do not share a common centre point")]
    NoCentre {
        /// the group's name
        group: String,
    },
    /// a patch has no corner at the centre
    #[error("corner group {group}: patch {patch} misses the centre")]
    MissesCentre {
        /// the group's name
        group: String,
        /// the patch's place in the group
        patch: usize,
    },
    /// a patch shares no internal curve with the next one
    #[error("corner group {group}: patch {patch} shares no internal curve with patch {next}")]
    NoInternalCurve {
        /// the group's name
        group: String,
        /// the patch's place in the group
        patch: usize,
        /// the next patch's place
        next: usize,
    },
    /// reversing or transposing a patch failed
    #[error("{0}")]
    Geometry(nurbs_core::Error),
    /// the mesh fairing and refit failed
    #[error("corner group {group}: {source}")]
    Discrete {
        /// the group's name
        group: String,
        /// why
        source: nside_discrete::NsideError,
    },
}

/// Fairs corner group `group` of `model` as one mesh and refits it; `current` holds the
/// masters as faired so far. Returns the new quads (in the model's parametrization, in group
/// order) and nside-discrete's report.
pub fn fair_group(
    model: &Model,
    current: &Model,
    group: &CornerGroup,
) -> Result<(Vec<BSplineSurface>, NsidedReport), CornerGroupError> {
    let quads: Vec<&BSplineSurface> = group
        .patches
        .iter()
        .map(|&k| &current.surfaces[k].surface)
        .collect();
    let n = quads.len();
    if n < 3 {
        return Err(CornerGroupError::TooFew {
            group: group.name.clone(),
            patches: n,
        });
    }
    let size = quads.iter().map(|q| q.size()).fold(0.0, f64::max);
    let tol = ON_SIDE * size;
    let centre = common_centre(&quads, tol).ok_or_else(|| CornerGroupError::NoCentre {
        group: group.name.clone(),
    })?;
    let mut orients = Vec::with_capacity(n);
    let mut oriented = Vec::with_capacity(n);
    for (k, q) in quads.iter().enumerate() {
        let o = orient(&quads, k, &centre, tol, &group.name)?;
        oriented.push(apply(q, o).map_err(CornerGroupError::Geometry)?);
        orients.push(o);
    }
    let neighbours: Vec<Option<Neighbour>> = oriented
        .iter()
        .zip(&group.patches)
        .map(|(t, &slave)| outer_neighbour(model, current, group, slave, t, tol))
        .collect();
    let (faired, report) =
        fair_corner(&oriented, &neighbours, &NsidedParams::default()).map_err(|source| {
            CornerGroupError::Discrete {
                group: group.name.clone(),
                source,
            }
        })?;
    let back = faired
        .iter()
        .zip(&orients)
        .map(|(s, &o)| undo(s, o))
        .collect::<nurbs_core::Result<Vec<_>>>()
        .map_err(CornerGroupError::Geometry)?;
    Ok((back, report))
}

/// The centre of a corner group: the corner of the first quad that every quad has (within
/// `tol`).
fn common_centre(quads: &[&BSplineSurface], tol: f64) -> Option<Point3> {
    corners(quads[0]).into_iter().map(|(p, _)| p).find(|p| {
        quads
            .iter()
            .all(|q| corners(q).iter().any(|(c, _)| near(c, p, tol)))
    })
}

/// How quad `k` of `quads` (of corner group `name`) is brought into nside-discrete's
/// convention: u and v reversed so that `centre` is at (1, 1), transposed when its internal
/// curve shared with the next quad is side v1 rather than u1.
fn orient(
    quads: &[&BSplineSurface],
    k: usize,
    centre: &Point3,
    tol: f64,
    name: &str,
) -> Result<Orient, CornerGroupError> {
    let (n, q) = (quads.len(), quads[k]);
    let (_, (at_u1, at_v1)) = corners(q)
        .into_iter()
        .find(|(c, _)| near(c, centre, tol))
        .ok_or_else(|| CornerGroupError::MissesCentre {
            group: name.to_string(),
            patch: k,
        })?;
    let mut o = Orient {
        reverse_u: !at_u1,
        reverse_v: !at_v1,
        transpose: false,
    };
    let t = apply(q, o).map_err(CornerGroupError::Geometry)?;
    let next = quads[(k + 1) % n];
    let shares = |side: Side| {
        let m = side_mid(&t, side);
        Side::ALL.iter().any(|&s| near(&side_mid(next, s), &m, tol))
    };
    if shares(Side::U1) {
    } else if shares(Side::V1) {
        o.transpose = true;
    } else {
        return Err(CornerGroupError::NoInternalCurve {
            group: name.to_string(),
            patch: k,
            next: (k + 1) % n,
        });
    }
    Ok(o)
}

/// The neighbour across outer side v0 of the oriented quad `t` (model surface `slave`): a side
/// of a master of `slave` outside the group that lies on it, as `current` has that master.
fn outer_neighbour<'m>(
    model: &Model,
    current: &'m Model,
    group: &CornerGroup,
    slave: usize,
    t: &BSplineSurface,
    tol: f64,
) -> Option<Neighbour<'m>> {
    let m = side_mid(t, Side::V0);
    model
        .links
        .iter()
        .filter(|l| l.slave == slave && !group.patches.contains(&l.master))
        .find_map(|l| {
            let master = &current.surfaces[l.master].surface;
            Side::ALL
                .into_iter()
                .find(|&s| lies_on(master, s, &m, tol))
                .map(|side| Neighbour {
                    surface: master,
                    side,
                })
        })
}

/// Whether side `s` of `master` lies on the point `m` (an outer side's midpoint, within `tol`):
/// its midpoint is `m`, or — the master side may be the whole boundary curve, whose midpoint is
/// then the corner V_{k+1}-side half's end — its point at a quarter or three quarters is.
fn lies_on(master: &BSplineSurface, s: Side, m: &Point3, tol: f64) -> bool {
    near(&side_mid(master, s), m, tol) || {
        let (a, b) = s.along_domain(master);
        let (u, v) = s.params(master, a + 0.25 * (b - a));
        let (u2, v2) = s.params(master, a + 0.75 * (b - a));
        near(&master.point(u, v), m, tol) || near(&master.point(u2, v2), m, tol)
    }
}
