//! The JSON surface format of `docs/model-format.md` (feature `serde`).
//!
//! A surface record has `degree_u`, `degree_v`, optional full knot vectors `knots_u`/`knots_v`
//! (absent: a Bézier patch), `control_points[i][j] = [x, y, z]` (i over u) and optional `weights`
//! of the same shape (Euclidean control points, not pre-multiplied). A file holds one record, a
//! list of records, `{"surfaces": [...]}` or `{"patches": [...]}`.

use serde::{Deserialize, Serialize};

use crate::Point3;
use crate::error::{Error, Result};
use crate::knots::KnotVector;
use crate::surface::BSplineSurface;

/// One B-spline surface as stored in JSON.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SurfaceRecord {
    /// degree in u
    pub degree_u: usize,
    /// degree in v
    pub degree_v: usize,
    /// full knot vector in u (absent for a Bézier patch)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub knots_u: Option<Vec<f64>>,
    /// full knot vector in v (absent for a Bézier patch)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub knots_v: Option<Vec<f64>>,
    /// `control_points[i][j] = [x, y, z]`
    pub control_points: Vec<Vec<[f64; 3]>>,
    /// `weights[i][j]`, absent for polynomial surfaces
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weights: Option<Vec<Vec<f64>>>,
}

fn knots(
    field: &'static str,
    degree: usize,
    given: &Option<Vec<f64>>,
    count: usize,
) -> Result<KnotVector> {
    if degree == 0 {
        return Err(Error::Format {
            detail: "degree must be at least 1, got 0".into(),
        }
        .context(field));
    }
    let kv = match given {
        Some(k) => KnotVector::new(degree, k.clone()),
        None if count == degree + 1 => KnotVector::bezier(degree),
        None => Err(Error::Format {
            detail: format!("no knots given, so a Bézier patch of degree {degree} needs {} control points in this direction, got {count}", degree + 1),
        }),
    }
    .map_err(|e| e.context(field))?;
    kv.check_count(if field == "knots_u" { "u" } else { "v" }, count)
        .map_err(|e| e.context(field))?;
    Ok(kv)
}

/// Largest control net a reader accepts (nu × nv): the fairing methods' memory and time grow
/// with the net, and 10⁶ points — a 1000 × 1000 net, 24 MB of coordinates — is far beyond any
/// measured or designed CAD surface.
pub const MAX_CONTROL_POINTS: usize = 1_000_000;

/// Largest ratio of a surface's largest to its smallest weight. Exact conics need ratios
/// around 1–10 (a 90° arc: 1/cos 45°; kernels' vertex blends up to about 3); at 10⁶ the
/// rational basis of a point is dominated by one weight so much that the least-squares systems
/// of the continuity and fairing steps lose six digits.
pub const MAX_WEIGHT_RATIO: f64 = 1e6;

pub use crate::MAX_COORDINATE;

/// The bounds of [`MAX_CONTROL_POINTS`], [`MAX_COORDINATE`] and [`MAX_WEIGHT_RATIO`] on a
/// surface built by a reader.
pub fn check_bounds(s: &BSplineSurface) -> Result<()> {
    let n = s.num_u() * s.num_v();
    if n > MAX_CONTROL_POINTS {
        return Err(Error::BeyondBound {
            what: format!("the control net {}×{}", s.num_u(), s.num_v()),
            value: n as f64,
            bound: MAX_CONTROL_POINTS as f64,
        });
    }
    for (k, p) in s.control_points().iter().enumerate() {
        let big = p.coords.amax();
        if big > MAX_COORDINATE {
            return Err(Error::BeyondBound {
                what: format!(
                    "a coordinate of control point [{}][{}]",
                    k / s.num_v(),
                    k % s.num_v()
                ),
                value: big,
                bound: MAX_COORDINATE,
            });
        }
    }
    if let Some(w) = s.weights() {
        let (lo, hi) = w.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
        if hi / lo > MAX_WEIGHT_RATIO {
            return Err(Error::BeyondBound {
                what: format!("the ratio of the largest weight ({hi:e}) to the smallest ({lo:e})"),
                value: hi / lo,
                bound: MAX_WEIGHT_RATIO,
            });
        }
    }
    Ok(())
}

