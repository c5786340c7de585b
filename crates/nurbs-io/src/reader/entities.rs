//! Access to an entity's parameters (a cursor whose errors name the entity), the entity's
//! transformation matrices (124, composed), its name, and the curves: 110, 100 and 126 as exact
//! NURBS curves (\[IGES\] §4.13, §4.3, §4.23, §4.21).

use nurbs_core::{BSplineCurve, KnotVector, Point3};

use super::records::{DirEntry, Global, Record, entity_params};
use super::{IgesCurve, MAX_TRANSFORM_CHAIN};
use crate::error::IgesError;
use crate::params::{Located, Param};

/// Sequential access to an entity's parameters with errors that name the entity.
pub(super) struct Cursor<'a> {
    pub(super) params: &'a [Located],
    pub(super) next: usize,
    pub(super) e: &'a DirEntry,
}

impl<'a> Cursor<'a> {
    /// An error of this entity.
    pub(super) fn err(&self, detail: String) -> IgesError {
        IgesError::Entity {
            de: self.e.seq,
            entity_type: self.e.entity_type,
            detail,
        }
    }
    /// The next parameter as a number (an empty field is 0).
    pub(super) fn real(&mut self) -> Result<f64, IgesError> {
        let k = self.next;
        let p = self.params.get(k).ok_or_else(|| {
            self.err(format!(
                "the data ends after {} parameters, but more are needed (count mismatch)",
                self.params.len()
            ))
        })?;
        self.next += 1;
        match &p.value {
            Param::Number(x) => Ok(*x),
            Param::Empty => Ok(0.0),
            Param::Text(_) => Err(IgesError::Parameter {
                line: p.line,
                detail: format!(
                    "parameter {k} of entity {} is a string, expected a number",
                    self.e.seq
                ),
            }),
        }
    }
    /// The next parameter as an integer.
    pub(super) fn int(&mut self) -> Result<i64, IgesError> {
        let line = self.params.get(self.next).map_or(0, |p| p.line);
        let x = self.real()?;
        if x.fract() != 0.0 || x.abs() > 1e15 {
            return Err(IgesError::Parameter {
                line,
                detail: format!(
                    "parameter {} of entity {} is {x}, expected an integer",
                    self.next - 1,
                    self.e.seq
                ),
            });
        }
        Ok(x as i64)
    }
    /// The next parameter as a count `what` of at least `min` (and at most 10⁶).
    pub(super) fn count(&mut self, what: &str, min: i64) -> Result<usize, IgesError> {
        let n = self.int()?;
        if n < min || n > 1_000_000 {
            return Err(self.err(format!("{what} is {n}")));
        }
        Ok(n as usize)
    }
    /// The next `n` parameters as numbers.
    pub(super) fn reals(&mut self, n: usize) -> Result<Vec<f64>, IgesError> {
        (0..n).map(|_| self.real()).collect()
    }
}

/// An affine map x ↦ R x + t.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Affine {
    r: [[f64; 3]; 3],
    t: [f64; 3],
}

impl Affine {
    /// The image of `p`.
    pub(super) fn apply(&self, p: &Point3) -> Point3 {
        let c = |k: usize| self.r[k][0] * p.x + self.r[k][1] * p.y + self.r[k][2] * p.z + self.t[k];
        Point3::new(c(0), c(1), c(2))
    }
    /// This map followed by `outer`.
    pub(super) fn then(&self, outer: &Affine) -> Affine {
        let mut r = [[0.0; 3]; 3];
        let mut t = [0.0; 3];
        for i in 0..3 {
            for j in 0..3 {
                r[i][j] = (0..3).map(|k| outer.r[i][k] * self.r[k][j]).sum();
            }
            t[i] = (0..3).map(|k| outer.r[i][k] * self.t[k]).sum::<f64>() + outer.t[i];
        }
        Affine { r, t }
    }
}

/// A file's directory and parameter data, read entity by entity.
pub(super) struct Reader<'a> {
    pub(super) dir: Vec<DirEntry>,
    pub(super) p: Vec<Record<'a>>,
    pub(super) global: Global,
}

