//! Knot insertion, refinement, removal, degree elevation and extraction on homogeneous control
//! polygons — the curve algorithms that the curve and surface methods apply (to every row or
//! column for surfaces).
//!
//! - Insertion (\[NB\] A5.1, Boehm): inserting ū r times into span k rewrites P_{k−p+1..k−s}
//!   by Q_i = α_i P_i + (1 − α_i) P_{i−1}, α_i = (ū − t_i)/(t_{i+p} − t_i), repeated r times.
//! - Refinement (\[NB\] A5.4 in effect): successive single insertions of a sorted knot list.
//! - Removal (\[NB\] A5.8, Tiller): solves the insertion equations from both ends and accepts the
//!   removal when the two solutions meet within the tolerance; the tolerance bounds the
//!   Euclidean deviation of the curve (for rational curves scaled by w_min/(1 + max|P|), eq. 5.30).
//! - Degree elevation: decomposition into Bézier segments (insertion), per-segment elevation
//!   Q_i = (i/(p+1)) P_{i−1} + (1 − i/(p+1)) P_i (\[NB\] eq. 5.41), and exact removal of the surplus
//!   knots — the same result as \[NB\] A5.9, built from the operations above.
//! - Extraction: the sub-curve over [a, b] by inserting a and b to multiplicity p.

use crate::error::{Error, Result};
use crate::homogeneous::{distance4, lerp4};
use crate::knots::KnotVector;

/// A knot vector with its homogeneous control polygon.
pub(crate) type Polygon = (KnotVector, Vec<[f64; 4]>);

/// Relative tolerance (against the polygon's extent) of the exact knot removals that degree
/// elevation performs: the removed knots are removable in exact arithmetic, so only rounding
/// (~1e-15 relative) must pass.
pub const EXACT_REMOVAL_REL_TOL: f64 = 1e-9;

/// Inserts `u` `times` times (\[NB\] A5.1).
pub(crate) fn insert(kv: &KnotVector, pw: &[[f64; 4]], u: f64, times: usize) -> Result<Polygon> {
    kv.check_param(u)?;
    let p = kv.degree();
    let knots = kv.knots();
    let s = kv.multiplicity(u);
    if times == 0 {
        return Ok((kv.clone(), pw.to_vec()));
    }
    if s + times > p {
        return Err(Error::InsertionOverflow {
            value: u,
            times,
            multiplicity: s,
            degree: p,
        });
    }
    let np = pw.len() - 1;
    let mp = knots.len() - 1;
    // k: last index with t_k ≤ u (t_k ≤ u < t_{k+1})
    let k = knots.partition_point(|&t| t <= u) - 1;
    let mut uq = Vec::with_capacity(knots.len() + times);
    uq.extend_from_slice(&knots[..=k]);
    uq.extend(std::iter::repeat_n(u, times));
    uq.extend_from_slice(&knots[k + 1..=mp]);
    let mut qw = vec![[0.0; 4]; pw.len() + times];
    qw[..=k - p].copy_from_slice(&pw[..=k - p]);
    qw[k - s + times..=np + times].copy_from_slice(&pw[k - s..=np]);
    let mut rw: Vec<[f64; 4]> = pw[k - p..=k - s].to_vec();
    let mut l = 0;
    for j in 1..=times {
        l = k - p + j;
        for i in 0..=(p - j - s) {
            let alpha = (u - knots[l + i]) / (knots[i + k + 1] - knots[l + i]);
            rw[i] = lerp4(&rw[i + 1], alpha, &rw[i], 1.0 - alpha);
        }
        qw[l] = rw[0];
        qw[k + times - j - s] = rw[p - j - s];
    }
    if l + 1 < k - s {
        qw[l + 1..k - s].copy_from_slice(&rw[1..k - s - l]);
    }
    Ok((KnotVector::new(p, uq)?, qw))
}

/// Inserts every knot of `xs` (any order, repeats allowed) once per occurrence.
pub(crate) fn refine(kv: &KnotVector, pw: &[[f64; 4]], xs: &[f64]) -> Result<Polygon> {
    let mut sorted = xs.to_vec();
    if let Some(&bad) = sorted.iter().find(|x| !x.is_finite()) {
        let (start, end) = kv.domain();
        return Err(Error::ParameterOutOfDomain {
            value: bad,
            start,
            end,
        });
    }
    sorted.sort_by(f64::total_cmp);
    let mut cur = (kv.clone(), pw.to_vec());
    for x in sorted {
        cur = insert(&cur.0, &cur.1, x, 1)?;
    }
    Ok(cur)
}

