//! The residuals read only the derivative fields [`residual_fields`] names (and the point, for
//! the gap alone): the central differences [`Problem::gradient`] leaves out are exactly zero,
//! so leaving them out changes no bit of the polish.

use super::*;
use nurbs_core::shapes::torus;

/// A sample of `master` at (u, v) as [`samples`] builds it.
fn sample_at(master: &BSplineSurface, (u, v): (f64, f64), zoned: bool) -> Sample {
    let dm = master.derivatives(u, v);
    let nm = dm.normal().unwrap();
    let t1 = (dm.du - nm * nm.dot(&dm.du)).normalize();
    Sample {
        link: 0,
        u,
        v,
        foot: dm.point,
        ff: dm.fundamental_forms(),
        dm,
        nm,
        t1,
        t2: nm.cross(&t1),
        zoned,
    }
}

#[test]
fn residuals_read_only_the_fields_named() {
    let t = torus(10.0, 3.0).unwrap();
    let ((u0, u1), (v0, v1)) = (t.domain_u(), t.domain_v());
    let at = |a: f64, b: f64, f: f64| a + (b - a) * f;
    let units = Units {
        g0: 1e-3,
        g1: 0.01f64.to_radians(),
        g2: 5e-3,
        flat: 1e-4,
    };
    for side in Side::ALL {
        for target in [Continuity::G0, Continuity::G1, Continuity::G2] {
            for zoned in [false, true] {
                let sm = sample_at(&t, (at(u0, u1, 0.3), at(v0, v1, 0.4)), zoned);
                // the slave a little off the master: every residual is non-zero
                let ds = t.derivatives(at(u0, u1, 0.302), at(v0, v1, 0.397));
                let base = residuals(&ds, &sm, side, target, units);
                let read = residual_fields(side, target, zoned);
                for f in 0..FIELDS {
                    let mut changed = false;
                    for d in 0..3 {
                        let mut moved = ds;
                        field(&mut moved, f)[d] += 0.125 * (1.0 + field(&mut moved, f).norm());
                        let r = residuals(&moved, &sm, side, target, units);
                        changed |= r != base;
                        if f == 0 {
                            // the point: the gap, and nothing else
                            assert_ne!(r[d], base[d]);
                            assert_eq!(r[3..], base[3..], "{side:?} {target:?} point");
                        } else if !read.contains(&f) {
                            assert_eq!(r, base, "{side:?} {target:?} {zoned} field {f}");
                        }
                    }
                    // every field named is read
                    assert!(
                        f == 0 || !read.contains(&f) || changed,
                        "{side:?} {target:?} {f}"
                    );
                }
                // the cross second derivative is named exactly where a G2 residual is taken
                let second = match side.cross_direction() {
                    Direction::U => 3,
                    Direction::V => 5,
                };
                assert_eq!(
                    read.contains(&second),
                    target == Continuity::G2 && !zoned,
                    "{side:?} {target:?} {zoned}"
                );
            }
        }
    }
}
