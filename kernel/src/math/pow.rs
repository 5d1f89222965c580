//! Power `x^y = exp(y ln x)` with `ln x` in double-double.
//!
//! The scheme of Szabolcs Nagy's `pow` for ARM's optimized-routines (MIT; also musl's and
//! glibc's since 2018), written for stoss without fused multiply-add: `ln x = hi + lo` to a
//! relative `2^-68`, `y (hi + lo) = ehi + elo` with `ehi` exact from 26-bit halves, then
//! `exp(ehi + elo)`.

use super::exp::{exp_with_tail, top12};
use super::log::ln_double_double;

/// `x^y`, error below 0.52 ulp for normal results (measured bound in `kernel/tests/math.rs`)
/// on the table-driven path: `x` positive normal finite, `2^-65 <= |y| < 2^63`. Every other
/// case (zero, negative or subnormal `x`, infinities, NaN, `y` huge or tiny) goes to
/// `libm::pow`, so the special values are libm's. The same results on every target.
#[inline]
pub fn pow(x: f64, y: f64) -> f64 {
    let ix = x.to_bits();
    let iy = y.to_bits();
    let topx = top12(x);
    let topy = top12(y) & 0x7ff;
    if topx.wrapping_sub(0x001) >= 0x7fe || topy.wrapping_sub(0x3be) >= 0x43e - 0x3be {
        return libm::pow(x, y);
    }
    let (hi, lo) = ln_double_double(ix);
    // y hi = yhi lhi + (ylo lhi + y llo): yhi and lhi have 26 significant bits, so their
    // product is exact; |elo| < 2^-25 |ehi|.
    let yhi = f64::from_bits(iy & (u64::MAX << 27));
    let ylo = y - yhi;
    let lhi = f64::from_bits(hi.to_bits() & (u64::MAX << 27));
    let llo = hi - lhi + lo;
    let ehi = yhi * lhi;
    let elo = ylo * lhi + y * llo;
    exp_with_tail(ehi, elo)
}
