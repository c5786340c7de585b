//! A face's parameter box on its surface, from its bound loops (\[ISO42\] topology_schema:
//! `face_bound`, `advanced_face`). Each loop is put in the surface's own frame — it runs with the face on its
//! left when the bound's orientation and the face's sense agree, and is reversed otherwise
//! (the normal of every surface here is σ_u × σ_v, so "left" is the side of +v for a loop
//! running in +u). In a periodic direction (an angle; a B-spline closed in that direction) the
//! loop's parameters are unwrapped, each step taken as the shorter way round, and:
//!
//! - a loop that winds once round (a full circle, a closed edge) makes the face cover the whole
//!   period, and in the other direction it extends from that loop to the side the face lies on:
//!   to the pole there (a spherical cap), to the loop that winds back (a band), or to the
//!   surface's bound;
//! - a loop that passes through a pole (a sphere's, the apex of a cone: a point on the axis
//!   whose angle says nothing) goes along the pole in the sense that keeps the face on its
//!   left: +u along the lower bound of v, −u along the upper (a half sphere bounded by a great
//!   circle through the poles is the half on the loop's left);
//! - a seam edge used twice leaves the loop spanning exactly the period;
//! - otherwise the face spans its outer loop's unwrapped range.
//!
//! # Deviation from the standard
//! A loop that winds round nothing is taken to bound the face from outside whichever way it
//! runs: writers get the sense of such loops wrong (a seamed torus fillet in a file Open
//! CASCADE wrote, and 6 of the 46 faces of a EUCLID file, run clockwise about the face normal),
//! and a face that is a closed surface outside one contractible loop (a sphere with one hole)
//! is rare. Such a face comes in over that loop's box.
//!
//! A face bounded by no edge loop (no bounds, or VERTEX_LOOPs only: a whole sphere or torus) is
//! the surface's natural parameter box.

use std::f64::consts::{FRAC_PI_2, TAU};

use super::ON_SURFACE_RELATIVE;
use super::faces::BoundLoop;
use super::surfaces::Surface;

/// Two parameters of a periodic direction whose difference is within this fraction of the
/// period of a whole number of periods are the same place on the seam: the kernel's relative
/// tolerance ([`ON_SURFACE_RELATIVE`]), far below any face's extent.
const SEAM_SNAP: f64 = ON_SURFACE_RELATIVE;

/// A point within this fraction of the surface's size of the axis of a sphere, cone or surface
/// of revolution is on the axis, where the angle is undefined (the kernel's tolerance).
const POLE_RELATIVE: f64 = ON_SURFACE_RELATIVE;

/// A box in (u, v).
pub(super) type ParamBox = ((f64, f64), (f64, f64));

/// What bounds a surface's parameters.
struct Carrier {
    /// per direction, the period where it is periodic
    period: [Option<f64>; 2],
    /// per direction, the natural range where it is bounded
    natural: [Option<(f64, f64)>; 2],
    /// whether a full period may start anywhere (an angle) or only at the natural start (a
    /// closed B-spline, whose knots fix where its seam is)
    shiftable: bool,
    /// values of v where u degenerates (a sphere's poles, a cone's apex)
    poles: Vec<f64>,
    /// a B-spline's boundary curves that collapse to a point, with the direction whose
    /// parameter is undefined there (v at a collapsed u = const boundary, u at a v = const one)
    collapsed: Vec<(nurbs_core::Point3, usize)>,
    /// distance within which a point is at a collapsed boundary
    collapsed_tol: f64,
}

