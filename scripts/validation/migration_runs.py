"""Reading and combining the runs of a migration study (one particle started
at several heights): what scripts/validation/confined_migration.py and
giesekus_migration.py share. Heights in units of H, velocities in gamma_dot H."""
import csv
import os
import re
import shutil
import subprocess

from case_runs import ROOT, read_csv, summary_of


# The migration figures' mesh on 20 equator nodes; a finer level refines it as a
# whole by 20 / N: the interface, far and wall sizes and the growth alike.
BASE_MESH = {"far_size": 2.0, "growth": 0.4, "wall_size": 0.5}


def refined_mesh(text, nodes):
    """The case `text` with its [mesh] sizes those of `nodes` equator nodes (BASE_MESH refined by 20 / nodes)."""
    values = {"equator_nodes": f"{nodes}", **{k: f"{v * 20 / nodes:.6g}" for k, v in BASE_MESH.items()}}
    for key, value in values.items():
        text, count = re.subn(rf"^{key} = .*$", f"{key} = {value}", text, flags=re.MULTILINE)
        assert count == 1, f"the case has {count} lines of {key}"
    return text


def read_migration(directory, height):
    """The first object's t, y_p / H, v_p / (gamma_dot H) and Delta S per step."""
    rows = [r for r in read_csv(os.path.join(directory, "migration.csv")) if r["object"] == "1"]
    return {
        "t": [float(r["t"]) for r in rows],
        "y": [float(r["y_p"]) / height for r in rows],
        "v": [float(r["v_p"]) / height for r in rows],
        "dS": [float(r["delta_s"]) for r in rows],
    }


def completed_run(directory, height, t_end=None):
    """(read_migration's series, summary.json) of a completed run, or None while it runs, or if it stopped
    before `t_end` (e.g. at a wall gap)."""
    summary = summary_of(directory)
    if summary.get("status") != "completed":
        return None
    r = read_migration(directory, height)
    return None if t_end is not None and r["t"][-1] < t_end - 1e-9 else (r, summary)


def mirror_parts(value, mirror_value):
    """(the mirror average, what the two meshes add) of a quantity odd under the flow's half turn about the
    z axis (y_p, v_p, Delta S), from a start and its mirror start at -y_p0 on a mesh of its own."""
    return 0.5 * (value - mirror_value), 0.5 * (value + mirror_value)


def mean_velocity(r, transient, t_end=float("inf")):
    """The slope of y_p(t) between the first row at t >= transient and the last
    at t <= t_end (the mean v_p after the transient), or None without two rows."""
    rows = [i for i, t in enumerate(r["t"]) if transient - 1e-9 <= t <= t_end + 1e-9]
    if len(rows) < 2:
        return None
    i, j = rows[0], rows[-1]
    return (r["y"][j] - r["y"][i]) / (r["t"][j] - r["t"][i])


def window_velocities(r, windows):
    """mean_velocity over each (start, end) window, None for a window past the run's end."""
    t_last = r["t"][-1] if r["t"] else 0.0
    return [mean_velocity(r, a, b) if t_last >= b - 1e-9 else None for a, b in windows]


def read_starts(work, starts, case_name, height):
    """{start: (directory, series)} of the starts whose runs have begun, by height."""
    runs = {}
    for s in sorted(starts):
        directory = os.path.join(work, case_name(s))
        if os.path.exists(os.path.join(directory, "migration.csv")):
            runs[s] = (directory, read_migration(directory, height))
    return runs


def combine(build, work, runs, transient, name="combined"):
    """`softflow migration` over the runs (master curves, neutral heights) into
    work/NAME; returns the lines of its migration.md after the title."""
    combined = os.path.join(work, name)
    # Run from the repository, so that the report names the runs by their
    # paths in it (output/...), not by this machine's.
    def short(path):
        path = os.path.abspath(path)
        return os.path.relpath(path, ROOT) if path.startswith(ROOT + os.sep) else path

    subprocess.run([os.path.abspath(os.path.join(build, "softflow")), "migration",
                    *[short(d) for d, _ in runs.values()], "--transient", str(transient), "-o", short(combined)],
                   check=True, cwd=ROOT)
    md = os.path.join(combined, "migration.md")
    return [line.rstrip("\n") for line in open(md)][1:] if os.path.exists(md) else []


def write_series(path, runs):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["y_p0_over_H", "t", "y_p_over_H", "v_p_over_gamma_dot_H", "delta_S"])
        for s, (_, r) in runs.items():
            for row in zip(r["t"], r["y"], r["v"], r["dS"]):
                w.writerow([f"{s:.2f}", *(f"{x:.6g}" for x in row)])


def remeshes(directory):
    path = os.path.join(directory, "remesh.csv")
    return len(read_csv(path)) if os.path.exists(path) else 0


