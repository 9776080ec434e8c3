#!/usr/bin/python3
"""The Giesekus migration trajectory of issue 35's 4-hour target, quasi-steady:
`softflow migration --trajectory-from` along the master curve of short runs
from several heights, instead of one time-stepped run of hundreds of time units
(23 h at dt = 0.04, docs/benchmarks/migration_trajectory.md). The case is the
trajectory's (giesekus_trajectory_time_step.py's at dt = 0.04: beta = 0.2,
Ca_e = 0.1 so p = 4.5, Wi = 0.5, alpha_m = 0.2, 20 equator nodes, step-limited
SUPG parameter, remeshing), started at seven heights and run to t = 6; the curve drops
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
import dataclasses
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import giesekus_neutral_height as neutral_height  # noqa: E402
import giesekus_trajectory_time_step as step_study  # noqa: E402
from case_runs import ROOT, read_csv, run_case, run_linked, summary_of, validation_main, write_csv  # noqa: E402
from migration_runs import mean_velocity, quasi_steady_path, read_migration  # noqa: E402

OUT = os.path.join(ROOT, "docs", "validation")
DT = 0.04
STEP_STUDY_WORK = "giesekus_trajectory_time_step"  # its work directory's name (and data/runs/'s)
TRANSIENT, STRETCH = 2.0, 2.0
T_END = step_study.T_END  # each start's run
HEIGHT = step_study.HEIGHT
Y_MAX_OVER_H = 0.4  # y_p,max / H = (1 - beta) / 2
TIME_STEPPED_HOURS = 23.3  # docs/benchmarks/migration_trajectory.md, p = 4.5, one rank


@dataclasses.dataclass(frozen=True)
class Level:
    """One setting of the curve: its mesh, its starts and where its report goes."""
    nodes: int  # equator nodes asked
    starts: tuple  # y_p0 / H, in the order they run
    symmetric_below: float  # starts below this y_p0 / H are carried from the point-symmetric mesh
    shared: tuple  # starts run by giesekus_trajectory_time_step.py, linked from its work directory
    stem: str  # docs/validation/STEM.{md,csv,png}

    def symmetric(self, start):
        return start < self.symmetric_below

    def name(self, start):
        if self.nodes == neutral_height.NODES and not self.symmetric(start):
            return step_study.name(start, DT)
        return f"yp0_{start:.2f}_N{self.nodes}" + ("_sym" if self.symmetric(start) else "")

    def case_text(self, start):
        if self.nodes == neutral_height.NODES and not self.symmetric(start):
            return step_study.case_text(start, DT)
        symmetric = self.symmetric(start)
        base = neutral_height.text(step_study.CA_E, start, self.nodes, neutral_height.TAU, symmetric)
        old_name = f'name = "{neutral_height.run_name(step_study.CA_E, start, self.nodes, symmetric)}"'
        assert base.count(old_name) == 1 and f"step = {DT:g}\n" in base, "giesekus_neutral_height's case changed"
        return base.replace(old_name, f'name = "{self.name(start)}"')

    def jobs(self):
        return [(self.name(s), self.case_text(s)) for s in self.starts]

    def runner(self, build, work, run_name, text):
        """run_case, but the shared starts in the time-step study's work directory, linked here."""
        start = next(s for s in self.starts if self.name(s) == run_name)
        if start not in self.shared:
            return run_case(build, work, run_name, text)
        return run_linked(build, work, STEP_STUDY_WORK, run_name, text)


# The 20-node curve: the trajectory's own case.
COARSE = Level(nodes=neutral_height.NODES, starts=(0.35, 0.20, 0.15, 0.10, 0.28, 0.24, 0.32), symmetric_below=0.0,
               shared=(0.10, 0.28), stem="giesekus_quasi_steady_trajectory")