impl Surface {
    /// Its periods, natural ranges and poles (\[ISO42\] geometry_schema: the angle u of an elementary
    /// surface in [0, 2π), a sphere's latitude in [−π/2, π/2], a torus's v an angle).
    fn carrier(&self) -> Carrier {
        let angle = Some((0.0, TAU));
        let (period, natural, poles) = match self {
            Surface::Plane(..) => ([None, None], [None, None], vec![]),
            Surface::Cone(_, _, _, _, r, semi) => {
                let apex = if *semi == 0.0 {
                    vec![]
                } else {
                    vec![-r / semi.tan()]
                };
                ([Some(TAU), None], [angle, None], apex)
            }
            Surface::Sphere(..) => {
                let lat = (-FRAC_PI_2, FRAC_PI_2);
                ([Some(TAU), None], [angle, Some(lat)], vec![lat.0, lat.1])
            }
            Surface::Torus(..) => ([Some(TAU), Some(TAU)], [angle, angle], vec![]),
            Surface::Revolution(c, ..) => ([Some(TAU), None], [angle, Some(c.domain())], vec![]),
            Surface::Extrusion(c, ..) => ([None, None], [Some(c.domain()), None], vec![]),
            Surface::Spline(s) => {
                let (u, v) = (s.domain_u(), s.domain_v());
                let closed = crate::seam::spline_closed(s, ON_SURFACE_RELATIVE);
                let period = [
                    closed[0].then_some(u.1 - u.0),
                    closed[1].then_some(v.1 - v.0),
                ];
                return Carrier {
                    period,
                    natural: [Some(u), Some(v)],
                    shiftable: false,
                    poles: vec![],
                    collapsed: spline_collapsed(s),
                    collapsed_tol: POLE_RELATIVE * s.size(),
                };
            }
        };
        Carrier {
            period,
            natural,
            shiftable: true,
            poles,
            collapsed: vec![],
            collapsed_tol: 0.0,
        }
    }

    /// Per direction, whether its parameter is undefined at `p`: u on the axis of a sphere,
    /// cone or surface of revolution; either at a B-spline's collapsed boundary.
    fn pole_flags(&self, c: &Carrier, p: &nurbs_core::Point3) -> [bool; 2] {
        let mut flags = [self.on_axis(p), false];
        for (q, d) in &c.collapsed {
            flags[*d] |= (p - q).norm() <= c.collapsed_tol;
        }
        flags
    }

    /// Whether `p` lies on the axis of a sphere, cone or surface of revolution.
    fn on_axis(&self, p: &nurbs_core::Point3) -> bool {
        let off = |o: &nurbs_core::Point3, z: &nurbs_core::Vector3, scale: f64| {
            let d = p - o;
            (d - z * d.dot(z)).norm() <= POLE_RELATIVE * scale
        };
        match self {
            Surface::Sphere(o, _, _, z, r) => off(o, z, *r),
            Surface::Cone(o, _, _, z, r, _) => off(o, z, r.max((p - o).norm())),
            Surface::Revolution(c, o, z, _) => {
                let size = c
                    .control_points()
                    .iter()
                    .fold(0.0_f64, |s, q| s.max((q - o).norm()));
                off(o, z, size)
            }
            _ => false,
        }
    }
}

/// The boundary curves of `s` that collapse to a point (9 points each within the kernel's
/// tolerance of the first, [`crate::seam::collapsed_sides`]): the point, and the direction whose
/// parameter is undefined there (v along a collapsed u = const side, u along a v = const one).
fn spline_collapsed(s: &nurbs_core::BSplineSurface) -> Vec<(nurbs_core::Point3, usize)> {
    crate::seam::collapsed_sides(s, POLE_RELATIVE)
        .into_iter()
        .zip([1, 1, 0, 0])
        .filter_map(|(q, d)| q.map(|q| (q, d)))
        .collect()
}

/// A loop in the surface's frame: its parameters (unwrapped in periodic directions) and, per
/// direction, how often it winds round.
struct Oriented {
    uv: Vec<[f64; 2]>,
    winding: [i64; 2],
    /// it spans no range in a periodic direction but passes through a pole there (a sphere's
    /// seam meridian alone: the whole sphere)
    seam_only: bool,
    outer: bool,
}

/// Why a face has no parameter box ([`face_box`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub(super) enum BoxError {
    /// No edge loop, and the surface has no natural box.
    #[error("the face has no edge loop and its surface is unbounded")]
    Unbounded,
    /// The bounds span no range in one direction.
    #[error("the face's bounds span no range in {direction}")]
    NoRange {
        /// "u" or "v"
        direction: &'static str,
    },
}

