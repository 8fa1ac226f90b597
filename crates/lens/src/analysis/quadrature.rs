//! Gauss–Legendre quadrature, for integrals over the pupil that must converge
//! fast (a smooth integrand of degree 2n - 1 is integrated exactly by n nodes).

/// Nodes and weights of the `n`-point Gauss–Legendre rule on [a, b].
/// The weights sum to b - a.
///
/// ```
/// let (x, w) = lens::analysis::quadrature::gauss_legendre(5, 0.0, 1.0);
/// let integral: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(9)).sum();
/// assert!((integral - 0.1).abs() < 1e-15);
/// ```
pub fn gauss_legendre(n: usize, a: f64, b: f64) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = Vec::with_capacity(n);
    let mut weights = Vec::with_capacity(n);
    let (mid, half) = ((a + b) / 2.0, (b - a) / 2.0);
    for i in 0..n {
        // Newton's iteration on P_n from Tricomi's initial guess.
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (p, d) = legendre(n, x);
            dp = d;
            let dx = p / d;
            x -= dx;
            if dx.abs() <= 1e-16 * x.abs().max(1.0) {
                break;
            }
        }
        let (_, d) = legendre(n, x);
        if d.is_finite() {
            dp = d;
        }
        nodes.push(mid - half * x);
        weights.push(half * 2.0 / ((1.0 - x * x) * dp * dp));
    }
    (nodes, weights)
}

/// P_n(x) and its derivative, by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return (1.0, 0.0);
    }
    for k in 2..=n {
        let k = k as f64;
        let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
    }
    let d = n as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_sum_to_interval_and_integrate_polynomials_exactly() {
        for n in [1, 2, 7, 32, 64] {
            let (x, w) = gauss_legendre(n, -1.0, 3.0);
            assert!((w.iter().sum::<f64>() - 4.0).abs() < 1e-13, "n = {n}");
            let deg = 2 * n - 1;
            let got: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(deg as i32)).sum();
            let exact = (3f64.powi(deg as i32 + 1) - 1.0) / (deg as f64 + 1.0);
            assert!(((got - exact) / exact).abs() < 1e-12, "n = {n}: {got} vs {exact}");
        }
    }
}
