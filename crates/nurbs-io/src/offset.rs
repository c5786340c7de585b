//! Offset surfaces (IGES 140): S(u, v) + d N(u, v) is no NURBS surface in general, so it is
//! approximated by a polynomial B-spline over the base surface's domain, fitted by least squares
//! to the exact offset and refined until it is within a stated tolerance (\[IGES\], entity 140).

use nurbs_core::{BSplineSurface, KnotVector, Point3};

/// Largest distance of an approximated offset surface from the exact offset, as a fraction of
/// the base surface's size: 1e-6, the relative precision of the geometry a CAD kernel writes
/// (Open CASCADE's default tolerance, 1e-7, on a part of size 0.1), so the approximation adds no
/// error above the data's own.
pub const OFFSET_TOLERANCE_RELATIVE: f64 = 1e-6;

/// Largest control net per direction of an approximated offset surface.
pub const OFFSET_MAX_NET: usize = 128;

/// Why an offset surface is not approximated ([`approximate_offset`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OffsetError {
    /// The fit stays farther from the exact offset than the tolerance at the largest net.
    #[error(
        "the offset surface is approximated only to {worst:.3e} (tolerance {tol:.3e}) within {OFFSET_MAX_NET} control points per direction"
    )]
    NotWithinTolerance {
        /// largest distance of the last fit from the exact offset
        worst: f64,
        /// the tolerance ([`OFFSET_TOLERANCE_RELATIVE`] of the base's size)
        tol: f64,
    },
    /// The base surface's normal is undefined at a point the fit needs.
    #[error("the base surface has no normal at ({u}, {v})")]
    NoNormal {
        /// parameter u of the point
        u: f64,
        /// parameter v of the point
        v: f64,
    },
    /// The kernel refused the fit's knots, template or least-squares fit.
    #[error(transparent)]
    Core(#[from] nurbs_core::Error),
}

/// The offset of `base` by `d` along its unit normal: a polynomial B-spline of degree
/// max(3, the base's) on the base's breakpoints, every span halved until the fit lies within
/// [`OFFSET_TOLERANCE_RELATIVE`] of the base's size at points between the fitted ones (up to
/// [`OFFSET_MAX_NET`] control points per direction); otherwise, or where the base's normal is
/// undefined, why not.
pub fn approximate_offset(base: &BSplineSurface, d: f64) -> Result<BSplineSurface, OffsetError> {
    let tol = OFFSET_TOLERANCE_RELATIVE * base.size();
    let degrees = (base.degree_u().max(3), base.degree_v().max(3));
    let (du, dv) = (base.domain_u(), base.domain_v());
    let mut bu = breakpoints(base.knots_u(), du);
    let mut bv = breakpoints(base.knots_v(), dv);
    loop {
        let (fit, worst) = fit_once(base, d, &bu, &bv, degrees)?;
        if worst <= tol {
            return Ok(fit);
        }
        if 2 * fit.num_u() > OFFSET_MAX_NET || 2 * fit.num_v() > OFFSET_MAX_NET {
            return Err(OffsetError::NotWithinTolerance { worst, tol });
        }
        bu = halved(&bu);
        bv = halved(&bv);
    }
}

/// The exact offset point at (u, v).
fn exact(base: &BSplineSurface, d: f64, u: f64, v: f64) -> Result<Point3, OffsetError> {
    let s = base.derivatives(u, v);
    let n = s.normal().ok_or(OffsetError::NoNormal { u, v })?;
    Ok(s.point + n * d)
}

/// One fit on the breakpoints `bu`, `bv` and its largest error between the fitted points.
fn fit_once(
    base: &BSplineSurface,
    d: f64,
    bu: &[f64],
    bv: &[f64],
    (p, q): (usize, usize),
) -> Result<(BSplineSurface, f64), OffsetError> {
    let ku = KnotVector::new(p, clamped(bu, p))?;
    let kv = KnotVector::new(q, clamped(bv, q))?;
    let (nu, nv) = (ku.num_basis(), kv.num_basis());
    // twice as many points per span as the degree needs, then checked halfway between them
    let (us, vs) = (ku.span_samples(2 * (p + 1)), kv.span_samples(2 * (q + 1)));
    let mut params = Vec::with_capacity(us.len() * vs.len());
    let mut points = Vec::with_capacity(us.len() * vs.len());
    for &u in &us {
        for &v in &vs {
            params.push((u, v));
            points.push(exact(base, d, u, v)?);
        }
    }
    let template = BSplineSurface::new(ku, kv, vec![Point3::origin(); nu * nv], None)?;
    let mask = nurbs_core::ControlMask::all_free(nu, nv);
    let fit = nurbs_core::fit::FitParams::default();
    let (fit, _) = nurbs_core::fit::fit_surface(&template, &mask, &params, &points, &fit)?;
    let mut worst: f64 = 0.0;
    for &u in &halfway(&us) {
        for &v in &halfway(&vs) {
            worst = worst.max((fit.point(u, v) - exact(base, d, u, v)?).norm());
        }
    }
    Ok((fit, worst))
}

/// The domain's ends and the distinct interior knots.
fn breakpoints(kv: &KnotVector, (a, b): (f64, f64)) -> Vec<f64> {
    let mut k = vec![a];
    k.extend(kv.interior_knots().iter().map(|&(x, _)| x));
    k.push(b);
    k
}

/// A clamped knot vector of degree `deg` on the breakpoints `b` (interior knots simple).
fn clamped(b: &[f64], deg: usize) -> Vec<f64> {
    let mut k = vec![b[0]; deg + 1];
    k.extend(&b[1..b.len() - 1]);
    k.extend(vec![b[b.len() - 1]; deg + 1]);
    k
}

/// The points halfway between consecutive values of `xs`.
fn halfway(xs: &[f64]) -> Vec<f64> {
    xs.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect()
}

/// The breakpoints with every span halved.
fn halved(b: &[f64]) -> Vec<f64> {
    let mut out = vec![b[0]];
    for w in b.windows(2) {
        out.push(0.5 * (w[0] + w[1]));
        out.push(w[1]);
    }
    out
}
