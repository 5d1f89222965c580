//! Scalar mathematics of the kernel, kept in one place so that every transcendental has one
//! definition that gives the same bits on every target, in debug and release.
//!
//! `exp`, `ln` and `pow` are stoss's own table-driven functions (one per file; tables from
//! `kernel/tools/math_tables.py`): only IEEE additions, multiplications and integer bit
//! operations, never a fused multiply-add or a platform math library, so each result is the
//! same everywhere. Their error is below 0.52 ulp, measured against a 50-digit oracle and
//! against `libm` in `kernel/tests/math.rs`. Arguments outside their fast ranges (and
//! `sqrt`, which IEEE rounds correctly, and `erf`, `expm1`, `ln_1p`, which only the
//! Preston-Tonks-Wallace model uses) go to the `libm` crate.

mod exp;
pub mod lanes;
mod log;
mod pow;
mod tables;

pub use exp::exp;
pub use log::ln;
pub use pow::pow;

/// Square root, `libm::sqrt` (IEEE correctly rounded).
#[inline]
pub fn sqrt(x: f64) -> f64 {
    libm::sqrt(x)
}

/// Error function, `libm::erf` (pure Rust, the same bits on every target).
#[inline]
pub fn erf(x: f64) -> f64 {
    libm::erf(x)
}

/// `exp(x) - 1` without cancellation near 0, `libm::expm1`.
#[inline]
pub fn expm1(x: f64) -> f64 {
    libm::expm1(x)
}

/// `ln(1 + x)` without cancellation near 0, `libm::log1p`.
#[inline]
pub fn ln_1p(x: f64) -> f64 {
    libm::log1p(x)
}

/// Clamp `x` to `[lo, hi]` without panicking on NaN (NaN passes through).
#[inline]
pub fn clamp(x: f64, lo: f64, hi: f64) -> f64 {
    if x < lo {
        lo
    } else if x > hi {
        hi
    } else {
        x
    }
}

/// `true` if every value is finite: `v * 0` is `0` for a finite `v` and NaN for an infinite or
/// NaN one, and NaN survives the sums. Two interleaved sums (even and odd positions) are
/// independent, so the compiler can run them as one two-lane vector sum; one branch in all.
#[inline(always)]
pub fn all_finite<const N: usize>(values: &[f64; N]) -> bool {
    let mut lanes = [0.0_f64; 2];
    for pair in values.chunks(2) {
        for (lane, value) in lanes.iter_mut().zip(pair) {
            *lane += *value * 0.0;
        }
    }
    lanes[0] + lanes[1] == 0.0
}

/// `true` if `x` is finite (neither NaN nor infinite).
#[inline]
pub fn finite(x: f64) -> bool {
    x.is_finite()
}
