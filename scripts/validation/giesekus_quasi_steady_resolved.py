#!/usr/bin/python3
"""The quasi-steady Giesekus trajectory of giesekus_quasi_steady_trajectory.py
on the resolved setting: the resolution half of issue 35's 4-hour target ("with
the mesh that the convergence study says is needed for v_p to 10 %").

The convergence study at one start (delta_s_resolution.py, beta = 0.2 at
0.25 y_p,max): v_p moves -28 % from 20 to 28 equator nodes and +1.2 % from 28
to 40, so 28 nodes. The curve's starts below 0.20 H are meshed point-symmetric
and carried to their height (`mesh.point_symmetric_start`, no remeshing; to
0.15 H the carried mesh's quality is 0.159), once read as free of gmsh's mesh
bias near the centre plane. The mirror starts below (each height's start at -y
on gmsh's own mesh) showed the reverse: gmsh's two meshes add -1.3e-6 to
+3.1e-5 gamma_dot H together, while the carried starts are slowed by their
carry (1e-4 to 2.4e-4). So the report also builds the curve on gmsh's meshes
only, mirror-averaged (GMSH_CURVE). The rest is the 20-node trajectory's case: beta = 0.2,
Ca_e = 0.1 (p = 4.5), Wi = 0.5, alpha_m = 0.2, step-limited SUPG parameter,
dt = 0.04, each start to t = 6, the curve from t >= 2 in stretches of 2.

Writes docs/validation/giesekus_quasi_steady_resolved.{md,csv,png}.
Usage: scripts/validation/giesekus_quasi_steady_resolved.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import dataclasses
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import giesekus_quasi_steady_trajectory as coarse  # noqa: E402
from case_runs import validation_main  # noqa: E402
from migration_runs import (mean_velocity, mirror_averaged_run, mirror_parts, quasi_steady_path,  # noqa: E402
                            read_migration, refined_mesh)

NODES = 28
SYMMETRIC_BELOW = 0.20  # y_p0 / H: starts below it are carried from the point-symmetric mesh
STARTS = (0.35, 0.10, 0.20, 0.15, 0.28, 0.24, 0.32)  # y_p0 / H, in the order they run
LEVEL = coarse.Level(nodes=NODES, starts=STARTS, symmetric_below=SYMMETRIC_BELOW, shared=(),
                     stem="giesekus_quasi_steady_resolved")
# The seam: v_p jumps between the symmetric 0.15 H start and gmsh's 0.20 H one.
# The carry to 0.20 H takes two steps (it inverted an element in one), so the
# 0.20 H start from the symmetric mesh tells whether the jump is gmsh's mesh's.
SEAM = coarse.Level(nodes=NODES, starts=(0.20,), symmetric_below=0.21, shared=(), stem=LEVEL.stem)
# What gmsh's meshes add: mirror starts on gmsh's mesh of them (not the half
# turn's image of the +y start's). The flow is point-symmetric, so
# v_p(-y) = -v_p(y) but for what the two meshes add. -0.20 H: is the seam
# gmsh's meshes' or the carried mesh's (quality 0.090)?
MIRROR = coarse.Level(nodes=NODES, starts=(-0.28, -0.20, -0.10, -0.15), symmetric_below=-1.0, shared=(),
                      stem=LEVEL.stem)
# At 0.20 H the carried mesh is the outlier: what do gmsh's meshes add at
# 0.10 and 0.15 H, where the curve's starts are carried? The gmsh starts, beside their mirrors.
GMSH_LOW = coarse.Level(nodes=NODES, starts=(0.10, 0.15), symmetric_below=0.0, shared=(), stem=LEVEL.stem)
# And on the 20-node curve's mesh: is its 0.10 H start's -3.3e-4 (the carried
# start: +3e-6) gmsh's meshes' part, or the particle's? Its mirror start.
MIRROR_COARSE = coarse.Level(nodes=coarse.COARSE.nodes, starts=(-0.10,), symmetric_below=-1.0, shared=(),
                             stem=coarse.COARSE.stem)
# Is 28 nodes the level the target asks for (v_p to 10 %) in the Giesekus liquid
# too? One start on 40 nodes where 20 -> 28 moved v_p the most (0.75 at 0.28 H).
# Near the centre plane the mirror-averaged v_p at 0.10 H moves from -4.0e-4 (20
# nodes) to -1.18e-4 (28): the 0.10 H start and its mirror on 40 nodes too.
FINE = coarse.Level(nodes=40, starts=(0.28, 0.10, -0.10), symmetric_below=-1.0, shared=(), stem=LEVEL.stem)


def fine_text(start):
    """gmsh's 28-node start's case on 40 nodes, the whole mesh refined alike (migration_runs.refined_mesh)."""
    gmsh = dataclasses.replace(LEVEL, starts=(start,), symmetric_below=-1.0)
    text = gmsh.case_text(start).replace(f'name = "{gmsh.name(start)}"', f'name = "{FINE.name(start)}"')
    assert refined_mesh(text, NODES) == text, "the 28-node mesh is no longer the 20-node one refined by 20/28"
    return refined_mesh(text, FINE.nodes)


def jobs():
    return (LEVEL.jobs() + SEAM.jobs() + [(FINE.name(s), fine_text(s)) for s in FINE.starts] + MIRROR.jobs()
            + GMSH_LOW.jobs() + MIRROR_COARSE.jobs())


def beside_gmsh(work, other, height=lambda start: start):
    """(other's finished start, this level's gmsh start at height(start)) wherever both have run."""
    heights = tuple(height(x) for x in other.starts)
    gmsh = {d["start"]: d for d in coarse.finished_starts(work, dataclasses.replace(LEVEL, starts=heights,
                                                                                    symmetric_below=0.0))}
    return [(d, gmsh[height(d["start"])]) for d in coarse.finished_starts(work, other) if height(d["start"]) in gmsh]


def seam_lines(work):
    """The symmetric 0.20 H start beside gmsh's."""
    return [line for s, g in beside_gmsh(work, SEAM) for line in (
        "", f"The seam at 0.20 H: from the point-symmetric mesh (carried in steps) v_p = {s['v_p']:.4e}, "
        f"on gmsh's mesh {g['v_p']:.4e} ({s['wall_seconds']:.0f} s; not in the curve above).")]


