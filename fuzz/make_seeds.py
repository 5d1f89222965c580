#!/usr/bin/env python3
"""Write the small committed seed corpus of every fuzz target (deterministic).

The harness (src/source.rs) reads a regime byte, then per value a mode byte and eight bytes;
input that runs out reads as zeros. So:
  minimum      one zero byte: every value at the minimum of its domain, one step;
  maximum      0x00 then 0x01...: every value at the maximum of its domain, every flag set;
  midpoint     0x00 then 0x02...: midpoints (linear) and a fixed fraction (log), three steps;
  random-N     a regime byte below 192 (everything in domain), then pseudo-random bytes;
  chaos        a regime byte of 0xf0 (values may leave their domain), then pseudo-random bytes.
abi_batch reads a mode byte after the regime byte (3 mod 4: stoss_lsdyna_umat, else
stoss_update_batch); its umat-* seeds are the same five kinds with that byte set to 3.
update_lanes: a family byte, then eight random in-domain cases of equal length.
Usage: python3 fuzz/make_seeds.py (rewrites fuzz/corpus/<target>/seed-*).
"""
import os
import random

TARGETS = ["strength_update_jc", "strength_update_za", "strength_update_mjc",
           "strength_update_tjc", "eos", "rht_update", "abi_batch", "kc_update",
           "strength_update_ptw", "strength_update_khl", "strength_update_vk",
           "strength_update_mts"]

here = os.path.dirname(os.path.abspath(__file__))
for index, target in enumerate(TARGETS):
    rng = random.Random(20240 + index)
    seeds = {
        "minimum": bytes([0]),
        "maximum": bytes([0]) + bytes([1]) * 640,
        "midpoint": bytes([0]) + bytes([2]) * 640,
        "chaos": bytes([0xF0]) + bytes(rng.getrandbits(8) for _ in range(700)),
    }
    for n in range(3):
        length = rng.randrange(300, 1000)
        seeds[f"random-{n}"] = bytes([rng.randrange(0, 192)]) + bytes(
            rng.getrandbits(8) for _ in range(length))
    if target == "abi_batch":
        for name, data in list(seeds.items()):
            seeds[f"umat-{name}"] = data[:1] + bytes([3]) + data[2:]
    directory = os.path.join(here, "corpus", target)
    os.makedirs(directory, exist_ok=True)
    for name, data in seeds.items():
        with open(os.path.join(directory, f"seed-{name}"), "wb") as f:
            f.write(data)

# update_lanes: a family byte (0 JC, 1 MJC, 2 TJC, 3 ZA), then eight equal parts, each a
# strength case (lane states and steps differ; the first part's material is every lane's).
rng = random.Random(20299)
directory = os.path.join(here, "corpus", "update_lanes")
os.makedirs(directory, exist_ok=True)
for family in range(4):
    for n in range(2):
        parts = [bytes([rng.randrange(0, 192)]) + bytes(rng.getrandbits(8) for _ in range(399))
                 for _ in range(8)]
        with open(os.path.join(directory, f"seed-family{family}-{n}"), "wb") as f:
            f.write(bytes([family]) + b"".join(parts))
