//! The knots of the B-spline forms whose knots the file leaves implied (\[ISO42\] geometry_schema:
//! `uniform_curve` / `uniform_surface`, `quasi_uniform_curve` / `quasi_uniform_surface`,
//! `bezier_curve` / `bezier_surface`, `piecewise_bezier_curve` / `_surface`), and which of the
//! forms an instance is. For n + 1 control points of degree p (upper index k = n):
//!
//! - uniform: the knots −p, −p + 1, …, n + 1, each once (n + p + 2 knots, domain [0, n − p + 1]);
//! - quasi-uniform: 0, 1, …, n − p + 1, the ends p + 1 times and the others once;
//! - Bézier (and piecewise Bézier): 0, 1, …, n / p, the ends p + 1 times and the others p
//!   times, which needs n a multiple of p (n / p Bézier segments).

use super::lexer::Instance;

/// A B-spline form whose knots are derived from the degree and the number of control points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum ImpliedKnots {
    Uniform,
    QuasiUniform,
    Bezier,
}

/// The implied-knot form of a curve (`surface` false) or surface instance, `None` when the
/// instance lists its knots (`…_WITH_KNOTS`) or is no B-spline.
pub(super) fn implied_form(inst: &Instance, surface: bool) -> Option<ImpliedKnots> {
    let kind = if surface { "SURFACE" } else { "CURVE" };
    let has = |prefix: &str| {
        inst.parts
            .iter()
            .any(|(n, _)| *n == format!("{prefix}_{kind}"))
    };
    if has("UNIFORM") {
        Some(ImpliedKnots::Uniform)
    } else if has("QUASI_UNIFORM") {
        Some(ImpliedKnots::QuasiUniform)
    } else if has("BEZIER") || has("PIECEWISE_BEZIER") {
        Some(ImpliedKnots::Bezier)
    } else {
        None
    }
}

/// Whether `inst` is a B-spline curve (`surface` false) or surface in any of the forms read.
pub(super) fn is_spline(inst: &Instance, surface: bool) -> bool {
    let knots = if surface {
        "B_SPLINE_SURFACE_WITH_KNOTS"
    } else {
        "B_SPLINE_CURVE_WITH_KNOTS"
    };
    inst.parts.iter().any(|(n, _)| n == knots) || implied_form(inst, surface).is_some()
}

/// Why the knots of an implied-knot form cannot be made ([`implied_knots`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub(super) enum KnotsError {
    /// No more control points than the degree (or degree 0).
    #[error("{count} control points of degree {degree}: a B-spline needs more than its degree")]
    TooFewPoints {
        /// control points given
        count: usize,
        /// the degree
        degree: usize,
    },
    /// A Bézier form whose control points are not a multiple of its degree plus one.
    #[error(
        "a Bézier form of degree {degree} needs a multiple of {degree} plus one control points, not {count}"
    )]
    BezierCount {
        /// the degree
        degree: usize,
        /// control points given
        count: usize,
    },
}

/// The full knot vector of `form` for `count` control points of `degree`, or what is wrong.
pub(super) fn implied_knots(
    form: ImpliedKnots,
    degree: usize,
    count: usize,
) -> Result<Vec<f64>, KnotsError> {
    if degree == 0 || count <= degree {
        return Err(KnotsError::TooFewPoints { count, degree });
    }
    let n = count - 1;
    Ok(match form {
        ImpliedKnots::Uniform => (0..=n + degree + 1)
            .map(|i| i as f64 - degree as f64)
            .collect(),
        ImpliedKnots::QuasiUniform => {
            let last = n - degree + 1;
            let mut k = vec![0.0; degree];
            k.extend((0..=last).map(|i| i as f64));
            k.extend(std::iter::repeat_n(last as f64, degree));
            k
        }
        ImpliedKnots::Bezier => {
            if !n.is_multiple_of(degree) {
                return Err(KnotsError::BezierCount { degree, count });
            }
            let segments = n / degree;
            let mut k = vec![0.0];
            for s in 0..=segments {
                k.extend(std::iter::repeat_n(s as f64, degree));
            }
            k.push(segments as f64);
            k
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn implied_knots_count_control_points_plus_degree_plus_one() {
        for form in [
            ImpliedKnots::Uniform,
            ImpliedKnots::QuasiUniform,
            ImpliedKnots::Bezier,
        ] {
            let k = implied_knots(form, 3, 7).unwrap();
            assert_eq!(k.len(), 7 + 3 + 1, "{form:?}");
            assert!(k.windows(2).all(|w| w[0] <= w[1]));
        }
        assert_eq!(
            implied_knots(ImpliedKnots::QuasiUniform, 2, 5).unwrap(),
            [0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 3.0, 3.0]
        );
        assert_eq!(
            implied_knots(ImpliedKnots::Bezier, 2, 5).unwrap(),
            [0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0, 2.0]
        );
        assert_eq!(
            implied_knots(ImpliedKnots::Uniform, 1, 3).unwrap(),
            [-1.0, 0.0, 1.0, 2.0, 3.0]
        );
        assert!(implied_knots(ImpliedKnots::Bezier, 3, 6).is_err());
        assert!(implied_knots(ImpliedKnots::Uniform, 2, 2).is_err());
    }
}
