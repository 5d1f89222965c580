//! Symmetric second-order tensors in Voigt order `xx yy zz xy yz zx` with **tensor** shear
//! components (`eps_xy`, not `gamma_xy = 2 eps_xy`).

/// A symmetric 3x3 tensor stored as `[xx, yy, zz, xy, yz, zx]`.
pub type Sym = [f64; 6];

/// 6x6 matrix acting on [`Sym`] vectors: `dsigma_i = sum_j C[i][j] deps_j`, with `deps_j` the
/// tensor shear component (so an isotropic elastic matrix has `2G` on the shear diagonal).
pub type Matrix6 = [[f64; 6]; 6];

/// The zero tensor.
pub const ZERO: Sym = [0.0; 6];

/// Trace `xx + yy + zz`.
#[inline]
pub fn trace(a: &Sym) -> f64 {
    a[0] + a[1] + a[2]
}

/// Mean of the normal components `tr(a)/3`.
#[inline]
pub fn mean(a: &Sym) -> f64 {
    trace(a) / 3.0
}

/// Deviatoric part `a - tr(a)/3 I`.
#[inline]
pub fn deviator(a: &Sym) -> Sym {
    deviator_and_mean(a).0
}

/// Deviatoric part `a - tr(a)/3 I` and the mean `tr(a)/3`, with one division.
#[inline]
pub fn deviator_and_mean(a: &Sym) -> (Sym, f64) {
    let mean = mean(a);
    (
        [a[0] - mean, a[1] - mean, a[2] - mean, a[3], a[4], a[5]],
        mean,
    )
}

/// Double contraction `a : b` (shear terms counted twice).
#[inline]
pub fn contract(a: &Sym, b: &Sym) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + 2.0 * (a[3] * b[3] + a[4] * b[4] + a[5] * b[5])
}

/// von Mises equivalent of a deviator: `q = sqrt(3/2 s:s)`.
#[inline]
pub fn von_mises(deviator: &Sym) -> f64 {
    crate::math::sqrt(1.5 * contract(deviator, deviator))
}

/// `a * k`.
#[inline]
pub fn scale(a: &Sym, k: f64) -> Sym {
    [a[0] * k, a[1] * k, a[2] * k, a[3] * k, a[4] * k, a[5] * k]
}

/// `a + b`.
#[inline]
pub fn add(a: &Sym, b: &Sym) -> Sym {
    [
        a[0] + b[0],
        a[1] + b[1],
        a[2] + b[2],
        a[3] + b[3],
        a[4] + b[4],
        a[5] + b[5],
    ]
}

/// `s - p I`: a stress from its deviator and pressure (pressure positive in compression).
#[inline]
pub fn from_deviator_and_pressure(deviator: &Sym, pressure: f64) -> Sym {
    [
        deviator[0] - pressure,
        deviator[1] - pressure,
        deviator[2] - pressure,
        deviator[3],
        deviator[4],
        deviator[5],
    ]
}

/// Pressure `p = -tr(sigma)/3` (positive in compression; IEEE division is odd in its
/// dividend, so this is `-mean` to the bit).
#[inline]
pub fn pressure(stress: &Sym) -> f64 {
    -mean(stress)
}

/// Solve the 2x2 linear system `m x = r` by Cramer's rule; `None` if singular.
pub fn solve2(m: [[f64; 2]; 2], r: [f64; 2]) -> Option<[f64; 2]> {
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    Some([
        (r[0] * m[1][1] - m[0][1] * r[1]) / det,
        (m[0][0] * r[1] - m[1][0] * r[0]) / det,
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn von_mises_of_uniaxial_stress_is_the_axial_stress() {
        // GOAL: q of a uniaxial stress state equals |sigma_xx|.
        // SETUP: sigma = diag(300, 0, 0); REFERENCE: exact, q = 300.
        let s = deviator(&[300.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        assert!((von_mises(&s) - 300.0).abs() < 1e-12);
    }

    #[test]
    fn von_mises_of_pure_shear_is_root_three_tau() {
        // GOAL: q of pure shear tau is sqrt(3) tau. REFERENCE: exact.
        let s = [0.0, 0.0, 0.0, 100.0, 0.0, 0.0];
        assert!((von_mises(&s) - 100.0 * libm::sqrt(3.0)).abs() < 1e-12);
    }
}
