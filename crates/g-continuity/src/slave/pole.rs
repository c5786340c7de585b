//! The curvature at a pole: a side collapsed to one point P, where the G2 sides that end there
//! meet (\[SV\] §3.3, curvature compatibility at a vertex).
//!
//! # Why
//! Near a pole the surface's cross-pole parameter lines shrink to P: along the pole ring the
//! metric goes to zero, so whatever differs between the rows a G2 side step sets and the rows
//! next to them is squeezed into a point there. With P the pole, a(t) = S_x(t, pole) the
//! derivative away from it (x the cross parameter) and b(t) = S_xx(t, pole), the curvature
//! around the pole is bounded and continuous only if n·b(t) = II(a(t), a(t)) for every t, one
//! second fundamental form II at P — else the ring's normal curvature near P is
//! ½ e''(t) / |a'(t)|² with e = n·b − II(a, a), unbounded as the ring shrinks. A sphere corner whose
//! G2 sides bring the curvature across them to 0 while the ring between them kept the sphere's
//! 0.2 /mm peaked 8–10× next to its pole.
//!
//! # What
//! [`set_pole_curvature`] takes II from the G2 masters at P (each master's normal curvature in
//! three directions of the pole's tangent plane, averaged over the masters: where they agree
//! that is their common curvature, where they do not the mean is the compromise the vertex
//! allows) and moves the interior points of the pole's third row (row 2) along n only, so that
//! n·b(t) = II(a(t), a(t)) in the least-squares sense at samples of t. The pole point and the
//! tangent row (rows 0 and 1) stay. The G2 side steps then keep those rows next to the pole
//! (`status`), so the sides and the ring share one curvature at P.

use nalgebra::DMatrix;
use nurbs_core::{BSplineSurface, Continuity, Direction, Side, Vector3};

use super::SideLink;
use crate::measure::is_collapsed;
use crate::params::SetParams;

/// Samples along the pole ring per control point of its row: enough equations that the
/// least-squares fit sees every basis function several times (a degree-p spline row has at
/// most p + 1 non-zero functions at a sample).
const SAMPLES_PER_POINT: usize = 4;

/// The second fundamental form at a pole in an orthonormal frame (e1, e2) of its tangent plane.
#[derive(Debug, Clone, Copy)]
struct PoleForm {
    e1: Vector3,
    e2: Vector3,
    /// II(e1, e1), II(e1, e2), II(e2, e2)
    l: f64,
    m: f64,
    nn: f64,
}

impl PoleForm {
    fn at(&self, a: &Vector3) -> f64 {
        let (x, y) = (a.dot(&self.e1), a.dot(&self.e2));
        self.l * x * x + 2.0 * self.m * x * y + self.nn * y * y
    }
}

/// The G2 links of `s` whose side ends at the pole `side` (a neighbour of it) with the pole's
/// corner inside the link's part.
fn pole_masters<'a>(
    s: &BSplineSurface,
    side: Side,
    links: &'a [SideLink<'a>],
) -> Vec<&'a SideLink<'a>> {
    let (start, end) = side.neighbours();
    links
        .iter()
        .filter(|l| {
            if l.target < Continuity::G2 || (l.side != start && l.side != end) {
                return false;
            }
            let (a, b) = l.domain(s);
            let (t0, t1) = l.side.along_domain(s);
            let corner = if side.is_start() { t0 } else { t1 };
            let slack = 1e-9 * (t1 - t0).abs();
            corner >= a - slack && corner <= b + slack
        })
        .collect()
}

/// The derivative away from the pole and the second one at along-parameter `t`.
fn across(s: &BSplineSurface, side: Side, t: f64) -> (Vector3, Vector3) {
    let (u, v) = side.params(s, t);
    let d = s.derivatives(u, v);
    match side.cross_direction() {
        Direction::U => (d.du, d.duu),
        Direction::V => (d.dv, d.dvv),
    }
}

/// The pole's unit normal from its tangent row (the fan of row 1 around P), oriented as the
/// surface's normal next to the pole; `None` when the row does not span a plane.
fn pole_normal(s: &BSplineSurface, side: Side) -> Option<Vector3> {
    let (nu, nv) = (s.num_u(), s.num_v());
    let p = s.control_points()[s.index(side.row(0, nu, nv)[0].0, side.row(0, nu, nv)[0].1)];
    let ring: Vec<Vector3> = side
        .row(1, nu, nv)
        .iter()
        .map(|&(i, j)| s.control_points()[s.index(i, j)] - p)
        .collect();
    let mut fan = Vector3::zeros();
    for w in ring.windows(2) {
        fan += w[0].cross(&w[1]);
    }
    let n = fan.try_normalize(1e-12 * ring.iter().map(|d| d.norm_squared()).sum::<f64>())?;
    // orientation: the normal S_u × S_v a little inside, at the middle of the ring
    let (t0, t1) = side.along_domain(s);
    let (u, v) = side.params(s, 0.5 * (t0 + t1));
    let (c0, c1) = match side.cross_direction() {
        Direction::U => s.domain_u(),
        Direction::V => s.domain_v(),
    };
    let step = 1e-3 * (c1 - c0) * if side.is_start() { 1.0 } else { -1.0 };
    let (u, v) = match side.cross_direction() {
        Direction::U => (u + step, v),
        Direction::V => (u, v + step),
    };
    let inside = s.derivatives(u, v).normal()?;
    Some(if inside.dot(&n) < 0.0 { -n } else { n })
}

