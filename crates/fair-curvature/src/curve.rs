//! Target-curvature fairing of a B-spline curve (\[SSV08\]; \[SV\] §5.2).
//!
//! The curve is sampled at equal arc length (a dense parameter sampling, its cumulative chord
//! length inverted by linear interpolation), the samples are faired by
//! [`crate::polyline::fair_polyline`] (end curvatures kept or prescribed: this is how a G2 end
//! condition is kept), and the curve is refitted by nurbs-core's constrained least squares
//! ([`nurbs_core::fit_curve`]), in which points with `free[k] == false` keep their values.
//! Displacements beyond the tolerance are scaled back (convex hull property).
//!
//! # Tolerance
//! The faired samples stay within `pull_tolerance_fraction` × tolerance of the originals; the
//! control displacements within the tolerance (model units).

use nurbs_core::{BSplineCurve, FitParams, Point3, fit_curve};

use crate::error::{CurvatureError, Result, check_tolerance};
use crate::polyline::{EndCurvature, PolylineParams, fair_polyline};

/// Dense parameter samples per arc-length sample used to invert the arc length.
pub(crate) const ARC_LENGTH_OVERSAMPLING: usize = 16;

/// Settings of curve fairing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveParams {
    /// Arc-length samples per non-empty knot span (≥ 1). Default 8: the refit sees every basis
    /// function at ≥ 8 samples.
    pub samples_per_span: usize,
    /// Smoothing and integration. Default [`PolylineParams::default`].
    pub polyline: PolylineParams,
    /// End curvatures. Default [`EndCurvature::Keep`].
    pub ends: EndCurvature,
    /// D / tolerance ∈ (0, 1]. Default 0.9.
    pub pull_tolerance_fraction: f64,
}

impl Default for CurveParams {
    fn default() -> Self {
        Self {
            samples_per_span: 8,
            polyline: PolylineParams::default(),
            ends: EndCurvature::Keep,
            pull_tolerance_fraction: 0.9,
        }
    }
}

/// What a curve run achieved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveReport {
    /// number of arc-length samples
    pub samples: usize,
    /// largest distance between the refitted curve and the faired samples (model units)
    pub refit_max_error: f64,
    /// root mean square of those distances (model units)
    pub refit_rms_error: f64,
    /// factor the control displacements were scaled by (1 = none)
    pub scale: f64,
    /// largest control-point displacement (model units)
    pub max_control_move: f64,
}

/// Parameters of `count` points at equal arc length along `curve`.
pub fn arc_length_params(curve: &BSplineCurve, count: usize) -> Vec<f64> {
    let count = count.max(2);
    let dense = curve
        .knots()
        .uniform_params((count - 1) * ARC_LENGTH_OVERSAMPLING + 1);
    let pts: Vec<Point3> = dense.iter().map(|&t| curve.point(t)).collect();
    let mut cum = vec![0.0];
    for w in pts.windows(2) {
        cum.push(cum[cum.len() - 1] + (w[1] - w[0]).norm());
    }
    let total = cum[cum.len() - 1];
    if !(total > 0.0) {
        return curve.knots().uniform_params(count);
    }
    let mut out = Vec::with_capacity(count);
    let mut seg = 0;
    for k in 0..count {
        let s = total * k as f64 / (count - 1) as f64;
        while seg + 2 < cum.len() && cum[seg + 1] < s {
            seg += 1;
        }
        let len = cum[seg + 1] - cum[seg];
        let f = if len > 0.0 {
            ((s - cum[seg]) / len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(dense[seg] + f * (dense[seg + 1] - dense[seg]));
    }
    out[0] = dense[0];
    out[count - 1] = dense[dense.len() - 1];
    out
}

/// Fairs a polynomial curve, moving only points with `free[k]`, each within `tolerance`.
pub fn fair_curve(
    curve: &BSplineCurve,
    free: &[bool],
    tolerance: f64,
    params: &CurveParams,
) -> Result<(BSplineCurve, CurveReport)> {
    check_tolerance(tolerance)?;
    params.polyline.check()?;
    if params.samples_per_span == 0 {
        return Err(CurvatureError::InvalidParameter {
            name: "samples_per_span",
            value: 0.0,
            expected: "≥ 1",
        });
    }
    crate::error::check_fraction("pull_tolerance_fraction", params.pull_tolerance_fraction)?;
    let n = curve.control_points().len();
    if free.len() != n {
        return Err(CurvatureError::MaskLength {
            flags: free.len(),
            points: n,
        });
    }
    let spans = curve.knots().spans().count();
    let count = spans * params.samples_per_span + 1;
    let ts = arc_length_params(curve, count.max(4));
    let pts: Vec<Point3> = ts.iter().map(|&t| curve.point(t)).collect();
    let faired = fair_polyline(
        &pts,
        params.pull_tolerance_fraction * tolerance,
        &params.polyline,
        params.ends,
    )?;
    let (fitted, fit) = fit_curve(curve, free, &ts, &faired, &FitParams::default())?;
    let mut delta: Vec<_> = curve
        .control_points()
        .iter()
        .zip(fitted.control_points())
        .map(|(a, b)| b - a)
        .collect();
    let scale = crate::normal::limit_to_tolerance(&mut delta, tolerance);
    let mut out = curve.clone();
    for (k, p) in out.control_points_mut().iter_mut().enumerate() {
        if free[k] {
            *p += delta[k];
        }
    }
    Ok((
        out,
        CurveReport {
            samples: ts.len(),
            refit_max_error: fit.max_error,
            refit_rms_error: fit.rms_error,
            scale,
            max_control_move: crate::normal::max_norm(&delta),
        },
    ))
}
