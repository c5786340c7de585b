//! The plane section of a fillet and its one-hump profile: the reference section read off the
//! surface, the curvature profile with ramps at its ends solved to join the same contact points
//! with the same tangents, and its least-squares quintic B-spline.

use nalgebra::{DMatrix, DVector, Matrix3, Vector2, Vector3 as V3};
use nurbs_core::{BSplineSurface, Direction, KnotVector, Point3, Vector3};

use crate::error::{Error, Result};

/// Samples of the reference section along its parameter: enough that the trapezoidal arc length
/// and turning angle of a quarter circle are exact to 1e-6 relative (error O(h²), h = 1/400).
pub const SECTION_SAMPLES: usize = 401;

/// Newton iterations of the profile solve; it converges quadratically from the scaled start (a
/// circle: 3–4 iterations), so twenty only bound a section it cannot join.
const PROFILE_ITERATIONS: usize = 20;

/// Largest distance, relative to the section's length, of a contact point from the master it
/// takes its curvature from ([`Section::with_contacts`]): a side on its master lies within the
/// model's G0 tolerance, far below a thousandth of a fillet's section.
const CONTACT_DISTANCE: f64 = 1e-3;

/// Least |n · N| (the section's normal against the master's) at which a contact curvature is
/// taken: below it the section's plane lies almost in the master's tangent plane and κ = k_n /
/// (n · N) grows without bound (cos 60°).
const MIN_CONTACT_COS: f64 = 0.5;

/// Relative residual (to the section's length) at which the profile's end meets the contact
/// point: far below any model tolerance, above the trapezoid's rounding.
const PROFILE_RESIDUAL: f64 = 1e-11;

/// Spans in each ramp. On a 90° arc the least-squares misfit leaves the plateau within the
/// hysteresis at which a comb's extrema are counted (0.5 %, the relative G2 tolerance) from four
/// spans on, at every ramp width up to [`super::MAX_RAMP`] and with both ramp shapes (four: at
/// most 0.17 %, the flat ramp at a quarter; three: 0.61 % there, two extrema more; five: 0.06 %).
/// Five, because a ramp that rises from a master's curvature of the other sign, section by
/// section (a freeform fillet on a convex pipe), overshoots that curvature beside the contact
/// line by about 1 % of the plateau with four — an extremum more. Every span is a control row
/// more in each surface that takes the section's knots along a side (a vertex blend set G2
/// against the fillet's end curve), whose net the fairness bound counts (docs/benchmarks.md,
/// "the ramps' spans").
pub(crate) const RAMP_SPANS: usize = 5;

/// Degree of the new section: quintic, the lead-in degree ([`crate::LEAD_IN_DEGREE`]).
pub const SECTION_DEGREE: usize = 5;

/// The reference section in its own plane: E0 at the origin, the start tangent along +x.
pub(super) struct Section {
    /// normalized arc length of each sample, 0..=1
    sigma: Vec<f64>,
    /// signed curvature in the plane at each sample
    kappa: Vec<f64>,
    /// the section's arc length
    pub(super) length: f64,
    /// the end point and the turning angle from the start tangent to the end tangent
    end: Vector2<f64>,
    turn: f64,
    /// the end tangents' meeting point (on +x)
    pub(super) corner: Vector2<f64>,
    /// spans of the reference in the cross direction
    pub(super) spans: usize,
    /// the section's plane in space: E0 and the directions of +x and +y
    origin: V3<f64>,
    ex: V3<f64>,
    ey: V3<f64>,
    /// the unit tangent at the end, in the plane (forward, along the section)
    end_dir: Vector2<f64>,
    /// the signed curvature (in the plane) the section takes at its start and end contact
    /// points: its masters' normal curvature across there ([`Section::with_contacts`]; 0 for a
    /// plane, and without a master)
    contact: (f64, f64),
}

/// How the curvature of a one-hump section leaves a contact line, where it is 0 (a plane's):
/// the shape ρ of its ramp from 0 to the plateau over the ramp's fraction of the length. Both
/// shapes have ρ(0) = 0 (G2 to a plane) and ρ'(1) = ρ''(1) = 0 (the curvature plot has no kink
/// where the ramp meets the plateau). What a ramp costs in deviation is its deficit ∫(1 − ρ):
/// the plateau must turn what the ramp does not, so the middle of the section moves in
/// proportion to it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RampShape {
    /// ρ(x) = 1 − (1 − x)³, the least polynomial with those end conditions: the curvature rises
    /// linearly from the contact line (as a railway's easement from a straight into a curve)
    /// and the deficit is ¼ — half the flat ramp's, so the same deviation allows a ramp twice
    /// as wide.
    Linear,
    /// ρ(x) = x³(10 − 15x + 6x²), "smootherstep": also ρ'(0) = ρ''(0) = 0, so the curvature
    /// leaves the contact line flat; deficit ½. A surface that meets the section's end curve
    /// at a contact point with a master of its own (the part across a fillet ring's seam)
    /// finds there a curvature with no slope along the curve, as on its master.
    Flat,
}