impl SurfaceRecord {
    /// Validates the record and builds the surface; errors name the field at fault.
    pub fn to_surface(&self) -> Result<BSplineSurface> {
        let nu = self.control_points.len();
        let nv = self.control_points.first().map_or(0, Vec::len);
        if nu == 0 || nv == 0 {
            return Err(Error::ControlNetShape {
                detail: "control_points is empty".into(),
            }
            .context("control_points"));
        }
        if let Some((i, row)) = self
            .control_points
            .iter()
            .enumerate()
            .find(|(_, r)| r.len() != nv)
        {
            return Err(Error::ControlNetShape {
                detail: format!("row {i} has {} points, row 0 has {nv}", row.len()),
            }
            .context("control_points"));
        }
        let ku = knots("knots_u", self.degree_u, &self.knots_u, nu)?;
        let kv = knots("knots_v", self.degree_v, &self.knots_v, nv)?;
        let points: Vec<Point3> = self
            .control_points
            .iter()
            .flatten()
            .map(|c| Point3::new(c[0], c[1], c[2]))
            .collect();
        let weights = match &self.weights {
            None => None,
            Some(w) => {
                if w.len() != nu || w.iter().any(|r| r.len() != nv) {
                    return Err(Error::ControlNetShape {
                        detail: format!("weights must be {nu}×{nv} like the control net"),
                    }
                    .context("weights"));
                }
                Some(w.iter().flatten().copied().collect())
            }
        };
        let surface = BSplineSurface::new(ku, kv, points, weights)?;
        check_bounds(&surface)?;
        // an unclamped knot vector is clamped: the same surface over its domain, with the
        // boundary curves as its outer control rows, which the masks and frames of every
        // method assume (model-format.md)
        surface.clamped()
    }

    /// The record of a surface (full knot vectors, weights only when rational).
    pub fn from_surface(s: &BSplineSurface) -> Self {
        let (nu, nv) = (s.num_u(), s.num_v());
        Self {
            degree_u: s.degree_u(),
            degree_v: s.degree_v(),
            knots_u: Some(s.knots_u().knots().to_vec()),
            knots_v: Some(s.knots_v().knots().to_vec()),
            control_points: (0..nu)
                .map(|i| {
                    (0..nv)
                        .map(|j| s.control_point(i, j).coords.into())
                        .collect()
                })
                .collect(),
            weights: s.weights().map(|_| {
                (0..nu)
                    .map(|i| (0..nv).map(|j| s.weight(i, j)).collect())
                    .collect()
            }),
        }
    }
}

/// The shapes a surface file may take.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
enum SurfaceFileShape {
    Wrapped { surfaces: Vec<serde_json::Value> },
    Patches { patches: Vec<serde_json::Value> },
    List(Vec<serde_json::Value>),
    One(serde_json::Value),
}

/// Parses a surface file (one record, a list, `{"surfaces": …}` or `{"patches": …}`) and
/// validates every surface; errors name the surface and the field.
pub fn surfaces_from_json(text: &str) -> Result<Vec<BSplineSurface>> {
    let shape: SurfaceFileShape = serde_json::from_str(text).map_err(|e| Error::Format {
        detail: format!("malformed JSON: {e}"),
    })?;
    let (values, single) = match shape {
        SurfaceFileShape::Wrapped { surfaces } => (surfaces, false),
        SurfaceFileShape::Patches { patches } => (patches, false),
        SurfaceFileShape::List(list) => (list, false),
        SurfaceFileShape::One(v) => (vec![v], true),
    };
    if values.is_empty() {
        return Err(Error::Format {
            detail: "the file holds no surface".into(),
        });
    }
    values
        .into_iter()
        .enumerate()
        .map(|(k, value)| {
            let place = if single {
                "surface".to_string()
            } else {
                format!("surface {k}")
            };
            let record: SurfaceRecord =
                serde_json::from_value(value).map_err(|e| Error::Format {
                    detail: format!("{place}: {e}"),
                })?;
            record.to_surface().map_err(|e| e.context(place))
        })
        .collect()
}

/// Serializes one surface as a JSON record.
pub fn surface_to_json(surface: &BSplineSurface) -> String {
    serde_json::to_string(&SurfaceRecord::from_surface(surface))
        .expect("a surface record always serializes")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An unclamped knot vector is read as the same surface, clamped: equal points over the
    /// domain, the boundary curve as the outer control row.
    #[test]
    fn unclamped_knots_are_clamped_on_reading() {
        let text = r#"{"degree_u": 2, "degree_v": 1,
            "knots_u": [0, 0.1, 0.2, 0.8, 0.9, 1.0], "knots_v": [0, 0, 1, 1],
            "control_points": [[[0,0,0],[0,1,0]], [[1,0,1],[1,1,1]], [[2,0,0],[2,1,0.5]]]}"#;
        let read = surfaces_from_json(text).unwrap().remove(0);
        let record: SurfaceRecord = serde_json::from_str(text).unwrap();
        let raw = BSplineSurface::new(
            KnotVector::new(2, record.knots_u.clone().unwrap()).unwrap(),
            KnotVector::new(1, record.knots_v.clone().unwrap()).unwrap(),
            record
                .control_points
                .iter()
                .flatten()
                .map(|c| Point3::new(c[0], c[1], c[2]))
                .collect(),
            None,
        )
        .unwrap();
        assert!(read.knots_u().is_clamped() && !raw.knots_u().is_clamped());
        assert_eq!(read.domain_u(), raw.domain_u());
        for k in 0..=10 {
            let u = 0.2 + 0.6 * k as f64 / 10.0;
            for v in [0.0, 0.5, 1.0] {
                assert!((read.point(u, v) - raw.point(u, v)).norm() < 1e-13);
            }
        }
        // the outer control row is the boundary curve u = 0.2
        let corner = read.control_points()[0];
        assert!((corner - raw.point(0.2, 0.0)).norm() < 1e-13);
    }
}
