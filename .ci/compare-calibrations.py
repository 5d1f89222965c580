#!/usr/bin/env python3
"""Compare two stoss calibration folders bit for bit: the simulation logs (every candidate's
constants, scores and status, in key order; wall times and origins left out, as they say where
and how fast, not what) and the selected constants of report/result.json.

Usage: compare-calibrations.py RUN_A RUN_B   (exit 0 if identical, 1 with the differences)
"""
import json
import sys
from pathlib import Path


def log_of(folder):
    entries = {}
    for number, line in enumerate((Path(folder) / "simulations.jsonl").read_text().splitlines(), 1):
        entry = json.loads(line)
        key = json.dumps(entry["key"], sort_keys=True)
        entry.pop("origin", None)
        entry["evaluation"].pop("wall_time", None)
        entries[key] = entry
    return entries


def without_wall_times(value):
    if isinstance(value, dict):
        return {k: without_wall_times(v) for k, v in value.items() if k != "wall_time"}
    if isinstance(value, list):
        return [without_wall_times(v) for v in value]
    return value


def result_of(folder):
    return without_wall_times(json.loads((Path(folder) / "report" / "result.json").read_text()))


def main():
    a, b = sys.argv[1], sys.argv[2]
    log_a, log_b = log_of(a), log_of(b)
    differences = []
    for key in sorted(set(log_a) | set(log_b)):
        if log_a.get(key) != log_b.get(key):
            differences.append(f"candidate {key}:\n  {log_a.get(key)}\n  {log_b.get(key)}")
    if differences:
        print(f"{len(differences)} of {len(set(log_a) | set(log_b))} logged candidates differ:")
        print("\n".join(differences[:5]))
        return 1
    if result_of(a) != result_of(b):
        print("the logs agree but report/result.json differs (selection, finalists or histories)")
        return 1
    print(f"identical: {len(log_a)} logged candidates (constants, scores, status) and the "
          "selected constants, finalists and histories of report/result.json")
    return 0


if __name__ == "__main__":
    sys.exit(main())
