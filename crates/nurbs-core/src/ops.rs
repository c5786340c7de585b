//! Knot operations, degree elevation, extraction and isocurves on curves and surfaces.
//!
//! Surfaces apply the curve algorithms of [`crate::knot_ops`] to every column (u direction) or row
//! (v direction) of the homogeneous net (\[NB\] §5.3: surface knot insertion is curve insertion on
//! the iso-polygons). Isocurves are exact: the curve v ↦ S(ū, v) has the homogeneous control points
//! Q_j = Σ_i N_i(ū) w_ij P_ij on the v knot vector.

use crate::Point3;
use crate::basis::BasisEvaluator;
use crate::curve::BSplineCurve;
use crate::error::Result;
use crate::knot_ops::{self, Polygon};
use crate::knots::KnotVector;
use crate::surface::BSplineSurface;

/// A parametric direction of a surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum Direction {
    /// the u direction (rows i)
    U,
    /// the v direction (columns j)
    V,
}

/// The knot vector of the reversed parameter t ↦ a + b − t on the domain [a, b]:
/// k'_i = a + b − k_{m−i}.
fn reverse_kv(kv: &KnotVector) -> Result<KnotVector> {
    let (a, b) = kv.domain();
    let k: Vec<f64> = kv.knots().iter().rev().map(|&x| a + b - x).collect();
    KnotVector::new(kv.degree(), k)
}

/// Least degree of a direction into which knots are inserted before its control points move. A
/// simple knot joins the spans of degree p with C^{p−1} continuity, and that is all that is left
/// once the points on either side move independently (fairing, continuity rows): on a degree-1
/// direction — a plane, a cylinder's axis as kernels export them — every inserted knot becomes a
/// crease (a three-radii corner's trimmed fillet came out of `fair` with 19° ones), on degree 2 a
/// jump of curvature (tried: a variable-radius box's trimmed fillet, its rows moved over part of a
/// side, went from a thin-plate energy of 2.4e3 to 9.2e4 at 0.02 mm of deviation — a curvature
/// spike at the end of the moved part). The hierarchy's highest target is G2, curvature continuity,
/// so a direction that gains knots is raised to p = 3 first: every new join is C², exactly (degree
/// elevation does not change the surface).
pub const SMOOTH_JOIN_DEGREE: usize = 3;

impl BSplineCurve {
    /// The same curve run backwards: C'(t) = C(a + b − t) on the domain [a, b] (knots
    /// mirrored, control points and weights reversed).
    pub fn reversed(&self) -> Result<Self> {
        let mut points = self.control_points().to_vec();
        points.reverse();
        let weights = self.weights().map(|w| w.iter().rev().copied().collect());
        Self::new(reverse_kv(self.knots())?, points, weights)
    }

    fn apply(&self, f: impl FnOnce(&KnotVector, &[[f64; 4]]) -> Result<Polygon>) -> Result<Self> {
        let (kv, pw) = f(self.knots(), &self.homogeneous())?;
        Self::from_homogeneous_as(kv, &pw, self.is_rational())
    }

    /// Inserts the knot `t` `times` times; the curve is unchanged.
    pub fn insert_knot(&self, t: f64, times: usize) -> Result<Self> {
        self.apply(|kv, pw| knot_ops::insert(kv, pw, t, times))
    }

    /// Inserts all knots of `xs` (knot refinement); the curve is unchanged.
    pub fn refine(&self, xs: &[f64]) -> Result<Self> {
        self.apply(|kv, pw| knot_ops::refine(kv, pw, xs))
    }

    /// Removes the interior knot `t` up to `num` times while the curve moves by at most
    /// `tolerance` (model units); returns the curve and how many were removed (0 = failed).
    pub fn remove_knot(&self, t: f64, num: usize, tolerance: f64) -> Result<(Self, usize)> {
        let ((kv, pw), removed) =
            knot_ops::remove(self.knots(), &self.homogeneous(), t, num, tolerance)?;
        Ok((
            Self::from_homogeneous_as(kv, &pw, self.is_rational())?,
            removed,
        ))
    }

    /// Raises the degree by `by`; the curve is unchanged (the result is clamped).
    pub fn elevate_degree(&self, by: usize) -> Result<Self> {
        self.apply(|kv, pw| knot_ops::elevate(kv, pw, by))
    }

    /// The part over [a, b], clamped, with the same parametrization.
    pub fn extract(&self, a: f64, b: f64) -> Result<Self> {
        self.apply(|kv, pw| knot_ops::extract(kv, pw, a, b))
    }
}

