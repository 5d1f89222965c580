//! Natural logarithm, table-driven, in double-double for `pow`.
//!
//! The scheme of Szabolcs Nagy's `pow` for ARM's optimized-routines (MIT; also musl's and
//! glibc's since 2018), written for stoss without fused multiply-add so that every target
//! rounds the same operations the same way:
//!
//! `x = 2^k z`, `z` in `[OFF, 2 OFF)`; `ln x = k ln 2 - ln(invc) + ln(1 + r)` with
//! `r = z invc - 1` exact (`invc` has 8 significant bits, see [`LOG_TABLE`]) and
//! `|r| < 2^-7`, and `ln(1 + r)` a Taylor polynomial to `r^9` (truncation below
//! `|r|^10 / 10 < 2^-77`, relative to `|ln x|` below `2^-70`). The sum is carried as
//! `hi + lo` with the rounding errors of every addition recovered exactly.

use super::tables::{LN2_HI, LN2_LO, LOG_OFF, LOG_TABLE, LOG_TABLE_BITS};

/// Taylor coefficients of `ln(1 + r) - r + r^2/2`: `(-1)^(k+1) / k`, `k = 3..=9`.
const C3: f64 = 1.0 / 3.0;
const C4: f64 = -1.0 / 4.0;
const C5: f64 = 1.0 / 5.0;
const C6: f64 = -1.0 / 6.0;
const C7: f64 = 1.0 / 7.0;
const C8: f64 = -1.0 / 8.0;
const C9: f64 = 1.0 / 9.0;

/// `ln x = hi + lo` for the bits `ix` of a positive normal finite `x`; `hi` is `hi + lo`
/// rounded and `|lo| <= ulp(hi)/2`. The relative error of `hi + lo` is below `2^-68`
/// (tested against a 50-digit oracle in `kernel/tests/math.rs`).
#[inline(always)]
pub(super) fn ln_double_double(ix: u64) -> (f64, f64) {
    // x = 2^k z with z in [OFF, 2 OFF): subtracting OFF puts the exponent of x relative to
    // z's in the top 12 bits and the subinterval of z in the next 7.
    let tmp = ix.wrapping_sub(LOG_OFF);
    let i = ((tmp >> (52 - LOG_TABLE_BITS)) % (1 << LOG_TABLE_BITS)) as usize;
    let k = (tmp as i64) >> 52;
    let iz = ix.wrapping_sub(tmp & (0xfff << 52));
    let z = f64::from_bits(iz);
    let kd = k as f64;
    let (invc, logc, logc_tail) = LOG_TABLE[i];

    // r = z invc - 1 exactly: z = zhi + zlo with zhi of 21 significant bits, so that
    // zhi invc (29 bits) and rhi = zhi invc - 1 (Sterbenz) and rhi^2 are exact; rlo = zlo invc
    // is exact, and so is rhi + rlo (a multiple of 2^-60 below 2^-7).
    let zhi = f64::from_bits(iz.wrapping_add(1 << 31) & (u64::MAX << 32));
    let zlo = z - zhi;
    let rhi = zhi * invc - 1.0;
    let rlo = zlo * invc;
    let r = rhi + rlo;

    // k ln2 + ln(c) + r, with t1 exact (multiples of 2^-43 below 2^10) and the error of
    // t1 + r recovered.
    let t1 = kd * LN2_HI + logc;
    let t2 = t1 + r;
    let lo1 = kd * LN2_LO + logc_tail;
    let lo2 = t1 - t2 + r;

    // + (-r^2 / 2): rhi^2 is exact, the rest of r^2 is rlo (r + rhi).
    let half_r = -0.5 * r;
    let half_rhi = -0.5 * rhi;
    let half_rhi2 = rhi * half_rhi;
    let hi = t2 + half_rhi2;
    let lo3 = rlo * (half_r + half_rhi);
    let lo4 = t2 - hi + half_rhi2;

    // ln(1 + r) - r + r^2/2, Estrin's scheme.
    let r2 = r * r;
    let r3 = r * r2;
    let p = r3 * ((C3 + r * C4) + r2 * ((C5 + r * C6) + r2 * ((C7 + r * C8) + r2 * C9)));

    let lo = lo1 + lo2 + lo3 + lo4 + p;
    let y = hi + lo;
    (y, hi - y + lo)
}

/// Natural logarithm `ln x`, error below 0.52 ulp (measured bound in `kernel/tests/math.rs`).
/// Positive normal finite arguments take the table-driven path; zero, negative, subnormal,
/// infinite and NaN arguments go to `libm::log` (same results on every target either way).
#[inline]
pub fn ln(x: f64) -> f64 {
    let ix = x.to_bits();
    // Positive normal finite: top 12 bits (sign and exponent) in 0x001..=0x7fe.
    if (ix >> 52).wrapping_sub(0x001) >= 0x7fe {
        return libm::log(x);
    }
    ln_double_double(ix).0
}