impl RampShape {
    /// ρ(x) on [0, 1] (clamped outside).
    pub fn at(self, x: f64) -> f64 {
        let x = x.clamp(0.0, 1.0);
        match self {
            Self::Linear => {
                let y = 1.0 - x;
                1.0 - y * y * y
            }
            Self::Flat => x * x * x * (10.0 + x * (6.0 * x - 15.0)),
        }
    }
}

/// The ramp factor at σ with ramp fractions (f0, f1) of the section's length at its start and
/// end (0: no ramp at that end).
fn ramps(sigma: f64, f: (f64, f64), shape: RampShape) -> f64 {
    let a = if f.0 > 0.0 {
        shape.at(sigma / f.0)
    } else {
        1.0
    };
    let b = if f.1 > 0.0 {
        shape.at((1.0 - sigma) / f.1)
    } else {
        1.0
    };
    a * b
}

/// Where the lines p0 + s·t0 and p1 + t·t1 (unit directions) come closest: (s, t), or `None`
/// for parallel lines.
pub(super) fn meeting(
    p0: &V3<f64>,
    t0: &V3<f64>,
    p1: &V3<f64>,
    t1: &V3<f64>,
) -> Option<(f64, f64)> {
    let d = p0 - p1;
    let b = t0.dot(t1);
    let det = 1.0 - b * b;
    if det < 1e-12 {
        return None;
    }
    let s = (b * t1.dot(&d) - t0.dot(&d)) / det;
    let t = t1.dot(&d) + s * b;
    Some((s, t))
}

impl Section {
    /// The iso-curve of `s` across `cross` at the middle of the other direction, in its plane.
    pub(super) fn read(s: &BSplineSurface, cross: Direction) -> Result<Self> {
        let (a0, a1) = match cross {
            Direction::V => s.domain_u(),
            Direction::U => s.domain_v(),
        };
        Self::read_at(s, cross, 0.5 * (a0 + a1))
    }

    /// The point in space of the section-plane point `q` (E0 at the origin, the start tangent
    /// along +x).
    pub(super) fn to_space(&self, q: &Vector2<f64>) -> Point3 {
        Point3::from(self.origin + self.ex * q.x + self.ey * q.y)
    }

    /// The iso-curve of `s` across `cross` at the parameter `mid` of the other direction, in
    /// its plane.
    pub(super) fn read_at(s: &BSplineSurface, cross: Direction, mid: f64) -> Result<Self> {
        let bad = |reason: &str| Error::NoSection {
            reason: reason.to_string(),
        };
        let ((c0, c1), kv) = match cross {
            Direction::V => (s.domain_v(), s.knots_v()),
            Direction::U => (s.domain_u(), s.knots_u()),
        };
        let n = SECTION_SAMPLES;
        let mut points = Vec::with_capacity(n);
        let mut d1 = Vec::with_capacity(n);
        let mut d2 = Vec::with_capacity(n);
        for k in 0..n {
            let t = c0 + (c1 - c0) * k as f64 / (n - 1) as f64;
            let d = match cross {
                Direction::V => s.derivatives(mid, t),
                Direction::U => s.derivatives(t, mid),
            };
            let (c1d, c2d) = match cross {
                Direction::V => (d.dv, d.dvv),
                Direction::U => (d.du, d.duu),
            };
            points.push(d.point.coords);
            d1.push(c1d);
            d2.push(c2d);
        }
        let (e0, e1) = (points[0], points[n - 1]);
        let (t0, t1) = (d1[0].normalize(), -d1[n - 1].normalize());
        if !(t0.iter().chain(t1.iter()).all(|x| x.is_finite())) {
            return Err(bad("a side of the section is singular"));
        }
        let (sm, tm) = meeting(&e0, &t0, &e1, &t1).ok_or_else(|| bad("parallel end tangents"))?;
        if sm <= 0.0 || tm <= 0.0 {
            return Err(bad("the end tangents do not meet ahead of the section"));
        }
        let ex = t0;
        let chord = e1 - e0;
        let ey = chord - ex * chord.dot(&ex);
        if ey.norm() <= 1e-9 * chord.norm() {
            return Err(bad("the section is straight"));
        }
        let ey = ey.normalize();
        let plane = |v: &Vector3| Vector2::new(v.dot(&ex), v.dot(&ey));
        let mut arc = vec![0.0; n];
        let mut kappa = vec![0.0; n];
        for k in 0..n {
            let (p, q) = (plane(&d1[k]), plane(&d2[k]));
            let speed = p.norm();
            kappa[k] = (p.x * q.y - p.y * q.x) / (speed * speed * speed);
            if k > 0 {
                let h = (c1 - c0) / (n - 1) as f64;
                arc[k] = arc[k - 1] + 0.5 * h * (speed + plane(&d1[k - 1]).norm());
            }
        }
        let length = arc[n - 1];
        if !(length > 0.0 && kappa.iter().all(|k| k.is_finite())) {
            return Err(bad("the section has a singular point"));
        }
        let end_dir = plane(&d1[n - 1]);
        Ok(Self {
            sigma: arc.iter().map(|a| a / length).collect(),
            kappa,
            length,
            end: plane(&(e1 - e0)),
            turn: end_dir.y.atan2(end_dir.x),
            corner: Vector2::new(sm, 0.0),
            spans: kv.spans().count(),
            origin: e0,
            ex,
            ey,
            end_dir: end_dir.normalize(),
            contact: (0.0, 0.0),
        })
    }

