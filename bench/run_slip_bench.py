#!/usr/bin/python3
"""Cost of a time step with interfacial slip against a no-slip one on the same
mesh (issue 10 target: at most 1.5 times); see step_cost.py for the set-up:
  no_slip     a Newtonian drop, lambda = 1, Ca = 0.1
  slip_0.1    the same drop with slip alpha = 0.1 (velocity copies and
              multipliers at the interface)
  slip_1      alpha = 1
Writes docs/benchmarks/slip_step.{md,json}.

Usage: bench/run_slip_bench.py [build_dir] [--repeats N] [--work DIR]"""
from step_cost import compare_main

DROP = "viscosity_ratio = 1.0\ncapillary_number = 0.1\n"
CASES = {
    "no_slip": ("", DROP),
    "slip_0.1": ("", DROP + "slip = 0.1\n"),
    "slip_1": ("", DROP + "slip = 1.0\n"),
}


def main():
    compare_main(CASES, "bench_slip",
                 "Cost of a step with interfacial slip (issue 10)",
                 "run_slip_bench.py", "slip_step")


if __name__ == "__main__":
    main()
