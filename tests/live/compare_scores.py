#!/usr/bin/env python3
"""Compares two `roam-eval --format csv` outputs estimator by estimator.

    compare_scores.py REPLAY_CSV RECORDED_CSV TOLERANCE_M

Exit 0 iff the same estimators appear in both files (the `odometry` baseline row is ignored,
present or not, and so is the `run` column) and every estimator's full_mean_m differs by at most
TOLERANCE_M; a line per estimator says what was compared. Exit 1 on a difference or a missing
estimator, 2 on a usage or file error. Python standard library only.
"""
import csv
import math
import sys

IGNORED = {"odometry"}  # roam-eval's own dead-reckoning baseline row


def read_means(path):
    """estimator -> list of full_mean_m (float, NaN when empty), in file order."""
    means = {}
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        missing = {"estimator", "full_mean_m"} - set(reader.fieldnames or [])
        if missing:
            raise ValueError(f"{path}: not a roam-eval CSV (no column {', '.join(sorted(missing))})")
        for row in reader:
            name = row["estimator"]
            if name in IGNORED:
                continue
            text = (row["full_mean_m"] or "").strip()
            means.setdefault(name, []).append(float(text) if text else math.nan)
    return means


def main(argv):
    if len(argv) != 4:
        print("usage: compare_scores.py REPLAY_CSV RECORDED_CSV TOLERANCE_M", file=sys.stderr)
        return 2
    try:
        tolerance = float(argv[3])
        if not tolerance >= 0:
            raise ValueError(f"TOLERANCE_M: expected a number >= 0, got {argv[3]!r}")
        replay, recorded = read_means(argv[1]), read_means(argv[2])
    except (OSError, ValueError) as e:
        print(f"compare_scores: error: {e}", file=sys.stderr)
        return 2

    ok = True
    if not replay and not recorded:
        print("compare_scores: FAIL: no estimator rows in either file")
        return 1
    for name in sorted(set(replay) | set(recorded)):
        if name not in recorded:
            print(f"compare_scores: {name}: FAIL: missing from {argv[2]}")
            ok = False
            continue
        if name not in replay:
            print(f"compare_scores: {name}: FAIL: missing from {argv[1]}")
            ok = False
            continue
        a, b = replay[name], recorded[name]
        if len(a) != len(b):
            print(f"compare_scores: {name}: FAIL: {len(a)} row(s) in the replay, {len(b)} recorded")
            ok = False
            continue
        for x, y in zip(a, b):
            if math.isnan(x) and math.isnan(y):
                print(f"compare_scores: {name}: ok: no matched poses in either")
                continue
            diff = abs(x - y)  # NaN when only one side has a score: fails below
            good = diff <= tolerance
            ok = ok and good
            print(f"compare_scores: {name}: {'ok' if good else 'FAIL'}: mean error {x:.6f} m (replay) vs "
                  f"{y:.6f} m (recorded), difference {diff:.6f} m, tolerance {tolerance:g} m")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
