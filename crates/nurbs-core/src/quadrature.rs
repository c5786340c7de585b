//! Gauss–Legendre quadrature: ∫_a^b f ≈ Σ w_i f(x_i), exact for polynomials of degree ≤ 2n − 1.
//!
//! Nodes are the roots of the Legendre polynomial P_n, found by Newton's method from the
//! Tricomi estimate cos(π(i − 1/4)/(n + 1/2)); weights w_i = 2 / ((1 − x_i²) P_n'(x_i)²)
//! (\[AS\] 25.4.29).

/// Newton stops when the node moves less than this (the nodes lie in [−1, 1]).
const NODE_TOL: f64 = 1e-15;

/// An n-point Gauss–Legendre rule on [−1, 1].
#[derive(Debug, Clone, PartialEq)]
pub struct GaussLegendre {
    /// nodes in (−1, 1), ascending
    pub nodes: Vec<f64>,
    /// weights, summing to 2
    pub weights: Vec<f64>,
}

impl GaussLegendre {
    /// The rule with `n ≥ 1` points.
    pub fn new(n: usize) -> Self {
        let n = n.max(1);
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        for i in 0..n.div_ceil(2) {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            for _ in 0..100 {
                let (p, d) = legendre(n, x);
                let dx = p / d;
                x -= dx;
                if dx.abs() < NODE_TOL {
                    break;
                }
            }
            let dp = legendre(n, x).1;
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            nodes[i] = -x;
            nodes[n - 1 - i] = x;
            weights[i] = w;
            weights[n - 1 - i] = w;
        }
        Self { nodes, weights }
    }

    /// Nodes and weights mapped to [a, b].
    pub fn on(&self, a: f64, b: f64) -> impl Iterator<Item = (f64, f64)> + '_ {
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        self.nodes
            .iter()
            .zip(&self.weights)
            .map(move |(&x, &w)| (mid + half * x, half * w))
    }
}

/// P_n(x) and P_n'(x) by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=n {
        let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
        p0 = p1;
        p1 = p2;
    }
    let p = if n == 0 { 1.0 } else { p1 };
    let d = n as f64 * (x * p - p0) / (x * x - 1.0);
    (p, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_polynomials_exactly() {
        for n in 1..=8 {
            let rule = GaussLegendre::new(n);
            assert!((rule.weights.iter().sum::<f64>() - 2.0).abs() < 1e-14);
            for k in 0..(2 * n) {
                let integral: f64 = rule.on(0.5, 2.0).map(|(x, w)| w * x.powi(k as i32)).sum();
                let exact = (2f64.powi(k as i32 + 1) - 0.5f64.powi(k as i32 + 1)) / (k + 1) as f64;
                assert!(
                    (integral - exact).abs() < 1e-12 * exact.abs().max(1.0),
                    "n={n} k={k}"
                );
            }
        }
    }
}
