//! Lane versions of `exp`, `ln` and `pow`: the same operations in the same order as the
//! scalar functions, applied to `L` independent arguments at once, so every lane's bits are
//! the scalar function's. Lanes off the fast path are finished by the scalar function.
//!
//! The loops run over lane indices into several arrays at once, the form the compiler turns
//! into vector operations.
#![allow(clippy::needless_range_loop)]

use super::exp::top12;
use super::tables::{
    EXP_LN2_OVER_N_HI, EXP_LN2_OVER_N_LO, EXP_N_OVER_LN2, EXP_TABLE, LN2_HI, LN2_LO, LOG_OFF,
    LOG_TABLE, LOG_TABLE_BITS,
};

const SHIFT: f64 = 6755399441055744.0;
const E2: f64 = 1.0 / 2.0;
const E3: f64 = 1.0 / 6.0;
const E4: f64 = 1.0 / 24.0;
const E5: f64 = 1.0 / 120.0;
const L3: f64 = 1.0 / 3.0;
const L4: f64 = -1.0 / 4.0;
const L5: f64 = 1.0 / 5.0;
const L6: f64 = -1.0 / 6.0;
const L7: f64 = 1.0 / 7.0;
const L8: f64 = -1.0 / 8.0;
const L9: f64 = 1.0 / 9.0;
const TINY: f64 = f64::from_bits(0x3c90000000000000);

#[inline(always)]
fn ln_dd<const L: usize>(ix: [u64; L]) -> ([f64; L], [f64; L]) {
    let mut y = [0.0; L];
    let mut tail = [0.0; L];
    let mut invc = [0.0; L];
    let mut logc = [0.0; L];
    let mut logc_tail = [0.0; L];
    let mut kd = [0.0; L];
    let mut iz = [0u64; L];
    for l in 0..L {
        let tmp = ix[l].wrapping_sub(LOG_OFF);
        let i = ((tmp >> (52 - LOG_TABLE_BITS)) % (1 << LOG_TABLE_BITS)) as usize;
        kd[l] = ((tmp as i64) >> 52) as f64;
        iz[l] = ix[l].wrapping_sub(tmp & (0xfff << 52));
        (invc[l], logc[l], logc_tail[l]) = LOG_TABLE[i];
    }
    for l in 0..L {
        let z = f64::from_bits(iz[l]);
        let zhi = f64::from_bits(iz[l].wrapping_add(1 << 31) & (u64::MAX << 32));
        let zlo = z - zhi;
        let rhi = zhi * invc[l] - 1.0;
        let rlo = zlo * invc[l];
        let r = rhi + rlo;
        let t1 = kd[l] * LN2_HI + logc[l];
        let t2 = t1 + r;
        let lo1 = kd[l] * LN2_LO + logc_tail[l];
        let lo2 = t1 - t2 + r;
        let half_r = -0.5 * r;
        let half_rhi = -0.5 * rhi;
        let half_rhi2 = rhi * half_rhi;
        let hi = t2 + half_rhi2;
        let lo3 = rlo * (half_r + half_rhi);
        let lo4 = t2 - hi + half_rhi2;
        let r2 = r * r;
        let r3 = r * r2;
        let p = r3 * ((L3 + r * L4) + r2 * ((L5 + r * L6) + r2 * ((L7 + r * L8) + r2 * L9)));
        let lo = lo1 + lo2 + lo3 + lo4 + p;
        y[l] = hi + lo;
        tail[l] = hi - y[l] + lo;
    }
    (y, tail)
}

/// `exp` of each lane ([`super::exp`]'s bits).
#[inline]
pub fn exp<const L: usize>(x: [f64; L]) -> [f64; L] {
    if x.iter().any(|v| !v.is_finite()) {
        return x.map(super::exp);
    }
    exp_with_tail(x, [0.0; L])
}

