//! The rows of the Greiner method are the complete first-order linearization of the faired
//! surface's shape operator: against finite differences their error is of second order in the
//! displacement, while Greiner's plain rows (R's metric) err at first order.

mod common;

use common::*;
use fair_curvature::hessian::SampleGeometry;
use nurbs_core::{BSplineSurface, SurfaceBasis, SurfaceBasisEvaluator, Vector3};

/// Largest error of (plain, linearized) rows against S's shape operator in R's orthonormal
/// frame, at a sample of `r` displaced by `eps` × a smooth bump (normal and tangential parts).
fn row_errors(r: &BSplineSurface, u: f64, v: f64, eps: f64) -> (f64, f64) {
    let mut s = r.clone();
    let nv = s.num_v();
    for (k, p) in s.control_points_mut().iter_mut().enumerate() {
        let (i, j) = ((k / nv) as f64, (k % nv) as f64);
        let bump = (-((i - 7.5).powi(2) + (j - 6.5).powi(2)) / 8.0).exp();
        *p += eps * bump * Vector3::new(0.3, -0.2, 1.0);
    }
    let g = SampleGeometry::new(&r.evaluator().derivatives(u, v)).expect("regular");
    let gs = SampleGeometry::new(&s.evaluator().derivatives(u, v)).expect("regular");
    let truth = g.orthonormal_mixed(gs.shape);
    let mut basis = SurfaceBasis::new(r);
    SurfaceBasisEvaluator::new(r).eval(u, v, &mut basis);
    let cv = basis.count_v;
    let (mut plain, mut full) = ([0.0; 3], g.metric_constant());
    for k in 0..basis.value.len() {
        let p = s.control_points()[(basis.first_u + k / cv) * nv + basis.first_v + k % cv].coords;
        let m = g.covariant(
            [basis.du[k], basis.dv[k]],
            [basis.duu[k], basis.duv[k], basis.dvv[k]],
        );
        let y = g.orthonormal(m);
        let metric = g.metric_variation([basis.du[k], basis.dv[k]]);
        for e in 0..3 {
            plain[e] += y[e] * g.normal.dot(&p);
            full[e] += y[e] * g.normal.dot(&p) - (0..3).map(|c| metric[c][e] * p[c]).sum::<f64>();
        }
    }
    let err = |x: [f64; 3]| (0..3).map(|e| (x[e] - truth[e]).abs()).fold(0.0, f64::max);
    (err(plain), err(full))
}

#[test]
fn linearized_rows_err_at_second_order_plain_rows_at_first() {
    let r = saddle(12);
    for (u, v) in [(0.43, 0.61), (0.2, 0.7), (0.55, 0.35)] {
        let (p1, f1) = row_errors(&r, u, v, 1e-2);
        let (p2, f2) = row_errors(&r, u, v, 5e-3);
        println!("({u}, {v}): plain {p1:.3e} → {p2:.3e}, linearized {f1:.3e} → {f2:.3e}");
        // halving the displacement halves the plain error and quarters the linearized one
        assert!(p2 > 0.4 * p1 && p2 < 0.6 * p1, "plain {p1} {p2}");
        assert!(f2 < 0.3 * f1, "linearized {f1} {f2}");
        assert!(f1 < 0.1 * p1, "linearized {f1} vs plain {p1}");
    }
}