impl BSplineSurface {
    /// Applies a curve algorithm to every iso-polygon running in `dir`.
    fn map_polygons(
        &self,
        dir: Direction,
        f: impl Fn(&KnotVector, &[[f64; 4]]) -> Result<Polygon>,
    ) -> Result<Self> {
        let (nu, nv) = (self.num_u(), self.num_v());
        let hw = self.homogeneous();
        let (kv, count, len) = match dir {
            Direction::U => (self.knots_u(), nv, nu),
            Direction::V => (self.knots_v(), nu, nv),
        };
        let at = |line: usize, k: usize| match dir {
            Direction::U => k * nv + line,
            Direction::V => line * nv + k,
        };
        let mut results = Vec::with_capacity(count);
        for line in 0..count {
            let poly: Vec<[f64; 4]> = (0..len).map(|k| hw[at(line, k)]).collect();
            results.push(f(kv, &poly)?);
        }
        let new_kv = results[0].0.clone();
        let new_len = results[0].1.len();
        let (new_nu, new_nv) = match dir {
            Direction::U => (new_len, nv),
            Direction::V => (nu, new_len),
        };
        let mut net = vec![[0.0; 4]; new_nu * new_nv];
        for (line, (_, poly)) in results.iter().enumerate() {
            for (k, h) in poly.iter().enumerate() {
                let idx = match dir {
                    Direction::U => k * new_nv + line,
                    Direction::V => line * new_nv + k,
                };
                net[idx] = *h;
            }
        }
        match dir {
            Direction::U => {
                Self::from_homogeneous_as(new_kv, self.knots_v().clone(), &net, self.is_rational())
            }
            Direction::V => {
                Self::from_homogeneous_as(self.knots_u().clone(), new_kv, &net, self.is_rational())
            }
        }
    }

    /// Inserts the knot `t` `times` times in direction `dir`; the surface is unchanged.
    pub fn insert_knot(&self, dir: Direction, t: f64, times: usize) -> Result<Self> {
        self.map_polygons(dir, |kv, pw| knot_ops::insert(kv, pw, t, times))
    }

    /// Knot refinement in direction `dir`; the surface is unchanged.
    pub fn refine(&self, dir: Direction, xs: &[f64]) -> Result<Self> {
        self.map_polygons(dir, |kv, pw| knot_ops::refine(kv, pw, xs))
    }

    /// Removes the interior knot `t` of direction `dir` up to `num` times, each removal only when
    /// every iso-polygon allows it within `tolerance` (model units); returns the surface and the
    /// number removed.
    pub fn remove_knot(
        &self,
        dir: Direction,
        t: f64,
        num: usize,
        tolerance: f64,
    ) -> Result<(Self, usize)> {
        let mut cur = self.clone();
        let mut removed = 0;
        while removed < num {
            let attempt = cur.map_polygons(dir, |kv, pw| {
                let (poly, k) = knot_ops::remove(kv, pw, t, 1, tolerance)?;
                if k == 1 {
                    Ok(poly)
                } else {
                    Err(crate::Error::RemovalFailed {
                        value: t,
                        tolerance,
                    })
                }
            });
            match attempt {
                Ok(next) => {
                    cur = next;
                    removed += 1;
                }
                Err(crate::Error::RemovalFailed { .. }) => break,
                Err(e) => return Err(e),
            }
        }
        Ok((cur, removed))
    }

    /// The surface with the first (`last` false) or last knot span of direction `dir` replaced
    /// by the continuation of its neighbouring span (every iso-polygon in homogeneous
    /// coordinates, as `knot_ops::merge_first_span` does it): the same domain, one span fewer,
    /// the surface unchanged outside that span. What it does inside the span is the caller's to
    /// measure (a kernel's sliver span, a hundredth of a millimetre long, comes out within
    /// rounding of where it was; a span with a shape of its own does not).
    pub fn merge_end_span(&self, dir: Direction, last: bool) -> Result<Self> {
        if last {
            self.map_polygons(dir, knot_ops::merge_last_span)
        } else {
            self.map_polygons(dir, knot_ops::merge_first_span)
        }
    }

    /// Raises the degree of direction `dir` by `by`; the surface is unchanged.
    pub fn elevate_degree(&self, dir: Direction, by: usize) -> Result<Self> {
        self.map_polygons(dir, |kv, pw| knot_ops::elevate(kv, pw, by))
    }

    /// [`Self::with_control_count`] for rows whose points will move: a direction of degree
    /// below [`SMOOTH_JOIN_DEGREE`] that lacks points is first raised to it
    /// ([`Self::with_smooth_joins`], which adds points of its own), so that no inserted knot
    /// becomes a crease. Returns the surface and the number of knots inserted.
    pub fn with_smooth_control_count(&self, dir: Direction, count: usize) -> Result<(Self, usize)> {
        let short = match dir {
            Direction::U => self.num_u(),
            Direction::V => self.num_v(),
        } < count;
        if short {
            self.with_smooth_joins(dir)?.with_control_count(dir, count)
        } else {
            Ok((self.clone(), 0))
        }
    }