/// `ln` of each lane ([`super::ln`]'s bits).
#[inline]
pub fn ln<const L: usize>(x: [f64; L]) -> [f64; L] {
    let ix = x.map(f64::to_bits);
    if ix.iter().any(|&i| (i >> 52).wrapping_sub(0x001) >= 0x7fe) {
        return x.map(super::ln);
    }
    ln_dd(ix).0
}

/// `pow` of each lane ([`super::pow`]'s bits).
#[inline]
pub fn pow<const L: usize>(x: [f64; L], y: [f64; L]) -> [f64; L] {
    let mut special = false;
    for l in 0..L {
        let topx = top12(x[l]);
        let topy = top12(y[l]) & 0x7ff;
        special |= topx.wrapping_sub(0x001) >= 0x7fe || topy.wrapping_sub(0x3be) >= 0x43e - 0x3be;
    }
    if special {
        return core::array::from_fn(|l| super::pow(x[l], y[l]));
    }
    let (hi, lo) = ln_dd(x.map(f64::to_bits));
    let mut ehi = [0.0; L];
    let mut elo = [0.0; L];
    for l in 0..L {
        let yhi = f64::from_bits(y[l].to_bits() & (u64::MAX << 27));
        let ylo = y[l] - yhi;
        let lhi = f64::from_bits(hi[l].to_bits() & (u64::MAX << 27));
        let llo = hi[l] - lhi + lo[l];
        ehi[l] = yhi * lhi;
        elo[l] = ylo * lhi + y[l] * llo;
    }
    exp_with_tail(ehi, elo)
}

#[inline(always)]
fn exp_with_tail<const L: usize>(x: [f64; L], tail: [f64; L]) -> [f64; L] {
    let mut outside = false;
    for l in 0..L {
        let abstop = top12(x[l]) & 0x7ff;
        outside |= abstop.wrapping_sub(top12(TINY)) >= top12(512.0) - top12(TINY);
    }
    if outside {
        return core::array::from_fn(|l| super::exp::exp_with_tail(x[l], tail[l]));
    }
    let mut out = [0.0; L];
    let mut r = [0.0; L];
    let mut ki = [0u64; L];
    for l in 0..L {
        let z = EXP_N_OVER_LN2 * x[l];
        let shifted = z + SHIFT;
        ki[l] = shifted.to_bits();
        let kd = shifted - SHIFT;
        r[l] = x[l] - kd * EXP_LN2_OVER_N_HI - kd * EXP_LN2_OVER_N_LO + tail[l];
    }
    let mut tail_j = [0.0; L];
    let mut scale_bits = [0u64; L];
    for l in 0..L {
        let (t, s) = EXP_TABLE[(ki[l] % 128) as usize];
        tail_j[l] = t;
        scale_bits[l] = s.wrapping_add(ki[l].wrapping_shl(45));
    }
    for l in 0..L {
        let r2 = r[l] * r[l];
        let correction = tail_j[l] + r[l] + r2 * (E2 + r[l] * E3) + r2 * r2 * (E4 + r[l] * E5);
        let scale = f64::from_bits(scale_bits[l]);
        out[l] = scale + scale * correction;
    }
    out
}

/// Where a formula gets its `pow`, `ln` and `exp`: computed on the spot ([`Direct`]), or
/// taken from values computed beforehand in lanes ([`Given`]). Either way the bits are the
/// scalar functions'.
pub trait Transcendentals {
    /// `x^y` ([`super::pow`]).
    fn pow(&mut self, x: f64, y: f64) -> f64;
    /// `ln x` ([`super::ln`]).
    fn ln(&mut self, x: f64) -> f64;
    /// `e^x` ([`super::exp`]).
    fn exp(&mut self, x: f64) -> f64;
}

/// The scalar functions, called on the spot.
pub struct Direct;

impl Transcendentals for Direct {
    #[inline(always)]
    fn pow(&mut self, x: f64, y: f64) -> f64 {
        super::pow(x, y)
    }
    #[inline(always)]
    fn ln(&mut self, x: f64) -> f64 {
        super::ln(x)
    }
    #[inline(always)]
    fn exp(&mut self, x: f64) -> f64 {
        super::exp(x)
    }
}

