//! The thin-plate functional of a rational surface with its weights held fixed, as a quadratic
//! form in the control points.
//!
//! With fixed weights w_ij, S = Σ_a R_a P_a with the rational basis functions
//! R_ij = w_ij N_i M_j / Σ_kl w_kl N_k M_l (\[NB\] eq. 4.16), so every derivative of S is linear in
//! the control points and the thin plate of \[H\] (slide "Fairness criterion")
//! Π = ∬ |S_uu|² + 2|S_uv|² + |S_vv|² du dv = Σ_c x_cᵀ K x_c with
//! K_ab = ∬ R_a,uu R_b,uu + 2 R_a,uv R_b,uv + R_a,vv R_b,vv du dv.
//! The denominator couples all functions of a span, so K is no Kronecker sum of 1D Gram matrices
//! as in [`crate::SeparableStiffness`]; it is still banded in the 2D index sense: R_(i,j) and
//! R_(k,l) share a span only when |i − k| ≤ p and |j − l| ≤ q. K is stored as one
//! (2p + 1) × (2q + 1) stencil per control point, entry (p + k − i, q + l − j) of point (i, j)
//! holding K_{(i,j),(k,l)} (both halves of the symmetric K, so that a point's couplings are
//! contiguous for the local scheme).
//!
//! K is integrated span by span with Gauss–Legendre rules (\[AS\] 25.4.29); the rational basis and
//! its derivatives come from nurbs-core's [`SurfaceBasisEvaluator`]. With the columns
//! √w_g R_uu, √(2 w_g) R_uv, √w_g R_vv of every Gauss point g of a span in one matrix D, the
//! span's (p + 1)(q + 1) × (p + 1)(q + 1) block of K is D Dᵀ.
//!
//! Since R_ij ≥ 0 and Σ R_ij = 1, S moves by at most the largest control-point move, so the
//! ε-balls of the local scheme bound the surface deviation as for polynomial surfaces.
//!
//! # Deviation from the paper
//! \[H\] treats polynomial B-splines only. Here the weights stay as they are and only the control
//! points move; the functional is the same linearized thin plate, integrated numerically.
//!
//! # Tolerance
//! The integrand is rational, so no finite rule is exact. [`RationalStiffness::thin_plate`] takes
//! (p + 1 + [`RATIONAL_EXTRA_POINTS`]) × (q + 1 + [`RATIONAL_EXTRA_POINTS`]) points per span, the
//! rule of nurbs-core's [`nurbs_core::energy::thin_plate_energy`], so that xᵀ K x is that energy
//! up to rounding. A surface whose weights are given but all equal to 1 gets the same rule and is
//! integrated exactly. On conic surfaces (cylinder, sphere patch, torus) that rule is within 1e-6
//! of the converged integral (relative); weights that jump from point to point (random in
//! [0.5, 2]) leave it up to 1 % off. The local scheme then minimizes that quadrature's energy,
//! still a positive semi-definite form; [`RationalStiffness::thin_plate_with_extra_points`] takes
//! a finer rule.

use nalgebra::{DMatrix, DMatrixView};
use nurbs_core::energy::RATIONAL_EXTRA_POINTS;
use nurbs_core::quadrature::GaussLegendre;
use nurbs_core::{BSplineSurface, Point3, SurfaceBasis, SurfaceBasisEvaluator, Vector3};

use std::cell::RefCell;
use std::sync::Arc;

use rayon::prelude::*;

use crate::local::LocalStiffness;

/// Stiffnesses kept per thread by [`RationalStiffness::thin_plate_shared`]: two, so that a
/// surface whose job is interleaved with another's on the same worker thread (work stealing
/// while it waits in a parallel solve) still finds its own.
pub const MEMO_ENTRIES: usize = 2;

/// Largest stiffness [`RationalStiffness::thin_plate_shared`] keeps, in values (8 MB): a net of
/// about 20,000 bicubic control points (49 couplings each); larger ones are rebuilt per call, so
/// that the memo never holds more than a few tens of MB after a run.
pub const MEMO_MAX_VALUES: usize = 1 << 20;

/// What K depends on: degrees, quadrature and the bits of every knot and weight.
#[derive(PartialEq)]
struct MemoKey {
    degrees: (usize, usize),
    bits: Vec<u64>,
}