def mirror_velocities(m, i):
    """(v_p of start i mirror-averaged with its mirror start m, what their two meshes add): migration_runs.mirror_parts."""
    return mirror_parts(i["v_p"], m["v_p"])


def mirror_pairs(work):
    """(mirror start, its image's gmsh start) wherever both have run."""
    return beside_gmsh(work, MIRROR, height=lambda start: -start)


def carried_starts(work):
    """The starts carried from the point-symmetric mesh, by height: the curve's and the seam's."""
    return {d["start"]: d for level in (LEVEL, SEAM)
            for d in coarse.finished_starts(work, level) if level.symmetric(d["start"])}


def mirror_lines(work):
    """Each mirror start beside its image's: their mean is what the two meshes add; and the carried start."""
    pairs = mirror_pairs(work)
    if not pairs:
        return []
    carried = carried_starts(work)
    lines = ["", "Mirror starts on gmsh's own mesh of them (not the half turn's image of the +y start's mesh). The flow "
             "is point-symmetric, so v_p(-y) = -v_p(y) but for what the two meshes add: their part is the mean "
             "(v_p(y) + v_p(-y)) / 2, and the mirror-averaged v_p, (v_p(y) - v_p(-y)) / 2, is free of it. Beside it, "
             "the start carried from the point-symmetric mesh where one ran:", "",
             "| y_p0 / H | v_p(y), gmsh | v_p(-y), gmsh | meshes' part | mirror-averaged v_p | carried start's v_p | "
             "wall of -y [s] |", "|---|---|---|---|---|---|---|"]
    for m, i in sorted(pairs, key=lambda pair: pair[1]["start"]):
        c = carried.get(i["start"])
        carried_cell = f"{c['v_p']:.4e}" if c else ""
        averaged, meshes = mirror_velocities(m, i)
        lines.append(f"| {i['start']:g} | {i['v_p']:.4e} | {m['v_p']:.4e} | {meshes:+.2e} | "
                     f"{averaged:.4e} | {carried_cell} | {m['wall_seconds']:.0f} |")
    return lines


def coarse_mirror_lines(work, coarse_work):
    """The 20-node curve's start beside its mirror start, run here."""
    lines = []
    starts = {d["start"]: d for d in coarse.finished_starts(coarse_work, coarse.COARSE)}
    for m in coarse.finished_starts(work, MIRROR_COARSE):
        i = starts.get(-m["start"])
        if i:
            averaged, meshes = mirror_velocities(m, i)
            lines += ["", f"On the 20-node curve's mesh the same: the mirror start {m['start']:g} H on gmsh's mesh of "
                      f"it ({m['unknowns']} unknowns, {m['wall_seconds']:.0f} s) gives v_p = {m['v_p']:.4e} against "
                      f"{i['v_p']:.4e} from {i['start']:g} H: the meshes' part {meshes:+.2e}, the "
                      f"mirror-averaged v_p {averaged:.4e}."]
    return lines


