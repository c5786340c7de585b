//! A max tournament tree over a fixed set of keys: the priority structure of the local fairing
//! methods (rank of every control point, \[H\] slide "Ranking number"; the largest C³ jump of KRR,
//! \[SV\] §5.1).
//!
//! Leaves hold one value per key; every inner node holds the larger of its two children, so the
//! root is the maximum. Changing leaves and then refreshing their ancestors costs O(log n) per
//! leaf, less when the changed leaves are contiguous ([`MaxTree::refresh`] and
//! [`MaxTree::refresh_ranges`] walk whole leaf ranges level by level); finding the arg-max walks
//! down from the root in O(log n). No allocation after construction.

/// Value of a leaf that must never be chosen (fixed control points, empty slots).
pub const NEVER: f64 = f64::NEG_INFINITY;

/// max(a, b) for non-NaN values: one comparison (f64::max also handles NaN, which costs a blend on
/// the hot path).
#[inline(always)]
fn larger(a: f64, b: f64) -> f64 {
    if a >= b { a } else { b }
}

/// A complete binary max-tree over `len` leaves.
#[derive(Debug, Clone, PartialEq)]
pub struct MaxTree {
    len: usize,
    cap: usize,
    /// nodes: 1 = root, children of k are 2k and 2k + 1, leaves at cap..cap + len
    nodes: Vec<f64>,
}

impl MaxTree {
    /// A tree over `len` leaves, all [`NEVER`].
    pub fn new(len: usize) -> Self {
        let cap = len.max(1).next_power_of_two();
        Self {
            len,
            cap,
            nodes: vec![NEVER; 2 * cap],
        }
    }

    /// Number of leaves.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when the tree has no leaves.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Value of leaf `k`.
    #[inline]
    pub fn get(&self, k: usize) -> f64 {
        self.nodes[self.cap + k]
    }

    /// Sets leaf `k` without refreshing its ancestors: call [`MaxTree::refresh`] on the changed
    /// range afterwards (or use [`MaxTree::update`]). `value` must not be NaN (the hot path does
    /// not check; [`MaxTree::update`] maps NaN to [`NEVER`]).
    #[inline]
    pub fn set_leaf(&mut self, k: usize, value: f64) {
        debug_assert!(!value.is_nan(), "NaN leaf");
        self.nodes[self.cap + k] = value;
    }

    /// Sets leaf `k` (NaN is stored as [`NEVER`]) and refreshes its ancestors.
    pub fn update(&mut self, k: usize, value: f64) {
        self.set_leaf(k, if value.is_nan() { NEVER } else { value });
        self.refresh(k, k);
    }

    /// Recomputes the ancestors of the leaves `lo..=hi` (after [`MaxTree::set_leaf`]).
    pub fn refresh(&mut self, lo: usize, hi: usize) {
        if lo > hi || hi >= self.len {
            return;
        }
        let (mut a, mut b) = ((self.cap + lo) / 2, (self.cap + hi) / 2);
        while a >= 1 {
            for k in a..=b {
                self.nodes[k] = larger(self.nodes[2 * k], self.nodes[2 * k + 1]);
            }
            a /= 2;
            b /= 2;
        }
    }

    /// Recomputes the ancestors of the leaf ranges `lo..=hi` in `ranges` (ascending, disjoint),
    /// level by level, so ancestors shared by several ranges are computed once. The slice is used
    /// as scratch (its contents are changed).
    pub fn refresh_ranges(&mut self, ranges: &mut [(usize, usize)]) {
        if ranges.is_empty() || ranges.iter().any(|&(lo, hi)| lo > hi || hi >= self.len) {
            return;
        }
        for r in ranges.iter_mut() {
            *r = (self.cap + r.0, self.cap + r.1);
        }
        loop {
            let mut done = 0;
            for r in ranges.iter_mut() {
                let a = (r.0 / 2).max(done + 1);
                let b = r.1 / 2;
                for node in a..=b {
                    self.nodes[node] = larger(self.nodes[2 * node], self.nodes[2 * node + 1]);
                }
                done = done.max(b);
                *r = (r.0 / 2, b);
            }
            if ranges[0].0 <= 1 {
                break;
            }
        }
    }

    /// Recomputes every inner node (after setting many leaves).
    pub fn rebuild(&mut self) {
        for k in (1..self.cap).rev() {
            self.nodes[k] = larger(self.nodes[2 * k], self.nodes[2 * k + 1]);
        }
    }

    /// The largest leaf value (NEVER when empty).
    pub fn max(&self) -> f64 {
        self.nodes[1]
    }

    /// Index and value of a largest leaf, `None` when every leaf is [`NEVER`].
    pub fn arg_max(&self) -> Option<(usize, f64)> {
        let best = self.nodes[1];
        if best == NEVER {
            return None;
        }
        let mut k = 1;
        while k < self.cap {
            k = if self.nodes[2 * k] >= self.nodes[2 * k + 1] {
                2 * k
            } else {
                2 * k + 1
            };
        }
        Some((k - self.cap, best))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tracks_the_maximum_through_updates() {
        let values = [3.0, -1.0, 7.5, 2.0, 7.0, 0.0, 1.0];
        let mut tree = MaxTree::new(values.len());
        assert_eq!(tree.arg_max(), None);
        for (k, &v) in values.iter().enumerate() {
            tree.set_leaf(k, v);
        }
        tree.rebuild();
        assert_eq!(tree.arg_max(), Some((2, 7.5)));
        tree.update(2, NEVER);
        assert_eq!(tree.arg_max(), Some((4, 7.0)));
        for k in 3..=5 {
            tree.set_leaf(k, 10.0 + k as f64);
        }
        tree.refresh(3, 5);
        assert_eq!(tree.arg_max(), Some((5, 15.0)));
        tree.set_leaf(1, 30.0);
        tree.set_leaf(4, 31.0);
        tree.set_leaf(5, 32.0);
        tree.refresh_ranges(&mut [(1, 1), (4, 5)]);
        assert_eq!(tree.arg_max(), Some((5, 32.0)));
        tree.update(6, f64::NAN);
        assert_eq!(tree.get(6), NEVER);
    }

    #[test]
    fn agrees_with_a_scan_on_pseudo_random_updates() {
        let n = 37;
        let mut tree = MaxTree::new(n);
        let mut plain = vec![NEVER; n];
        let mut x: u64 = 12345;
        for _ in 0..500 {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let k = (x >> 33) as usize % n;
            let v = ((x >> 11) % 1000) as f64;
            if x.is_multiple_of(3) {
                // two runs of leaves (clamped to the end) through refresh_ranges
                let start = k.min(n - 6);
                for q in (start..start + 2).chain(start + 4..start + 6) {
                    tree.set_leaf(q, v + q as f64);
                    plain[q] = v + q as f64;
                }
                tree.refresh_ranges(&mut [(start, start + 1), (start + 4, start + 5)]);
            } else {
                tree.update(k, v);
                plain[k] = v;
            }
            let best = plain.iter().cloned().fold(NEVER, f64::max);
            let (at, value) = tree.arg_max().expect("non-empty");
            assert_eq!(value, best);
            assert_eq!(plain[at], best);
        }
    }
}
