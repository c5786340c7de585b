//! Target-curvature fairing of one sampled curve (\[SSV08\]; \[SV\] §5.2): the curvature
//! measurement and smoothing that the curve and surface methods share, and the fairing of a
//! single polyline.
//!
//! Given samples o_0 … o_{n−1} (chords ℓ_i = |o_{i+1} − o_i|, tangents t_i = (o_{i+1} − o_i)/ℓ_i):
//!
//! 1. **Curvature.** At vertex i the turning angle θ_i = ∠(t_{i−1}, t_i) gives the curvature of
//!    the circle through o_{i−1}, o_i, o_{i+1}, κ_i = 2 sin θ_i / |o_{i+1} − o_{i−1}|, in the
//!    direction of t_i − t_{i−1}, which is perpendicular to the vertex tangent
//!    T_i = (t_{i−1} + t_i)/|t_{i−1} + t_i|. The curvature vector k_i is stored by its components
//!    in a frame (T_i, m₁, m₂) transported from vertex to vertex by the smallest rotation taking
//!    T_{i−1} to T_i (a discrete Bishop frame): this describes a space curve up to a rigid motion
//!    without torsion singularities, and a planar curve has m₂ = its plane normal and one signed
//!    component.
//! 2. **Smoothing.** Jacobi sweeps k_i ← (1 − ω) k_i + ω (ℓ_i k_{i−1} + ℓ_{i−1} k_{i+1})/(ℓ_{i−1} + ℓ_i)
//!    (linear interpolation between the neighbours in arc length, so a clothoid is kept) give
//!    the target k̃. The values next to the ends are kept, prescribed ([`EndCurvature`]) — this
//!    is how a G2 end condition survives — or, on surfaces, smoothed with their one neighbour.
//! 3. **Integration.** The samples follow the wanted changes δ_i = k̃_i − k_i by least squares
//!    from both ends at once, softly pulled to the originals and within D of them
//!    (`crate::integrate`); for a curve the two end samples on each side are kept (ends and
//!    end tangents).
//!
//! A circle (or a line) sampled at any spacing has curvature vectors of one length that the
//! transport maps onto each other, so smoothing changes nothing and the integration returns
//! the samples to rounding: exact shapes stay put.
//!
//! # Deviation from the paper
//! \[SSV08\] smooths the scalar curvature of planar curves; for space curves we smooth the
//! curvature vector's components in a transported frame (equal to the signed curvature for
//! planar curves). \[SSV08\] integrates the target curvature from each end as an initial-value
//! problem (turning angle by turning angle) and blends the two; here one least-squares
//! boundary-value problem does both at once, because the two marching integrations drift
//! apart on noisy data and the pull needed to hold them brings the noise back.
//!
//! # Tolerance
//! D (model units) bounds the distance of every sample from its original; chords shorter than
//! [`DEGENERATE_CHORD_REL`] of the total length mark a collapsed curve, which is returned as is.

use nurbs_core::{Point3, Vector3};

use crate::error::{CurvatureError, Result, check_fraction, check_param, check_tolerance};
use crate::integrate::{Integration, Line};

/// Chord length, relative to the polyline's length, below which the polyline counts as collapsed
/// (a pole of the surface): its turning angles are meaningless there.
pub const DEGENERATE_CHORD_REL: f64 = 1e-9;

/// |t_i − t_{i−1}| (= 2 sin θ/2) below which a vertex counts as straight (no turning
/// direction); far below the turning of any visible bend, far above rounding of unit vectors
/// (~1e-16).
pub(crate) const STRAIGHT_SIN: f64 = 1e-14;

/// Settings of the curvature smoothing and integration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PolylineParams {
    /// Jacobi sweeps over the curvature values. Default 40: with ω = ½ it damps curvature
    /// oscillations of a wavelength of ≤ 8 samples (two to three bicubic spans) by > 99 %
    /// while leaving trends over the whole curve nearly untouched.
    pub smoothing_iterations: usize,
    /// ω ∈ (0, 1], the relaxation of each sweep (unit-free). Default ½.
    pub smoothing_weight: f64,
    /// ρ ∈ (0, 1], the pull of every sample towards its original relative to the mean
    /// diagonal of the curvature rows' normal matrix (unit-free). On evenly spaced samples a
    /// line's rows give the diagonal 6/h⁴ and a displacement wave of m samples' wavelength the
    /// eigenvalue (2 − 2 cos 2π/m)²/h⁴ ≈ (2π/m)⁴/h⁴: waves shorter than m ≈ 2π/(6ρ)^¼ follow
    /// the target curvature, longer ones are held (on a surface grid, with both families in the
    /// diagonal, m ≈ 2π/(12ρ)^¼). Default 1e-3: m ≈ 19–23 samples, six to seven spans at three
    /// samples per span; on the noisy sphere of the tests 1e-4 removes a little more curvature
    /// variance but moves the surface half as far again, 1e-2 removes too little.
    pub pull: f64,
}

