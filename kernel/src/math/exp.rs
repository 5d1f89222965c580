//! Exponential, table-driven, with a low-order tail for `pow`.
//!
//! The scheme of Szabolcs Nagy's `exp` for ARM's optimized-routines (MIT; also musl's and
//! glibc's since 2018), written for stoss without fused multiply-add:
//! `x = k ln2/128 + r`, `|r| <= ln2/256`; `exp x = 2^(k/128) exp(r)` with
//! `2^(j/128) = scale_j (1 + tail_j)` from [`EXP_TABLE`] and `exp(r) - 1` a Taylor polynomial
//! to `r^5` (truncation below `|r|^6 / 720 < 2^-60`).

use super::tables::{EXP_LN2_OVER_N_HI, EXP_LN2_OVER_N_LO, EXP_N_OVER_LN2, EXP_TABLE};

/// `1.5 * 2^52`: adding it rounds a double below `2^51` in magnitude to an integer, held in the
/// low bits of the sum's representation.
const SHIFT: f64 = 6755399441055744.0;

const C2: f64 = 1.0 / 2.0;
const C3: f64 = 1.0 / 6.0;
const C4: f64 = 1.0 / 24.0;
const C5: f64 = 1.0 / 120.0;

/// Top 12 bits (sign and biased exponent) of a double.
#[inline(always)]
pub(super) fn top12(x: f64) -> u64 {
    x.to_bits() >> 52
}

/// `2^-54` (bits): below it `exp(x)` rounds to `1 + x`.
const TINY: f64 = f64::from_bits(0x3c90000000000000);

/// `exp(x + tail)` for finite `x` and `|tail| < 2^-15`, `|tail| <= |x|` (or `tail = 0`).
/// Error below 0.52 ulp plus the effect of `tail`'s own error; `1 + x` for `|x| < 2^-54`;
/// `+inf` or `0` beyond `|x| >= 1024`; results near overflow and in the subnormal range
/// are scaled so that they are rounded once.
#[inline(always)]
pub(super) fn exp_with_tail(x: f64, tail: f64) -> f64 {
    let abstop = top12(x) & 0x7ff;
    let outside = abstop.wrapping_sub(top12(TINY)) >= top12(512.0) - top12(TINY);
    if outside {
        if abstop < top12(TINY) {
            return 1.0 + x;
        }
        if abstop >= top12(1024.0) {
            return if x < 0.0 { 0.0 } else { f64::INFINITY };
        }
    }
    // k = round(x 128/ln2); r = x - k ln2/128 (k EXP_LN2_OVER_N_HI exact).
    let z = EXP_N_OVER_LN2 * x;
    let shifted = z + SHIFT;
    let ki = shifted.to_bits();
    let kd = shifted - SHIFT;
    let r = x - kd * EXP_LN2_OVER_N_HI - kd * EXP_LN2_OVER_N_LO + tail;
    // 2^(k/128) = 2^(k >> 7) 2^(j/128), j = k mod 128; the scale's exponent field is added.
    let (tail_j, scale_bits) = EXP_TABLE[(ki % 128) as usize];
    let top = ki.wrapping_shl(45);
    let scale_bits = scale_bits.wrapping_add(top);
    let r2 = r * r;
    let correction = tail_j + r + r2 * (C2 + r * C3) + r2 * r2 * (C4 + r * C5);
    if outside {
        return scaled(correction, scale_bits, ki);
    }
    let scale = f64::from_bits(scale_bits);
    scale + scale * correction
}

/// `scale (1 + correction)` for `512 <= |x| < 1024`, where the exponent of `scale` (bits
/// `scale_bits`) may have wrapped: computed at a shifted exponent and scaled back by a power
/// of two, so that a result near overflow overflows cleanly and a subnormal result is rounded
/// once (the rounding to the subnormal grid is done at 1, where it is exact to emulate).
#[cold]
fn scaled(correction: f64, scale_bits: u64, ki: u64) -> f64 {
    if ki & 0x8000_0000 == 0 {
        // k > 0: the exponent may have overflowed by up to ~460.
        let scale = f64::from_bits(scale_bits.wrapping_sub(1009 << 52));
        return f64::from_bits(0x7f00000000000000) * (scale + scale * correction);
        // 2^1009
    }
    // k < 0: the result may be subnormal.
    let scale = f64::from_bits(scale_bits.wrapping_add(1022 << 52));
    let mut y = scale + scale * correction;
    if y < 1.0 {
        // Round y to the subnormal grid at 1, where 1 + y has it: hi + lo = 1 + y exactly.
        let lo = scale - y + scale * correction;
        let hi = 1.0 + y;
        let lo = 1.0 - hi + y + lo;
        y = (hi + lo) - 1.0;
        if y == 0.0 {
            y = 0.0;
        }
    }
    f64::from_bits(0x0010000000000000) * y // 2^-1022
}

/// Exponential `e^x`, error below 0.52 ulp for normal results (measured bound in
/// `kernel/tests/math.rs`); `1 + x` for `|x| < 2^-54`; infinities and NaN as IEEE and
/// `libm` give them. The same results on every target.
#[inline]
pub fn exp(x: f64) -> f64 {
    if !x.is_finite() {
        return libm::exp(x);
    }
    exp_with_tail(x, 0.0)
}