/// A transcendental function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Function {
    /// [`super::pow`] of `(x, y)`.
    Pow,
    /// [`super::ln`] of `x`.
    Ln,
    /// [`super::exp`] of `x`.
    Exp,
    /// [`super::exp`] of `x + y v`, `v` the value of an earlier slot (see
    /// [`Calls::push_exp_of_affine`]); [`evaluate`] resolves it to an [`Function::Exp`] call.
    ExpOfAffine,
}

/// Most calls a formula announces ([`Calls`]).
pub const MAXIMUM_CALLS: usize = 4;

/// The calls a formula is about to make, announced so that a group of points can evaluate
/// them in lanes first ([`evaluate`]). A formula announces the same list of functions
/// whatever its arguments, so that slot `k` is the same function in every lane; a call the
/// formula will skip is announced with the harmless arguments `(1, 1)`.
#[derive(Clone, Copy, Debug)]
pub struct Calls {
    function: [Function; MAXIMUM_CALLS],
    x: [f64; MAXIMUM_CALLS],
    y: [f64; MAXIMUM_CALLS],
    /// The earlier slot whose value an [`Function::ExpOfAffine`] slot's argument takes.
    source: [usize; MAXIMUM_CALLS],
    len: usize,
}

impl Default for Calls {
    fn default() -> Self {
        Calls {
            function: [Function::Pow; MAXIMUM_CALLS],
            x: [1.0; MAXIMUM_CALLS],
            y: [1.0; MAXIMUM_CALLS],
            source: [0; MAXIMUM_CALLS],
            len: 0,
        }
    }
}

impl Calls {
    /// Announce a call of `function` at `(x, y)` (`y` unused but by `pow`); past
    /// [`MAXIMUM_CALLS`] the call is left to be made on the spot. Returns the call's slot
    /// (`None` when it was left).
    #[inline(always)]
    pub fn push(&mut self, function: Function, x: f64, y: f64) -> Option<usize> {
        if self.len < MAXIMUM_CALLS {
            let slot = self.len;
            self.function[slot] = function;
            self.x[slot] = x;
            self.y[slot] = y;
            self.len += 1;
            Some(slot)
        } else {
            None
        }
    }

    /// Announce the call `exp(offset + slope v)`, `v` the value of the call announced in
    /// `source` (a formula's `exp(a + b ln x)` whose logarithm is announced first), so that
    /// both are evaluated in lanes, one after the other. `offset + slope v` is formed as
    /// written, the formula's own operations, so that its bits are the formula's argument.
    #[inline(always)]
    pub fn push_exp_of_affine(&mut self, source: usize, offset: f64, slope: f64) {
        if source < self.len {
            if let Some(slot) = self.push(Function::ExpOfAffine, offset, slope) {
                self.source[slot] = source;
            }
        }
    }
}

/// The announced calls' values, lane `l`'s in `values[l]`: each slot evaluated in lanes when
/// every lane that announced a call there announced the same function, lane by lane
/// otherwise, in slot order. An [`Function::ExpOfAffine`] slot takes its argument from the
/// value computed before it and becomes the [`Function::Exp`] call of that argument.
#[inline(always)]
pub fn evaluate<const L: usize>(calls: &mut [Calls; L]) -> [[f64; MAXIMUM_CALLS]; L] {
    let mut values = [[0.0; MAXIMUM_CALLS]; L];
    let len = calls.iter().map(|c| c.len).max().unwrap_or(0);
    for k in 0..len {
        // A lane that announced fewer calls holds (1, 1) in this slot and takes any function.
        let Some(function) = calls.iter().find(|c| c.len > k).map(|c| c.function[k]) else {
            break;
        };
        let uniform = calls
            .iter()
            .all(|c| c.len <= k || c.function[k] == function);
        for l in 0..L {
            let c = &mut calls[l];
            if c.len > k && c.function[k] == Function::ExpOfAffine {
                c.x[k] += c.y[k] * values[l][c.source[k]];
                c.y[k] = 1.0;
                c.function[k] = Function::Exp;
            }
        }
        let x: [f64; L] = core::array::from_fn(|l| calls[l].x[k]);
        let y: [f64; L] = core::array::from_fn(|l| calls[l].y[k]);
        let column = if uniform {
            match function {
                Function::Pow => pow(x, y),
                Function::Ln => ln(x),
                Function::Exp | Function::ExpOfAffine => exp(x),
            }
        } else {
            core::array::from_fn(|l| match calls[l].function[k] {
                Function::Pow => super::pow(x[l], y[l]),
                Function::Ln => super::ln(x[l]),
                Function::Exp | Function::ExpOfAffine => super::exp(x[l]),
            })
        };
        for l in 0..L {
            values[l][k] = column[l];
        }
    }
    values
}

