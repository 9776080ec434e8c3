#!/usr/bin/python3
"""Which SUPG parameter does the Giesekus migration near the centre plane
converge with? At 0.20 H the two parameters of the matrix's stress transport
meet on 28 equator nodes (giesekus_migration_supg.py: -4.05e-4 steady,
-3.86e-4 step-limited, where on 20 nodes they differ ten-fold), and the
step-limited one moves only 10 % from 20 to 28 nodes. At 0.10 H, carried from
the point-symmetric mesh so that gmsh's mesh bias does not enter, the two
parameters were last measured on different levels: the step-limited one on
20 nodes (+3.1e-6) and the steady one on 28 (-2.41e-4, giesekus_neutral_height.py),
and giesekus_quasi_steady_resolved.py's 28-node start with the step-limited
one gives -1.7e-5: on 28 nodes the two differ by more than the signal.

`supg_tau = "steady"` is steady in the particle too, whose shape then
does not converge as dt -> 0 (docs/case_file_keys.md); `"auto"` keeps the
steady one in the matrix and the step-limited one in the particle. The
three settings tell the matrix's part from the particle's: auto beside
steady is the particle's stabilisation, auto beside transient the matrix's.

This script completes the table, the three settings on both levels, from the
same start (beta = 0.2, Ca_e = 0.1 so p = 4.5, Wi = 0.5, alpha_m = 0.2,
y_p0 = 0.10 H, dt = 0.04, t = 6, no remeshing). The 28-node step-limited run
is giesekus_quasi_steady_resolved.py's (linked from its work directory). If
one parameter holds still from 20 to 28 nodes and the other moves towards it,
the first is the resolved answer at this height.

The carried start turned out biased itself (giesekus_quasi_steady_resolved.md:
at 0.10 H gmsh's meshes of the start and of its mirror start add only
+3.1e-5 together, and their mirror-averaged v_p is -1.18e-4 against the
carried start's -1.7e-5, both step-limited). So the 28-node matrix's part
is measured once more on gmsh's meshes: `auto` at +-0.10 H, mirror-averaged,
beside giesekus_quasi_steady_resolved.py's step-limited pair.
Writes docs/validation/giesekus_near_centre_supg.{md,csv}.
Usage: scripts/validation/giesekus_near_centre_supg.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import os

import giesekus_neutral_height as neutral_height
import giesekus_quasi_steady_resolved as resolved
from case_runs import ROOT, run_case, run_linked, validation_main, write_csv
from giesekus_trajectory_time_step import TRANSIENT, T_END
from migration_runs import completed_run, mean_velocity, mirror_parts, window_velocities

OUT = os.path.join(ROOT, "docs", "validation")
CA_E, START = 0.1, 0.10
HEIGHT = neutral_height.HEIGHT
LEVELS = (20, 28)
TAUS = ("transient", "steady", "auto")  # in the particle: step-limited, steady, step-limited
SETTING = {"transient": "transient (step-limited in both)", "steady": "steady (in both)",
           "auto": "auto (matrix steady, particle step-limited)"}
UNITS = [(float(a), float(a + 1)) for a in range(int(T_END))]
RESOLVED_WORK = "giesekus_quasi_steady_resolved"  # its work directory's name (and data/runs/'s)


def run_name(nodes, tau):
    return f"N{nodes}_{tau}"


def case_text(nodes, tau):
    base = neutral_height.text(CA_E, START, nodes, tau, symmetric=True)
    old_name = f'name = "{neutral_height.run_name(CA_E, START, nodes, symmetric=True)}"'
    assert base.count(old_name) == 1, "giesekus_neutral_height's case changed"
    return base.replace(old_name, f'name = "{run_name(nodes, tau)}"')


def shared(nodes, tau):
    """The resolved trajectory's own start: the same case under its name there."""
    return nodes == resolved.NODES and tau == "transient"


# The gmsh pair: (start, its mirror) on 28 nodes with `auto`, remeshing as the curve's gmsh starts.
GMSH_NODES, GMSH_TAU, GMSH_STARTS = resolved.NODES, "auto", (START, -START)


def gmsh_run_name(start):
    return f"N{GMSH_NODES}_{GMSH_TAU}_gmsh_yp0_{start:.2f}"


def gmsh_case_text(start):
    base = neutral_height.text(CA_E, start, GMSH_NODES, GMSH_TAU)
    old_name = f'name = "{neutral_height.run_name(CA_E, start, GMSH_NODES)}"'
    assert base.count(old_name) == 1, "giesekus_neutral_height's case changed"
    return base.replace(old_name, f'name = "{gmsh_run_name(start)}"')


def jobs():
    # The coarse level first, the settings never run before first.
    def order(n):  # on 28 nodes the steady one last: it stabilises the particle as no setting should
        return ("steady", "auto", "transient") if n == LEVELS[0] else ("transient", "auto", "steady")
    return ([(run_name(n, tau), case_text(n, tau)) for n in LEVELS for tau in order(n)]
            + [(gmsh_run_name(s), gmsh_case_text(s)) for s in GMSH_STARTS])


def runner(build, work, name, text):
    if any(name == gmsh_run_name(s) for s in GMSH_STARTS):
        return run_case(build, work, name, text)
    nodes, tau = next((n, t) for n in LEVELS for t in TAUS if run_name(n, t) == name)
    if not shared(nodes, tau):
        return run_case(build, work, name, text)
    theirs = resolved.LEVEL.name(START)
    assert resolved.LEVEL.case_text(START) == text.replace(f'name = "{name}"', f'name = "{theirs}"'), \
        "giesekus_quasi_steady_resolved.py's 0.10 H start is no longer this case"
    return run_linked(build, work, RESOLVED_WORK, name, resolved.LEVEL.case_text(START), other_name=theirs)


