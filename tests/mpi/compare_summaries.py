#!/usr/bin/env python3
"""Compares two summary.json files of the same case: same unknowns, same
solution quantities to solver tolerance (one Stokes solve: velocity,
pressure jumps; a time run: each object's final shape and volume). Exit 1
(and say what) if not."""
import json
import sys

RELATIVE_TOLERANCE = 1e-7


def close(a, b):
    return abs(a - b) <= RELATIVE_TOLERANCE * max(1.0, abs(a), abs(b))


def main(serial_path, parallel_path):
    serial = json.load(open(serial_path))
    parallel = json.load(open(parallel_path))
    failures = []
    if serial["unknowns"] != parallel["unknowns"]:
        failures.append(f"unknowns {serial['unknowns']} vs {parallel['unknowns']}")
    if parallel["mpi_ranks"] != 2:
        failures.append(f"parallel run used {parallel['mpi_ranks']} ranks")
    if "final" in serial:  # a time run: every object's shape and position at the end
        if serial["steps"] != parallel["steps"]:
            failures.append(f"steps {serial['steps']} vs {parallel['steps']}")
        pairs = []
        for s, p in zip(serial["final"], parallel["final"], strict=True):
            for key in ("D", "theta_deg", "L", "B", "W", "volume"):
                pairs.append((f"object {s['object']} {key}", s[key], p[key]))
    else:
        pairs = [("max_velocity", serial["max_velocity"], parallel["max_velocity"])]
    for s, p in zip(serial.get("objects", []), parallel.get("objects", [])):
        pairs.append(("pressure_jump", s["pressure_jump"], p["pressure_jump"]))
        for k in range(3):
            pairs.append((f"mean_interface_velocity[{k}]", s["mean_interface_velocity"][k],
                          p["mean_interface_velocity"][k]))
    for name, a, b in pairs:
        status = "ok" if close(a, b) else "DIFFERS"
        print(f"{name:28s} serial {a:+.12e}  2 ranks {b:+.12e}  {status}")
        if not close(a, b):
            failures.append(name)
    if failures:
        print("mismatch:", ", ".join(failures))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