    /// The section with the curvatures its contact points take from `masters` (at its start,
    /// at its end; `None`: no master, curvature 0 there): G2 sets a surface's normal curvature
    /// across a side to its master's in that direction, and the section's plane curvature κ
    /// gives the normal curvature κ (n · N) with n its normal in the plane and N the master's
    /// (Meusnier). A ramp then rises from that value instead of from 0, so the G2 step has
    /// nothing to bend at the contact line and the curvature does not dip beside it. A master
    /// the contact point is not on (farther than [`CONTACT_DISTANCE`] of the section's length),
    /// or whose normal is almost in the section's tangent plane, leaves 0.
    pub(super) fn with_contacts(mut self, masters: [Option<&BSplineSurface>; 2]) -> Self {
        let start = (self.origin, self.ex, self.ey);
        let end_point = self.to_space(&self.end).coords;
        let t1 = self.ex * self.end_dir.x + self.ey * self.end_dir.y;
        let n1 = self.ey * self.end_dir.x - self.ex * self.end_dir.y;
        let ends = [start, (end_point, t1, n1)];
        let mut k = [0.0; 2];
        for (i, master) in masters.iter().enumerate() {
            let Some(master) = master else { continue };
            let (p, t, n) = ends[i];
            let pr = nurbs_core::projection::project_to_surface(
                master,
                &Point3::from(p),
                &nurbs_core::projection::ProjectionParams::default(),
            );
            if !(pr.distance <= CONTACT_DISTANCE * self.length) {
                continue;
            }
            let d = master.derivatives(pr.u, pr.v);
            let (Some(normal), Some(kn)) = (d.normal(), d.normal_curvature(&t)) else {
                continue;
            };
            let cos = n.dot(&normal);
            if cos.abs() >= MIN_CONTACT_COS {
                k[i] = kn / cos;
            }
        }
        self.contact = (k[0], k[1]);
        self
    }

    /// The signed curvatures the section takes at its start and end contact points.
    #[cfg(test)]
    pub(super) fn contact_curvatures(&self) -> (f64, f64) {
        self.contact
    }

    /// Whether the section leaves its start and its end flat (curvature 0 there).
    pub(super) fn flat_ends(&self) -> (bool, bool) {
        (self.contact.0 == 0.0, self.contact.1 == 0.0)
    }

    /// What the contact curvatures add at σ: each end's, faded out over its ramp (1 − ρ), as
    /// the plateau fades in; nothing at an end without a ramp (it keeps the profile's own).
    fn contact_at(&self, sigma: f64, f: (f64, f64), shape: RampShape) -> f64 {
        let mut k = 0.0;
        if f.0 > 0.0 && self.contact.0 != 0.0 {
            k += (1.0 - shape.at(sigma / f.0)) * self.contact.0;
        }
        if f.1 > 0.0 && self.contact.1 != 0.0 {
            k += (1.0 - shape.at((1.0 - sigma) / f.1)) * self.contact.1;
        }
        k
    }

