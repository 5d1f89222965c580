//! Fuzzer bytes -> bounded numbers, with a record of whether every number drawn so far lay
//! inside its documented domain.
//!
//! The first byte chooses the regime: below [`CHAOS_THRESHOLD`] every value is drawn inside
//! its domain (endpoints and the midpoint included); otherwise each value's own mode byte may
//! put it just outside its domain, at a raw bit pattern (NaN, infinities, subnormals, huge
//! values) or at a special value. Input that runs out reads as zeros (the minimum of each
//! domain), so short inputs are valid and in domain.

use arbitrary::Unstructured;

/// First-byte values below this draw every value inside its domain (3/4 of inputs).
pub const CHAOS_THRESHOLD: u8 = 192;

/// Special values tried in the chaotic regime.
const SPECIALS: [f64; 12] = [
    0.0,
    -0.0,
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::MIN_POSITIVE,
    5e-324,
    f64::MAX,
    -f64::MAX,
    -1.0,
    1.0,
    1e300,
];

/// A cursor over the fuzzer's bytes.
pub struct Source<'a> {
    bytes: Unstructured<'a>,
    chaos: bool,
    in_domain: bool,
}

impl<'a> Source<'a> {
    /// Start reading `data`; its first byte selects the regime.
    pub fn new(data: &'a [u8]) -> Self {
        let mut bytes = Unstructured::new(data);
        let selector = bytes.arbitrary::<u8>().unwrap_or(0);
        Self {
            bytes,
            chaos: selector >= CHAOS_THRESHOLD,
            in_domain: true,
        }
    }

    /// `true` while every value drawn since the last [`Source::take_domain`] was in domain.
    pub fn in_domain(&self) -> bool {
        self.in_domain
    }

    /// Return the domain flag and reset it to `true` (to track one group of values).
    pub fn take_domain(&mut self) -> bool {
        core::mem::replace(&mut self.in_domain, true)
    }

    /// A raw byte.
    pub fn byte(&mut self) -> u8 {
        self.bytes.arbitrary::<u8>().unwrap_or(0)
    }

    /// A choice among `count` alternatives (`count >= 1`).
    pub fn choice(&mut self, count: u8) -> u8 {
        self.byte() % count
    }

    /// A boolean.
    pub fn flag(&mut self) -> bool {
        self.byte() & 1 == 1
    }

    /// An integer in `min..=max`.
    pub fn count(&mut self, min: u8, max: u8) -> u8 {
        min + self.byte() % (max - min + 1)
    }

    fn raw(&mut self) -> (u8, u64) {
        let mode = self.byte();
        let bits = self.bytes.arbitrary::<u64>().unwrap_or(0);
        (mode, bits)
    }

    fn note(&mut self, value: f64, min: f64, max: f64) -> f64 {
        if !(value >= min && value <= max) {
            self.in_domain = false;
        }
        value
    }

    /// Outside-the-domain draw shared by the linear and logarithmic maps: `None` means
    /// "draw inside".
    fn wild(&mut self, mode: u8, bits: u64, below: f64, above: f64) -> Option<f64> {
        if !self.chaos || mode < 160 {
            return None;
        }
        Some(match mode % 4 {
            0 => below,
            1 => above,
            2 => f64::from_bits(bits),
            _ => SPECIALS[(bits % SPECIALS.len() as u64) as usize],
        })
    }

    /// A value in `[min, max]` (uniform, with the endpoints and the midpoint hit often), or in
    /// the chaotic regime sometimes outside it.
    pub fn linear(&mut self, min: f64, max: f64) -> f64 {
        let (mode, bits) = self.raw();
        let fraction = unit(bits);
        let width = max - min;
        let below = min - width * (fraction + 1e-6) - min.abs() * 1e-12;
        let above = max + width * (fraction + 1e-6) + max.abs() * 1e-12;
        let value = match self.wild(mode, bits, below, above) {
            Some(value) => value,
            None => match mode % 16 {
                0 => min,
                1 => max,
                2 => 0.5 * (min + max),
                _ => clamp(min + width * fraction, min, max),
            },
        };
        self.note(value, min, max)
    }

    /// A value in `[min, max]`, `0 < min < max`, uniform in the logarithm, or in the chaotic
    /// regime sometimes outside it.
    pub fn log(&mut self, min: f64, max: f64) -> f64 {
        let (mode, bits) = self.raw();
        let fraction = unit(bits);
        let ratio = (max / min).ln();
        let below = min * (-ratio * (fraction + 1e-6)).exp();
        let above = max * (ratio * (fraction + 1e-6)).exp();
        let value = match self.wild(mode, bits, below, above) {
            Some(value) => value,
            None => match mode % 16 {
                0 => min,
                1 => max,
                _ => clamp(min * (ratio * fraction).exp(), min, max),
            },
        };
        self.note(value, min, max)
    }

    /// Zero (one draw in eight) or a log-uniform value in `[min, max]`: rates that may vanish.
    pub fn zero_or_log(&mut self, min: f64, max: f64) -> f64 {
        if self.byte() & 7 == 0 {
            0.0
        } else {
            self.log(min, max)
        }
    }
}

/// `bits` -> `[0, 1)` with 53 significant bits.
fn unit(bits: u64) -> f64 {
    (bits >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

fn clamp(value: f64, min: f64, max: f64) -> f64 {
    value.max(min).min(max)
}
