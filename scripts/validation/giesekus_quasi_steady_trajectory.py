#!/usr/bin/python3
"""The Giesekus migration trajectory of issue 35's 4-hour target, quasi-steady:
`softflow migration --trajectory-from` along the master curve of short runs
from several heights, instead of one time-stepped run of hundreds of time units
(23 h at dt = 0.04, docs/benchmarks/migration_trajectory.md). The case is the
trajectory's (giesekus_trajectory_time_step.py's at dt = 0.04: beta = 0.2,
Ca_e = 0.1 so p = 4.5, Wi = 0.5, alpha_m = 0.2, 20 equator nodes, step-limited
SUPG parameter, remeshing), started at STARTS and run to t = 6; the curve drops
each run's first 2 time units and takes stretches of 2 (the protocol measured
against a time-stepped Newtonian trajectory in quasi_steady_trajectory.py:
1.1 % in time with starts 0.05 H apart, 3.9 % at 0.1 H).

The starts 0.10 and 0.28 H are giesekus_trajectory_time_step.py's runs (linked
from its work directory, restored from data/runs on a fresh clone); the others
run here. The trajectory starts at the 0.35 H run's first stretch. Reported: each
start's v_p and cost, the trajectory's length and end, and the cost of the curve
(the runs' wall times, each beside other work on the machine) against the
time-stepped projection.
Writes docs/validation/giesekus_quasi_steady_trajectory.{md,csv,png}.
Usage: scripts/validation/giesekus_quasi_steady_trajectory.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import os
import subprocess

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import giesekus_trajectory_time_step as step_study  # noqa: E402
from case_runs import ROOT, read_csv, run_case, summary_of, validation_main, write_csv  # noqa: E402
from migration_runs import mean_velocity, read_migration  # noqa: E402

OUT = os.path.join(ROOT, "docs", "validation")
DT = 0.04
STARTS = [0.35, 0.20, 0.15, 0.10, 0.28, 0.24, 0.32]  # y_p0 / H, in the order they run
SHARED = (0.10, 0.28)  # run by giesekus_trajectory_time_step.py
STEP_STUDY_WORK = "giesekus_trajectory_time_step"  # its work directory's name (and data/runs/'s)
TRANSIENT, STRETCH = 2.0, 2.0
HEIGHT = step_study.HEIGHT
Y_MAX_OVER_H = 0.4  # y_p,max / H = (1 - beta) / 2
TIME_STEPPED_HOURS = 23.3  # docs/benchmarks/migration_trajectory.md, p = 4.5, one rank


def name(start):
    return step_study.name(start, DT)


def jobs():
    return [(name(s), step_study.case_text(s, DT)) for s in STARTS]


def runner(build, work, run_name, text):
    """run_case, but the shared starts in the time-step study's work directory, linked here."""
    start = next(s for s in STARTS if name(s) == run_name)
    if start not in SHARED:
        return run_case(build, work, run_name, text)
    other = os.path.join(os.path.dirname(os.path.abspath(work)), STEP_STUDY_WORK)
    directory = run_case(build, other, run_name, text)
    link = os.path.join(work, run_name)
    os.makedirs(work, exist_ok=True)
    if not os.path.lexists(link):
        os.symlink(directory, link)
    return link


