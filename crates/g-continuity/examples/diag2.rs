use g_continuity::*;
use nurbs_core::{BSplineSurface, Continuity, KnotVector, Point3, Side, Vector3};
use rand::Rng;
fn bicubic(nu: usize, nv: usize, f: impl Fn(usize, usize) -> Point3) -> BSplineSurface {
    let ku = KnotVector::clamped_uniform(3, nu).unwrap();
    let kv = KnotVector::clamped_uniform(3, nv).unwrap();
    let pts = (0..nu)
        .flat_map(|i| (0..nv).map(move |j| (i, j)))
        .map(|(i, j)| f(i, j))
        .collect();
    BSplineSurface::new(ku, kv, pts, None).unwrap()
}
fn main() {
    let w = bicubic(16, 16, |i, j| {
        let (x, y) = (3.0 * i as f64 / 15.0, 3.0 * j as f64 / 15.0);
        Point3::new(x, y, 0.4 * (1.1 * x).sin() * (0.9 * y).cos() + 0.1 * x * y)
    });
    let (a, b) = (1.0 / 3.0, 2.0 / 3.0);
    let left = w.extract((0.0, a), (0.0, 1.0)).unwrap();
    let right = w.extract((b, 1.0), (0.0, 1.0)).unwrap();
    let bottom = w.extract((0.0, 1.0), (0.0, a)).unwrap();
    let top = w.extract((0.0, 1.0), (b, 1.0)).unwrap();
    let centre = w.extract((a, b), (a, b)).unwrap();
    let mut r = nurbs_core::testing::rng(7);
    let mut slave = centre.clone();
    let (nu, nv) = (slave.num_u(), slave.num_v());
    for i in 1..nu - 1 {
        for j in 1..nv - 1 {
            let idx = slave.index(i, j);
            slave.control_points_mut()[idx] += Vector3::new(
                r.random_range(-0.02..0.02),
                r.random_range(-0.02..0.02),
                r.random_range(-0.02..0.02),
            );
        }
    }
    let links = [
        SideLink {
            side: Side::U0,
            master: &left,
            target: Continuity::G2,
        },
        SideLink {
            side: Side::U1,
            master: &right,
            target: Continuity::G2,
        },
        SideLink {
            side: Side::V0,
            master: &bottom,
            target: Continuity::G2,
        },
        SideLink {
            side: Side::V1,
            master: &top,
            target: Continuity::G2,
        },
    ];
    let (s, report) = connect_slave(&slave, &links, &ConnectParams::default()).unwrap();
    println!(
        "centre {}x{} -> {}x{} knots {} refinements {} move {:.3e}",
        nu,
        nv,
        s.num_u(),
        s.num_v(),
        report.knots_inserted,
        report.refinements,
        report.max_control_movement
    );
    for sd in &report.sides {
        println!(
            "{:?} g2 {:?} -> {:?} g1 {:?}",
            sd.side, sd.before.g2_rel, sd.after.g2_rel, sd.after.g1_deg
        );
    }
}