impl MemoKey {
    fn of(surface: &BSplineSurface) -> Self {
        let (ku, kv) = (surface.knots_u().knots(), surface.knots_v().knots());
        let w = surface.weights().unwrap_or(&[]);
        let mut bits = Vec::with_capacity(ku.len() + kv.len() + w.len() + 3);
        bits.push(ku.len() as u64);
        bits.push(kv.len() as u64);
        bits.push(w.len() as u64);
        bits.extend(ku.iter().chain(kv).chain(w).map(|x| x.to_bits()));
        Self {
            degrees: (surface.degree_u(), surface.degree_v()),
            bits,
        }
    }
}

thread_local! {
    static MEMO: RefCell<Vec<(MemoKey, Arc<RationalStiffness>)>> = const { RefCell::new(Vec::new()) };
}

/// One span's (p + 1)(q + 1) × (p + 1)(q + 1) block of K and the index of its first
/// non-vanishing function.
struct SpanBlock {
    first: (usize, usize),
    block: DMatrix<f64>,
}

/// K_{(i,j),(k,l)} = ∬ R_ij,uu R_kl,uu + 2 R_ij,uv R_kl,uv + R_ij,vv R_kl,vv over an n_u × n_v
/// control net (flat index i·n_v + j), weights held fixed.
#[derive(Debug, Clone, PartialEq)]
pub struct RationalStiffness {
    nu: usize,
    nv: usize,
    p: usize,
    q: usize,
    /// per control point (2p + 1)(2q + 1) couplings, see the module doc
    data: Vec<f64>,
}

impl RationalStiffness {
    /// The thin-plate functional of `surface` (rational or not) with its weights held fixed,
    /// integrated with the rule of [`nurbs_core::energy::thin_plate_energy`]: p + 1 (q + 1)
    /// points per span, [`RATIONAL_EXTRA_POINTS`] more per direction when weights are present.
    pub fn thin_plate(surface: &BSplineSurface) -> Self {
        let extra = if surface.is_rational() {
            RATIONAL_EXTRA_POINTS
        } else {
            0
        };
        Self::thin_plate_with_extra_points(surface, extra)
    }

    /// [`RationalStiffness::thin_plate`], shared with the last calls on this thread: K depends
    /// only on the degrees, the knots and the weights, which the stages of one surface keep
    /// (only control points move), so consecutive fairing runs of a surface build it once. The
    /// memo is exact (keyed on the bits of every knot and weight), holds the last
    /// [`MEMO_ENTRIES`] stiffnesses of at most [`MEMO_MAX_VALUES`] values each per thread, and
    /// gives the same K as a fresh build.
    pub fn thin_plate_shared(surface: &BSplineSurface) -> Arc<Self> {
        let key = MemoKey::of(surface);
        if let Some(k) = MEMO.with(|m| {
            m.borrow()
                .iter()
                .find(|(k, _)| *k == key)
                .map(|(_, v)| Arc::clone(v))
        }) {
            return k;
        }
        let k = Arc::new(Self::thin_plate(surface));
        if k.data.len() <= MEMO_MAX_VALUES {
            MEMO.with(|m| {
                let mut m = m.borrow_mut();
                if m.len() == MEMO_ENTRIES {
                    m.remove(0);
                }
                m.push((key, Arc::clone(&k)));
            });
        }
        k
    }