    /// The reference curvature at normalized arc length σ (linear between samples).
    fn kappa_at(&self, sigma: f64) -> f64 {
        let k = self
            .sigma
            .partition_point(|&x| x < sigma)
            .clamp(1, self.sigma.len() - 1);
        let (x0, x1) = (self.sigma[k - 1], self.sigma[k]);
        let w = if x1 > x0 {
            (sigma - x0) / (x1 - x0)
        } else {
            0.0
        };
        self.kappa[k - 1] + w * (self.kappa[k] - self.kappa[k - 1])
    }

    /// The curve of curvature ρ(σ)·(c + d(σ − ½))·κ_ref(σ) over length `len` from the origin
    /// along +x, sampled at `steps` + 1 equal steps of σ: points and the end heading.
    fn integrate(
        &self,
        f: (f64, f64),
        shape: RampShape,
        z: &V3<f64>,
        steps: usize,
    ) -> (Vec<Vector2<f64>>, f64) {
        let (c, d, len) = (z.x, z.y, z.z);
        let k = |s: f64| {
            ramps(s, f, shape) * (c + d * (s - 0.5)) * self.kappa_at(s)
                + self.contact_at(s, f, shape)
        };
        let h = 1.0 / steps as f64;
        let mut pts = Vec::with_capacity(steps + 1);
        let (mut p, mut phi) = (Vector2::zeros(), 0.0f64);
        pts.push(p);
        let mut k_prev = k(0.0);
        for i in 1..=steps {
            let s = i as f64 * h;
            let k_next = k(s);
            let phi_next = phi + 0.5 * h * len * (k_prev + k_next);
            // the heading is integrated exactly for curvature linear on the step (the chord of a
            // circle arc): direction at the mean heading, length scaled by sinc
            let dphi = phi_next - phi;
            let sinc = if dphi.abs() < 1e-8 {
                1.0
            } else {
                (0.5 * dphi).sin() / (0.5 * dphi)
            };
            let mean = 0.5 * (phi + phi_next);
            p += h * len * sinc * Vector2::new(mean.cos(), mean.sin());
            pts.push(p);
            (phi, k_prev) = (phi_next, k_next);
        }
        (pts, phi)
    }

    /// The profile with ramps `f` that joins the section's end point with its end tangent:
    /// (c, d, length) solved by Newton's method from (turn / ∫ρκ, 0, length).
    pub(super) fn profile(
        &self,
        f: (f64, f64),
        shape: RampShape,
        steps: usize,
    ) -> Result<Vec<Vector2<f64>>> {
        let h = 1.0 / steps as f64;
        let integral: f64 = (0..=steps)
            .map(|i| ramps(i as f64 * h, f, shape) * self.kappa_at(i as f64 * h))
            .sum::<f64>()
            * h;
        let contact: f64 = (0..=steps)
            .map(|i| self.contact_at(i as f64 * h, f, shape))
            .sum::<f64>()
            * h;
        // the plateau turns what the contact curvatures do not (the same start as before where
        // both are 0)
        let c0 = if contact == 0.0 {
            self.turn / (integral * self.length)
        } else {
            (self.turn / self.length - contact) / integral
        };
        let mut z = V3::new(c0, 0.0, self.length);
        let residual = |z: &V3<f64>| {
            let (pts, phi) = self.integrate(f, shape, z, steps);
            let e = pts[steps] - self.end;
            V3::new(e.x, e.y, (phi - self.turn) * self.length)
        };
        for _ in 0..PROFILE_ITERATIONS {
            let r = residual(&z);
            if r.norm() <= PROFILE_RESIDUAL * self.length {
                return Ok(self.integrate(f, shape, &z, steps).0);
            }
            let mut jac = Matrix3::zeros();
            for col in 0..3 {
                let step = 1e-7
                    * z[col]
                        .abs()
                        .max(1e-3 * if col == 2 { self.length } else { z.x });
                let mut zp = z;
                zp[col] += step;
                jac.set_column(col, &((residual(&zp) - r) / step));
            }
            let Some(dz) = jac.lu().solve(&(-r)) else {
                break;
            };
            z += dz;
            if !(z.z > 0.0 && z.iter().all(|x| x.is_finite())) {
                break;
            }
        }
        Err(Error::NoSection {
            reason: format!(
                "no curvature profile with ramps ({:.3}, {:.3}) joins the section's ends",
                f.0, f.1
            ),
        })
    }
}