/// The parameter box of a face with `bounds` on `surface` (`same_sense`: the face's normal is
/// the surface's), or why there is none.
pub(super) fn face_box(
    surface: &Surface,
    bounds: &[BoundLoop],
    same_sense: bool,
) -> Result<ParamBox, BoxError> {
    let c = surface.carrier();
    let loops: Vec<Oriented> = bounds
        .iter()
        .filter(|b| b.points.len() >= 2)
        .map(|b| orient(surface, &c, b, same_sense))
        .collect();
    if loops.is_empty() {
        // no edge loop: the whole surface
        return match c.natural {
            [Some(u), Some(v)] => Ok((u, v)),
            _ => Err(BoxError::Unbounded),
        };
    }
    let outer = loops.iter().position(|l| l.outer).unwrap_or_else(|| {
        (0..loops.len())
            .max_by(|&a, &b| box_area(&loops[a].uv).total_cmp(&box_area(&loops[b].uv)))
            .unwrap_or(0)
    });
    // every point, the vertex loops' too (a cone's apex)
    // (but for those whose projection found no foot, [`BoundLoop::found`])
    let all: Vec<(f64, f64)> = bounds
        .iter()
        .flat_map(|b| b.params.iter().zip(&b.found).filter(|(_, f)| **f))
        .map(|(q, _)| *q)
        .collect();
    let mut range = [(0.0, 0.0); 2];
    for (d, r) in range.iter_mut().enumerate() {
        *r = match c.period[d] {
            Some(p) => periodic_range(&c, &loops, outer, d, p),
            None => linear_range(&c, &loops, &all, d),
        };
        if !(r.1 > r.0) {
            return Err(BoxError::NoRange {
                direction: ["u", "v"][d],
            });
        }
    }
    Ok((range[0], range[1]))
}

/// Bound `b` in the surface's frame, unwrapped in the periodic directions.
fn orient(surface: &Surface, c: &Carrier, b: &BoundLoop, same_sense: bool) -> Oriented {
    let mut uv: Vec<[f64; 2]> = b.params.iter().map(|&(u, v)| [u, v]).collect();
    let mut pole: Vec<[bool; 2]> = b.points.iter().map(|p| surface.pole_flags(c, p)).collect();
    let mut found = b.found.clone();
    if b.forward != same_sense {
        uv.reverse();
        pole.reverse();
        found.reverse();
    }
    let mut winding = [0; 2];
    let mut seam_only = false;
    for d in 0..2 {
        let Some(period) = c.period[d] else { continue };
        let poles: Vec<bool> = pole.iter().map(|f| f[d]).collect();
        if let Some((values, w)) = unwrap(&uv, d, &poles, &found, period) {
            let (lo, hi) = span(&values);
            seam_only |= hi - lo <= SEAM_SNAP * period && poles.iter().any(|&p| p);
            for (q, x) in uv.iter_mut().zip(values) {
                q[d] = x;
            }
            winding[d] = w;
        }
    }
    Oriented {
        uv,
        winding,
        seam_only,
        outer: b.outer,
    }
}

/// The parameters of direction `d` along a closed loop, unwrapped (each step the shorter way
/// round, a step across a pole in the sense that keeps the face on the left), pole points and
/// points whose projection found no foot (not `found`) given their predecessor's value; and
/// the number of turns. `None` when no point is both found and off the poles.
fn unwrap(
    uv: &[[f64; 2]],
    d: usize,
    pole: &[bool],
    found: &[bool],
    period: f64,
) -> Option<(Vec<f64>, i64)> {
    let n = uv.len();
    let k0 = (0..n).find(|&k| !pole[k] && found[k])?;
    let snap = SEAM_SNAP * period;
    let mut values = vec![uv[k0][d]; n];
    let (start, mut prev) = (uv[k0][d], uv[k0][d]);
    let mut pending: Option<usize> = None;
    for step in 1..=n {
        let i = (k0 + step) % n;
        if pole[i] {
            pending = Some(i);
            values[i] = prev;
            continue;
        }
        if !found[i] {
            values[i] = prev;
            continue;
        }
        let m = (uv[i][d] - prev).rem_euclid(period);
        let delta = match pending.take() {
            // along the pole with the face on the left: at the lower bound of v (the loop goes
            // on above the pole) +u, at the upper −u; at the lower bound of u −v, at the upper +v
            Some(p) => {
                let lower = uv[i][1 - d] > uv[p][1 - d];
                if lower == (d == 0) {
                    if m > period - snap { m - period } else { m }
                } else if m < snap {
                    m
                } else {
                    m - period
                }
            }
            None if m > 0.5 * period => m - period,
            None => m,
        };
        prev += delta;
        if step < n {
            values[i] = prev;
        }
    }
    Some((values, ((prev - start) / period).round() as i64))
}