/// Tries to remove the interior knot `u` up to `num` times with Euclidean deviation at most
/// `tolerance` (\[NB\] A5.8); returns the new polygon and how many times it was removed.
pub(crate) fn remove(
    kv: &KnotVector,
    pw: &[[f64; 4]],
    u: f64,
    num: usize,
    tolerance: f64,
) -> Result<(Polygon, usize)> {
    let p = kv.degree();
    let knots = kv.knots();
    let (start, end) = kv.domain();
    let s = kv.multiplicity(u);
    if !(u > start && u < end) || s == 0 {
        return Err(Error::ParameterOutOfDomain {
            value: u,
            start,
            end,
        });
    }
    let r = knots.partition_point(|&t| t <= u) - 1;
    let n = pw.len() - 1;
    let m = n + p + 1;
    let removal = Removal {
        knots,
        u,
        ord: p + 1,
        tol: homogeneous_tolerance(pw, tolerance),
    };
    let fout = (2 * r - s - p) / 2;
    let mut first = r - p;
    let mut last = r - s;
    let mut pw = pw.to_vec();
    let mut temp = vec![[0.0; 4]; 2 * p + 1];
    let mut t = 0;
    while t < num.min(s) {
        if !removal.attempt(&mut pw, &mut temp, first, last, t) {
            break;
        }
        first -= 1;
        last += 1;
        t += 1;
    }
    if t == 0 {
        return Ok(((kv.clone(), pw), 0));
    }
    let mut new_knots = knots.to_vec();
    for k in (r + 1)..=m {
        new_knots[k - t] = new_knots[k];
    }
    new_knots.truncate(m + 1 - t);
    drop_removed_points(&mut pw, fout, t);
    Ok(((KnotVector::new(p, new_knots)?, pw), t))
}

/// The removal tolerance on the homogeneous polygon for a Euclidean deviation of `tolerance`:
/// scaled by w_min / (1 + max |P|) (\[NB\] eq. 5.30).
fn homogeneous_tolerance(pw: &[[f64; 4]], tolerance: f64) -> f64 {
    let wmin = pw.iter().map(|q| q[3]).fold(f64::INFINITY, f64::min);
    let pmax = pw
        .iter()
        .map(|q| (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt() / q[3])
        .fold(0.0, f64::max);
    tolerance * wmin / (1.0 + pmax)
}

/// One knot removal of \[NB\] A5.8: the knot `u` at `knots`, the order p + 1 and the homogeneous
/// tolerance.
struct Removal<'a> {
    knots: &'a [f64],
    u: f64,
    ord: usize,
    tol: f64,
}

impl Removal<'_> {
    /// Removal number t + 1: solves the insertion equations for the points first..=last of `pw`
    /// from both ends (into `temp`) and, when the two solutions meet within the tolerance,
    /// writes them into `pw`; returns whether it did.
    fn attempt(
        &self,
        pw: &mut [[f64; 4]],
        temp: &mut [[f64; 4]],
        first: usize,
        last: usize,
        t: usize,
    ) -> bool {
        let (knots, u, ord) = (self.knots, self.u, self.ord);
        let off = first - 1;
        temp[0] = pw[off];
        temp[last + 1 - off] = pw[last + 1];
        let (mut i, mut j) = (first, last);
        let (mut ii, mut jj) = (1usize, last - off);
        while j as isize - i as isize > t as isize {
            let alfi = (u - knots[i]) / (knots[i + ord + t] - knots[i]);
            let alfj = (u - knots[j - t]) / (knots[j + ord] - knots[j - t]);
            temp[ii] = lerp4(&pw[i], 1.0 / alfi, &temp[ii - 1], -(1.0 - alfi) / alfi);
            temp[jj] = lerp4(
                &pw[j],
                1.0 / (1.0 - alfj),
                &temp[jj + 1],
                -alfj / (1.0 - alfj),
            );
            i += 1;
            ii += 1;
            j -= 1;
            jj -= 1;
        }
        let ok = if (j as isize - i as isize) < t as isize {
            distance4(&temp[ii - 1], &temp[jj + 1]) <= self.tol
        } else {
            let alfi = (u - knots[i]) / (knots[i + ord + t] - knots[i]);
            let guess = lerp4(&temp[ii + t + 1], alfi, &temp[ii - 1], 1.0 - alfi);
            distance4(&pw[i], &guess) <= self.tol
        };
        if !ok {
            return false;
        }
        let (mut i, mut j) = (first, last);
        while j as isize - i as isize > t as isize {
            pw[i] = temp[i - off];
            pw[j] = temp[j - off];
            i += 1;
            j -= 1;
        }
        true
    }
}