/// The interior knots (fractions of the domain) of the new section: [`RAMP_SPANS`] equal spans in
/// each ramp (its last knot the ramp's end) and the middle in `middle` equal spans.
fn section_knots(f: (f64, f64), middle: usize) -> Vec<f64> {
    let mut xs = Vec::new();
    if f.0 > 0.0 {
        xs.extend((1..RAMP_SPANS).map(|k| f.0 * k as f64 / RAMP_SPANS as f64));
    }
    let (a, b) = (f.0, 1.0 - f.1);
    for k in 0..=middle {
        let x = a + (b - a) * k as f64 / middle as f64;
        if x > 0.0 && x < 1.0 {
            xs.push(x);
        }
    }
    if f.1 > 0.0 {
        xs.extend(
            (1..RAMP_SPANS)
                .rev()
                .map(|k| 1.0 - f.1 * k as f64 / RAMP_SPANS as f64),
        );
    }
    xs
}

/// One control point of the fitted section: fixed, a scalar (unknown `usize`) along a line
/// (point, direction), or a free 2D point (unknowns `usize`, `usize + 1`).
#[derive(Clone, Copy)]
enum Var {
    Fixed(Vector2<f64>),
    Along(Vector2<f64>, Vector2<f64>, usize),
    Free(usize),
}

/// The unknowns of the section's `n` control points (see [`fit_profile`]) and their count.
fn unknowns(
    n: usize,
    flat: (bool, bool),
    (e0, e1): (Vector2<f64>, Vector2<f64>),
    end_tangent: Vector2<f64>,
) -> (Vec<Var>, usize) {
    let tx = Vector2::new(1.0, 0.0);
    let mut vars = Vec::with_capacity(n);
    let mut m = 0;
    for j in 0..n {
        let v = if j == 0 {
            Var::Fixed(e0)
        } else if j == n - 1 {
            Var::Fixed(e1)
        } else if j == 1 || (j == 2 && flat.0) {
            m += 1;
            Var::Along(e0, tx, m - 1)
        } else if j == n - 2 || (j == n - 3 && flat.1) {
            m += 1;
            Var::Along(e1, end_tangent, m - 1)
        } else {
            m += 2;
            Var::Free(m - 2)
        };
        vars.push(v);
    }
    (vars, m)
}

/// The quintic B-spline (knots in [0, 1]) fitted by least squares to `points` at their
/// normalized arc length, its first and last points at the ends, its second and third on the
/// end tangent where that end has a ramp and is `flat` (zero curvature there, as the profile
/// has), else its second on the tangent (the tangent plane kept) and its third free.
pub(super) fn fit_profile(
    points: &[Vector2<f64>],
    f: (f64, f64),
    middle: usize,
    end_tangent: Vector2<f64>,
    flat: (bool, bool),
) -> Result<(KnotVector, Vec<Vector2<f64>>)> {
    let p = SECTION_DEGREE;
    let mut knots = vec![0.0; p + 1];
    knots.extend(section_knots(f, middle));
    knots.extend(vec![1.0; p + 1]);
    let kv = KnotVector::new(p, knots)?;
    let n = kv.num_basis();
    let last = points.len() - 1;
    let (e0, e1) = (points[0], points[last]);
    let (vars, m) = unknowns(
        n,
        (f.0 > 0.0 && flat.0, f.1 > 0.0 && flat.1),
        (e0, e1),
        end_tangent,
    );
    let rows = points.len();
    let mut a = DMatrix::zeros(2 * rows, m);
    let mut rhs = DVector::zeros(2 * rows);
    for (k, q) in points.iter().enumerate() {
        let t = k as f64 / last as f64;
        let (span, vals) = nurbs_core::basis::basis_derivatives(&kv, t, 0);
        let mut target = *q;
        for (o, &b) in vals.iter().take(p + 1).enumerate() {
            match vars[span - p + o] {
                Var::Fixed(x) => target -= b * x,
                Var::Along(base, dir, c) => {
                    target -= b * base;
                    a[(2 * k, c)] += b * dir.x;
                    a[(2 * k + 1, c)] += b * dir.y;
                }
                Var::Free(c) => {
                    a[(2 * k, c)] += b;
                    a[(2 * k + 1, c + 1)] += b;
                }
            }
        }
        rhs[2 * k] = target.x;
        rhs[2 * k + 1] = target.y;
    }
    let sol = least_squares(a, rhs)?;
    let out = vars
        .iter()
        .map(|v| match *v {
            Var::Fixed(x) => x,
            Var::Along(base, dir, c) => base + sol[c] * dir,
            Var::Free(c) => Vector2::new(sol[c], sol[c + 1]),
        })
        .collect();
    Ok((kv, out))
}