    /// The same with (p + 1 + `extra`) × (q + 1 + `extra`) Gauss–Legendre points per span.
    pub fn thin_plate_with_extra_points(surface: &BSplineSurface, extra: usize) -> Self {
        let (nu, nv) = (surface.num_u(), surface.num_v());
        let (p, q) = (surface.degree_u(), surface.degree_v());
        let m = (p + 1) * (q + 1);
        let rule_u = GaussLegendre::new(p + 1 + extra);
        let rule_v = GaussLegendre::new(q + 1 + extra);
        let (ku, kv) = (surface.knots_u().knots(), surface.knots_v().knots());
        let spans_v: Vec<usize> = surface.knots_v().spans().collect();
        // the univariate derivatives (orders 0..=2) at the Gauss nodes: each depends on one
        // coordinate, so they are computed once per node (the v ones once for all rows of
        // spans) and the points combine them ([`SurfaceBasisEvaluator::eval_from`], the same
        // values as evaluating each point)
        let nodes_v: Vec<Vec<(Vec<f64>, f64)>> = spans_v
            .iter()
            .map(|&sv| node_derivatives(kv, sv, q, &rule_v))
            .collect();
        // the spans' blocks are independent: one row of spans (fixed u-span) per task, each
        // with its own evaluator; they are added into K below in the sequential order, so the
        // sums are the same whatever the number of threads
        let points = rule_u.nodes.len() * rule_v.nodes.len();
        let rows: Vec<Vec<SpanBlock>> = surface
            .knots_u()
            .spans()
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|su| {
                let mut basis = SurfaceBasis::new(surface);
                let eval = SurfaceBasisEvaluator::new(surface);
                let nodes_u = node_derivatives(ku, su, p, &rule_u);
                // per span D (m × 3 n_g, column-major): the columns √w R_uu, √(2w) R_uv,
                // √w R_vv of each Gauss point, so that the span's block of K is D Dᵀ (one
                // matrix product)
                let mut d = DMatrix::<f64>::zeros(m, 3 * points);
                spans_v
                    .iter()
                    .zip(&nodes_v)
                    .map(|(&sv, nodes_v)| {
                        let mut columns = d.as_mut_slice().chunks_exact_mut(3 * m);
                        for (du, wu) in &nodes_u {
                            for (dv, wv) in nodes_v {
                                let (wu, wv) = (*wu, *wv);
                                eval.eval_from((su, sv), du, dv, &mut basis);
                                let (s1, s2) = ((wu * wv).sqrt(), (2.0 * wu * wv).sqrt());
                                let c = columns.next().expect("one column triple per Gauss point");
                                let (cuu, rest) = c.split_at_mut(m);
                                let (cuv, cvv) = rest.split_at_mut(m);
                                for a in 0..m {
                                    cuu[a] = s1 * basis.duu[a];
                                    cuv[a] = s2 * basis.duv[a];
                                    cvv[a] = s1 * basis.dvv[a];
                                }
                            }
                        }
                        let dt =
                            DMatrixView::from_slice_with_strides(d.as_slice(), 3 * points, m, m, 1);
                        let mut block = DMatrix::<f64>::zeros(m, m);
                        block.gemm(1.0, &d, &dt, 0.0);
                        // every Gauss point of a span has the same non-vanishing functions
                        SpanBlock {
                            first: (basis.first_u, basis.first_v),
                            block,
                        }
                    })
                    .collect()
            })
            .collect();
        let data = add_blocks(rows.iter().flatten(), (nu, nv), (p, q));
        Self { nu, nv, p, q, data }
    }

    /// Control points in u.
    pub fn num_u(&self) -> usize {
        self.nu
    }
    /// Control points in v.
    pub fn num_v(&self) -> usize {
        self.nv
    }
    /// Stencil half-widths (p, q): K couples (i, j) and (k, l) only when |i − k| ≤ p and
    /// |j − l| ≤ q.
    pub fn stencil(&self) -> (usize, usize) {
        (self.p, self.q)
    }

    /// Entry K_{(i,j),(k,l)} (zero outside the stencil or the net).
    pub fn entry(&self, (i, j): (usize, usize), (k, l): (usize, usize)) -> f64 {
        let inside = i < self.nu && k < self.nu && j < self.nv && l < self.nv;
        if !inside || i.abs_diff(k) > self.p || j.abs_diff(l) > self.q {
            return 0.0;
        }
        let width = (2 * self.p + 1) * (2 * self.q + 1);
        self.data[(i * self.nv + j) * width + (self.p + k - i) * (2 * self.q + 1) + self.q + l - j]
    }

    /// g = K d (one vector per control point).
    pub fn multiply(&self, d: &[Point3], g: &mut [Vector3]) {
        let (p, q, nv) = (self.p, self.q, self.nv);
        let (cols, width) = (2 * q + 1, (2 * p + 1) * (2 * q + 1));
        for i in 0..self.nu {
            let (k0, k1) = (i.saturating_sub(p), (i + p).min(self.nu - 1));
            for j in 0..nv {
                let (l0, l1) = (j.saturating_sub(q), (j + q).min(nv - 1));
                let point = &self.data[(i * nv + j) * width..(i * nv + j + 1) * width];
                let mut acc = Vector3::zeros();
                for k in k0..=k1 {
                    let row = &point[(p + k - i) * cols + q + l0 - j..];
                    for (kij, dk) in row.iter().zip(&d[k * nv + l0..=k * nv + l1]) {
                        acc += *kij * dk.coords;
                    }
                }
                g[i * nv + j] = acc;
            }
        }
    }

    /// The functional's value Σ_c x_cᵀ K x_c.
    pub fn energy(&self, d: &[Point3]) -> f64 {
        let mut g = vec![Vector3::zeros(); d.len()];
        self.multiply(d, &mut g);
        d.iter().zip(&g).map(|(p, v)| p.coords.dot(v)).sum()
    }
}

