//! Smoothing of per-sample values on the parameter grid (the curvature targets of \[SV\] §5.3).
//!
//! Jacobi sweeps x_ab ← (1 − ω) x_ab + ω (x_{a−1,b} + x_{a+1,b} + x_{a,b−1} + x_{a,b+1})/4 over all
//! samples; on the grid's border the average runs over the neighbours that exist. The stencil treats u and v alike, so swapping the parametric roles of
//! a surface swaps the result.

/// Smooths `values` (`mu × mv`, row a over u) by `iterations` sweeps of weight `omega`.
pub fn smooth_grid<const K: usize>(
    values: &mut Vec<[f64; K]>,
    mu: usize,
    mv: usize,
    iterations: usize,
    omega: f64,
) {
    if mu < 2 || mv < 2 {
        return;
    }
    let mut next = values.clone();
    for _ in 0..iterations {
        for a in 0..mu {
            for b in 0..mv {
                let k = a * mv + b;
                let mut sum = [0.0; K];
                let mut count = 0.0;
                let mut add = |n: usize| {
                    for c in 0..K {
                        sum[c] += values[n][c];
                    }
                    count += 1.0;
                };
                if a > 0 {
                    add(k - mv);
                }
                if a + 1 < mu {
                    add(k + mv);
                }
                if b > 0 {
                    add(k - 1);
                }
                if b + 1 < mv {
                    add(k + 1);
                }
                for c in 0..K {
                    next[k][c] = (1.0 - omega) * values[k][c] + omega * sum[c] / count;
                }
            }
        }
        std::mem::swap(values, &mut next);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_fields_are_kept_and_noise_is_damped() {
        let (mu, mv) = (9, 7);
        let mut lin: Vec<[f64; 1]> = (0..mu * mv).map(|_| [0.3]).collect();
        let orig = lin.clone();
        smooth_grid(&mut lin, mu, mv, 10, 0.5);
        for (a, b) in lin.iter().zip(&orig) {
            assert!((a[0] - b[0]).abs() < 1e-13);
        }
        let mut checker: Vec<[f64; 1]> = (0..mu * mv)
            .map(|k| {
                [if (k / mv + k % mv) % 2 == 0 {
                    1.0
                } else {
                    -1.0
                }]
            })
            .collect();
        smooth_grid(&mut checker, mu, mv, 1, 0.5);
        assert!(checker[mv + 1][0].abs() < 1e-15);
    }
}