impl Default for PolylineParams {
    fn default() -> Self {
        Self {
            smoothing_iterations: 40,
            smoothing_weight: 0.5,
            pull: 1e-3,
        }
    }
}

impl PolylineParams {
    pub(crate) fn check(&self) -> Result<()> {
        check_fraction("smoothing_weight", self.smoothing_weight)?;
        check_fraction("pull", self.pull)
    }
}

/// What the curvature next to the ends becomes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum EndCurvature {
    /// the original curvature at the first and last inner samples is kept (default)
    #[default]
    Keep,
    /// these curvatures (1/model units) at the first and last inner samples, in the direction
    /// the original bends there (a negative value bends the other way)
    Prescribed {
        /// at the start
        start: f64,
        /// at the end
        end: f64,
    },
}

/// How the smoothing treats the vertices next to the ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum SmoothedEnds {
    /// as [`EndCurvature`] says (curves)
    Fixed(EndCurvature),
    /// smoothed with their one neighbour (isocurves of a surface, whose boundary the control
    /// mask guards)
    Free,
}

/// Buffers of [`curvature_change`], reused from line to line.
#[derive(Default)]
pub(crate) struct CurvatureWork {
    chords: Vec<f64>,
    tangents: Vec<Vector3>,
    frames: Vec<[Vector3; 2]>,
    k: Vec<[f64; 2]>,
    original: Vec<[f64; 2]>,
    next: Vec<[f64; 2]>,
}

/// A unit vector perpendicular to the unit vector `t`.
fn perpendicular(t: &Vector3) -> Vector3 {
    let axis = if t.x.abs() <= t.y.abs() && t.x.abs() <= t.z.abs() {
        Vector3::x()
    } else if t.y.abs() <= t.z.abs() {
        Vector3::y()
    } else {
        Vector3::z()
    };
    (axis - axis.dot(t) * t).normalize()
}

/// `v` rotated by the smallest rotation taking the unit `a` to the unit `b` (Rodrigues);
/// `None` for opposite vectors.
fn transport(v: &Vector3, a: &Vector3, b: &Vector3) -> Option<Vector3> {
    let c = a.dot(b);
    if !(c > -1.0 + STRAIGHT_SIN) {
        return None;
    }
    let w = a.cross(b);
    Some(c * v + w.cross(v) + w * (w.dot(v) / (1.0 + c)))
}

/// Steps 1–2 of the module docs: writes the wanted change δ_i = k̃_i − k_i of the curvature
/// vector at every vertex of `points` into `delta` (zero at the two ends). Returns `false` and
/// all zeros for a collapsed polyline.
pub(crate) fn curvature_change(
    points: &[Point3],
    params: &PolylineParams,
    ends: SmoothedEnds,
    work: &mut CurvatureWork,
    delta: &mut Vec<Vector3>,
) -> bool {
    let n = points.len();
    delta.clear();
    delta.resize(n, Vector3::zeros());
    if n < 3 {
        return true;
    }
    let w = work;
    if !w.chords_and_tangents(points) {
        return false;
    }
    // 1. curvature vectors in the transported frame
    w.curvature_vectors(points);
    w.original.clone_from(&w.k);
    let fixed_ends = w.set_end_curvature(ends);
    // 2. smoothing
    w.smooth(params, fixed_ends);
    for i in 1..=n - 2 {
        let [m1, m2] = w.frames[i];
        let o = w.original[i];
        delta[i] = (w.k[i][0] - o[0]) * m1 + (w.k[i][1] - o[1]) * m2;
    }
    true
}

impl CurvatureWork {
    /// Fills the chords ℓ_i and unit tangents t_i of `points`; `false` when a chord is shorter
    /// than [`DEGENERATE_CHORD_REL`] of the length (a collapsed polyline).
    fn chords_and_tangents(&mut self, points: &[Point3]) -> bool {
        self.chords.clear();
        self.chords
            .extend(points.windows(2).map(|p| (p[1] - p[0]).norm()));
        let total: f64 = self.chords.iter().sum();
        if !(self.chords.iter().fold(f64::INFINITY, |m, &c| m.min(c))
            > DEGENERATE_CHORD_REL * total)
        {
            return false;
        }
        self.tangents.clear();
        self.tangents.extend(
            points
                .windows(2)
                .zip(&self.chords)
                .map(|(p, l)| (p[1] - p[0]) / *l),
        );
        true
    }

