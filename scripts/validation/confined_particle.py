#!/usr/bin/python3
"""Validation of a neo-Hookean particle centred between two walls (thesis §3.2.1,
Figs. 3.2-3.4, eqs. 3.1-3.5): runs the cases below with the softflow binary,
then writes docs/validation/confined_particle.{md,csv,png}.

An initially spherical neo-Hookean particle (R = 1, no interfacial tension)
centred between walls at y = +-H/2 in a Newtonian matrix (eta_m = 1, shear
rate 1), periodic cell 10 particle diameters long and wide (as the thesis),
H = 2R / beta. beta = 0 is the same cell with H = 30 (15 diameters, a
"blockage" of 1/15 whose eq. 3.3 correction, 8/5 beta^3 = 5e-4, is far below
the mesh error).

Study C: beta = 0, 0.1, 0.2, 0.4, 0.6 x Ca_e = 0.05 ... 0.5 on 28 equator nodes,
         dt = 0.04, to t = 12: steady D and theta (Fig. 3.3), theta vs D
         (Fig. 3.4), the xy projection of the interface (Fig. 3.2), and the
         small-Ca_e slopes of eqs. 3.1-3.2 fitted through the origin for
         Ca_e <= 0.2, giving A(beta), B(beta) beside 8/5 beta^3 and 11/3 beta^3
         (eqs. 3.3-3.4). A and B are also fitted relative to beta = 0 on the
         same mesh (D(beta) / D(0) - 1 at each Ca_e), which cancels the part of
         the discretisation error common to both.
Study M: Ca_e = 0.1 at beta = 0, 0.4 and 0.6, the whole mesh refined by one
         factor (20/28/40 equator nodes): the mesh error of D, theta and of the
         confinement effect D(beta)/D(0) - 1.

The 28-node runs at beta = 0.4 remesh before their first step (REMESHED:
gmsh's mesh starts below time.min_quality there).

Steady values are means over the last 2 pi time units (the period of the slow
oscillation the initial state leaves, as in elastic_particle.py).
Finished cases (a summary.json in their directory) are not rerun.
Usage: scripts/validation/confined_particle.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import base64
import csv
import math
import os
import struct
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from case_runs import PARTICLE_FIGURES_CONFORMATION, meshed_size, read_run, richardson, validation_main  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts", "theory"))
OUT = os.path.join(ROOT, "docs", "validation")
T_END = 12.0
DT = 0.04
WINDOW = 2.0 * math.pi
UNBOUNDED_HEIGHT = 30.0

BETAS = [0.0, 0.1, 0.2, 0.4, 0.6]
CAS = [0.05, 0.1, 0.15, 0.2, 0.35, 0.5]
FIT_MAX_CA = 0.2
# (equator nodes, far size, growth): one refinement factor for all three, as
# in elastic_particle.py.
MESHES = {20: (20, 4.5, 0.56), 28: (28, 3.2, 0.4), 40: (40, 2.25, 0.28)}
STUDY_M_BETAS = [0.0, 0.4, 0.6]
STUDY_M_NODES = [20, 28, 40]
SHAPE_BETAS = [0.2, 0.6]
SHAPE_CAS = [0.05, 0.2, 0.35, 0.5]


# gmsh's 28-node mesh at beta = 0.4 starts with a sliver at the particle's
# surface (quality 0.0137 < time.min_quality = 0.02: the run is refused, and
# node relocation cannot save it, the element collapsing at the second step):
# those runs remesh before their first step (the remesher's mesh starts at
# 0.28) and whenever the quality falls below 0.03.
REMESHED = {(0.4, 28)}
REMESH = "[remesh]\nquality = 0.03\n"


def case_name(beta, ca_e, n):
    return f"beta{beta:g}_Cae{ca_e:g}_N{n}"


def case_text(name, beta, ca_e, n):
    equator, far, growth = MESHES[n]
    height = f"height = {UNBOUNDED_HEIGHT}" if beta == 0 else f"blockage_ratio = {beta}"
    quality = REMESH if (beta, n) in REMESHED else ""
    return f"""[case]
