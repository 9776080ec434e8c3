#!/usr/bin/python3
"""The quasi-steady Giesekus trajectory of giesekus_quasi_steady_trajectory.py
on the resolved setting: the resolution half of issue 35's 4-hour target ("with
the mesh that the convergence study says is needed for v_p to 10 %").

The convergence study at one start (delta_s_resolution.py, beta = 0.2 at
0.25 y_p,max): v_p moves -28 % from 20 to 28 equator nodes and +1.2 % from 28
to 40, so 28 nodes. Near the centre plane gmsh's meshes bias v_p by ~3e-4
gamma_dot H of either sign (giesekus_neutral_height.py's symmetric starts),
more than the signal there: the starts below 0.20 H are meshed point-symmetric
and carried to their height (`mesh.point_symmetric_start`, no remeshing; the
carry to 0.20 H inverts an element on this mesh, to 0.15 H the carried mesh's
quality is 0.159). The rest is the 20-node trajectory's case: beta = 0.2,
Ca_e = 0.1 (p = 4.5), Wi = 0.5, alpha_m = 0.2, step-limited SUPG parameter,
dt = 0.04, each start to t = 6, the curve from t >= 2 in stretches of 2.

Writes docs/validation/giesekus_quasi_steady_resolved.{md,csv,png}.
Usage: scripts/validation/giesekus_quasi_steady_resolved.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import dataclasses
import os

import giesekus_quasi_steady_trajectory as coarse
from case_runs import validation_main

NODES = 28
SYMMETRIC_BELOW = 0.20  # y_p0 / H: starts below it are carried from the point-symmetric mesh
STARTS = (0.35, 0.10, 0.20, 0.15, 0.28, 0.24, 0.32)  # y_p0 / H, in the order they run
LEVEL = coarse.Level(nodes=NODES, starts=STARTS, symmetric_below=SYMMETRIC_BELOW, shared=(),
                     stem="giesekus_quasi_steady_resolved")
# The seam: v_p jumps between the symmetric 0.15 H start and gmsh's 0.20 H one.
# The carry to 0.20 H takes two steps (it inverted an element in one), so the
# 0.20 H start from the symmetric mesh tells whether the jump is gmsh's mesh's.
SEAM = coarse.Level(nodes=NODES, starts=(0.20,), symmetric_below=0.21, shared=(), stem=LEVEL.stem)


def jobs():
    return LEVEL.jobs() + SEAM.jobs()


def seam_lines(work):
    """The symmetric 0.20 H start beside gmsh's, once both have run."""
    seam = coarse.finished_starts(work, SEAM)
    gmsh = coarse.finished_starts(work, dataclasses.replace(LEVEL, starts=SEAM.starts))
    if not seam or not gmsh:
        return []
    s, g = seam[0], gmsh[0]
    return ["", f"The seam at 0.20 H: from the point-symmetric mesh (carried in steps) v_p = {s['v_p']:.4e}, "
            f"on gmsh's mesh {g['v_p']:.4e} ({s['wall_seconds']:.0f} s; not in the curve above)."]


def report(work, build):
    # The 20-node curve's runs: in giesekus_quasi_steady_trajectory.py's work directory beside this one.
    coarse_work = os.path.join(os.path.dirname(os.path.abspath(work)), "giesekus_quasi_steady_trajectory")
    coarse.report(work, build, LEVEL, reference=(coarse.COARSE, coarse_work), extra=seam_lines(work))


if __name__ == "__main__":
    validation_main("giesekus_quasi_steady_resolved", jobs, report)