/// One lane's announced calls with their values: a call whose function and arguments (bit
/// for bit) match an announced one takes its value; any other is computed on the spot.
pub struct Given<'a> {
    calls: &'a Calls,
    values: &'a [f64; MAXIMUM_CALLS],
    /// The slot the next call is expected in (formulas call in the order they announce).
    next: usize,
}

impl<'a> Given<'a> {
    /// Lane values `values` of the calls `calls`.
    #[inline(always)]
    pub fn new(calls: &'a Calls, values: &'a [f64; MAXIMUM_CALLS]) -> Self {
        Given {
            calls,
            values,
            next: 0,
        }
    }

    /// Whether slot `k` holds the call `function(x, y)`.
    #[inline(always)]
    fn holds(&self, k: usize, function: Function, x: f64, y: f64) -> bool {
        self.calls.function[k] == function
            && self.calls.x[k].to_bits() == x.to_bits()
            && self.calls.y[k].to_bits() == y.to_bits()
    }

    /// The value of the call `function(x, y)` if it was announced: the expected slot first,
    /// then any.
    #[inline(always)]
    fn find(&mut self, function: Function, x: f64, y: f64) -> Option<f64> {
        let k = if self.next < self.calls.len && self.holds(self.next, function, x, y) {
            self.next
        } else {
            (0..self.calls.len).find(|&k| self.holds(k, function, x, y))?
        };
        self.next = k + 1;
        Some(self.values[k])
    }
}

