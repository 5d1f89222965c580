#!/usr/bin/env python3
"""A 50-digit oracle for stoss's `exp`, `ln` and `pow` (kernel/src/math).

Draws arguments (seeded, so every run draws the same), evaluates them with mpmath at 200 bits,
and either

  * writes a fixture for `kernel/tests/math.rs` (the CI check):

        python3 kernel/tools/math_oracle.py write --count 2000 > kernel/tests/data/math_oracle.txt

    one line per call, `<function> <x bits> [<y bits>] <correctly rounded bits> <rest>`, where
    `rest = (exact - rounded) / ulp` (between -0.5 and 0.5); or

  * measures the error of the kernel's functions over many arguments (the validation run
    reported in docs/benchmarks.md):

        cargo build --release -p stoss-kernel --example math_values
        python3 kernel/tools/math_oracle.py check --count 1000000 target/release/examples/math_values

    which prints, per function and argument family, the largest error in ulps and where.

Needs `mpmath` (pip install mpmath).
"""
import argparse
import math
import random
import struct
import subprocess
import sys

import mpmath
from mpmath import mp, mpf

mp.prec = 200


def bits(x):
    return struct.unpack("<Q", struct.pack("<d", x))[0]


def from_bits(b):
    return struct.unpack("<d", struct.pack("<Q", b))[0]


def log_uniform(rng, lo_exp, hi_exp):
    """A double with a uniform exponent in [lo_exp, hi_exp) and a uniform mantissa."""
    e = rng.randrange(lo_exp, hi_exp)
    return math.ldexp(1.0 + rng.random(), e)


# Argument families: (function, family name, sampler). The kernel's own calls are the
# families marked "kernel": plastic strains to the power of hardening exponents, homologous
# temperatures to thermal exponents, rate ratios, Voce decays, RHT and JWL terms.
def families():
    return [
        ("exp", "wide [-708, 709]", lambda r: (r.uniform(-708.0, 709.0),)),
        ("exp", "kernel [-50, 5]", lambda r: (r.uniform(-50.0, 5.0),)),
        ("exp", "subnormal results [-745, -708]", lambda r: (r.uniform(-745.0, -708.4),)),
        ("exp", "small [-2^-10, 2^-10]", lambda r: (r.uniform(-1.0, 1.0) * 2.0**-10,)),
        ("ln", "wide 2^[-1022, 1023]", lambda r: (log_uniform(r, -1022, 1023),)),
        ("ln", "near 1 (1 +- 0.3)", lambda r: (1.0 + r.uniform(-0.3, 0.3),)),
        ("ln", "very near 1 (1 +- 2^-[1, 52])",
         lambda r: (1.0 + r.choice((-1.0, 1.0)) * math.ldexp(1.0 + r.random(), -r.randrange(1, 52)),)),
        ("ln", "kernel rate ratios 1..1e9", lambda r: (10.0 ** r.uniform(0.0, 9.0),)),
        ("pow", "kernel x in 1e-8..10, y in 0..2",
         lambda r: (10.0 ** r.uniform(-8.0, 1.0), r.uniform(0.0, 2.0))),
        ("pow", "wide x 2^[-60, 60], y in -8..8",
         lambda r: (log_uniform(r, -60, 60), r.uniform(-8.0, 8.0))),
        ("pow", "x near 1, large y",
         lambda r: near_one_large_y(r)),
    ]


def near_one_large_y(r):
    x = 1.0 + r.choice((-1.0, 1.0)) * math.ldexp(1.0 + r.random(), -r.randrange(4, 40))
    limit = 700.0 / abs(math.log(x))
    return (x, r.uniform(-limit, limit))


def exact(function, args):
    if function == "exp":
        return mpmath.exp(mpf(args[0]))
    if function == "ln":
        return mpmath.log(mpf(args[0]))
    return mpmath.power(mpf(args[0]), mpf(args[1]))


def ulp_of(value):
    """ulp of the double nearest to `value` (2^-1074 in the subnormal range)."""
    m, e = mpmath.frexp(value)  # value = m 2^e, 0.5 <= |m| < 1
    return mpf(2) ** max(int(e) - 53, -1074)


def draw(count, seed):
    rng = random.Random(seed)
    calls = []
    fams = families()
    per_family = max(1, count // len(fams))
    for function, name, sampler in fams:
        for _ in range(per_family):
            calls.append((function, name, sampler(rng)))
    return calls


def call_line(function, args):
    return " ".join([function] + [f"{bits(a):016x}" for a in args])


def write(count, seed):
    for function, _, args in draw(count, seed):
        value = exact(function, args)
        rounded = float(value)  # mpmath rounds to nearest
        rest = (value - mpf(rounded)) / ulp_of(mpf(rounded)) if rounded != 0.0 else mpf(0)
        print(f"{call_line(function, args)} {bits(rounded):016x} {float(rest):+.6f}")


def check(count, seed, binary):
    calls = draw(count, seed)
    feed = "\n".join(call_line(f, a) for f, _, a in calls) + "\n"
    result = subprocess.run([binary], input=feed, capture_output=True, text=True, check=True)
    values = [from_bits(int(w, 16)) for w in result.stdout.split()]
    assert len(values) == len(calls)
    worst = {}
    for (function, name, args), ours in zip(calls, values):
        value = exact(function, args)
        if not math.isfinite(ours) or value == 0:
            continue
        error = float(abs(mpf(ours) - value) / ulp_of(value))
        key = (function, name)
        seen = worst.get(key, (0.0, None, 0))
        worst[key] = (max(seen[0], error), args if error >= seen[0] else seen[1], seen[2] + 1)
    print(f"{'function':<5} {'arguments':<36} {'calls':>8} {'max error (ulp)':>16}  worst at")
    for (function, name), (error, args, n) in worst.items():
        where = ", ".join(repr(a) for a in args)
        print(f"{function:<5} {name:<36} {n:>8} {error:>16.4f}  {where}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("mode", choices=["write", "check"])
    parser.add_argument("binary", nargs="?", help="math_values example (check mode)")
    parser.add_argument("--count", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=2026)
    options = parser.parse_intermixed_args()
    if options.mode == "write":
        write(options.count, options.seed)
    else:
        if not options.binary:
            sys.exit("check needs the path of the math_values example")
        check(options.count, options.seed, options.binary)


if __name__ == "__main__":
    main()