/// The derivatives of orders 0..=2 of the `degree` + 1 functions of span `span` at each node of
/// `rule` on that span (laid out as [`nurbs_core::BasisEvaluator::derivatives`] writes them),
/// with the node's weight.
fn node_derivatives(
    knots: &[f64],
    span: usize,
    degree: usize,
    rule: &GaussLegendre,
) -> Vec<(Vec<f64>, f64)> {
    let mut e = nurbs_core::BasisEvaluator::new(degree);
    rule.on(knots[span], knots[span + 1])
        .map(|(t, w)| {
            let mut d = vec![0.0; 3 * (degree + 1)];
            e.derivatives(knots, span, t, 2, &mut d);
            (d, w)
        })
        .collect()
}

/// K's stencil storage (per control point (2p + 1)(2q + 1) couplings) of an `nu` × `nv` net
/// from the spans' blocks, added in the order given.
fn add_blocks<'a>(
    blocks: impl Iterator<Item = &'a SpanBlock>,
    (nu, nv): (usize, usize),
    (p, q): (usize, usize),
) -> Vec<f64> {
    let (cols, width) = (2 * q + 1, (2 * p + 1) * (2 * q + 1));
    let m = (p + 1) * (q + 1);
    let mut data = vec![0.0; nu * nv * width];
    for SpanBlock {
        first: (fu, fv),
        block,
    } in blocks
    {
        for a in 0..m {
            let (i, j) = (fu + a / (q + 1), fv + a % (q + 1));
            let point = &mut data[(i * nv + j) * width..(i * nv + j + 1) * width];
            for b in 0..m {
                let (k, l) = (fu + b / (q + 1), fv + b % (q + 1));
                // one triangle for both halves: K stays exactly symmetric
                let kab = block[(a.min(b), a.max(b))];
                point[(p + k - i) * cols + q + l - j] += kab;
            }
        }
    }
    data
}

/// The loaded stencil of one point (k, l): where its row i0 starts in `data`, and the column of
/// j0 inside a row.
pub(crate) struct StencilAt {
    row0: usize,
    col0: usize,
}

impl LocalStiffness for RationalStiffness {
    type Stencil = StencilAt;