/// The least-squares solution of `a x = rhs`: by Householder QR where R's diagonal is well
/// away from zero (a column no sample reaches would leave it 0), else by the SVD with its small
/// singular values dropped. The QR is the same solution for a full-rank `a` at a fraction of the
/// SVD's cost: the section is fitted once per control column when it is taken section by
/// section, and the SVD was half of a fillet's time there (docs/benchmarks.md).
fn least_squares(a: DMatrix<f64>, rhs: DVector<f64>) -> Result<DVector<f64>> {
    let m = a.ncols();
    let qr = a.clone().qr();
    let r = qr.r();
    let largest = r.diagonal().amax();
    // Householder QR loses about cond(A)·ε; a pivot below 1e-10 of the largest means a
    // condition beyond what the fit's 1e-9 accuracy tolerates, so the SVD decides instead
    if largest > 0.0 && r.diagonal().iter().all(|d| d.abs() > 1e-10 * largest) {
        let mut b = rhs.clone();
        qr.q_tr_mul(&mut b);
        if let Some(x) = r.solve_upper_triangular(&b.rows(0, m)) {
            return Ok(x);
        }
    }
    a.svd(true, true)
        .solve(&rhs, 1e-14)
        .map_err(|e| Error::NoSection {
            reason: format!("the section's fit: {e}"),
        })
}

/// The affine coordinates (α, β) of the plane point `q` in the frame E0 = 0, M = `corner`,
/// E1 = `end`: q = α·M + β·(E1 − M).
pub(super) fn frame_coordinates(
    q: &Vector2<f64>,
    corner: &Vector2<f64>,
    end: &Vector2<f64>,
) -> Option<(f64, f64)> {
    let b = end - corner;
    let det = corner.x * b.y - corner.y * b.x;
    if det.abs() < 1e-300 {
        return None;
    }
    let alpha = (q.x * b.y - q.y * b.x) / det;
    let beta = (corner.x * q.y - corner.y * q.x) / det;
    Some((alpha, beta))
}

/// The point with frame coordinates (α, β) in the frame (E0, M, E1) of a control column.
pub(super) fn from_frame(ab: (f64, f64), e0: &Point3, m: &Point3, e1: &Point3) -> Point3 {
    e0 + (m - e0) * ab.0 + (e1 - m) * ab.1
}

impl Section {
    /// The section's end point in its plane.
    pub(super) fn end(&self) -> Vector2<f64> {
        self.end
    }

    /// The unit end tangent pointing back along the section (from E1 towards M).
    pub(super) fn end_tangent(&self) -> Vector2<f64> {
        (self.corner - self.end).normalize()
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{DMatrix, DVector};

    use super::least_squares;

    /// The QR path gives the SVD's least-squares solution on a full-rank system, and a column
    /// no row reaches (rank deficient) goes to the SVD, which leaves its unknown at 0.
    #[test]
    fn least_squares_by_qr_matches_the_svd_and_falls_back_on_rank_deficiency() {
        let rows = 40;
        let a = DMatrix::from_fn(rows, 3, |i, j| {
            let t = i as f64 / (rows - 1) as f64;
            t.powi(j as i32)
        });
        // a quadratic with a residual (a sine) that a quadratic cannot fit
        let rhs = DVector::from_fn(rows, |i, _| {
            let t = i as f64 / (rows - 1) as f64;
            1.0 - 2.0 * t + 0.5 * t * t + 0.01 * (12.0 * t).sin()
        });
        let x = least_squares(a.clone(), rhs.clone()).unwrap();
        let svd = a.clone().svd(true, true).solve(&rhs, 1e-14).unwrap();
        assert!((&x - &svd).amax() < 1e-12, "{x} against {svd}");
        // the normal equations hold: the residual is orthogonal to the columns
        let r = &rhs - &a * &x;
        assert!((a.transpose() * r).amax() < 1e-12);
        // a zero column: no pivot, the SVD's minimum-norm solution
        let mut b = DMatrix::zeros(rows, 4);
        b.columns_mut(0, 3).copy_from(&a);
        let y = least_squares(b, rhs).unwrap();
        assert!((y.rows(0, 3) - &svd).amax() < 1e-12);
        assert_eq!(y[3], 0.0);
    }
}