    /// Step 1: the transported frame (m₁, m₂) at every inner vertex of `points` and the
    /// curvature vector's components k_i in it (zero at straight vertices and the ends).
    fn curvature_vectors(&mut self, points: &[Point3]) {
        let n = points.len();
        self.frames.clear();
        self.frames.resize(n, [Vector3::zeros(); 2]);
        self.k.clear();
        self.k.resize(n, [0.0; 2]);
        let mut previous: Option<Vector3> = None;
        for i in 1..n - 1 {
            let (a, b) = (self.tangents[i - 1], self.tangents[i]);
            let sum = a + b;
            let len = sum.norm();
            let t = if len > STRAIGHT_SIN { sum / len } else { b };
            let m1 = match previous.and_then(|p| transport(&self.frames[i - 1][0], &p, &t)) {
                Some(m) => (m - m.dot(&t) * t).normalize(),
                None => perpendicular(&t),
            };
            self.frames[i] = [m1, t.cross(&m1)];
            previous = Some(t);
            let d = b - a;
            let dn = d.norm();
            if dn > STRAIGHT_SIN {
                let kappa = 2.0 * a.cross(&b).norm() / (points[i + 1] - points[i - 1]).norm();
                let kv = d * (kappa / dn);
                self.k[i] = [kv.dot(&self.frames[i][0]), kv.dot(&self.frames[i][1])];
            }
        }
    }

    /// Sets the curvature at the first and last inner vertices as `ends` prescribes; whether
    /// the smoothing keeps them.
    fn set_end_curvature(&mut self, ends: SmoothedEnds) -> bool {
        let (lo, hi) = (1, self.k.len() - 2);
        match ends {
            SmoothedEnds::Free => false,
            SmoothedEnds::Fixed(EndCurvature::Keep) => true,
            SmoothedEnds::Fixed(EndCurvature::Prescribed { start, end }) => {
                for (i, value) in [(lo, start), (hi, end)] {
                    let k = self.k[i];
                    let m = (k[0] * k[0] + k[1] * k[1]).sqrt();
                    self.k[i] = if m > 0.0 {
                        [k[0] / m * value, k[1] / m * value]
                    } else {
                        [value, 0.0]
                    };
                }
                true
            }
        }
    }

    /// Step 2: Jacobi sweeps over the inner vertices' curvature, interpolating between the
    /// neighbours in arc length; the vertices next to the ends are kept when `fixed_ends`,
    /// otherwise smoothed with their one neighbour.
    fn smooth(&mut self, params: &PolylineParams, fixed_ends: bool) {
        let (lo, hi) = (1, self.k.len() - 2);
        let omega = params.smoothing_weight;
        self.next.clone_from(&self.k);
        let (first, last) = if fixed_ends {
            (lo + 1, hi)
        } else {
            (lo, hi + 1)
        };
        if hi <= lo {
            return;
        }
        for _ in 0..params.smoothing_iterations {
            for i in first..last {
                let interp = if i == lo {
                    self.k[i + 1]
                } else if i == hi {
                    self.k[i - 1]
                } else {
                    let (l0, l1) = (self.chords[i - 1], self.chords[i]);
                    let (k0, k1) = (self.k[i - 1], self.k[i + 1]);
                    [
                        (l1 * k0[0] + l0 * k1[0]) / (l0 + l1),
                        (l1 * k0[1] + l0 * k1[1]) / (l0 + l1),
                    ]
                };
                for c in 0..2 {
                    self.next[i][c] = (1.0 - omega) * self.k[i][c] + omega * interp[c];
                }
            }
            std::mem::swap(&mut self.k, &mut self.next);
        }
    }
}