/// The mean second fundamental form of `masters` at the pole point `p`, in a frame of the
/// tangent plane with normal `n`; `None` when no master has a curvature there.
fn masters_form(
    p: &nurbs_core::Point3,
    n: Vector3,
    first: Vector3,
    masters: &[&SideLink],
    params: &SetParams,
) -> Option<PoleForm> {
    let e1 = (first - n * n.dot(&first)).try_normalize(1e-12)?;
    let e2 = n.cross(&e1);
    let diag = (e1 + e2) / std::f64::consts::SQRT_2;
    let (mut l, mut m, mut nn, mut count) = (0.0, 0.0, 0.0, 0usize);
    for link in masters {
        let foot = nurbs_core::project_to_surface(link.master, p, &params.projection);
        let d = link.master.derivatives(foot.u, foot.v);
        let Some(ff) = d.fundamental_forms() else {
            continue;
        };
        let sign = if ff.normal.dot(&n) < 0.0 { -1.0 } else { 1.0 };
        let k = |dir: &Vector3| d.normal_curvature_with(&ff, dir).map(|x| sign * x);
        let (Some(k1), Some(k2), Some(k3)) = (k(&e1), k(&e2), k(&diag)) else {
            continue;
        };
        l += k1;
        nn += k2;
        m += k3 - 0.5 * (k1 + k2);
        count += 1;
    }
    (count > 0).then(|| {
        let c = count as f64;
        PoleForm {
            e1,
            e2,
            l: l / c,
            m: m / c,
            nn: nn / c,
        }
    })
}

/// Sets the curvature at every pole of `s` that a G2 side ends at (see the module docs):
/// the interior points of the pole's row 2 move along the pole normal. Returns the largest
/// movement (0 when `s` has no such pole).
pub(super) fn set_pole_curvature(
    s: &mut BSplineSurface,
    links: &[SideLink],
    params: &SetParams,
) -> f64 {
    let mut moved = 0.0f64;
    for side in Side::ALL {
        if !is_collapsed(s, side) {
            continue;
        }
        let masters = pole_masters(s, side, links);
        if masters.is_empty() {
            continue;
        }
        moved = moved.max(set_one_pole(s, side, &masters, params).unwrap_or(0.0));
    }
    moved
}