def finished_starts(work, level):
    """The level's completed starts in `work`, lowest first: v_p and mean y_p over t >= TRANSIENT, cost, series."""
    done = []
    for s in sorted(level.starts):
        directory = os.path.join(work, level.name(s))
        summary = summary_of(directory)
        if summary.get("status") != "completed":
            continue
        r = read_migration(directory, HEIGHT)
        if r["t"][-1] < T_END - 1e-9:  # stopped early by a module (e.g. a wall gap): no t = 2-6 window
            print(f"note: {directory} ended at t = {r['t'][-1]:g}, before {T_END:g}: left out")
            continue
        done.append({"start": s, "directory": directory, "v_p": mean_velocity(r, TRANSIENT),
                     "y_mean": sum(y for t, y in zip(r["t"], r["y"]) if t >= TRANSIENT) /
                     sum(1 for t in r["t"] if t >= TRANSIENT),
                     "wall_seconds": summary["wall_seconds"], "unknowns": summary["unknowns"],
                     "series": r})
    return done


def report(work, build, level=COARSE, reference=None, extra=()):
    """Writes the level's report; `reference`, a (Level, work directory) of a coarser level, adds the
    comparison of v_p start by start and of the two trajectories; `extra`: lines to end it with, or a
    function of the level's trajectory (its t and y_p / H lists) that returns them."""
    done = finished_starts(work, level)
    if len(done) < 2 or done[-1]["start"] != max(level.starts):
        print(f"{len(done)} starts finished; the trajectory needs the {max(level.starts):g} H start and one more")
        for d in done:
            print(f"  {d['start']:g} H: v_p = {d['v_p']:.4e}, {d['wall_seconds']:.0f} s")
        return
    top = done[-1]["series"]
    q = quasi_steady_path(build, [d["directory"] for d in done], os.path.join(work, "curves"), (top["t"], top["y"]),
                          TRANSIENT, STRETCH, Y_MAX_OVER_H)
    t0, y0, ts, ys, ends, neutral = q["t0"], q["y0"], q["t"], q["y"], q["ends"], q["neutral"]

    write_csv(os.path.join(OUT, level.stem + ".csv"), ["t", "y_p_over_H"],
              [{"t": t, "y_p_over_H": y} for t, y in zip(ts, ys)])
    cost = sum(d["wall_seconds"] for d in done)
    projected = "the same trajectory" if level == COARSE else "the 20-node trajectory"  # the benchmark's case
    carried = [f"{x:g}" for x in sorted(level.starts) if level.symmetric(x)]
    symmetric_note = (f" (the {' and '.join(carried)} H starts: meshed point-symmetric, carried to their height, not "
                      "remeshed)") if carried else ""
    lines = ["# The Giesekus migration trajectory, quasi-steady (issue 35's 4-hour target)", "",
             f"Generated by `scripts/validation/{level.stem}.py`: beta = 0.2, Ca_e = 0.1 "
             f"(p = 4.5), Wi = 0.5, alpha_m = 0.2, {level.nodes} equator nodes, step-limited SUPG parameter, dt = 0.04, "
             f"remeshing{symmetric_note}; each start run to t = 6, the curve from t >= 2 in stretches of 2, the trajectory "
             f"(`softflow migration --trajectory-from`) from the {max(level.starts):g} H start's first stretch. y_p in H, "
             "v_p in gamma_dot H; wall: each run's, beside other work on the 2-core machine.", "",
             "| y_p0 | mean y_p, t >= 2 | v_p, t = 2-6 | unknowns | wall [s] | run by |", "|---|---|---|---|---|---|"]
    for d in done:
        by = "giesekus_trajectory_time_step.py" if d["start"] in level.shared else "this script"
        lines.append(f"| {d['start']:g} | {d['y_mean']:.4f} | {d['v_p']:.4e} | {d['unknowns']} | "
                     f"{d['wall_seconds']:.0f} | {by} |")
    lines += ["", f"Neutral heights of the curve: {neutral}", "",
              f"The trajectory: from y_p = {y0:.4f} H at t = {t0:g}, it ends {ends} at t = {ts[-1]:.1f} "
              f"(y_p = {ys[-1]:.4f} H).", "",
              f"Cost: the {len(done)} starts' runs took {cost:.0f} s = {cost / 3600:.2f} h on one core in all "
              f"(at best {cost / 7200:.2f} h on two, two starts at a time); {projected} time-stepped at dt = 0.04: "
              f"{TIME_STEPPED_HOURS:g} h projected on one rank (docs/benchmarks/migration_trajectory.md)."]
    compared = compare_levels(level, reference, done, ts, ys) if reference else None
    if compared:
        lines += ["", *compared["lines"]]
    lines += list(extra(ts, ys) if callable(extra) else extra)
    with open(os.path.join(OUT, level.stem + ".md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))

    fig, (ax_v, ax_y) = plt.subplots(1, 2, figsize=(11, 4))
    for d in done:
        r = d["series"]
        ax_y.plot(r["t"], r["y"], lw=1, label=f"run from {d['start']:g} H")
        ax_v.plot(d["y_mean"], d["v_p"], "ko")
    ax_y.plot(ts, ys, "k--", lw=1.5, label="quasi-steady trajectory")
    if compared:
        ax_v.plot([d["y_mean"] for d in compared["starts"]], [d["v_p"] for d in compared["starts"]], "o",
                  color="gray", mfc="none", label=f"{reference[0].nodes} nodes")
        ax_v.legend(fontsize=7)
        ax_y.plot(compared["t"], compared["y"], ":", color="gray", lw=1.5,
                  label=f"quasi-steady, {reference[0].nodes} nodes")
    ax_y.set_xlabel("gamma_dot t")
    ax_y.set_ylabel("y_p / H")
    ax_y.legend(fontsize=7)
    ax_v.axhline(0.0, color="gray", lw=0.5)
    ax_v.set_xlabel("mean y_p / H over t = 2-6")
    ax_v.set_ylabel("v_p / (gamma_dot H)")
    ax_v.set_title("the starts' mean migration")
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, level.stem + ".png"), dpi=120)