/// Closes the gap the `t` removals left in `pw` around index `fout` (\[NB\] A5.8's last loop)
/// and drops the last t points.
fn drop_removed_points(pw: &mut Vec<[f64; 4]>, fout: usize, t: usize) {
    let n = pw.len() - 1;
    let mut j = fout;
    let mut i = j;
    for k in 1..t {
        if k % 2 == 1 {
            i += 1;
        } else {
            j -= 1;
        }
    }
    for k in (i + 1)..=n {
        pw[j] = pw[k];
        j += 1;
    }
    pw.truncate(n + 1 - t);
}

/// The part of the curve over [a, b] as a clamped polygon. A bound within
/// [`crate::knots::KNOT_MERGE_RELATIVE`] of a knot or an end of the domain is taken as that knot
/// ([`KnotVector::snap`]): no sliver span is made next to it.
pub(crate) fn extract(kv: &KnotVector, pw: &[[f64; 4]], a: f64, b: f64) -> Result<Polygon> {
    let (a, b) = (kv.snap(a), kv.snap(b));
    kv.check_param(a)?;
    kv.check_param(b)?;
    if !(a < b) {
        return Err(Error::Degenerate {
            detail: format!("extraction range [{a}, {b}] is empty"),
        });
    }
    let p = kv.degree();
    let mut cur = (kv.clone(), pw.to_vec());
    for x in [a, b] {
        let s = cur.0.multiplicity(x);
        if s < p {
            cur = insert(&cur.0, &cur.1, x, p - s)?;
        }
    }
    let knots = cur.0.knots();
    let r_a = knots.partition_point(|&t| t <= a) - 1;
    let f_b = knots.partition_point(|&t| t < b);
    let (first, last) = (r_a - p, f_b - 1);
    let mut sub = vec![a; p + 1];
    sub.extend_from_slice(&knots[r_a + 1..f_b]);
    sub.extend(std::iter::repeat_n(b, p + 1));
    Ok((KnotVector::new(p, sub)?, cur.1[first..=last].to_vec()))
}

/// The curve with its first knot span [a, u₁] replaced by the polynomial of the next span
/// [u₁, u₂] continued over it (in homogeneous coordinates, so a rational curve continues its
/// rational piece): the part over [u₁, b] is extracted, u₂ raised to multiplicity p so that
/// the first p + 1 points are that span's Bézier polygon, the polygon extended to [a, u₂] by de
/// Casteljau's subdivision at r = (a − u₁)/(u₂ − u₁) < 0 (the right part, \[NB\] §5.6 — the
/// same polynomial), and the copies of u₂ removed again (exactly: the curve on both sides of
/// u₂ is what it was). The domain stays [a, b]; the curve over [u₁, b] does not change.
pub(crate) fn merge_first_span(kv: &KnotVector, pw: &[[f64; 4]]) -> Result<Polygon> {
    let p = kv.degree();
    let (a, b) = kv.domain();
    let inner = kv.interior_knots();
    let Some(&(u1, _)) = inner.first() else {
        return Err(Error::Degenerate {
            detail: "a curve of one knot span has no span to merge its first into".to_string(),
        });
    };
    let u2 = inner.get(1).map_or(b, |&(t, _)| t);
    let (kv1, pw1) = extract(kv, pw, u1, b)?;
    let raised = if u2 < b {
        p.saturating_sub(kv1.multiplicity(u2))
    } else {
        0
    };
    let (kv2, mut pw2) = if raised > 0 {
        insert(&kv1, &pw1, u2, raised)?
    } else {
        (kv1, pw1)
    };
    let r = (a - u1) / (u2 - u1);
    let mut level: Vec<[f64; 4]> = pw2[..=p].to_vec();
    for j in 1..=p {
        for i in 0..=p - j {
            level[i] = lerp4(&level[i], 1.0 - r, &level[i + 1], r);
        }
        // b_{p−j}^j is the right part's point p − j
        pw2[p - j] = level[p - j];
    }
    let mut knots = vec![a; p + 1];
    knots.extend_from_slice(&kv2.knots()[p + 1..]);
    let merged = (KnotVector::new(p, knots)?, pw2);
    if raised == 0 {
        return Ok(merged);
    }
    let tolerance = EXACT_REMOVAL_REL_TOL * extent4(&merged.1).max(f64::MIN_POSITIVE);
    let (out, removed) = remove(&merged.0, &merged.1, u2, raised, tolerance)?;
    if removed != raised {
        return Err(Error::RemovalFailed {
            value: u2,
            tolerance,
        });
    }
    Ok(out)
}

