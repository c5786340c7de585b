//! Narrow helpers of the g-continuity tests: constructed surface pairs and orientation changes.
#![allow(dead_code)]

use g_continuity::{ConnectParams, ConnectReport, SideLink, connect_slave};
use nurbs_core::{BSplineSurface, Continuity, KnotVector, Point3, Side};

/// A bicubic surface from a control-point function over a clamped uniform net on [0, 1]².
pub fn bicubic(nu: usize, nv: usize, f: impl Fn(usize, usize) -> Point3) -> BSplineSurface {
    let ku = KnotVector::clamped_uniform(3, nu).unwrap();
    let kv = KnotVector::clamped_uniform(3, nv).unwrap();
    let pts = (0..nu)
        .flat_map(|i| (0..nv).map(move |j| (i, j)))
        .map(|(i, j)| f(i, j))
        .collect();
    BSplineSurface::new(ku, kv, pts, None).unwrap()
}

/// A wavy master over x ∈ [0, 3], y ∈ [0, 4]; its side u1 is the line x = 3.
pub fn wavy_master() -> BSplineSurface {
    bicubic(7, 8, |i, j| {
        let (x, y) = (3.0 * i as f64 / 6.0, 4.0 * j as f64 / 7.0);
        Point3::new(
            x,
            y,
            0.3 * (0.8 * x).sin() * (0.6 * y).cos() + 0.05 * y * y / 4.0,
        )
    })
}

/// A slave on the u1 side of `wavy_master` through its side u0: row 0 is the master's last row,
/// rows i ≥ 1 continue the master's last cross leg rotated by `kink_deg` about the v direction,
/// with a `bend` added to the heights of rows ≥ 2 (so the join is G1 but not G2 when
/// `kink_deg` = 0 and `bend` ≠ 0). Same v knots, so the boundary lies in the master's space.
pub fn kinked_slave(master: &BSplineSurface, kink_deg: f64, bend: f64) -> BSplineSurface {
    let n = master.num_u();
    let (c, s) = (kink_deg.to_radians().cos(), kink_deg.to_radians().sin());
    bicubic(6, master.num_v(), |i, j| {
        let p0 = master.control_point(n - 1, j);
        let leg = master.control_point(n - 1, j) - master.control_point(n - 2, j);
        // rotate the leg about the y axis by the kink
        let leg = nurbs_core::Vector3::new(c * leg.x - s * leg.z, leg.y, s * leg.x + c * leg.z);
        let mut p = p0 + leg * (i as f64);
        if i >= 2 {
            p.z += bend * ((i - 1) * (i - 1)) as f64 * (1.0 + 0.3 * (j as f64).sin());
        }
        p
    })
}

/// The surface with the u (or v) parameter reversed.
pub fn reversed(s: &BSplineSurface, in_u: bool) -> BSplineSurface {
    let (nu, nv) = (s.num_u(), s.num_v());
    let flip = |kv: &KnotVector| {
        let k = kv.knots();
        let (a, b) = (k[0], k[k.len() - 1]);
        KnotVector::new(kv.degree(), k.iter().rev().map(|&t| a + b - t).collect()).unwrap()
    };
    let pts = (0..nu)
        .flat_map(|i| (0..nv).map(move |j| (i, j)))
        .map(|(i, j)| {
            if in_u {
                s.control_point(nu - 1 - i, j)
            } else {
                s.control_point(i, nv - 1 - j)
            }
        })
        .collect();
    let (ku, kv) = if in_u {
        (flip(s.knots_u()), s.knots_v().clone())
    } else {
        (s.knots_u().clone(), flip(s.knots_v()))
    };
    BSplineSurface::new(ku, kv, pts, None).unwrap()
}

/// The surface with u and v swapped.
pub fn transposed(s: &BSplineSurface) -> BSplineSurface {
    let (nu, nv) = (s.num_u(), s.num_v());
    let pts = (0..nv)
        .flat_map(|j| (0..nu).map(move |i| (i, j)))
        .map(|(i, j)| s.control_point(i, j))
        .collect();
    BSplineSurface::new(s.knots_v().clone(), s.knots_u().clone(), pts, None).unwrap()
}

/// One of 8 re-parametrizations (bit 0: reverse u, bit 1: reverse v, bit 2: transpose) and where
/// the side `u0` of the original ends up.
pub fn reoriented(s: &BSplineSurface, code: u8) -> (BSplineSurface, Side) {
    let mut out = s.clone();
    let mut side = Side::U0;
    if code & 1 != 0 {
        out = reversed(&out, true);
        side = Side::U1;
    }
    if code & 2 != 0 {
        out = reversed(&out, false);
    }
    if code & 4 != 0 {
        out = transposed(&out);
        side = if side == Side::U0 { Side::V0 } else { Side::V1 };
    }
    (out, side)
}

/// Connects one side with default parameters.
pub fn connect_one(
    master: &BSplineSurface,
    slave: &BSplineSurface,
    side: Side,
    target: Continuity,
) -> (BSplineSurface, ConnectReport) {
    connect_slave(
        slave,
        &[SideLink {
            side,
            master,
            target,
            range: None,
            g2_zones: [0.0; 2],
        }],
        &ConnectParams::default(),
    )
    .unwrap()
}

/// The control points of row `k` of `side`.
pub fn row_points(s: &BSplineSurface, side: Side, k: usize) -> Vec<Point3> {
    side.row(k, s.num_u(), s.num_v())
        .into_iter()
        .map(|(i, j)| s.control_point(i, j))
        .collect()
}