/// The range of a periodic direction `d` (period `p`).
fn periodic_range(c: &Carrier, loops: &[Oriented], outer: usize, d: usize, p: f64) -> (f64, f64) {
    let o = 1 - d;
    // the face lies on the +d side of a loop winding +1 in the other direction when d is v
    // (left of +u is +v), on its −d side when d is u (left of +v is −u)
    let side = if d == 1 { 1 } else { -1 };
    let wraps = loops.iter().position(|l| l.winding[d] != 0 || l.seam_only);
    let bottoms: Vec<&Oriented> = loops.iter().filter(|l| l.winding[o] * side > 0).collect();
    let tops: Vec<&Oriented> = loops.iter().filter(|l| l.winding[o] * side < 0).collect();
    let full_from = |lo: f64| {
        if c.shiftable {
            (lo, lo + p)
        } else {
            c.natural[d].unwrap_or((lo, lo + p))
        }
    };
    let (lo, hi) = if let Some(k) = wraps {
        full_from(span_of(&loops[k].uv, d).0)
    } else if !bottoms.is_empty() || !tops.is_empty() {
        // a band between loops that wind round the other way
        let lo = bottoms.iter().map(|l| span_of(&l.uv, d).0).reduce(f64::min);
        let hi = tops.iter().map(|l| span_of(&l.uv, d).1).reduce(f64::max);
        match (lo, hi) {
            (Some(lo), Some(hi)) => (lo, hi - ((hi - lo) / p).ceil() * p + p),
            (Some(lo), None) => full_from(lo),
            (None, Some(hi)) => full_from(hi - p),
            // (no loop winds round the other direction: not reached)
            (None, None) => span_of(&loops[outer].uv, d),
        }
    } else {
        span_of(&loops[outer].uv, d)
    };
    let hi = hi.min(lo + p);
    let snap = SEAM_SNAP * p;
    if c.shiftable {
        // the angle from [0, 2π) on: the one range of the elementary surfaces' parameters
        // ([ISO42] geometry_schema), so the same face gets the same parametrization however its
        // loop is listed
        let k = ((lo + snap) / p).floor();
        return (lo - k * p, hi - k * p);
    }
    // a closed B-spline: the range moved by whole periods into the domain, the whole domain
    // where it crosses the seam
    let (a, b) = c.natural[d].unwrap_or((lo, hi));
    let k = ((a - snap - lo) / p).ceil();
    let (lo, hi) = (lo + k * p, hi + k * p);
    if hi > b + snap {
        (a, b)
    } else {
        (lo.max(a), hi.min(b))
    }
}

/// The range of a non-periodic direction `d` over every bound point, extended to the pole or
/// bound on the face's side of a loop that winds round the other direction.
fn linear_range(c: &Carrier, loops: &[Oriented], all: &[(f64, f64)], d: usize) -> (f64, f64) {
    let pick = |q: &(f64, f64)| if d == 0 { q.0 } else { q.1 };
    let (mut lo, mut hi) = all
        .iter()
        .map(pick)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
    let o = 1 - d;
    let side = if d == 1 { 1 } else { -1 };
    let net: i64 = loops.iter().map(|l| l.winding[o]).sum::<i64>() * side;
    let mut targets = c.poles.clone();
    if let Some((a, b)) = c.natural[d] {
        targets.extend([a, b]);
    }
    // the nearest pole or bound beyond the face's extreme point on the side it lies on
    let above = targets
        .iter()
        .copied()
        .filter(|&t| t >= hi)
        .reduce(f64::min);
    let below = targets
        .iter()
        .copied()
        .filter(|&t| t <= lo)
        .reduce(f64::max);
    match (net.signum(), above, below) {
        (1, Some(t), _) => hi = t,
        (-1, _, Some(t)) => lo = t,
        _ => {}
    }
    match c.natural[d] {
        Some((a, b)) => (lo.max(a), hi.min(b)),
        None => (lo, hi),
    }
}

/// (min, max) of `values`.
fn span(values: &[f64]) -> (f64, f64) {
    values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        })
}

/// (min, max) of coordinate `d` of `uv`.
fn span_of(uv: &[[f64; 2]], d: usize) -> (f64, f64) {
    span(&uv.iter().map(|q| q[d]).collect::<Vec<_>>())
}

/// Area of the box of `uv`.
fn box_area(uv: &[[f64; 2]]) -> f64 {
    let ((a, b), (c, d)) = (span_of(uv, 0), span_of(uv, 1));
    (b - a).max(0.0) * (d - c).max(0.0)
}
