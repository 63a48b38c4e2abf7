//! Eigenvalues of a symmetric 3x3 matrix by cyclic Jacobi rotations:
//! square roots and divisions only (no trigonometry), a fixed number of
//! sweeps, deterministic on every target.

/// Sweeps over the three off-diagonal pairs. Jacobi converges
/// quadratically; 5 sweeps reach `f32` rounding for any 3x3 input.
pub const SWEEPS: usize = 5;

/// Eigenvalues, ascending, of the symmetric matrix
/// `[[a11, a12, a13], [a12, a22, a23], [a13, a23, a33]]`.
pub fn symmetric3(a11: f32, a22: f32, a33: f32, a12: f32, a13: f32, a23: f32) -> [f32; 3] {
    let mut m = Sym {
        d: [a11, a22, a33],
        o12: a12,
        o13: a13,
        o23: a23,
    };
    for _ in 0..SWEEPS {
        m.rotate12();
        m.rotate13();
        m.rotate23();
    }
    let [mut x, mut y, mut z] = m.d;
    // Sort ascending with a fixed compare-and-swap network.
    if x > y {
        core::mem::swap(&mut x, &mut y);
    }
    if y > z {
        core::mem::swap(&mut y, &mut z);
    }
    if x > y {
        core::mem::swap(&mut x, &mut y);
    }
    [x, y, z]
}

struct Sym {
    d: [f32; 3],
    o12: f32,
    o13: f32,
    o23: f32,
}

/// `(t, c, s)` of the Jacobi rotation that annihilates `apq`.
#[inline(always)]
fn jacobi(app: f32, aqq: f32, apq: f32) -> Option<(f32, f32, f32)> {
    let scale = app.abs() + aqq.abs();
    if apq == 0.0 || apq.abs() <= scale * 1e-12 {
        return None;
    }
    let theta = (aqq - app) / (2.0 * apq);
    let t = if theta.abs() > 1e15 {
        0.5 / theta
    } else {
        let r = (theta * theta + 1.0).sqrt_fw();
        let t = 1.0 / (theta.abs() + r);
        if theta < 0.0 {
            -t
        } else {
            t
        }
    };
    let c = 1.0 / (t * t + 1.0).sqrt_fw();
    Some((t, c, t * c))
}

/// Square root through `omniad_core::Real::root` (the FPU instruction on
/// the Cortex-M4F, correctly rounded like the host's).
trait SqrtFw {
    fn sqrt_fw(self) -> Self;
}
impl SqrtFw for f32 {
    #[inline(always)]
    fn sqrt_fw(self) -> f32 {
        omniad_core::Real::root(self)
    }
}

impl Sym {
    #[inline(always)]
    fn rotate12(&mut self) {
        let [a11, a22, a33] = self.d;
        if let Some((t, c, s)) = jacobi(a11, a22, self.o12) {
            self.d = [a11 - t * self.o12, a22 + t * self.o12, a33];
            self.o12 = 0.0;
            let (r1, r2) = (self.o13, self.o23);
            self.o13 = c * r1 - s * r2;
            self.o23 = s * r1 + c * r2;
        }
    }
    #[inline(always)]
    fn rotate13(&mut self) {
        let [a11, a22, a33] = self.d;
        if let Some((t, c, s)) = jacobi(a11, a33, self.o13) {
            self.d = [a11 - t * self.o13, a22, a33 + t * self.o13];
            self.o13 = 0.0;
            let (r1, r3) = (self.o12, self.o23);
            self.o12 = c * r1 - s * r3;
            self.o23 = s * r1 + c * r3;
        }
    }
    #[inline(always)]
    fn rotate23(&mut self) {
        let [a11, a22, a33] = self.d;
        if let Some((t, c, s)) = jacobi(a22, a33, self.o23) {
            self.d = [a11, a22 - t * self.o23, a33 + t * self.o23];
            self.o23 = 0.0;
            let (r2, r3) = (self.o12, self.o13);
            self.o12 = c * r2 - s * r3;
            self.o13 = s * r2 + c * r3;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_spectrum() {
        // [[2,1,0],[1,2,0],[0,0,-3]]: eigenvalues -3, 1, 3.
        let e = symmetric3(2.0, 2.0, -3.0, 1.0, 0.0, 0.0);
        assert!(
            (e[0] + 3.0).abs() < 1e-5 && (e[1] - 1.0).abs() < 1e-5 && (e[2] - 3.0).abs() < 1e-5,
            "{e:?}"
        );
        // Full matrix: trace and determinant are preserved.
        let (a, b, c, d, f, g) = (4.0f32, -1.0, 2.5, 0.7, -1.3, 0.4);
        let e = symmetric3(a, b, c, d, f, g);
        let trace = a + b + c;
        let det = a * (b * c - g * g) - d * (d * c - g * f) + f * (d * g - b * f);
        assert!((e.iter().sum::<f32>() - trace).abs() < 1e-4);
        assert!((e[0] * e[1] * e[2] - det).abs() < 1e-3, "{e:?} {det}");
        assert!(e[0] <= e[1] && e[1] <= e[2]);
    }
}