def fine_lines(work):
    """The 40-node starts beside the same starts on 28 nodes, mirror-averaged where both levels have the mirror."""
    lines = []
    mirrors = {-m["start"]: m for m, _ in mirror_pairs(work)}
    fine = {d["start"]: d for d in coarse.finished_starts(work, FINE)}
    for f, m in beside_gmsh(work, dataclasses.replace(FINE, starts=tuple(x for x in FINE.starts if x > 0))):
        line = (f"The start on 40 equator nodes ({f['start']:g} H, gmsh's mesh, {f['unknowns']} unknowns, "
                f"{f['wall_seconds']:.0f} s): v_p = {f['v_p']:.4e}, against {m['v_p']:.4e} on 28 nodes "
                f"(28 -> 40: {100 * (f['v_p'] / m['v_p'] - 1):+.1f} %)")
        if f["start"] in mirrors:
            averaged = mirror_velocities(mirrors[f["start"]], m)[0]
            line += (f"; against the mirror-averaged 28-node value {averaged:.4e}: "
                     f"{100 * (f['v_p'] / averaged - 1):+.1f} %")
            if -f["start"] in fine:
                fm = fine[-f["start"]]
                fine_averaged, fine_meshes = mirror_velocities(fm, f)
                line += (f". Its mirror start on 40 nodes ({fm['wall_seconds']:.0f} s) gives {fm['v_p']:.4e}: the "
                         f"meshes' part {fine_meshes:+.2e}, the mirror-averaged v_p "
                         f"{fine_averaged:.4e}, {100 * (fine_averaged / averaged - 1):+.1f} % from 28 nodes' "
                         "mirror average")
        lines += ["", line + "."]
    return lines


# The curve on gmsh's meshes only: LEVEL's heights, every start on gmsh's mesh
# (GMSH_LOW's below 0.20 H), averaged with MIRROR's starts where those ran.
GMSH_CURVE = dataclasses.replace(LEVEL, symmetric_below=0.0)


def gmsh_curve_jobs():
    """The gmsh-only curve's runs, in the order this script's jobs() would run them."""
    names = {GMSH_CURVE.name(s) for s in GMSH_CURVE.starts} | {MIRROR.name(s) for s in MIRROR.starts}
    return [(name, text) for name, text in jobs() if name in names]


def mirror_averaged_curve(work, build):
    """The 28-node curve on gmsh's meshes only: at each height the start averaged with its mirror start
    (migration_runs.mirror_averaged_run) where that ran, the start alone elsewhere; its quasi-steady
    trajectory from the 0.35 H start as the curve's. None until the 0.35 H start and one more have run."""
    gmsh = coarse.finished_starts(work, GMSH_CURVE)
    if len(gmsh) < 2 or gmsh[-1]["start"] != max(LEVEL.starts):
        return None
    mirrors = {-m["start"]: m for m in coarse.finished_starts(work, MIRROR)}
    starts = []
    for d in gmsh:
        m = mirrors.get(d["start"])
        directory = (mirror_averaged_run(d["directory"], m["directory"],
                                         os.path.join(work, "mirror_averaged", os.path.basename(d["directory"])))
                     if m else d["directory"])
        series = read_migration(directory, coarse.HEIGHT)
        after = [y for t, y in zip(series["t"], series["y"]) if t >= coarse.TRANSIENT]
        starts.append({"start": d["start"], "directory": directory, "mirrored": m is not None, "series": series,
                       "v_p": mean_velocity(series, coarse.TRANSIENT), "y_mean": sum(after) / len(after),
                       "wall_seconds": d["wall_seconds"] + (m["wall_seconds"] if m else 0.0)})
    top = starts[-1]["series"]
    q = quasi_steady_path(build, [d["directory"] for d in starts], os.path.join(work, "curves_mirror_averaged"),
                          (top["t"], top["y"]), coarse.TRANSIENT, coarse.STRETCH, coarse.Y_MAX_OVER_H)
    return {"starts": starts, **q}