impl Reader<'_> {
    /// The directory entry a pointer of entity `from` names.
    pub(super) fn entry(&self, pointer: i64, from: &DirEntry) -> Result<&DirEntry, IgesError> {
        if pointer < 1 || pointer % 2 == 0 || (pointer as usize).div_ceil(2) > self.dir.len() {
            return Err(IgesError::Entity {
                de: from.seq,
                entity_type: from.entity_type,
                detail: format!("pointer {pointer} does not name a directory entry"),
            });
        }
        Ok(&self.dir[(pointer as usize - 1) / 2])
    }

    /// The composite transformation of an entity (identity when it has none).
    pub(super) fn transform(&self, e: &DirEntry) -> Result<Option<Affine>, IgesError> {
        let mut total: Option<Affine> = None;
        let mut pointer = e.transform;
        let mut depth = 0;
        while pointer != 0 {
            depth += 1;
            if depth > MAX_TRANSFORM_CHAIN {
                return Err(IgesError::Entity {
                    de: e.seq,
                    entity_type: e.entity_type,
                    detail: "transformation matrices form a cycle".into(),
                });
            }
            let m = self.entry(pointer, e)?;
            if m.entity_type != 124 {
                return Err(IgesError::Entity {
                    de: e.seq,
                    entity_type: e.entity_type,
                    detail: format!(
                        "transformation pointer {pointer} names entity type {}",
                        m.entity_type
                    ),
                });
            }
            let params = entity_params(m, &self.p, &self.global)?;
            let mut c = Cursor {
                params: &params,
                next: 1,
                e: m,
            };
            let v = c.reals(12)?;
            let a = Affine {
                r: [[v[0], v[1], v[2]], [v[4], v[5], v[6]], [v[8], v[9], v[10]]],
                t: [v[3], v[7], v[11]],
            };
            total = Some(match total {
                None => a,
                Some(inner) => inner.then(&a),
            });
            pointer = m.transform;
        }
        Ok(total)
    }

    /// The entity's label and subscript, or `iges<de>`.
    pub(super) fn name(e: &DirEntry) -> String {
        let label = String::from_utf8_lossy(&e.label).trim().to_string();
        match (label.is_empty(), e.subscript) {
            (true, _) => format!("iges{}", e.seq),
            (false, 0) => label,
            (false, s) => format!("{label}_{s}"),
        }
    }

    /// The kernel's error as an error of entity `e`.
    pub(super) fn geometry_err(e: &DirEntry) -> impl Fn(nurbs_core::Error) -> IgesError + '_ {
        move |source| IgesError::Geometry {
            de: e.seq,
            entity_type: e.entity_type,
            source,
        }
    }

    /// Points from coordinates of entity `e`, its transformation and the model scale applied.
    pub(super) fn points(
        &self,
        e: &DirEntry,
        coords: &[f64],
        scale: f64,
    ) -> Result<Vec<Point3>, IgesError> {
        let affine = self.transform(e)?;
        Ok(coords
            .chunks(3)
            .map(|c| {
                let p = Point3::new(c[0], c[1], c[2]);
                let p = affine.map_or(p, |a| a.apply(&p));
                if scale != 1.0 {
                    Point3::from(p.coords / scale)
                } else {
                    p
                }
            })
            .collect())
    }

    /// A curve entity as an exact NURBS curve: 110 (line segment, degree 1), 100 (circular arc,
    /// rational quadratic, \[IGES\] §4.3: centre, start and end in the plane z = ZT of its
    /// definition space, counterclockwise; start = end is a full circle) or 126. The entity's
    /// transformation applies to the control points, which is exact for a rational curve.
    pub(super) fn any_curve(&self, e: &DirEntry, scale: f64) -> Result<BSplineCurve, IgesError> {
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let g = Self::geometry_err(e);
        match e.entity_type {
            110 => {
                let ends = c.reals(6)?;
                let pts = self.points(e, &ends, scale)?;
                BSplineCurve::new(nurbs_core::KnotVector::bezier(1).map_err(&g)?, pts, None)
                    .map_err(&g)
            }
            100 => {
                let v = c.reals(7)?;
                let (zt, centre) = (v[0], (v[1], v[2]));
                let (a, b) = (
                    (v[3] - centre.0, v[4] - centre.1),
                    (v[5] - centre.0, v[6] - centre.1),
                );
                let r = a.0.hypot(a.1);
                let start = a.1.atan2(a.0);
                let mut end = b.1.atan2(b.0);
                while end <= start + 1e-12 {
                    end += std::f64::consts::TAU;
                }
                let arc = nurbs_core::shapes::arc(
                    Point3::new(centre.0, centre.1, zt),
                    nurbs_core::Vector3::x(),
                    nurbs_core::Vector3::y(),
                    r,
                    start,
                    end,
                )
                .map_err(&g)?;
                let coords: Vec<f64> = arc
                    .control_points()
                    .iter()
                    .flat_map(|p| [p.x, p.y, p.z])
                    .collect();
                let pts = self.points(e, &coords, scale)?;
                BSplineCurve::new(arc.knots().clone(), pts, arc.weights().map(<[f64]>::to_vec))
                    .map_err(&g)
            }
            126 => Ok(self.curve(e, scale)?.curve),
            other => Err(IgesError::Entity {
                de: e.seq,
                entity_type: other,
                detail:
                    "a curve of this type is not read (lines 110, arcs 100 and B-splines 126 are)"
                        .to_string(),
            }),
        }
    }

    /// Entity 126, the rational B-spline curve (\[IGES\] §4.23).
    pub(super) fn curve(&self, e: &DirEntry, scale: f64) -> Result<IgesCurve, IgesError> {
        let params = entity_params(e, &self.p, &self.global)?;
        let mut c = Cursor {
            params: &params,
            next: 1,
            e,
        };
        let k = c.count("K (upper index of the control points)", 1)?;
        let m = c.count("M (degree)", 1)?;
        let _props = c.reals(4)?;
        let knots = c.reals(k + m + 2)?;
        let w = c.reals(k + 1)?;
        let coords = c.reals(3 * (k + 1))?;
        let range = c.reals(2)?;
        let points = self.points(e, &coords, scale)?;
        let polynomial = w.iter().all(|&x| x == w[0]) && w[0] > 0.0;
        let g = Self::geometry_err(e);
        let kv = KnotVector::new(m, knots).map_err(|x| g(x.context("knots")))?;
        let curve = BSplineCurve::new(kv, points, (!polynomial).then_some(w)).map_err(&g)?;
        Ok(IgesCurve {
            de: e.seq,
            name: Self::name(e),
            curve,
            param_range: [range[0], range[1]],
        })
    }
}
