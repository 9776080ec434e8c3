#!/usr/bin/python3
"""Cost of a viscoelastic time step against a Newtonian one on the same mesh
(issue 9 target: at most twice); see step_cost.py for the set-up:
  newtonian   a Newtonian drop, lambda = 1, Ca = 0.1 (no conformation)
  particle    a neo-Hookean particle, Ca_e = 0.1 (conformation in the object)
  ob_matrix   a Newtonian drop in an Oldroyd-B matrix (conformation in the
              matrix: the whole mesh but the drop carries it)
Writes docs/benchmarks/viscoelastic_step.{md,json}.

Usage: bench/run_viscoelastic_bench.py [build_dir] [--repeats N] [--work DIR]"""
from step_cost import compare_main

CASES = {
    "newtonian": ("", "viscosity_ratio = 1.0\ncapillary_number = 0.1\n"),
    "particle": ("", 'model = "neo_hookean"\nelastic_capillary_number = 0.1\n'),
    "ob_matrix": ('[matrix]\nmodel = "oldroyd_b"\nsolvent_viscosity = 0.5\npolymer_viscosity = 0.5\n'
                  "relaxation_time = 0.5\n", "viscosity_ratio = 1.0\ncapillary_number = 0.1\n"),
}


def main():
    compare_main(CASES, "bench_viscoelastic",
                 "Cost of a viscoelastic step (issue 9)",
                 "run_viscoelastic_bench.py", "viscoelastic_step")


if __name__ == "__main__":
    main()