    /// The same surface with direction `dir` raised to at least [`SMOOTH_JOIN_DEGREE`] (exact;
    /// a clone where the degree is there already). Call it before knots go into a direction
    /// whose points will then move: see [`SMOOTH_JOIN_DEGREE`].
    pub fn with_smooth_joins(&self, dir: Direction) -> Result<Self> {
        let degree = match dir {
            Direction::U => self.degree_u(),
            Direction::V => self.degree_v(),
        };
        if degree >= SMOOTH_JOIN_DEGREE {
            return Ok(self.clone());
        }
        self.elevate_degree(dir, SMOOTH_JOIN_DEGREE - degree)
    }

    /// The same surface with its parameter in `dir` moved by `delta`: S'(u + δ, v) = S(u, v)
    /// (every knot of `dir` plus δ).
    pub fn shifted(&self, dir: Direction, delta: f64) -> Result<Self> {
        let moved = |kv: &KnotVector| {
            KnotVector::new(kv.degree(), kv.knots().iter().map(|k| k + delta).collect())
        };
        let (ku, kv) = match dir {
            Direction::U => (moved(self.knots_u())?, self.knots_v().clone()),
            Direction::V => (self.knots_u().clone(), moved(self.knots_v())?),
        };
        Self::new(
            ku,
            kv,
            self.control_points().to_vec(),
            self.weights().map(<[f64]>::to_vec),
        )
    }

    /// This surface followed by `next` in direction `dir`, as one surface: `next` must start
    /// where this one ends in `dir` (same parameter, same boundary curve), with the same degree
    /// in `dir` and the same knots in the other direction. The shared boundary becomes a knot
    /// of multiplicity p (a C⁰ join that keeps both shapes exactly); its control points are the
    /// two sides' averages (they agree to the curves' own accuracy). A rational `next` whose
    /// weights along the shared boundary are those of this surface times one factor is scaled
    /// by it (the same surface); other weights are [`crate::error::Error::ControlNetShape`].
    ///
    /// A face on a closed surface that runs across the seam (a torus band from −90° to 90°)
    /// is the piece after the seam joined to the piece before it: one surface over the face's
    /// box.
    pub fn joined(&self, dir: Direction, next: &Self) -> Result<Self> {
        let shape = |detail: String| crate::error::Error::ControlNetShape { detail };
        // both in u: the join runs along v
        let (a, b) = match dir {
            Direction::U => (self.clone(), next.clone()),
            Direction::V => (self.transposed()?, next.transposed()?),
        };
        let (ka, kb) = (a.knots_u(), b.knots_u());
        let p = ka.degree();
        if kb.degree() != p || a.knots_v() != b.knots_v() {
            return Err(shape(
                "joining two surfaces needs the same degree along the join and the same knots across it".into(),
            ));
        }
        let end = ka.domain().1;
        let start = kb.domain().0;
        if (end - start).abs() > 1e-12 * (1.0 + end.abs()) {
            return Err(shape(format!(
                "the second surface starts at {start}, not where the first ends ({end})"
            )));
        }
        let nv = a.num_v();
        let (ha, mut hb) = (a.homogeneous(), b.homogeneous());
        // the factor that makes next's weights along the join equal to this one's
        let last = (a.num_u() - 1) * nv;
        let ratio = ha[last][3] / hb[0][3];
        if (0..nv)
            .any(|j| (hb[j][3] * ratio - ha[last + j][3]).abs() > 1e-12 * ha[last + j][3].abs())
        {
            return Err(shape(
                "the weights along the join differ by more than one factor".into(),
            ));
        }
        for h in &mut hb {
            for c in h.iter_mut() {
                *c *= ratio;
            }
        }
        let mut knots = ka.knots()[..ka.knots().len() - 1].to_vec();
        knots.extend_from_slice(&kb.knots()[p + 1..]);
        let mut net = ha;
        for j in 0..nv {
            for c in 0..4 {
                net[last + j][c] = 0.5 * (net[last + j][c] + hb[j][c]);
            }
        }
        net.extend_from_slice(&hb[nv..]);
        let ku = KnotVector::new(p, knots)?;
        let rational = a.is_rational() || b.is_rational();
        let joined = BSplineSurface::from_homogeneous_as(ku, a.knots_v().clone(), &net, rational)?;
        match dir {
            Direction::U => Ok(joined),
            Direction::V => joined.transposed(),
        }
    }

