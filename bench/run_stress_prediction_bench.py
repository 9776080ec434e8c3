#!/usr/bin/python3
"""Cost of a time step with the consistent predicted stress against the Euler
one ([conformation] stress_prediction; docs/viscoelastic.md, "The predicted
stress and the transported one"); see step_cost.py for the set-up:
  ob_matrix_*  a Newtonian drop in an Oldroyd-B matrix (conformation in the
               whole mesh but the drop)
  particle_*   a neo-Hookean particle, Ca_e = 0.1 (conformation in the object)
The consistent prediction adds, per step, c_{n-1} node by node, the
prediction at every quadrature point of the phases with a conformation after
the solve and the defect there; its time is in the `conformation` stage.
Writes docs/benchmarks/stress_prediction_step.{md,json}.

Usage: bench/run_stress_prediction_bench.py [build_dir] [--repeats N] [--work DIR]"""
from step_cost import compare_main

OB = ('[matrix]\nmodel = "oldroyd_b"\nsolvent_viscosity = 0.5\npolymer_viscosity = 0.5\n'
      "relaxation_time = 0.5\n")
DROP = "viscosity_ratio = 1.0\ncapillary_number = 0.1\n"
PARTICLE = 'model = "neo_hookean"\nelastic_capillary_number = 0.1\n'


def with_prediction(obj, prediction):
    # The object's keys end its table; [conformation] opens the next one.
    return obj + f'[conformation]\nstress_prediction = "{prediction}"\n'


CASES = {
    "ob_matrix_euler": (OB, with_prediction(DROP, "euler")),
    "ob_matrix_consistent": (OB, with_prediction(DROP, "consistent")),
    "particle_euler": ("", with_prediction(PARTICLE, "euler")),
    "particle_consistent": ("", with_prediction(PARTICLE, "consistent")),
}


def main():
    compare_main(CASES, "bench_stress_prediction",
                 "Cost of a step: the consistent predicted stress against the Euler one",
                 "run_stress_prediction_bench.py", "stress_prediction_step")


if __name__ == "__main__":
    main()