name = "{name}"
[cell]
length = 20.0
width = 20.0
{height}
[flow]
shear_rate = 1.0
[[objects]]
model = "neo_hookean"
elastic_capillary_number = {ca_e}
[mesh]
equator_nodes = {equator}
far_size = {far}
growth = {growth}
[time]
step = {DT}
end = {T_END}
{quality}[checkpoint]
interval_minutes = 0
[output]
fields = true
""" + PARTICLE_FIGURES_CONFORMATION


def all_cases():
    cases = {case_name(b, c, 28): (b, c, 28) for b in BETAS for c in CAS}
    cases.update({case_name(b, 0.1, n): (b, 0.1, n) for b in STUDY_M_BETAS for n in STUDY_M_NODES})
    return cases


def vtu_points(path):
    """The points of a VTU written by softflow (inline binary: base64 of a UInt32 byte count
    followed by the Float64 coordinates)."""
    text = open(path).read()
    start = text.index(">", text.index('Name="Points"')) + 1
    raw = base64.b64decode(text[start:text.index("<", start)].strip())
    count = struct.unpack("<I", raw[:4])[0] // 8
    values = struct.unpack(f"<{count}d", raw[4:4 + 8 * count])
    return [values[i:i + 3] for i in range(0, count, 3)]


def interface_nodes(directory):
    """Interface nodes of object 1 at the run's end: the points its region's VTU shares with
    the matrix's (double interface nodes sit at the same place)."""
    fields = os.path.join(directory, "fields")
    if not os.path.isdir(fields):
        return []
    last = sorted(f for f in os.listdir(fields) if f.startswith("object_1_"))
    if not last:
        return []
    suffix = last[-1][len("object_1_"):]
    key = lambda p: tuple(round(x, 12) for x in p)  # noqa: E731
    matrix = {key(p) for p in vtu_points(os.path.join(fields, "matrix_" + suffix))}
    return [p for p in vtu_points(os.path.join(fields, last[-1])) if key(p) in matrix]


def reached_steady(r):
    return r is not None and (r["status"] == "completed" or r["end"] >= 8.0)


def slope_through_origin(xs, ys):
    return sum(x * y for x, y in zip(xs, ys)) / sum(x * x for x in xs)


def roscoe():
    """Roscoe's finite-deformation theory when scripts/theory/roscoe_particle.py is there,
    else None (the small-Ca_e limits are drawn in any case)."""
    try:
        from roscoe_particle import roscoe_steady
    except ImportError:
        return None
    return roscoe_steady


def fits(results):
    """Per beta: slopes of D and theta - pi/4 (rad) vs Ca_e for Ca_e <= FIT_MAX_CA, A and B of
    eqs. 3.1-3.2, and A, B relative to beta = 0 on the same mesh."""
    out = {}
    for b in BETAS:
        pts = [(c, results[case_name(b, c, 28)]) for c in CAS if c <= FIT_MAX_CA]
        pts = [(c, r) for c, r in pts if reached_steady(r)]
        if len(pts) < 2:
            continue
        cs = [c for c, _ in pts]
        sd = slope_through_origin(cs, [r["D_steady"] for _, r in pts])
        st = slope_through_origin(cs, [math.radians(r["theta_steady"]) - math.pi / 4 for _, r in pts])
        out[b] = {"n": len(pts), "slope_D": sd, "slope_theta": st, "A": sd / 1.25 - 1, "B": st / -0.75 - 1}
    if 0.0 in out:
        for b, f in out.items():
            f["A_rel"] = f["slope_D"] / out[0.0]["slope_D"] - 1
            f["B_rel"] = f["slope_theta"] / out[0.0]["slope_theta"] - 1
    return out


