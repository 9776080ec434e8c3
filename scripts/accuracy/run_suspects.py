#!/usr/bin/env python3
"""Regenerates the tables of docs/accuracy.md (issue 13, part 1).

    python3 scripts/accuracy/run_suspects.py [--build build] [--out docs/accuracy]

Runs the standalone programs of examples/accuracy/ (built with the project's
CMake, targets ellipsoid_fit_sampling and sphere_tension) and stores their
tables as text files next to docs/accuracy.md.
"""
import argparse
import pathlib
import subprocess
import sys

PROGRAMS = ["ellipsoid_fit_sampling", "sphere_tension"]


def main() -> int:
    root = pathlib.Path(__file__).resolve().parents[2]
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=str(root / "build"))
    ap.add_argument("--out", default=str(root / "docs" / "accuracy"))
    ap.add_argument("--nodes", nargs="*", default=["16", "24", "32", "48", "64"],
                    help="equator_nodes values")
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for prog in PROGRAMS:
        exe = pathlib.Path(args.build) / "examples" / "accuracy" / prog
        if not exe.exists():
            print(f"missing {exe}: build the target {prog} first", file=sys.stderr)
            return 1
        res = subprocess.run([str(exe), *args.nodes], capture_output=True, text=True, check=True)
        (out / f"{prog}.txt").write_text(res.stdout)
        print(res.stdout)
    # The sphere at the resolutions of issue 13 (28/40/50/60).
    exe = pathlib.Path(args.build) / "examples" / "accuracy" / "sphere_tension"
    res = subprocess.run([str(exe), "28", "40", "50", "60"], capture_output=True, text=True, check=True)
    (out / "sphere_tension_issue_n.txt").write_text(res.stdout)
    print(res.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(main())