def gmsh_pair_lines(work):
    """The start and its mirror on gmsh's 28-node meshes, step-limited (the resolved curve's) and auto."""
    resolved_work = os.path.join(os.path.dirname(os.path.abspath(work)), RESOLVED_WORK)
    pairs = {"transient": [os.path.join(resolved_work, resolved.GMSH_LOW.name(START)),
                           os.path.join(resolved_work, resolved.MIRROR.name(-START))],
             GMSH_TAU: [os.path.join(work, gmsh_run_name(s)) for s in GMSH_STARTS]}
    rows = {}
    for tau, directories in pairs.items():
        runs = [completed_run(d, HEIGHT, T_END) for d in directories]
        if all(runs):
            up, down = (mean_velocity(r, TRANSIENT) for r, _ in runs)
            rows[tau] = (up, down, *mirror_parts(up, down))
    if not rows:
        return []
    lines = ["", f"On gmsh's own {GMSH_NODES}-node meshes instead of the carried one: the 0.10 H start and its mirror "
             "start (-0.10 H), remeshing; the flow is point-symmetric, so the mirror-averaged v_p, "
             "(v_p(y) - v_p(-y)) / 2, is free of what the two meshes add, their mean. The step-limited pair is "
             "giesekus_quasi_steady_resolved.py's.", "",
             "| SUPG parameter | v_p(0.10 H) | v_p(-0.10 H) | mirror-averaged v_p | meshes' part |", "|---|---|---|---|---|"]
    for tau, (up, down, averaged, meshes) in rows.items():
        lines.append(f"| {SETTING[tau]} | {up:.3e} | {down:.3e} | {averaged:.3e} | {meshes:+.2e} |")
    if len(rows) == 2:
        lines += ["", f"- {GMSH_NODES} nodes, gmsh's meshes, mirror-averaged: the matrix's part (auto - transient) "
                  f"{rows[GMSH_TAU][2] - rows['transient'][2]:+.2e}"]
    return lines


def report(work):
    rows = []
    for nodes in LEVELS:
        for tau in TAUS:
            directory = os.path.join(work, run_name(nodes, tau))
            if shared(nodes, tau) and not os.path.exists(directory):  # not linked yet: read it where it is
                directory = os.path.join(os.path.dirname(os.path.abspath(work)), RESOLVED_WORK,
                                         resolved.LEVEL.name(START))
            run = completed_run(directory, HEIGHT, T_END)
            if not run:
                continue
            r, summary = run
            rows.append({"equator_nodes": nodes, "supg_tau": tau, "unknowns": summary["unknowns"],
                         "v_p_t2_6": mean_velocity(r, TRANSIENT),
                         **{f"v_p_t{a:g}_{b:g}": v for (a, b), v in zip(UNITS, window_velocities(r, UNITS))},
                         "wall_seconds": summary["wall_seconds"]})
    if not rows:
        print("no run finished")
        return
    write_csv(os.path.join(OUT, "giesekus_near_centre_supg.csv"), list(rows[0]), rows)
    lines = ["# The SUPG parameter near the centre plane (Giesekus migration, 0.10 H)", "",
             "Generated by `scripts/validation/giesekus_near_centre_supg.py`: beta = 0.2, Ca_e = 0.1 (p = 4.5), "
             "Wi = 0.5, alpha_m = 0.2, y_p0 = 0.10 H carried from the point-symmetric mesh (no remeshing), "
             "dt = 0.04, t = 6. v_p in gamma_dot H (negative: towards the centre plane); eq. 3.8 (Newtonian) "
             "there: -3.95e-4.", "",
             "| equator nodes | SUPG parameter | unknowns | v_p, t = 2-6 | v_p each unit of t = 0-6 | wall [s] |",
             "|---|---|---|---|---|---|"]
    for x in rows:
        units = ", ".join(f"{x[f'v_p_t{a:g}_{b:g}']:+.1e}" for a, b in UNITS)
        lines.append(f"| {x['equator_nodes']} | {SETTING[x['supg_tau']]} | {x['unknowns']} | {x['v_p_t2_6']:.3e} | {units} | "
                     f"{x['wall_seconds']:.0f} |")
    lines += ["", "The parts of v_p (t = 2-6) that the stabilisation sets, where a level has the runs:", ""]
    by = {(x["equator_nodes"], x["supg_tau"]): x["v_p_t2_6"] for x in rows}
    for nodes in LEVELS:
        parts = []
        if (nodes, "auto") in by and (nodes, "transient") in by:
            parts.append(f"the matrix's (auto - transient) {by[nodes, 'auto'] - by[nodes, 'transient']:+.2e}")
        if (nodes, "steady") in by and (nodes, "auto") in by:
            parts.append(f"the particle's (steady - auto) {by[nodes, 'steady'] - by[nodes, 'auto']:+.2e}")
        if parts:
            lines.append(f"- {nodes} nodes: " + "; ".join(parts))
    for tau in TAUS:
        if all((n, tau) in by for n in LEVELS):
            lines.append(f"- {tau}, {LEVELS[0]} -> {LEVELS[1]} nodes: {by[LEVELS[1], tau] - by[LEVELS[0], tau]:+.2e}")
    lines += gmsh_pair_lines(work)
    with open(os.path.join(OUT, "giesekus_near_centre_supg.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    validation_main("giesekus_near_centre_supg", jobs, report, runner=runner)