def start_table(runs, transient):
    """One Markdown row per start: heights, the mean v_p after the transient
    (slope of y_p), Delta S at the end, remeshes, size, time and status."""
    lines = [f"| y_p0 / H | y_p / H at t = {transient:g} | y_p / H at end | mean v_p, t >= {transient:g} | "
             "Delta S at end | remeshes | unknowns | wall s | status |",
             "|---|---|---|---|---|---|---|---|---|"]
    for s, (directory, r) in runs.items():
        summary = summary_of(directory)
        late = [i for i, t in enumerate(r["t"]) if t >= transient]
        at_transient = r["y"][late[0]] if late else float("nan")
        mean_v = mean_velocity(r, transient)
        mean_v = float("nan") if mean_v is None else mean_v
        lines.append(f"| {s:.2f} | {at_transient:.4f} | {r['y'][-1]:.4f} | {mean_v:.3e} | {r['dS'][-1]:.3e} | "
                     f"{remeshes(directory)} | {summary.get('unknowns', '')} | "
                     f"{summary.get('wall_seconds', 0):.0f} | {summary.get('status', 'running')} "
                     f"(t = {r['t'][-1]:g}) |")
    return lines


def plot_trajectories(ax, runs, y_max, transient, prefix="", linestyle="-", marker="."):
    """Trajectories (ax[0]) and v_p(y_p) after the transient (ax[1]); labels
    start with `prefix` when several series share the axes."""
    for s, (_, r) in runs.items():
        label = f"{prefix}y_p0 = {s:.2f} H"
        line, = ax[0].plot(r["t"], r["y"], linestyle, label=label)
        late = [i for i, t in enumerate(r["t"]) if t >= transient]
        ax[1].plot([r["y"][i] for i in late], [r["v"][i] for i in late], marker, ms=2, color=line.get_color(),
                   label=label)
    ax[0].axhspan(y_max, 0.5, color="0.85")
    ax[0].set(xlabel="gamma_dot t", ylabel="y_p / H", ylim=(0, 0.5))
    ax[1].set(xlabel="y_p / H", ylabel="v_p / (gamma_dot H)")


def mirror_averaged_run(run, mirror, out):
    """A run directory `out` holding the point-symmetric mean of the run `run` and of its mirror start
    `mirror` (started at -y_p0 on a mesh of its own): the shear flow between walls is symmetric under the
    half turn about the z axis, which takes y_p, v_p and Delta S to minus themselves, so the mean
    (q(run) - q(mirror)) / 2 keeps the particle's migration and drops what the two meshes add. Row by
    row: the two runs must have the same times; case.toml is `run`'s (what `softflow migration` reads besides)."""
    def rows(directory):
        return {round(float(r["t"]), 9): r for r in read_csv(os.path.join(directory, "migration.csv"))
                if r["object"] == "1"}
    a, b = rows(run), rows(mirror)
    if set(a) != set(b):  # both at the same fixed step to the same end, or they are no pair
        raise ValueError(f"{run} and {mirror} have different times ({len(a)} and {len(b)} rows): not a mirror pair")
    os.makedirs(out, exist_ok=True)
    shutil.copyfile(os.path.join(run, "case.toml"), os.path.join(out, "case.toml"))
    odd = ("y_p", "y_p_rel", "v_p", "delta_s")
    with open(os.path.join(out, "migration.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(("step", "t", "object") + odd)
        for t in sorted(a):
            w.writerow([a[t]["step"], a[t]["t"], 1] +
                       [repr(mirror_parts(float(a[t][k]), float(b[t][k]))[0]) for k in odd])
    return out


def quasi_steady_path(build, runs, out, top, transient, stretch, y_max):
    """`softflow migration --trajectory-from` over the run directories `runs` into `out`, from the
    first stretch after `transient` of the series `top` (t and y_p / H lists: the start the trajectory
    leaves from), placed at that stretch's middle time. Returns its t, y_p / H, where it ends (the
    command's words), the curve's neutral heights section and its number of stretch heights."""
    t, y = top
    i = next(k for k, x in enumerate(t) if x >= transient - 1e-9)
    j = next(k for k, x in enumerate(t) if x >= transient + stretch - 1e-9)
    t0, y0 = 0.5 * (t[i] + t[j]), 0.5 * (y[i] + y[j])
    command = [os.path.abspath(os.path.join(build, "softflow")), "migration", *runs, "--transient",
               f"{transient:g}", "--segment", f"{stretch:g}", "--trajectory-from", f"{y0 / y_max:.12g}", "-o", out]
    subprocess.run(command, check=True, env=dict(os.environ, SOFTFLOW_PLOTS="0"))
    path = read_csv(os.path.join(out, "migration_trajectory.csv"))
    md = open(os.path.join(out, "migration.md")).read()
    return {"t0": t0, "y0": y0, "t": [t0 + float(r["t"]) for r in path],
            "y": [float(r["y_p_rel"]) * y_max for r in path],
            "ends": md.split("## Quasi-steady trajectory", 1)[1].split("it ends ", 1)[1].split(" after t", 1)[0],
            "neutral": md.split("## Neutral heights (v_p = 0)", 1)[1].split("##", 1)[0].strip(),
            "stretches": md.split("## Mean migration", 1)[1].split("## Neutral", 1)[0].count("\n| ") - 1}
