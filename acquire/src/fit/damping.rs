//! The damping tensor D (eq. 6): its six parameters, the map `D ↦ D Ω`, and
//! the projection onto positive definite matrices (§4.1).

use nalgebra::{Matrix3, SMatrix, Vector3};
use omniad_core::math::{symmetric_from_six, symmetric_times_vector_rows};

/// `D Ω = M(Ω) d` with `d = [d11, d22, d33, d12, d13, d23]`.
pub fn omega_map(w: &Vector3<f64>) -> SMatrix<f64, 3, 6> {
    let [a, b, c] = symmetric_times_vector_rows(w);
    SMatrix::<f64, 3, 6>::from_row_slice(&[a, b, c].concat())
}

/// The symmetric matrix of six parameters.
pub fn matrix(d: &[f64; 6]) -> Matrix3<f64> {
    symmetric_from_six(*d)
}

/// The nearest (Frobenius) symmetric matrix whose eigenvalues are at least
/// `floor` (> 0 keeps D positive definite).
pub fn positive_definite(d: &Matrix3<f64>, floor: f64) -> Matrix3<f64> {
    let sym = 0.5 * (d + d.transpose());
    let eig = sym.symmetric_eigen();
    let clamped = eig.eigenvalues.map(|l| l.max(floor));
    eig.eigenvectors * Matrix3::from_diagonal(&clamped) * eig.eigenvectors.transpose()
}

/// The fitted `raw` `[d11, d22, d33, d12, d13, d23]` projected onto
/// positive definite matrices, no eigenvalue below `relative_floor` times
/// the largest (D must dissipate, §4), in the same layout.
pub fn with_floor(raw: &[f64; 6], relative_floor: f64) -> [f64; 6] {
    let d = positive_definite(&matrix(raw), 0.0);
    let floor = relative_floor * d.symmetric_eigen().eigenvalues.max().max(1e-9);
    six(&positive_definite(&matrix(raw), floor))
}

/// `[d11, d22, d33, d12, d13, d23]` of a symmetric matrix (the inverse of
/// [`matrix`]).
pub fn six(d: &Matrix3<f64>) -> [f64; 6] {
    [
        d[(0, 0)],
        d[(1, 1)],
        d[(2, 2)],
        d[(0, 1)],
        d[(0, 2)],
        d[(1, 2)],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn omega_map_matches_matrix_product() {
        let d = [1.0, 2.0, 3.0, 0.1, -0.2, 0.3];
        let w = Vector3::new(0.5, -1.0, 2.0);
        assert!(
            (omega_map(&w) * SMatrix::<f64, 6, 1>::from_row_slice(&d) - matrix(&d) * w).norm()
                < 1e-12
        );
    }

    #[test]
    fn projection_clamps_negative_eigenvalues() {
        let d = Matrix3::new(1.0, 0.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, 3.0);
        let p = positive_definite(&d, 1e-6);
        assert!(p.symmetric_eigen().eigenvalues.min() >= 1e-6 - 1e-12);
        assert!((p[(0, 0)] - 1.0).abs() < 1e-12 && (p[(2, 2)] - 3.0).abs() < 1e-12);
    }
}