def mirror_curve_lines(work, curve, ts, ys):
    """The gmsh-only curve's starts, neutral heights and trajectory beside the curve above's (ts, ys)."""
    if curve is None:
        return []
    parts = [mirror_velocities(m, i)[1] for m, i in mirror_pairs(work)]
    lines = ["", f"The same curve on gmsh's meshes only ({NODES} nodes; no carried start): each height's start "
             "averaged with its mirror start where that ran (`migration_runs.mirror_averaged_run`: the point-symmetric "
             "mean of the two runs, step by step), the start alone elsewhere (there the meshes' part is not removed; "
             f"it was {min(parts):+.1e} to {max(parts):+.1e} where measured, above):", "",
             "| y_p0 / H | v_p, t = 2-6 | from |", "|---|---|---|"]
    for d in curve["starts"]:
        lines.append(f"| {d['start']:g} | {d['v_p']:.4e} | {'start and mirror, averaged' if d['mirrored'] else 'the start alone'} |")
    lines += ["", f"Neutral heights of this curve: {curve['neutral']}", "",
              f"Its trajectory: from y_p = {curve['y0']:.4f} H at t = {curve['t0']:g}, it ends {curve['ends']} at "
              f"t = {curve['t'][-1]:.1f} (y_p = {curve['y'][-1]:.4f} H).", "",
              f"Cost: its {sum(1 + d['mirrored'] for d in curve['starts'])} runs took "
              f"{sum(d['wall_seconds'] for d in curve['starts']) / 3600:.2f} h on one core in all (each beside other "
              "work on the 2-core machine).", "",
              "Time to each height, this curve beside the curve above (carried starts below 0.20 H):", "",
              "| y_p / H | curve above | gmsh only, mirror-averaged | ratio |", "|---|---|---|---|"]
    for y in (0.30, 0.25, 0.20, 0.15, 0.12, 0.10):
        a, b = coarse.time_at(ts, ys, y), coarse.time_at(curve["t"], curve["y"], y)
        if a is not None and b is not None:
            lines.append(f"| {y:.2f} | {a:.1f} | {b:.1f} | {b / a:.3f} |")
    return lines


def plot_mirror_curve(work, curve, ts, ys):
    """docs/validation/STEM_mirror_averaged.png: the two 28-node curves' v_p and trajectories."""
    fig, (ax_v, ax_y) = plt.subplots(1, 2, figsize=(11, 4))
    above = coarse.finished_starts(work, LEVEL)
    ax_v.plot([d["y_mean"] for d in above], [d["v_p"] for d in above], "o", color="gray", mfc="none",
              label="curve with carried starts below 0.20 H")
    ax_v.plot([d["y_mean"] for d in curve["starts"]],
              [d["v_p"] for d in curve["starts"]], "ko", label="gmsh only, mirror-averaged")
    ax_v.axhline(0.0, color="gray", lw=0.5)
    ax_v.set_xlabel("mean y_p / H over t = 2-6")
    ax_v.set_ylabel("v_p / (gamma_dot H), t = 2-6")
    ax_v.legend(fontsize=7)
    ax_y.plot(ts, ys, ":", color="gray", lw=1.5, label="curve with carried starts")
    ax_y.plot(curve["t"], curve["y"], "k-", lw=1.5, label="gmsh only, mirror-averaged")
    ax_y.set_xlabel("gamma_dot t")
    ax_y.set_ylabel("y_p / H")
    ax_y.legend(fontsize=7)
    fig.suptitle(f"Giesekus, p = 4.5, {NODES} equator nodes: the quasi-steady trajectory from 0.35 H")
    fig.tight_layout()
    fig.savefig(os.path.join(coarse.OUT, LEVEL.stem + "_mirror_averaged.png"), dpi=120)


def report(work, build):
    # The 20-node curve's runs: in giesekus_quasi_steady_trajectory.py's work directory beside this one.
    coarse_work = os.path.join(os.path.dirname(os.path.abspath(work)), "giesekus_quasi_steady_trajectory")
    curve = mirror_averaged_curve(work, build)

    def extra(ts, ys):
        if curve:
            plot_mirror_curve(work, curve, ts, ys)
        return (seam_lines(work) + mirror_lines(work) + coarse_mirror_lines(work, coarse_work) + fine_lines(work)
                + mirror_curve_lines(work, curve, ts, ys))

    coarse.report(work, build, LEVEL, reference=(coarse.COARSE, coarse_work), extra=extra)


if __name__ == "__main__":
    validation_main("giesekus_quasi_steady_resolved", jobs, report)
