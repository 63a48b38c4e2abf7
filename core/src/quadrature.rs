//! Gauss-Legendre quadrature on [-1, 1]: the latitude rule for integrals
//! over the unit sphere such as eqs. (11) and (13).

/// Fills `nodes` with the `n = nodes.len()` Gauss-Legendre nodes and
/// weights `(x_i, w_i)` on [-1, 1] (Newton's method on `P_n`), exact for
/// polynomials of degree `< 2n`. No allocation.
pub fn gauss_legendre(nodes: &mut [(f64, f64)]) {
    let n = nodes.len();
    let nf = n as f64;
    for (i, slot) in nodes.iter_mut().enumerate() {
        let mut x = libm::cos(core::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5));
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = nf * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-15 {
                break;
            }
        }
        *slot = (x, 2.0 / ((1.0 - x * x) * dp * dp));
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn weights_sum_to_two_and_integrate_x_squared() {
        let mut nodes = [(0.0, 0.0); 7];
        super::gauss_legendre(&mut nodes);
        let sum: f64 = nodes.iter().map(|p| p.1).sum();
        let x2: f64 = nodes.iter().map(|p| p.1 * p.0 * p.0).sum();
        assert!((sum - 2.0).abs() < 1e-14 && (x2 - 2.0 / 3.0).abs() < 1e-14);
    }
}
