//! Thin-plate energy and sampled deviation between two surfaces.
//!
//! E(S) = ∬ |S_uu|² + 2|S_uv|² + |S_vv|² du dv over the domain (\[SV\] §5, \[H\]). It is integrated
//! span by span with Gauss–Legendre rules: (p + 1) × (q + 1) points are exact for polynomial
//! surfaces (the integrand has degree ≤ 2p in u and ≤ 2q in v); rational surfaces get
//! [`RATIONAL_EXTRA_POINTS`] more per direction.
//!
//! The deviation of a modified surface from its original is measured at samples: each sample of
//! the modified surface is projected onto the original starting from the same parameters, so
//! the figure is a true surface-to-surface distance, not a control-point displacement.

use crate::projection::{ProjectionParams, project_to_surface_from};
use crate::quadrature::GaussLegendre;
use crate::surface::BSplineSurface;

/// Extra Gauss points per span and direction for rational surfaces (the integrand is not a
/// polynomial there; 3 more points bring the quadrature error far below the energy changes
/// fairing reports).
pub const RATIONAL_EXTRA_POINTS: usize = 3;

/// Thin-plate energy ∬ |S_uu|² + 2|S_uv|² + |S_vv|² du dv.
///
/// The Gauss nodes of all spans form one tensor grid, evaluated row by row through the grid
/// kernels of [`crate::grid`] (the u basis contracted once per row, the v basis once per
/// column): the same quadrature as span by span, several times faster on large nets, in memory
/// linear in the nodes of one direction.
pub fn thin_plate_energy(surface: &BSplineSurface) -> f64 {
    let extra = if surface.is_rational() {
        RATIONAL_EXTRA_POINTS
    } else {
        0
    };
    let nodes = |rule: &GaussLegendre, knots: &crate::knots::KnotVector| {
        let k = knots.knots();
        let mut ts = Vec::new();
        let mut ws = Vec::new();
        for span in knots.spans() {
            for (t, w) in rule.on(k[span], k[span + 1]) {
                ts.push(t);
                ws.push(w);
            }
        }
        (ts, ws)
    };
    let (us, wu) = nodes(
        &GaussLegendre::new(surface.degree_u() + 1 + extra),
        surface.knots_u(),
    );
    let (vs, wv) = nodes(
        &GaussLegendre::new(surface.degree_v() + 1 + extra),
        surface.knots_v(),
    );
    let plan = crate::grid::GridPlan::new(surface, &us, &vs, crate::grid::GridOrder::Second);
    let mut rows = plan.row_scratch();
    let mut total = 0.0;
    for (a, &w_a) in wu.iter().enumerate() {
        plan.contract_row(a, &mut rows);
        let mut row_total = 0.0;
        plan.for_row(&rows, |b, d| {
            row_total +=
                wv[b] * (d.duu.norm_squared() + 2.0 * d.duv.norm_squared() + d.dvv.norm_squared());
        });
        total += w_a * row_total;
    }
    total
}

/// [`thin_plate_energy`] node by node through one evaluator, span by span: the reference the
/// grid version is tested and benchmarked against (`cargo bench -p nurbs-core --bench eval --
/// thin_plate`).
pub fn thin_plate_energy_pointwise(surface: &BSplineSurface) -> f64 {
    let extra = if surface.is_rational() {
        RATIONAL_EXTRA_POINTS
    } else {
        0
    };
    let ru = GaussLegendre::new(surface.degree_u() + 1 + extra);
    let rv = GaussLegendre::new(surface.degree_v() + 1 + extra);
    let (ku, kv) = (surface.knots_u().knots(), surface.knots_v().knots());
    let mut eval = surface.evaluator();
    let mut total = 0.0;
    for su in surface.knots_u().spans() {
        for (u, wu) in ru.on(ku[su], ku[su + 1]) {
            for sv in surface.knots_v().spans() {
                for (v, wv) in rv.on(kv[sv], kv[sv + 1]) {
                    let d = eval.derivatives(u, v);
                    total += wu
                        * wv
                        * (d.duu.norm_squared()
                            + 2.0 * d.duv.norm_squared()
                            + d.dvv.norm_squared());
                }
            }
        }
    }
    total
}

/// Largest distance, over an `n × n` parameter grid of `modified`, from `modified` to `original`
/// (closest points on `original`, found from the same parameters).
pub fn max_deviation(original: &BSplineSurface, modified: &BSplineSurface, n: usize) -> f64 {
    let us = modified.knots_u().uniform_params(n.max(2));
    let vs = modified.knots_v().uniform_params(n.max(2));
    let points = modified.eval_grid_points(&us, &vs);
    let params = ProjectionParams::default();
    let mut worst: f64 = 0.0;
    for (a, &u) in us.iter().enumerate() {
        for (b, &v) in vs.iter().enumerate() {
            let p = points[a * vs.len() + b];
            let proj = project_to_surface_from(original, &p, (u, v), &params);
            worst = worst.max(proj.distance);
        }
    }
    worst
}
