#!/usr/bin/python3
"""The quasi-steady migration trajectory against a time-stepped one (issue 35's
trajectory target; `softflow migration --trajectory-from`).

A particle that settles (shape, flow, a few 1/gamma_dot) much faster than it
crosses the channel migrates at the master curve's v_p(y_p) wherever it is, so
its trajectory follows from dy_p/dt = v_p(y_p) along a curve measured by short
runs from a few heights. The check: the Newtonian trajectory of Fig. 3.5
(beta = 0.4, Ca_e = 0.1, 20 equator nodes, dt = 0.04, remeshing), time-stepped
from y_p0 = 0.27 H to t = 35 (confined_migration_long.py; its first 15 units are
confined_migration.py's 0.27 H start), against the quasi-steady trajectory along
the curve of confined_migration.py's five starts (0.05 ... 0.27 H):

- "6 units": each start cut at t = 6, its first 2 units dropped, stretches of 2
  (what a user would run: five starts of 6 time units);
- "15 units": the whole 15 units of each start, the figures' transient 5,
  stretches of 2.5;
- "3 starts": only 0.05, 0.15 and 0.27 H at 6 units, a curve as sparse as the
  Giesekus one of Fig. 3.14 (starts 0.07-0.1 H apart).

The quasi-steady trajectory starts at the highest point of its curve (the 0.27 H
start's first stretch) at that stretch's middle time. The runs' per-step series
come from the committed docs/validation/confined_migration.csv (y_p / H to 6
digits), written back into run directories (case.toml from confined_migration.py's
case text, migration.csv) for `softflow migration`; the time-stepped trajectory is
that csv's 0.27 H series to t = 15 and confined_migration_long.csv's stretches
after it. No simulation runs here: seconds.
Writes docs/validation/quasi_steady_trajectory.{md,csv,png}.
Usage: scripts/validation/quasi_steady_trajectory.py [build_dir] [work_dir]"""
import bisect
import collections
import os
import shutil
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import confined_migration as starts  # noqa: E402
from case_runs import ROOT, read_csv, write_csv  # noqa: E402
from migration_runs import quasi_steady_path  # noqa: E402

OUT = os.path.join(ROOT, "docs", "validation")
Y_MAX_OVER_H = starts.Y_MAX  # y_p,max / H = (1 - beta) / 2
TARGET = 0.1  # y_p / H whose crossing time is compared (the long run's report: t = 30.3)
# (name, starts, last time kept per start, transient, stretch)
PROTOCOLS = [("6 units", starts.STARTS, 6.0, 2.0, 2.0), ("15 units", starts.STARTS, 15.0, 5.0, 2.5),
             ("3 starts", [0.05, 0.15, 0.27], 6.0, 2.0, 2.0)]


def read_series():
    """{y_p0 / H: (t, y_p / H, v_p / (gamma_dot H), Delta S) lists} from the committed report."""
    series = collections.defaultdict(lambda: ([], [], [], []))
    for r in read_csv(os.path.join(OUT, "confined_migration.csv")):
        s = series[round(float(r["y_p0_over_H"]), 4)]
        for column, key in zip(s, ("t", "y_p_over_H", "v_p_over_gamma_dot_H", "delta_S")):
            column.append(float(r[key]))
    return dict(series)


def write_run(directory, start, series, t_last):
    """A run directory as `softflow migration` reads it: case.toml and migration.csv to t_last."""
    os.makedirs(directory)
    name = starts.case_name(start)
    with open(os.path.join(directory, "case.toml"), "w") as f:
        f.write(starts.case_text(name, start))
    height = starts.HEIGHT
    y_max = Y_MAX_OVER_H * height
    with open(os.path.join(directory, "migration.csv"), "w") as f:
        f.write("step,t,object,y_p,y_p_rel,v_p,delta_s\n")
        for step, (t, y, v, ds) in enumerate(zip(*series)):
            if t <= t_last + 1e-9:
                f.write(f"{step},{t!r},1,{y * height!r},{y * height / y_max!r},{v * height!r},{ds!r}\n")


def direct_trajectory(series):
    """The time-stepped trajectory from 0.27 H: (t, y_p / H), per step to t = 15, then the long
    run's stretch middles; and how far the two runs differ where both exist."""
    t, y = series[0.27][0], series[0.27][1]
    long_rows = read_csv(os.path.join(OUT, "confined_migration_long.csv"))
    overlap = []
    for r in long_rows:  # the long run's stretch middles against the start's own series
        tm = float(r["t_mid"])
        if tm + 1.25 <= t[-1] + 1e-9:
            i, j = bisect.bisect_left(t, tm - 1.25 - 1e-9), bisect.bisect_left(t, tm + 1.25 - 1e-9)
            overlap.append(abs(0.5 * (y[i] + y[j]) - float(r["y_p_over_H"])))
    tail = [(float(r["t_mid"]), float(r["y_p_over_H"])) for r in long_rows if float(r["t_mid"]) > t[-1]]
    return list(t) + [a for a, _ in tail], list(y) + [b for _, b in tail], max(overlap)


def at(ts, ys, time):
    """ys linear in ts, at `time` (None outside)."""
    if not ts or time < ts[0] - 1e-12 or time > ts[-1] + 1e-12:
        return None
    i = min(max(bisect.bisect_left(ts, time), 1), len(ts) - 1)
    w = (time - ts[i - 1]) / (ts[i] - ts[i - 1])
    return ys[i - 1] + w * (ys[i] - ys[i - 1])


def crossing(ts, ys, level):
    """The first time ys falls to `level` (linear between samples), or None."""
    for i in range(1, len(ts)):
        if ys[i - 1] > level >= ys[i]:
            return ts[i - 1] + (ts[i] - ts[i - 1]) * (ys[i - 1] - level) / (ys[i - 1] - ys[i])
    return None


