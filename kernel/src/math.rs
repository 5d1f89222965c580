//! Scalar helpers on top of `libm`. Kept in one place so that every transcendental call in
//! the kernel is a `libm` call (bit-identical on every target).

/// Natural logarithm, `libm::log`.
#[inline]
pub fn ln(x: f64) -> f64 {
    libm::log(x)
}

/// Exponential, `libm::exp`.
#[inline]
pub fn exp(x: f64) -> f64 {
    libm::exp(x)
}

/// Power `x^y`, `libm::pow`.
#[inline]
pub fn pow(x: f64, y: f64) -> f64 {
    libm::pow(x, y)
}

/// Square root, `libm::sqrt` (IEEE correctly rounded).
#[inline]
pub fn sqrt(x: f64) -> f64 {
    libm::sqrt(x)
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

/// `true` if `x` is finite (neither NaN nor infinite).
#[inline]
pub fn finite(x: f64) -> bool {
    x.is_finite()
}