def report(work, build):
    done = []
    for s in sorted(STARTS):
        directory = os.path.join(work, name(s))
        summary = summary_of(directory)
        if summary.get("status") != "completed":
            continue
        r = read_migration(directory, HEIGHT)
        done.append({"start": s, "directory": directory, "v_p": mean_velocity(r, TRANSIENT),
                     "y_mean": sum(y for t, y in zip(r["t"], r["y"]) if t >= TRANSIENT) /
                     sum(1 for t in r["t"] if t >= TRANSIENT),
                     "wall_seconds": summary["wall_seconds"], "unknowns": summary["unknowns"],
                     "series": r})
    if len(done) < 2 or done[-1]["start"] != max(STARTS):
        print(f"{len(done)} starts finished; the trajectory needs the {max(STARTS):g} H start and one more")
        return
    top = done[-1]["series"]
    i = next(k for k, t in enumerate(top["t"]) if t >= TRANSIENT - 1e-9)
    j = next(k for k, t in enumerate(top["t"]) if t >= TRANSIENT + STRETCH - 1e-9)
    t0, y0 = 0.5 * (top["t"][i] + top["t"][j]), 0.5 * (top["y"][i] + top["y"][j])
    out = os.path.join(work, "curves")
    command = [os.path.abspath(os.path.join(build, "softflow")), "migration", *[d["directory"] for d in done],
               "--transient", f"{TRANSIENT:g}", "--segment", f"{STRETCH:g}",
               "--trajectory-from", f"{y0 / Y_MAX_OVER_H:.12g}", "-o", out]
    subprocess.run(command, check=True, env=dict(os.environ, SOFTFLOW_PLOTS="0"))
    path = read_csv(os.path.join(out, "migration_trajectory.csv"))
    ts = [t0 + float(r["t"]) for r in path]
    ys = [float(r["y_p_rel"]) * Y_MAX_OVER_H for r in path]
    md = open(os.path.join(out, "migration.md")).read()
    section = md.split("## Quasi-steady trajectory", 1)[1]
    ends = section.split("it ends ", 1)[1].split(" after t", 1)[0]
    neutral = md.split("## Neutral heights (v_p = 0)", 1)[1].split("##", 1)[0].strip()

    write_csv(os.path.join(OUT, "giesekus_quasi_steady_trajectory.csv"), ["t", "y_p_over_H"],
              [{"t": t, "y_p_over_H": y} for t, y in zip(ts, ys)])
    cost = sum(d["wall_seconds"] for d in done)
    lines = ["# The Giesekus migration trajectory, quasi-steady (issue 35's 4-hour target)", "",
             "Generated by `scripts/validation/giesekus_quasi_steady_trajectory.py`: beta = 0.2, Ca_e = 0.1 "
             "(p = 4.5), Wi = 0.5, alpha_m = 0.2, 20 equator nodes, step-limited SUPG parameter, dt = 0.04, "
             "remeshing; each start run to t = 6, the curve from t >= 2 in stretches of 2, the trajectory "
             f"(`softflow migration --trajectory-from`) from the {max(STARTS):g} H start's first stretch. y_p in H, "
             "v_p in gamma_dot H; wall: each run's, beside other work on the 2-core machine.", "",
             "| y_p0 | mean y_p, t >= 2 | v_p, t = 2-6 | unknowns | wall [s] | run by |", "|---|---|---|---|---|---|"]
    for d in done:
        by = "giesekus_trajectory_time_step.py" if d["start"] in SHARED else "this script"
        lines.append(f"| {d['start']:g} | {d['y_mean']:.4f} | {d['v_p']:.4e} | {d['unknowns']} | "
                     f"{d['wall_seconds']:.0f} | {by} |")
    lines += ["", f"Neutral heights of the curve: {neutral}", "",
              f"The trajectory: from y_p = {y0:.4f} H at t = {t0:g}, it ends {ends} at t = {ts[-1]:.1f} "
              f"(y_p = {ys[-1]:.4f} H).", "",
              f"Cost: the {len(done)} starts' runs took {cost:.0f} s = {cost / 3600:.2f} h on one core in all "
              f"({cost / 7200:.2f} h on two, two starts at a time); the same trajectory time-stepped at dt = 0.04: "
              f"{TIME_STEPPED_HOURS:g} h projected on one rank (docs/benchmarks/migration_trajectory.md)."]
    with open(os.path.join(OUT, "giesekus_quasi_steady_trajectory.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))

    fig, (ax_v, ax_y) = plt.subplots(1, 2, figsize=(11, 4))
    for d in done:
        r = d["series"]
        ax_y.plot(r["t"], r["y"], lw=1, label=f"run from {d['start']:g} H")
        ax_v.plot(d["y_mean"], d["v_p"], "ko")
    ax_y.plot(ts, ys, "k--", lw=1.5, label="quasi-steady trajectory")
    ax_y.set_xlabel("gamma_dot t")
    ax_y.set_ylabel("y_p / H")
    ax_y.legend(fontsize=7)
    ax_v.axhline(0.0, color="gray", lw=0.5)
    ax_v.set_xlabel("mean y_p / H over t = 2-6")
    ax_v.set_ylabel("v_p / (gamma_dot H)")
    ax_v.set_title("the starts' mean migration")
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "giesekus_quasi_steady_trajectory.png"), dpi=120)


if __name__ == "__main__":
    validation_main("giesekus_quasi_steady_trajectory", jobs, report, runner=runner)