def report(work):
    os.makedirs(OUT, exist_ok=True)
    results = {name: read_run(os.path.join(work, name), WINDOW) for name in all_cases()}
    theory = roscoe()
    md = ["# A neo-Hookean particle centred between walls (thesis §3.2.1, Figs. 3.2-3.4, eqs. 3.1-3.5)", "",
          "Unit sphere, no interfacial tension, Newtonian matrix (eta_m = 1, shear rate 1), walls at "
          "y = +-H/2 with H = 2R / beta, periodic cell 20 x H x 20 (10 diameters, as the thesis). "
          f"beta = 0 is H = {UNBOUNDED_HEIGHT:g}. 28 equator nodes (far size 3.2, growth 0.4), dt = {DT:g}, "
          f"to t = {T_END:g}; steady values are means over the last 2 pi time units, `D ampl.` the "
          "half-amplitude of D over that window. `y_c` is the particle's centre at the end: it should "
          "stay 0 by symmetry (its drift is the noise floor of issue 35 item 6). "
          "Generated by `scripts/validation/confined_particle.py`.", "",
          "## Steady D and theta vs Ca_e and beta (Fig. 3.3)", "",
          "| beta | Ca_e | unknowns | D | D ampl. | D / D(beta=0) - 1 | theta [deg] | theta - theta(beta=0) [deg] "
          "| y_c at end | wall time [s] | status |",
          "|---|---|---|---|---|---|---|---|---|---|---|"]
    csv_rows = []
    for b in BETAS:
        for c in CAS:
            r = results[case_name(b, c, 28)]
            ref = results[case_name(0.0, c, 28)]
            if r is None:
                md.append(f"| {b:g} | {c:g} | | | | | | | | | not run |")
                continue
            yc = float(r["rows"][-1]["yc"])
            if not reached_steady(r):
                md.append(f"| {b:g} | {c:g} | {r['unknowns']} | (D = {r['D'][-1]:.3f} when it stopped) | | | | | "
                          f"{yc:+.1e} | {r['wall']:.0f} | {r['status']} (t = {r['end']:g}): "
                          f"{r['summary'].get('stop_reason', '')[:70]}... |")
                continue
            rel_d = f"{r['D_steady'] / ref['D_steady'] - 1:+.1%}" if reached_steady(ref) else ""
            rel_t = f"{r['theta_steady'] - ref['theta_steady']:+.2f}" if reached_steady(ref) else ""
            md.append(f"| {b:g} | {c:g} | {r['unknowns']} | {r['D_steady']:.4f} | {r['D_amplitude']:.1e} | {rel_d} | "
                      f"{r['theta_steady']:.2f} | {rel_t} | {yc:+.1e} | {r['wall']:.0f} | {r['status']} (t = {r['end']:g}) |")
            csv_rows.append([b, c, 28, r["unknowns"], r["D_steady"], r["D_amplitude"], r["theta_steady"], yc,
                             r["volume_drift"], r["wall"], r["status"]])

    f = fits(results)
    md += ["", f"## Small-Ca_e slopes: A(beta), B(beta) of eqs. 3.1-3.4 (fits through the origin, Ca_e <= {FIT_MAX_CA:g})", "",
           "D = 5/4 (1 + A) Ca_e and theta - pi/4 = -3/4 (1 + B) Ca_e. `A`, `B`: from the slopes "
           "themselves (at beta = 0 they measure the mesh's departure from Roscoe's limits). "
           "`A rel.`, `B rel.`: the slopes over the beta = 0 slopes on the same mesh, minus 1 "
           "(the confinement effect with the common discretisation error divided out).", "",
           "| beta | points | dD/dCa_e | dtheta/dCa_e [rad] | A | A rel. | 8/5 beta^3 (eq. 3.3) | B | B rel. | 11/3 beta^3 (eq. 3.4) |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    for b, v in f.items():
        md.append(f"| {b:g} | {v['n']} | {v['slope_D']:.4f} | {v['slope_theta']:.4f} | {v['A']:+.4f} | "
                  f"{v.get('A_rel', float('nan')):+.4f} | {1.6 * b ** 3:.4f} | {v['B']:+.4f} | "
                  f"{v.get('B_rel', float('nan')):+.4f} | {11 / 3 * b ** 3:.4f} |")
    conf = [(b, v) for b, v in f.items() if b >= 0.4 and "A_rel" in v]
    if conf:
        ka = sum(v["A_rel"] * b ** 3 for b, v in conf) / sum(b ** 6 for b, _ in conf)
        kb = sum(v["B_rel"] * b ** 3 for b, v in conf) / sum(b ** 6 for b, _ in conf)
        md += ["", f"Cubic fits A rel. = a beta^3, B rel. = b beta^3 through beta = 0.4 and 0.6: "
               f"a = {ka:.3f} (thesis 8/5 = 1.600), b = {kb:.3f} (thesis 11/3 = {11 / 3:.3f})."]

    md += mesh_study(results)
    md += roscoe_section(results, theory)

    with open(os.path.join(OUT, "confined_particle.csv"), "w", newline="") as fcsv:
        w = csv.writer(fcsv)
        w.writerow(["beta", "Ca_e", "equator_nodes", "unknowns", "D", "D_amplitude", "theta_deg", "y_c_end",
                    "volume_drift", "wall_seconds", "status"])
        w.writerows(csv_rows)

    plot(work, results, theory)
    with open(os.path.join(OUT, "confined_particle.md"), "w") as fmd:
        fmd.write("\n".join(md) + "\n\n![confined particle](confined_particle.png)\n")


def mesh_study(results):
    md = ["", "## Mesh study at Ca_e = 0.1 (equator nodes, far size and growth refined together)", "",
          "| beta | equator nodes | unknowns | D | D ampl. | theta [deg] | D / D(beta=0) - 1 | wall time [s] | status |",
          "|---|---|---|---|---|---|---|---|---|"]
    for b in STUDY_M_BETAS:
        values, hs = [], []
        for n in STUDY_M_NODES:
            r, ref = results[case_name(b, 0.1, n)], results[case_name(0.0, 0.1, n)]
            if not reached_steady(r):
                md.append(f"| {b:g} | {n} | | | | | | | {r['status'] if r else 'not run'} |")
                continue
            rel = f"{r['D_steady'] / ref['D_steady'] - 1:+.2%}" if reached_steady(ref) else ""
            values.append(r["D_steady"])
            hs.append(meshed_size(r))
            md.append(f"| {b:g} | {n} | {r['unknowns']} | {r['D_steady']:.5f} | {r['D_amplitude']:.1e} | "
                      f"{r['theta_steady']:.3f} | {rel} | {r['wall']:.0f} | {r['status']} |")
        if len(values) == 3:
            fit = richardson(hs, values)
            md.append("")
            md.append(f"beta = {b:g}: " + (f"observed order {fit[0]:.2f}, Richardson D = {fit[1]:.5f}, "
                                          f"the 28-node run {values[1] / fit[1] - 1:+.2%} from it"
                                          if fit else "differences not monotone: no order") + "")
            md.append("")
    return md


def roscoe_section(results, theory):
    """beta = 0 against Roscoe's finite-deformation theory (scripts/theory/roscoe_particle.py)."""
    if theory is None:
        return []
    md = ["", "## beta = 0 against Roscoe's exact finite-deformation theory (docs/roscoe.md)", "",
          "| Ca_e | equator nodes | D | Roscoe D | D / Roscoe - 1 | theta [deg] | Roscoe theta [deg] | difference [deg] |",
          "|---|---|---|---|---|---|---|---|"]
    rows = [(c, 28) for c in CAS] + [(0.1, n) for n in STUDY_M_NODES if n != 28]
    for c, n in rows:
        r = results[case_name(0.0, c, n)]
        if not reached_steady(r):
            continue
        d, th = theory(c)[:2]
        md.append(f"| {c:g} | {n} | {r['D_steady']:.5f} | {d:.5f} | {r['D_steady'] / d - 1:+.2%} | "
                  f"{r['theta_steady']:.3f} | {th:.3f} | {r['theta_steady'] - th:+.3f} |")
    values = [results[case_name(0.0, 0.1, n)] for n in STUDY_M_NODES]
    if all(reached_steady(r) for r in values):
        fit = richardson([meshed_size(r) for r in values], [r["D_steady"] for r in values])
        if fit:
            d = theory(0.1)[0]
            md += ["", f"Ca_e = 0.1, mesh study above: Richardson D = {fit[1]:.5f}, "
                   f"{fit[1] / d - 1:+.2%} from Roscoe's {d:.5f}."]
    return md


def plot(work, results, theory):
    fig, axes = plt.subplots(1, 5, figsize=(24, 4.4))
    grid = [0.5 * i / 50 for i in range(1, 51)]
    markers = {0.0: "o", 0.1: "D", 0.2: "^", 0.4: "*", 0.6: "s"}
    for k, b in enumerate(SHAPE_BETAS):
        ax = axes[k]
        for c in SHAPE_CAS:
            # the interface nodes near the shear plane z = 0, as the thesis's figure
            pts = [p for p in interface_nodes(os.path.join(work, case_name(b, c, 28))) if abs(p[2]) < 0.1]
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], ".", ms=3, label=f"Ca_e = {c:g}")
        circle = [2 * math.pi * i / 200 for i in range(201)]
        ax.plot([math.cos(a) for a in circle], [math.sin(a) for a in circle], "k--", lw=0.8)
        ax.set(aspect="equal", xlabel="x / R", ylabel="y / R", title=f"xy shape, beta = {b:g} (Fig. 3.2)")
        ax.legend(fontsize=7)
    for b in BETAS:
        pts = [(c, results[case_name(b, c, 28)]) for c in CAS]
        pts = [(c, r) for c, r in pts if reached_steady(r)]
        m = markers[b]
        axes[2].plot([c for c, _ in pts], [r["D_steady"] for _, r in pts], m, label=f"beta = {b:g}")
        axes[3].plot([c for c, _ in pts], [r["theta_steady"] for _, r in pts], m, label=f"beta = {b:g}")
        line = axes[4].plot([r["D_steady"] for _, r in pts], [r["theta_steady"] for _, r in pts], m, label=f"beta = {b:g}")
        ds = [0.6 * i / 50 for i in range(51)]
        # eq. 3.5 with the denominator (1 + 8/5 beta^3) that eqs. 3.1-3.4 give (SPEC §9)
        axes[4].plot(ds, [math.degrees(math.pi / 4 - 0.6 * (1 + 11 / 3 * b ** 3) / (1 + 1.6 * b ** 3) * d) for d in ds],
                     "--", lw=0.8, color=line[0].get_color())
    axes[2].plot(grid, [1.25 * c for c in grid], ":", color="gray", label="5/4 Ca_e (Roscoe, small Ca_e)")
    axes[3].plot(grid, [math.degrees(math.pi / 4 - 0.75 * c) for c in grid], ":", color="gray", label="45 deg - 3/4 Ca_e")
    if theory:
        exact = [theory(c) for c in grid]
        axes[2].plot(grid, [e[0] for e in exact], "--", color="gray", label="Roscoe (finite deformation)")
        axes[3].plot(grid, [e[1] for e in exact], "--", color="gray", label="Roscoe (finite deformation)")
    axes[2].set(xlabel="Ca_e", ylabel="steady D", title="D vs Ca_e (Fig. 3.3a)")
    axes[3].set(xlabel="Ca_e", ylabel="steady theta [deg]", title="theta vs Ca_e (Fig. 3.3b)")
    axes[4].set(xlabel="steady D", ylabel="steady theta [deg]", title="theta vs D; dashed: eq. 3.5 (Fig. 3.4)")
    for a in axes[2:]:
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "confined_particle.png"), dpi=110)


def main():
    validation_main("validation_confined_particle",
                    lambda: [(name, case_text(name, *spec)) for name, spec in all_cases().items()], report)


if __name__ == "__main__":
    main()
