#!/usr/bin/env python3
"""Compares a timeseries.csv with a stored reference, column by column.
Usage: compare_timeseries.py RESULT.csv REFERENCE.csv
Every physical column must match to a mixed tolerance |a - b| <= atol + rtol |b|;
timing and iteration columns are not compared. Prints the worst difference per column."""
import csv
import math
import sys

TOLERANCES = {  # column: (atol, rtol)
    "t": (1e-12, 0.0),
    "D": (2e-6, 1e-5),
    "theta_deg": (2e-4, 1e-5),
    "L": (2e-6, 1e-5), "B": (2e-6, 1e-5), "W": (2e-6, 1e-5),
    "xc": (2e-6, 0.0), "yc": (2e-6, 0.0), "zc": (2e-6, 0.0),
    "uc": (2e-5, 0.0), "vc": (2e-5, 0.0), "wc": (2e-5, 0.0),
    "volume": (1e-7, 1e-6), "area": (1e-7, 1e-6),
    "ellipsoid_dev": (1e-6, 1e-4),
    "min_quality": (1e-6, 1e-5),
}


def main(result_path, reference_path):
    result = list(csv.DictReader(open(result_path)))
    reference = list(csv.DictReader(open(reference_path)))
    if len(result) != len(reference):
        print(f"rows: {len(result)} vs reference {len(reference)}")
        return 1
    failed = False
    for column, (atol, rtol) in TOLERANCES.items():
        worst = 0.0
        for r, ref in zip(result, reference):
            a, b = float(r[column]), float(ref[column])
            if math.isnan(a) or math.isnan(b):  # undefined (theta of a sphere): both or neither
                if math.isnan(a) != math.isnan(b):
                    failed = True
                    print(f"{column}: step {r['step']}: {a!r} vs reference {b!r}")
                    break
                continue
            excess = abs(a - b) - (atol + rtol * abs(b))
            worst = max(worst, abs(a - b))
            if excess > 0:
                failed = True
                print(f"{column}: step {r['step']}: {a!r} vs reference {b!r}")
                break
        print(f"{column:14s} max |difference| {worst:.2e}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