def quasi_steady(build, work, series, protocol):
    name, used, t_last, transient, stretch = protocol
    root = os.path.join(work, name.replace(" ", "_"))
    shutil.rmtree(root, ignore_errors=True)
    runs = []
    for start in used:
        runs.append(os.path.join(root, starts.case_name(start)))
        write_run(runs[-1], start, series[start], t_last)
    # Where the curve begins: the 0.27 H start's first stretch (its middle height and time).
    q = quasi_steady_path(build, runs, os.path.join(root, "curves"), series[0.27][:2], transient, stretch,
                          Y_MAX_OVER_H)
    return dict(q, name=name, t_last=t_last, transient=transient, stretch=stretch, starts=used,
                simulated=len(used) * t_last)


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build")
    work = sys.argv[2] if len(sys.argv) > 2 else os.path.join(ROOT, "output", "validation_quasi_steady_trajectory")
    series = read_series()
    t_direct, y_direct, overlap = direct_trajectory(series)
    direct_cross = crossing(t_direct, y_direct, TARGET)
    results = [quasi_steady(build, work, series, p) for p in PROTOCOLS]
    # The comparison times: the time-stepped run's stretch middles (every 2.5 units) and its end.
    check_times = [1.25 + 2.5 * k for k in range(14)]
    rows, lines = [], []
    for q in results:
        diffs = []
        for tc in check_times:
            yd, yq = at(t_direct, y_direct, tc), at(q["t"], q["y"], tc)
            if yd is not None and yq is not None and tc >= q["t0"]:
                diffs.append((tc, yd, yq))
                rows.append({"protocol": q["name"], "t": tc, "y_direct_over_H": yd, "y_quasi_steady_over_H": yq,
                             "difference_over_H": yq - yd})
        q_cross = crossing(q["t"], q["y"], TARGET)
        worst = max(diffs, key=lambda d: abs(d[2] - d[1]))
        q.update(diffs=diffs, cross=q_cross, worst=worst)
    write_csv(os.path.join(OUT, "quasi_steady_trajectory.csv"), list(rows[0]), rows)

    lines += ["# The quasi-steady migration trajectory against a time-stepped one", "",
              "Generated by `scripts/validation/quasi_steady_trajectory.py`: beta = 0.4, Ca_e = 0.1 (Fig. 3.5's "
              "particle, 20 equator nodes, dt = 0.04, remeshing). Time-stepped: the run from y_p0 = 0.27 H to "
              "t = 35 (confined_migration.py's start to t = 15, confined_migration_long.py's stretch middles "
              f"after; the two runs' stretch middles differ by at most {overlap:.1e} H where both exist). "
              "Quasi-steady: `softflow migration --trajectory-from` along the master curve of confined_migration.py's "
              "starts (0.05 ... 0.27 H, the curve from each row's starts; per-step series from confined_migration.csv), from the 0.27 H "
              "start's first stretch, placed at that stretch's middle time. y_p in H, t in 1/gamma_dot.", "",
              f"| curve from | time simulated | stretches on the curve | starts at t, y_p | time-stepped: t at y_p = {TARGET:g} | "
              f"quasi-steady: t at {TARGET:g} | difference | largest y_p difference (at t) | quasi-steady trajectory ends |",
              "|---|---|---|---|---|---|---|---|---|"]
    for q in results:
        travel = direct_cross - q["t0"]
        diff = "" if q["cross"] is None else f"{q['cross'] - direct_cross:+.2f} ({(q['cross'] - direct_cross) / travel:+.1%} of the time from the start)"
        cross = "not reached" if q["cross"] is None else f"{q['cross']:.2f}"
        tw, yd, yq = q["worst"]
        lines.append(f"| {' / '.join(f'{s:g}' for s in q['starts'])} H x {q['t_last']:g} units (transient {q['transient']:g}, stretches of {q['stretch']:g}) | "
                     f"{q['simulated']:g} | {q['stretches']} | {q['t0']:g}, {q['y0']:.4f} | {direct_cross:.2f} | {cross} | "
                     f"{diff} | {yq - yd:+.4f} ({tw:g}) | {q['ends']} |")
    lines += ["", "Along the way (y_p / H):", "",
              "| t | time-stepped | " + " | ".join(f"quasi-steady, {q['name']}" for q in results) + " |",
              "|---|---|" + "---|" * len(results)]
    for tc in check_times:
        yd = at(t_direct, y_direct, tc)
        cells = []
        for q in results:
            yq = at(q["t"], q["y"], tc) if tc >= q["t0"] else None
            cells.append("" if yq is None else f"{yq:.4f}")
        lines.append(f"| {tc:g} | {yd:.4f} | " + " | ".join(cells) + " |")
    with open(os.path.join(OUT, "quasi_steady_trajectory.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))

    fig, ax = plt.subplots(figsize=(6.5, 4))
    ax.plot(t_direct, y_direct, "k-", lw=1.5, label="time-stepped (dt = 0.04, 35 units)")
    for q, style in zip(results, ("C0--", "C1:", "C2-.")):
        ax.plot(q["t"], q["y"], style, lw=1.5,
                label=f"quasi-steady, curve from {len(q['starts'])} starts x {q['t_last']:g} units")
    ax.axhline(TARGET, color="gray", lw=0.5)
    ax.set_xlabel("gamma_dot t")
    ax.set_ylabel("y_p / H")
    ax.set_title("beta = 0.4, Ca_e = 0.1, from y_p0 = 0.27 H")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "quasi_steady_trajectory.png"), dpi=120)


if __name__ == "__main__":
    main()