    /// The sub-surface over [u0, u1] × [v0, v1], clamped, same parametrization.
    pub fn extract(&self, (u0, u1): (f64, f64), (v0, v1): (f64, f64)) -> Result<Self> {
        self.map_polygons(Direction::U, |kv, pw| knot_ops::extract(kv, pw, u0, u1))?
            .map_polygons(Direction::V, |kv, pw| knot_ops::extract(kv, pw, v0, v1))
    }

    /// Inserts knots in direction `dir` — each at the middle of the widest knot span, the last
    /// such span on ties — until there are at least `count` control points; the surface is
    /// unchanged. Returns it and the number of knots inserted.
    pub fn with_control_count(&self, dir: Direction, count: usize) -> Result<(Self, usize)> {
        let mut s = self.clone();
        let mut inserted = 0;
        loop {
            let (n, kv) = match dir {
                Direction::U => (s.num_u(), s.knots_u()),
                Direction::V => (s.num_v(), s.knots_v()),
            };
            if n >= count {
                return Ok((s, inserted));
            }
            let k = kv.knots();
            let widest = kv
                .spans()
                .max_by(|&x, &y| (k[x + 1] - k[x]).total_cmp(&(k[y + 1] - k[y])))
                .unwrap_or(kv.degree());
            let mid = 0.5 * (k[widest] + k[widest + 1]);
            s = s.insert_knot(dir, mid, 1)?;
            inserted += 1;
        }
    }

    /// The same surface with direction `dir` reversed: S'(u, v) = S(a + b − u, v) for
    /// `Direction::U` on the domain [a, b] (knots k'_i = a + b − k_{m−i}, control rows reversed).
    pub fn reversed(&self, dir: Direction) -> Result<Self> {
        let (nu, nv) = (self.num_u(), self.num_v());
        let map = |i: usize, j: usize| match dir {
            Direction::U => (nu - 1 - i) * nv + j,
            Direction::V => i * nv + (nv - 1 - j),
        };
        let points: Vec<Point3> = (0..nu * nv)
            .map(|k| self.control_points()[map(k / nv, k % nv)])
            .collect();
        let weights = self
            .weights()
            .map(|w| (0..nu * nv).map(|k| w[map(k / nv, k % nv)]).collect());
        let (ku, kv) = match dir {
            Direction::U => (reverse_kv(self.knots_u())?, self.knots_v().clone()),
            Direction::V => (self.knots_u().clone(), reverse_kv(self.knots_v())?),
        };
        Self::new(ku, kv, points, weights)
    }

    /// The same surface with u and v swapped: S'(v, u) = S(u, v).
    pub fn transposed(&self) -> Result<Self> {
        let (nu, nv) = (self.num_u(), self.num_v());
        let points: Vec<Point3> = (0..nu * nv)
            .map(|k| self.control_point(k % nu, k / nu))
            .collect();
        let weights = self
            .weights()
            .map(|w| (0..nu * nv).map(|k| w[(k % nu) * nv + k / nu]).collect());
        Self::new(
            self.knots_v().clone(),
            self.knots_u().clone(),
            points,
            weights,
        )
    }

    /// A copy with clamped knot vectors in both directions (the same surface).
    pub fn clamped(&self) -> Result<Self> {
        if self.knots_u().is_clamped() && self.knots_v().is_clamped() {
            return Ok(self.clone());
        }
        self.extract(self.domain_u(), self.domain_v())
    }

    /// The exact isocurve at parameter `t` of direction `dir`: `Direction::U` fixes u = t and
    /// gives the curve v ↦ S(t, v); `Direction::V` fixes v = t and gives u ↦ S(u, t).
    pub fn isocurve(&self, dir: Direction, t: f64) -> Result<BSplineCurve> {
        let (fixed_kv, free_kv) = match dir {
            Direction::U => (self.knots_u(), self.knots_v()),
            Direction::V => (self.knots_v(), self.knots_u()),
        };
        fixed_kv.check_param(t)?;
        let p = fixed_kv.degree();
        let span = fixed_kv.span(t);
        let mut n = vec![0.0; p + 1];
        BasisEvaluator::new(p).values(fixed_kv.knots(), span, t, &mut n);
        let hw = self.homogeneous();
        let nv = self.num_v();
        let count = free_kv.num_basis();
        let mut q = vec![[0.0; 4]; count];
        for (k, out) in q.iter_mut().enumerate() {
            for (r, &b) in n.iter().enumerate() {
                let i = span - p + r;
                let h = match dir {
                    Direction::U => hw[i * nv + k],
                    Direction::V => hw[k * nv + i],
                };
                for d in 0..4 {
                    out[d] += b * h[d];
                }
            }
        }
        BSplineCurve::from_homogeneous_as(free_kv.clone(), &q, self.is_rational())
    }
}