def time_at(ts, ys, y):
    """When the falling trajectory (ts, ys) first reaches height y (linear between its points); None if never."""
    for (t0, y0), (t1, y1) in zip(zip(ts, ys), zip(ts[1:], ys[1:])):
        if y0 >= y >= y1 and y0 != y1:
            return t0 + (t1 - t0) * (y0 - y) / (y0 - y1)
    return None


def compare_levels(level, reference, done, ts, ys):
    """The lines comparing this level's starts and trajectory with the reference level's, and its data."""
    ref_level, ref_work = reference
    ref_done = {d["start"]: d for d in finished_starts(ref_work, ref_level)}
    ref_csv = os.path.join(OUT, ref_level.stem + ".csv")
    if not ref_done or not os.path.exists(ref_csv):
        print(f"note: the {ref_level.nodes}-node level's runs or {ref_csv} are absent: no comparison")
        return None
    ref_t, ref_y = zip(*[(float(x["t"]), float(x["y_p_over_H"])) for x in read_csv(ref_csv)])
    lines = [f"Against the {ref_level.nodes}-node curve (`{ref_level.stem}.py`: gmsh's mesh at every start, "
             "remeshing):", "",
             f"| y_p0 | v_p, {ref_level.nodes} nodes | v_p, {level.nodes} nodes | ratio | {level.nodes}-node mesh |",
             "|---|---|---|---|---|"]
    for d in done:
        r = ref_done.get(d["start"])
        if r:
            mesh = "point-symmetric, carried" if level.symmetric(d["start"]) else "gmsh's"
            lines.append(f"| {d['start']:g} | {r['v_p']:.4e} | {d['v_p']:.4e} | {d['v_p'] / r['v_p']:.3f} | {mesh} |")
    if any(level.symmetric(d["start"]) for d in done):
        lines += ["", "Where the finer level's start is carried from the point-symmetric mesh, its ratio holds the "
                  "carried mesh's own error (O(carry), odd in y_p, so no mirror start exposes it) as well as the "
                  "mesh error; gmsh's mirror pairs below measure it, against their mirror average."]
    lines += ["", "Time from the trajectories' starts to each height (t = 0: the start run's t = 0):", "",
              f"| y_p / H | {ref_level.nodes} nodes | {level.nodes} nodes | ratio |", "|---|---|---|---|"]
    for y in (0.30, 0.25, 0.20, 0.15, 0.12, 0.10):
        a, b = time_at(ref_t, ref_y, y), time_at(ts, ys, y)
        if a is not None and b is not None:
            lines.append(f"| {y:.2f} | {a:.1f} | {b:.1f} | {b / a:.3f} |")
    return {"lines": lines, "starts": list(ref_done.values()), "t": ref_t, "y": ref_y}


if __name__ == "__main__":
    validation_main("giesekus_quasi_steady_trajectory", COARSE.jobs, report, runner=COARSE.runner)