    #[inline]
    fn shape(&self) -> (usize, usize) {
        (self.nu, self.nv)
    }
    #[inline]
    fn half_widths(&self) -> (usize, usize) {
        (self.p, self.q)
    }
    fn diagonal(&self, r: usize) -> f64 {
        let (i, j) = (r / self.nv, r % self.nv);
        self.entry((i, j), (i, j))
    }
    fn multiply(&self, d: &[Point3], g: &mut [Vector3]) {
        RationalStiffness::multiply(self, d, g);
    }
    fn entry(&self, r: (usize, usize), s: (usize, usize)) -> f64 {
        RationalStiffness::entry(self, r, s)
    }
    fn new_stencil(&self) -> StencilAt {
        StencilAt { row0: 0, col0: 0 }
    }
    #[inline]
    fn load(&self, k: usize, l: usize, st: &mut StencilAt) {
        let (p, q) = (self.p, self.q);
        let (i0, j0) = (k.saturating_sub(p), l.saturating_sub(q));
        let width = (2 * p + 1) * (2 * q + 1);
        st.row0 = (k * self.nv + l) * width + (p + i0 - k) * (2 * q + 1);
        st.col0 = q + j0 - l;
    }
    #[inline(always)]
    fn row(&self, st: &StencilAt, a: usize) -> impl Iterator<Item = f64> {
        // K is symmetric: the stencil of (k, l) holds K_{(k,l),(i,j)} = K_{(i,j),(k,l)}
        let start = st.row0 + a * (2 * self.q + 1);
        self.data[start + st.col0..start + 2 * self.q + 1]
            .iter()
            .copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::SeparableStiffness;
    use nurbs_core::testing::random_surface;

    /// The local scheme's view ([`LocalStiffness::load`] and [`LocalStiffness::row`]) of every
    /// point's stencil, clamped at the borders of the net, against `entry`.
    fn assert_rows_match<K: LocalStiffness>(k: &K, entry: impl Fn(usize, usize) -> f64) {
        let (nu, nv) = k.shape();
        let (wu, wv) = k.half_widths();
        let mut st = k.new_stencil();
        for kr in 0..nu {
            for lr in 0..nv {
                k.load(kr, lr, &mut st);
                let r = kr * nv + lr;
                assert_eq!(k.diagonal(r).to_bits(), entry(r, r).to_bits());
                let (i0, i1) = (kr.saturating_sub(wu), (kr + wu).min(nu - 1));
                let (j0, j1) = (lr.saturating_sub(wv), (lr + wv).min(nv - 1));
                for (a, i) in (i0..=i1).enumerate() {
                    let row: Vec<f64> = k.row(&st, a).take(j1 - j0 + 1).collect();
                    assert_eq!(row.len(), j1 - j0 + 1, "row {i} of ({kr}, {lr}) too short");
                    for (j, x) in (j0..=j1).zip(row) {
                        assert_eq!(x.to_bits(), entry(i * nv + j, r).to_bits());
                    }
                }
            }
        }
    }

    #[test]
    fn stencil_rows_are_the_entries() {
        for seed in 0..4 {
            let s = random_surface(seed, 1..=4, 9, true);
            let k = RationalStiffness::thin_plate(&s);
            let nv = k.num_v();
            assert_rows_match(&k, |a, b| k.entry((a / nv, a % nv), (b / nv, b % nv)));
            let sep = SeparableStiffness::thin_plate(s.knots_u(), s.knots_v()).expect("K");
            assert_rows_match(&sep, |a, b| sep.entry((a / nv, a % nv), (b / nv, b % nv)));
        }
    }

    #[test]
    fn multiply_sums_the_entries() {
        let s = random_surface(7, 2..=3, 8, true);
        let k = RationalStiffness::thin_plate(&s);
        let (nu, nv) = (k.num_u(), k.num_v());
        let d = s.control_points();
        let mut g = vec![Vector3::zeros(); d.len()];
        k.multiply(d, &mut g);
        for r in 0..nu * nv {
            let want: Vector3 = (0..nu * nv)
                .map(|c| k.entry((r / nv, r % nv), (c / nv, c % nv)) * d[c].coords)
                .sum();
            assert!(
                (g[r] - want).norm() <= 1e-12 * (1.0 + want.norm()),
                "row {r}"
            );
        }
    }

    #[test]
    fn shared_stiffness_is_the_fresh_one_and_keyed_on_knots_and_weights() {
        let a = random_surface(3, 2..=3, 8, true);
        let ka = RationalStiffness::thin_plate_shared(&a);
        assert_eq!(
            *ka,
            RationalStiffness::thin_plate(&a),
            "same K as a fresh build"
        );
        // moving control points keeps K (and the memo gives it back)
        let mut moved = a.clone();
        moved.control_points_mut()[0].x += 1.0;
        assert!(Arc::ptr_eq(
            &ka,
            &RationalStiffness::thin_plate_shared(&moved)
        ));
        // other weights or other knots: another K, never the memo's
        let mut other = a.weights().expect("rational").to_vec();
        other[0] *= 2.0;
        let b = BSplineSurface::new(
            a.knots_u().clone(),
            a.knots_v().clone(),
            a.control_points().to_vec(),
            Some(other),
        )
        .expect("valid");
        let kb = RationalStiffness::thin_plate_shared(&b);
        assert!(!Arc::ptr_eq(&ka, &kb));
        assert_eq!(*kb, RationalStiffness::thin_plate(&b));
        let ku = a.knots_u().knots();
        let mid = 0.5 * (ku[0] + ku[ku.len() - 1]);
        let refined = a.refine(nurbs_core::Direction::U, &[mid]).expect("refine");
        assert_eq!(
            *RationalStiffness::thin_plate_shared(&refined),
            RationalStiffness::thin_plate(&refined)
        );
    }
}