/// Fairs the polyline `original` (see the module docs); every returned point lies within
/// `tolerance` of its original, the two points at each end are the original ones.
pub fn fair_polyline(
    original: &[Point3],
    tolerance: f64,
    params: &PolylineParams,
    ends: EndCurvature,
) -> Result<Vec<Point3>> {
    check_tolerance(tolerance)?;
    params.check()?;
    if let Some(k) = original
        .iter()
        .position(|p| !p.coords.iter().all(|c| c.is_finite()))
    {
        return Err(CurvatureError::NonFinite {
            what: "polyline point",
            index: k,
        });
    }
    if let EndCurvature::Prescribed { start, end } = ends {
        for (name, v) in [("start curvature", start), ("end curvature", end)] {
            check_param(name, v, f64::NEG_INFINITY, false, "finite")?;
        }
    }
    let n = original.len();
    if n < 5 {
        return Ok(original.to_vec());
    }
    let mut delta = Vec::new();
    let smooth = curvature_change(
        original,
        params,
        SmoothedEnds::Fixed(ends),
        &mut CurvatureWork::default(),
        &mut delta,
    );
    if !smooth {
        return Ok(original.to_vec());
    }
    let measure: Vec<f64> = (0..n)
        .map(|i| {
            let before = if i > 0 {
                original[i] - original[i - 1]
            } else {
                Vector3::zeros()
            };
            let after = if i + 1 < n {
                original[i + 1] - original[i]
            } else {
                Vector3::zeros()
            };
            (before.norm() + after.norm()) / 2.0
        })
        .collect();
    let mut fixed = vec![false; n];
    for i in [0, 1, n - 2, n - 1] {
        fixed[i] = true;
    }
    Integration {
        points: original,
        original,
        fixed: &fixed,
        measure: &measure,
        radius: tolerance,
        rho: params.pull,
    }
    .solve(&[Line {
        start: 0,
        stride: 1,
        len: n,
        delta,
    }])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arc(n: usize, r: f64, warp: f64) -> Vec<Point3> {
        (0..n)
            .map(|i| {
                let s = i as f64 / (n - 1) as f64;
                let a = 1.5 * (s + warp * s * (1.0 - s));
                Point3::new(r * a.cos(), r * a.sin(), 0.0)
            })
            .collect()
    }

    #[test]
    fn circles_and_lines_stay_put() {
        let p = PolylineParams::default();
        for pts in [
            arc(40, 2.0, 0.0),
            arc(40, 2.0, 0.6),
            (0..30)
                .map(|i| Point3::new(i as f64 * 0.1, 0.5 * i as f64 * 0.1, 0.0))
                .collect(),
        ] {
            let out = fair_polyline(&pts, 1e-3, &p, EndCurvature::Keep).unwrap();
            for (a, b) in pts.iter().zip(&out) {
                assert!((a - b).norm() < 1e-12, "{a:?} vs {b:?}");
            }
        }
    }

    #[test]
    fn a_tilted_helix_stays_close() {
        // a helix has constant curvature and torsion: the transported components rotate,
        // smoothing changes them little; the ball keeps the result within the tolerance
        let pts: Vec<Point3> = (0..60)
            .map(|i| {
                let a = i as f64 * 0.1;
                Point3::new(a.cos(), a.sin(), 0.2 * a)
            })
            .collect();
        let tol = 1e-2;
        let out = fair_polyline(&pts, tol, &PolylineParams::default(), EndCurvature::Keep).unwrap();
        for (a, b) in pts.iter().zip(&out) {
            assert!((a - b).norm() <= tol * (1.0 + 1e-12));
        }
    }

    /// Discrete curvatures 2 sin θ_i / |x_{i+1} − x_{i−1}|.
    fn curvatures(p: &[Point3]) -> Vec<f64> {
        (1..p.len() - 1)
            .map(|i| {
                let (a, b) = ((p[i] - p[i - 1]).normalize(), (p[i + 1] - p[i]).normalize());
                2.0 * a.cross(&b).norm() / (p[i + 1] - p[i - 1]).norm()
            })
            .collect()
    }

    #[test]
    fn curvature_waves_are_reduced_within_the_tolerance() {
        // a unit arc with a radial wave of 8 samples' wavelength (curvature error ±30 %)
        let clean = arc(81, 1.0, 0.0);
        let noisy: Vec<Point3> = clean
            .iter()
            .enumerate()
            .map(|(i, p)| p * (1.0 + 1e-4 * (i as f64 * std::f64::consts::TAU / 8.0).sin()))
            .collect();
        let tol = 0.01;
        let out =
            fair_polyline(&noisy, tol, &PolylineParams::default(), EndCurvature::Keep).unwrap();
        let spread = |pts: &[Point3]| -> f64 {
            let k = curvatures(pts);
            k[5..k.len() - 5]
                .iter()
                .map(|k| (k - 1.0).abs())
                .fold(0.0, f64::max)
        };
        let (before, after) = (spread(&noisy), spread(&out));
        println!("curvature spread {before:.4} -> {after:.4}");
        assert!(after < 0.1 * before, "{after} vs {before}");
        for (a, b) in noisy.iter().zip(&out) {
            assert!((a - b).norm() <= tol * (1.0 + 1e-12));
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        let pts = arc(10, 1.0, 0.0);
        let p = PolylineParams::default();
        assert!(fair_polyline(&pts, 0.0, &p, EndCurvature::Keep).is_err());
        let bad = PolylineParams { pull: 2.0, ..p };
        assert!(fair_polyline(&pts, 1.0, &bad, EndCurvature::Keep).is_err());
        let mut nan = pts.clone();
        nan[3].x = f64::NAN;
        assert!(fair_polyline(&nan, 1.0, &p, EndCurvature::Keep).is_err());
    }
}