/// [`merge_first_span`] at the other end: the last span replaced by the continuation of the one
/// before it (the curve reversed, merged, and reversed back).
pub(crate) fn merge_last_span(kv: &KnotVector, pw: &[[f64; 4]]) -> Result<Polygon> {
    let (rk, rp) = reverse(kv, pw)?;
    let (mk, mp) = merge_first_span(&rk, &rp)?;
    reverse(&mk, &mp)
}

/// The same curve with its parameter negated (t → −t, exact, so that reversing twice gives
/// the knots back bit for bit).
fn reverse(kv: &KnotVector, pw: &[[f64; 4]]) -> Result<Polygon> {
    let knots: Vec<f64> = kv.knots().iter().rev().map(|&t| -t).collect();
    let mut points = pw.to_vec();
    points.reverse();
    Ok((KnotVector::new(kv.degree(), knots)?, points))
}

/// Raises the degree by `by` keeping the curve (\[NB\] §5.5).
pub(crate) fn elevate(kv: &KnotVector, pw: &[[f64; 4]], by: usize) -> Result<Polygon> {
    if by == 0 {
        return Ok((kv.clone(), pw.to_vec()));
    }
    let (a, b) = kv.domain();
    let (kv, pw) = if kv.is_clamped() {
        (kv.clone(), pw.to_vec())
    } else {
        extract(kv, pw, a, b)?
    };
    let p = kv.degree();
    let interior = kv.interior_knots();
    let mut bez = (kv.clone(), pw.clone());
    for &(x, m) in &interior {
        if m < p {
            bez = insert(&bez.0, &bez.1, x, p - m)?;
        }
    }
    let q = p + by;
    let segments = interior.len() + 1;
    let mut out: Vec<[f64; 4]> = Vec::with_capacity(segments * q + 1);
    for seg in 0..segments {
        let mut cp: Vec<[f64; 4]> = bez.1[seg * p..=seg * p + p].to_vec();
        for deg in p..q {
            let mut next = Vec::with_capacity(deg + 2);
            next.push(cp[0]);
            for i in 1..=deg {
                let alpha = i as f64 / (deg + 1) as f64;
                next.push(lerp4(&cp[i - 1], alpha, &cp[i], 1.0 - alpha));
            }
            next.push(cp[deg]);
            cp = next;
        }
        let skip = usize::from(seg > 0);
        out.extend_from_slice(&cp[skip..]);
    }
    let mut knots = vec![a; q + 1];
    for &(x, _) in &interior {
        knots.extend(std::iter::repeat_n(x, q));
    }
    knots.extend(std::iter::repeat_n(b, q + 1));
    let mut cur = (KnotVector::new(q, knots)?, out);
    let extent = extent4(&cur.1);
    let tolerance = EXACT_REMOVAL_REL_TOL * extent.max(f64::MIN_POSITIVE);
    for &(x, m) in &interior {
        let want = p - m;
        if want == 0 {
            continue;
        }
        let (next, removed) = remove(&cur.0, &cur.1, x, want, tolerance)?;
        if removed != want {
            return Err(Error::RemovalFailed {
                value: x,
                tolerance,
            });
        }
        cur = next;
    }
    Ok(cur)
}

/// Largest Euclidean coordinate extent of a homogeneous polygon (after division by w).
fn extent4(pw: &[[f64; 4]]) -> f64 {
    let pts: Vec<crate::Point3> = pw
        .iter()
        .map(|q| crate::Point3::new(q[0] / q[3], q[1] / q[3], q[2] / q[3]))
        .collect();
    crate::homogeneous::bounding_diagonal(&pts)
        .max(pts.iter().map(|p| p.coords.norm()).fold(0.0, f64::max))
}
