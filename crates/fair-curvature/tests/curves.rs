//! Target-curvature fairing of curves: equal arc-length sampling, fixed ends, prescribed end
//! curvature, tolerance.

mod common;

use fair_curvature::{CurveParams, EndCurvature, arc_length_params, fair_curve};
use nurbs_core::{BSplineCurve, KnotVector, Point3};

fn wavy_arc(n: usize, wave: f64) -> BSplineCurve {
    let kv = KnotVector::clamped_uniform(3, n).unwrap();
    let pts = (0..n)
        .map(|i| {
            let a = 1.2 * i as f64 / (n - 1) as f64;
            let r = 1.0
                + if i > 1 && i + 2 < n {
                    wave * (-1f64).powi(i as i32)
                } else {
                    0.0
                };
            Point3::new(r * a.cos(), r * a.sin(), 0.0)
        })
        .collect();
    BSplineCurve::new(kv, pts, None).unwrap()
}

fn curvature_spread(c: &BSplineCurve) -> f64 {
    let (a, b) = c.domain();
    let ks: Vec<f64> = (5..=95)
        .map(|k| c.curvature(a + (b - a) * k as f64 / 100.0).unwrap())
        .collect();
    let m = ks.iter().sum::<f64>() / ks.len() as f64;
    (ks.iter().map(|k| (k - m).powi(2)).sum::<f64>() / ks.len() as f64).sqrt()
}

#[test]
fn arc_length_samples_are_equally_spaced() {
    let c = wavy_arc(12, 0.0);
    let t = arc_length_params(&c, 30);
    let d: Vec<f64> = t
        .windows(2)
        .map(|w| (c.point(w[1]) - c.point(w[0])).norm())
        .collect();
    let (lo, hi) = d
        .iter()
        .fold((f64::MAX, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
    assert!(hi - lo < 1e-3 * hi, "{lo} {hi}");
}

#[test]
fn noisy_arc_gets_fairer_within_tolerance_with_ends_fixed() {
    let c = wavy_arc(16, 0.004);
    let n = c.control_points().len();
    let mut free = vec![true; n];
    for k in [0, 1, 2, n - 3, n - 2, n - 1] {
        free[k] = false;
    }
    let tol = 0.01;
    let (out, report) = fair_curve(&c, &free, tol, &CurveParams::default()).unwrap();
    let (before, after) = (curvature_spread(&c), curvature_spread(&out));
    println!("curvature spread {before:.4} -> {after:.4}, {report:?}");
    // measured 0.969 -> 0.624 with the defaults (the alternating wave sits on control points
    // next to the fixed ends, whose curvature is kept)
    assert!(after < 0.7 * before, "{after} vs {before}");
    for k in 0..n {
        let (a, b) = (c.control_points()[k], out.control_points()[k]);
        if free[k] {
            assert!((a - b).norm() <= tol);
        } else {
            assert_eq!(a, b);
        }
    }
}

#[test]
fn prescribed_end_curvature_is_bad_input_when_not_finite() {
    let c = wavy_arc(10, 0.0);
    let free = vec![true; 10];
    let params = CurveParams {
        ends: EndCurvature::Prescribed {
            start: f64::NAN,
            end: 1.0,
        },
        ..CurveParams::default()
    };
    assert!(fair_curve(&c, &free, 0.01, &params).is_err());
}