impl Transcendentals for Given<'_> {
    #[inline(always)]
    fn pow(&mut self, x: f64, y: f64) -> f64 {
        self.find(Function::Pow, x, y)
            .unwrap_or_else(|| super::pow(x, y))
    }
    #[inline(always)]
    fn ln(&mut self, x: f64) -> f64 {
        self.find(Function::Ln, x, 1.0)
            .unwrap_or_else(|| super::ln(x))
    }
    #[inline(always)]
    fn exp(&mut self, x: f64) -> f64 {
        self.find(Function::Exp, x, 1.0)
            .unwrap_or_else(|| super::exp(x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A reproducible spread of doubles: every exponent, random mantissas, both signs, and
    /// the special values.
    fn arguments(count: usize, seed: u64) -> impl Iterator<Item = f64> {
        let mut state = seed;
        let specials = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            0.5,
            2.0,
        ];
        (0..count).map(move |i| {
            if i % 17 == 0 {
                return specials[(i / 17) % specials.len()];
            }
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let bits = state >> 1;
            // Mostly moderate magnitudes (where the fast paths run), sometimes any double.
            if i % 5 == 0 {
                f64::from_bits(bits)
            } else {
                let exponent = ((bits >> 52) % 80) as i32 - 40;
                let mantissa = 1.0 + (bits & ((1 << 52) - 1)) as f64 / (1u64 << 52) as f64;
                mantissa * libm::pow(2.0, f64::from(exponent))
            }
        })
    }

    fn same(a: f64, b: f64) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }

    #[test]
    fn every_lane_has_the_scalar_bits() {
        // GOAL: the lane functions return, lane by lane, exactly the scalar functions' bits.
        // SETUP: 40 000 arguments (random mantissas over 2^-40..2^40, random bit patterns,
        //        zeros, subnormals, infinities, NaN), in groups of 1, 4 and 8 lanes, so that
        //        fast-path and special lanes share a group.
        // REFERENCE: crate::math::{ln, pow} on each lane alone.
        let x: std::vec::Vec<f64> = arguments(40_000, 1).collect();
        let y: std::vec::Vec<f64> = arguments(40_000, 2).map(|v| v * 1e-3).collect();
        fn check<const L: usize>(x: &[f64], y: &[f64]) {
            for (xs, ys) in x.chunks_exact(L).zip(y.chunks_exact(L)) {
                let xs: [f64; L] = core::array::from_fn(|l| xs[l]);
                let ys: [f64; L] = core::array::from_fn(|l| ys[l]);
                let powered = pow(xs, ys);
                let logs = ln(xs);
                for l in 0..L {
                    assert!(
                        same(powered[l], super::super::pow(xs[l], ys[l])),
                        "pow({}, {})",
                        xs[l],
                        ys[l]
                    );
                    assert!(same(logs[l], super::super::ln(xs[l])), "ln({})", xs[l]);
                }
            }
        }
        check::<1>(&x, &y);
        check::<4>(&x, &y);
        check::<8>(&x, &y);
        // Moderate exponents only (the lane fast path throughout).
        let y: std::vec::Vec<f64> = arguments(40_000, 3).map(|v| libm::fmod(v, 3.0)).collect();
        let x: std::vec::Vec<f64> = x.iter().map(|v| v.abs()).collect();
        check::<4>(&x, &y);
        check::<8>(&x, &y);
    }

    #[test]
    fn a_chained_exp_has_the_formula_bits_and_is_matched() {
        // GOAL: an announced `exp(a + b ln x)` (Zerilli-Armstrong's activation) is evaluated
        //       after its `ln`, has the bits of the formula computed on the spot, and is the
        //       value the formula's own `exp` call is handed; lanes that announce other
        //       functions in the slot, or fewer calls, keep their own values.
        // SETUP: 8 lanes; lanes 0-5 announce ln(x), exp(a + b ln x); lane 6 announces
        //        exp(x), ln(x); lane 7 announces nothing. Rates from 1e-6 to 1e7, a and b
        //        from ZA steel constants at 300-1400 K.
        // REFERENCE: crate::math::{exp, ln} called as the formula calls them.
        let x = [1e-6, 3.7e-2, 1.0, 812.5, 1.3e4, 9.9e6, 0.75, 1.0];
        let temperature = [300.0, 455.0, 612.0, 800.0, 1100.0, 1400.0, 300.0, 300.0];
        let (c3, c4) = (0.00698, 0.000415);
        let mut calls = [Calls::default(); 8];
        for l in 0..6 {
            let log = calls[l].push(Function::Ln, x[l], 1.0).unwrap();
            calls[l].push_exp_of_affine(log, -c3 * temperature[l], c4 * temperature[l]);
        }
        calls[6].push(Function::Exp, x[6], 1.0);
        calls[6].push(Function::Ln, x[6], 1.0);
        let announced = calls;
        let values = evaluate(&mut calls);
        for l in 0..6 {
            let mut given = Given::new(&calls[l], &values[l]);
            let log = given.ln(x[l]);
            let argument = -c3 * temperature[l] + c4 * temperature[l] * log;
            let value = given.exp(argument);
            assert_eq!(log.to_bits(), super::super::ln(x[l]).to_bits());
            assert_eq!(value.to_bits(), super::super::exp(argument).to_bits());
            assert_eq!(
                value.to_bits(),
                values[l][1].to_bits(),
                "lane {l} not matched"
            );
            assert_eq!(given.next, 2);
        }
        assert_eq!(values[6][0].to_bits(), super::super::exp(x[6]).to_bits());
        assert_eq!(values[6][1].to_bits(), super::super::ln(x[6]).to_bits());
        assert_eq!(calls[6].x, announced[6].x);
        assert_eq!(calls[7].len, 0);
    }
}
