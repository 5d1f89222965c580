//! The kernel's own `exp`, `ln` and `pow` (kernel/src/math).
//!
//! GOAL: every result within 0.52 ulp of the exact value, the same bits on every target and
//! profile, and libm's special values.
//! SETUP: 3300 calls drawn over eleven argument families (wide ranges, arguments near 1,
//! subnormal results, the kernel's own ranges) with their exact values from a 200-bit mpmath
//! oracle (`kernel/tools/math_oracle.py write`); a million seeded arguments per function
//! against the `libm` crate; a hash of 300 000 results.
//! REFERENCE: mpmath 1.3 at 200 bits (the fixture); `libm` 0.2 (FreeBSD msun, < 1 ulp).

use stoss_kernel::math::{exp, ln, pow};

/// The measured error bound of the three functions, in ulps of the exact result.
const ERROR_BOUND_ULP: f64 = 0.52;

fn ulp_distance(a: f64, b: f64) -> i64 {
    // Both finite and of the same sign here: the integer difference of the bits counts ulps.
    a.to_bits() as i64 - b.to_bits() as i64
}

#[test]
fn within_bound_of_a_200_bit_oracle() {
    let fixture = include_str!("data/math_oracle.txt");
    let mut worst = [0.0_f64; 3];
    let mut count = 0;
    for (index, line) in fixture.lines().enumerate() {
        let words: Vec<&str> = line.split_whitespace().collect();
        let hex = |w: &str| f64::from_bits(u64::from_str_radix(w, 16).expect("hex bits"));
        let (slot, ours, rounded, rest) = match words[0] {
            "exp" => (0, exp(hex(words[1])), hex(words[2]), words[3]),
            "ln" => (1, ln(hex(words[1])), hex(words[2]), words[3]),
            "pow" => (
                2,
                pow(hex(words[1]), hex(words[2])),
                hex(words[3]),
                words[4],
            ),
            other => panic!("line {}: unknown function {other}", index + 1),
        };
        let rest: f64 = rest.parse().expect("rest");
        // exact = rounded + rest ulp, so ours - exact = (ours - rounded) - rest in ulps.
        let error = (ulp_distance(ours, rounded) as f64 - rest).abs();
        assert!(
            error <= ERROR_BOUND_ULP,
            "line {}: {line}: ours {ours:e} is {error:.3} ulp from the exact value",
            index + 1
        );
        worst[slot] = worst[slot].max(error);
        count += 1;
    }
    assert_eq!(count, 3300);
    // Each function's worst case is above 0.5 ulp only where it cannot round correctly; the
    // fixture must reach past 0.49 ulp for each, or it is not exercising the rounding.
    for (name, error) in ["exp", "ln", "pow"].iter().zip(worst) {
        assert!(error > 0.49, "{name}: worst {error}");
    }
}

/// splitmix64: a seeded stream of 64-bit words.
struct Stream(u64);

impl Stream {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next() >> 11) as f64 / (1u64 << 53) as f64)
    }
}

#[test]
fn within_one_ulp_of_libm_over_a_million_arguments() {
    const CALLS: usize = 1_000_000;
    let mut stream = Stream(2026);
    for _ in 0..CALLS {
        let x = stream.uniform(-700.0, 700.0);
        let (ours, theirs) = (exp(x), libm::exp(x));
        assert!(
            ulp_distance(ours, theirs).abs() <= 1,
            "exp({x:e}): {ours:e} vs {theirs:e}"
        );

        let x = libm::exp2(stream.uniform(-1000.0, 1000.0));
        let (ours, theirs) = (ln(x), libm::log(x));
        assert!(
            ulp_distance(ours, theirs).abs() <= 1,
            "ln({x:e}): {ours:e} vs {theirs:e}"
        );

        let x = libm::exp10(stream.uniform(-8.0, 3.0));
        let y = stream.uniform(-4.0, 4.0);
        let (ours, theirs) = (pow(x, y), libm::pow(x, y));
        assert!(
            ulp_distance(ours, theirs).abs() <= 1,
            "pow({x:e}, {y:e}): {ours:e} vs {theirs:e}"
        );
    }
}

#[test]
fn special_values_are_libm_s() {
    // Arguments outside the table-driven paths: zero, negative, subnormal, infinite, NaN.
    let xs = [
        0.0,
        -0.0,
        -1.0,
        -2.5,
        f64::MIN_POSITIVE / 4.0,
        1e-320,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
    ];
    let ys = [
        0.0,
        -0.0,
        f64::INFINITY,
        -f64::INFINITY,
        f64::NAN,
        1e-300,
        1e300,
    ];
    let same = |a: f64, b: f64| (a.is_nan() && b.is_nan()) || a.to_bits() == b.to_bits();
    for &x in &xs {
        assert!(same(ln(x), libm::log(x)), "ln({x:e})");
        for &y in ys.iter().chain(&[1.0, 2.0, 3.0, -1.0, 0.5]) {
            assert!(same(pow(x, y), libm::pow(x, y)), "pow({x:e}, {y:e})");
        }
    }
    for &y in &ys {
        for x in [1.0, 2.0, 0.5] {
            assert!(same(pow(x, y), libm::pow(x, y)), "pow({x:e}, {y:e})");
        }
    }
    for x in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN, 0.0, -0.0] {
        assert!(same(exp(x), libm::exp(x)), "exp({x:e})");
    }
    assert_eq!(exp(1e-300), 1.0);
    assert_eq!(exp(800.0), f64::INFINITY);
    assert_eq!(exp(-800.0), 0.0);
    assert_eq!(pow(2.0, 2000.0), f64::INFINITY);
    assert_eq!(pow(2.0, -2000.0), 0.0);
    assert_eq!(pow(2.0, -1074.0), f64::from_bits(1));
    assert_eq!(ln(1.0), 0.0);
}

/// FNV-1a over the bits of 100 000 results of each function (a NaN counted as one value).
#[test]
fn same_bits_on_every_target() {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    // A NaN's payload is not a result (targets differ in the default NaN): hash one NaN.
    let mut mix = |value: f64| {
        let value = if value.is_nan() { f64::NAN } else { value };
        for byte in value.to_bits().to_le_bytes() {
            hash ^= u64::from(byte);
            hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    let mut stream = Stream(7);
    for _ in 0..100_000 {
        mix(exp(stream.uniform(-745.0, 709.0)));
        mix(ln(f64::from_bits(stream.next() >> 1)));
        mix(pow(stream.uniform(0.0, 20.0), stream.uniform(-30.0, 30.0)));
    }
    // Recorded on x86_64 (debug and release); CI checks aarch64 under qemu against it.
    assert_eq!(
        hash, 0xbdb2_eb5d_ff67_ba11,
        "math results hash {hash:#018x}"
    );
}