/// [`set_pole_curvature`] at the pole `side`; `None` when the pole has no tangent plane, the
/// masters no curvature there, or the ring too few points.
fn set_one_pole(
    s: &mut BSplineSurface,
    side: Side,
    masters: &[&SideLink],
    params: &SetParams,
) -> Option<f64> {
    let (nu, nv) = (s.num_u(), s.num_v());
    let row2 = side.row(2, nu, nv);
    let m = row2.len();
    if m < 3 || side.row(0, nu, nv).len() != m {
        return None;
    }
    let (i0, j0) = side.row(0, nu, nv)[0];
    let p = s.control_points()[s.index(i0, j0)];
    let n = pole_normal(s, side)?;
    let (t0, t1) = side.along_domain(s);
    let form = masters_form(&p, n, across(s, side, t0).0, masters, params)?;
    let samples = (SAMPLES_PER_POINT * m).max(16);
    let ts: Vec<f64> = (0..samples)
        .map(|k| t0 + (t1 - t0) * k as f64 / (samples - 1) as f64)
        .collect();
    // n·b is linear in the control points (weights fixed): a move x of point (i, j) along n
    // changes it by x·R_ij,xx (nurbs-core's rational basis), so each sample is one row
    let free: Vec<(usize, usize)> = row2[1..m - 1].to_vec();
    let column = |ij: (usize, usize)| free.iter().position(|&f| f == ij);
    let mut basis = nurbs_core::SurfaceBasis::new(s);
    let mut evaluator = nurbs_core::SurfaceBasisEvaluator::new(s);
    let mut a = DMatrix::zeros(samples, free.len());
    let mut r0 = Vec::with_capacity(samples);
    for (k, &t) in ts.iter().enumerate() {
        let (u, v) = side.params(s, t);
        let (d, dd) = across(s, side, t);
        r0.push(form.at(&d) - n.dot(&dd));
        evaluator.eval(u, v, &mut basis);
        let second = match side.cross_direction() {
            Direction::U => &basis.duu,
            Direction::V => &basis.dvv,
        };
        for (e, &value) in second.iter().enumerate() {
            if let Some(c) = column(basis.control_index(e)) {
                a[(k, c)] = value;
            }
        }
    }
    let b = DMatrix::from_column_slice(samples, 1, &r0);
    let x = crate::lsq::solve_min_norm(a, &b).ok()?;
    let mut largest = 0.0f64;
    for (c, &(i, j)) in free.iter().enumerate() {
        let idx = s.index(i, j);
        s.control_points_mut()[idx] += n * x[(c, 0)];
        largest = largest.max(x[(c, 0)].abs());
    }
    Some(largest)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs_core::{KnotVector, Point3};

    const R: f64 = 5.0;

    /// The sphere octant from its pole (side U0), refined so that its pole row 2 has interior
    /// points and row 2 is not the opposite side.
    fn octant() -> BSplineSurface {
        let s = nurbs_core::shapes::sphere_octant(R).unwrap();
        let s = s.elevate_degree(Direction::U, 3).unwrap();
        let s = s.elevate_degree(Direction::V, 3).unwrap();
        let s = s.refine(Direction::U, &[0.25, 0.5, 0.75]).unwrap();
        s.refine(Direction::V, &[0.2, 0.4, 0.6, 0.8]).unwrap()
    }

    fn links<'a>(m: &'a BSplineSurface) -> Vec<SideLink<'a>> {
        [Side::V0, Side::V1]
            .into_iter()
            .map(|side| SideLink {
                side,
                master: m,
                target: Continuity::G2,
                range: None,
                g2_zones: [0.0; 2],
            })
            .collect()
    }

    /// n·S_uu / |S_u|² at the pole along the ring: the normal curvature of each meridian there.
    fn ring_curvatures(s: &BSplineSurface) -> Vec<f64> {
        let n = pole_normal(s, Side::U0).unwrap();
        (0..=20)
            .map(|k| {
                let (a, b) = across(s, Side::U0, k as f64 / 20.0);
                n.dot(&b) / a.norm_squared()
            })
            .collect()
    }

    /// Masters that are the sphere itself ask for the curvature the pole has: nothing moves.
    #[test]
    fn a_pole_with_its_masters_curvature_stays() {
        let mut s = octant();
        let before = s.clone();
        let master = before.clone();
        let moved = set_pole_curvature(&mut s, &links(&master), &SetParams::default());
        assert!(moved < 1e-9 * R, "moved {moved}");
        for k in ring_curvatures(&s) {
            assert!((k.abs() - 1.0 / R).abs() < 1e-9, "{k}");
        }
    }

    /// A master that agrees with the sphere along both meridians but is twisted between them
    /// (z = R − (x² + y²)/2R − m·x·y, a biquadratic patch: II = [[1/R, m], [m, 1/R]] at the
    /// pole): the ring takes the master's curvature in every direction, 1/R + m·sin 2θ, where
    /// it had the sphere's 1/R; the pole and its tangent row stay, and only row 2 moves, along
    /// the pole normal.
    #[test]
    fn a_twisted_master_turns_the_pole_curvature() {
        let m = 0.5 / R;
        let a = 2.0 * R;
        let (xs, x2) = ([-a, 0.0, a], [a * a, -a * a, a * a]);
        let mut pts = Vec::new();
        for i in 0..3 {
            for j in 0..3 {
                let z = R - (x2[i] + x2[j]) / (2.0 * R) - m * xs[i] * xs[j];
                pts.push(Point3::new(xs[i], xs[j], z));
            }
        }
        let k = KnotVector::clamped_uniform(2, 3).unwrap();
        let master = BSplineSurface::new(k.clone(), k, pts, None).unwrap();
        let mut s = octant();
        let before = s.clone();
        let n = pole_normal(&before, Side::U0).unwrap();
        let moved = set_pole_curvature(&mut s, &links(&master), &SetParams::default());
        assert!(moved > 0.0);
        for k in 0..=20 {
            let (a, b) = across(&s, Side::U0, k as f64 / 20.0);
            let theta = a.y.atan2(a.x);
            let want = 1.0 / R + m * (2.0 * theta).sin();
            let got = (n.dot(&b) / a.norm_squared()).abs();
            assert!((got - want).abs() < 1e-3 / R, "at {k}: {got} want {want}");
        }
        let (nu, nv) = (s.num_u(), s.num_v());
        for i in 0..nu {
            for j in 0..nv {
                let d = s.control_points()[s.index(i, j)] - before.control_points()[s.index(i, j)];
                if i == 2 && j > 0 && j + 1 < nv {
                    assert!(d.cross(&n).norm() < 1e-12 * R, "({i}, {j}) off the normal");
                } else {
                    assert_eq!(d.norm(), 0.0, "({i}, {j}) moved");
                }
            }
        }
    }

    /// No G2 master at the pole: nothing to set.
    #[test]
    fn a_pole_without_g2_masters_stays() {
        let mut s = octant();
        let master = s.clone();
        let mut ls = links(&master);
        for l in &mut ls {
            l.target = Continuity::G1;
        }
        assert_eq!(set_pole_curvature(&mut s, &ls, &SetParams::default()), 0.0);
    }
}
