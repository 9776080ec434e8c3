#!/usr/bin/python3
"""Validation of the neo-Hookean elastic particle in unbounded shear (thesis
§2.5.4, Figs. 2.13-2.15): runs the cases below with the softflow binary (two at
a time), then writes docs/validation/elastic_particle.{md,csv,png}.

An initially spherical neo-Hookean particle (R = 1, no interfacial tension) in a
Newtonian matrix (eta_m = 1, shear rate 1) in a periodic box 30 x 30 x 30 (15
particle diameters), elastic capillary number Ca_e = eta_m gamma_dot / G.
Study C: Ca_e = 0.025 ... 0.5 on 28 equator nodes, dt = 0.02, to t = 12:
         steady D and theta vs Roscoe's small-Ca_e limits D = 5/4 Ca_e,
         theta = pi/4 - 3/4 Ca_e (SPEC §3), and the volume-averaged stress
         inside the particle, its principal values and spread (Fig. 2.15).
Study M: Ca_e = 0.1, the whole mesh refined by one factor (interface size,
         far size and growth together): 20/28/40 equator nodes.
Study T: Ca_e = 0.1, 28 equator nodes, dt = 0.04/0.02/0.01.

Steady values are means over the last 2 pi time units (half a rotation of the
particle's material at gamma_dot / 2, the period of the slow oscillation the
initial state leaves); the half-amplitude of D over that window is reported.
Finished cases (a summary.json in their directory) are not rerun.
Usage: scripts/validation/elastic_particle.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import argparse
import concurrent.futures
import csv
import json
import math
import os
import subprocess

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
T_END = 12.0
WINDOW = 2.0 * math.pi

# (equator nodes, far size, growth): one refinement factor for all three.
MESHES = {20: (20, 4.5, 0.56), 28: (28, 3.2, 0.4), 40: (40, 2.25, 0.28)}
STUDY_C = [0.025, 0.05, 0.1, 0.2, 0.3, 0.5]
STUDY_M = [20, 28, 40]
STUDY_T = [0.04, 0.02, 0.01]


def case_name(ca_e, n, dt):
    return f"Cae{ca_e:g}_N{n}_dt{dt:g}"


def case_text(name, ca_e, n, dt):
    equator, far, growth = MESHES[n]
    return f"""[case]
name = "{name}"
[cell]
length = 30.0
height = 30.0
width = 30.0
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
step = {dt}
end = {T_END}
[checkpoint]
interval_minutes = 0
[output]
fields = false
"""


def all_cases():
    cases = {case_name(c, 28, 0.02): (c, 28, 0.02) for c in STUDY_C}
    cases.update({case_name(0.1, n, 0.02): (0.1, n, 0.02) for n in STUDY_M})
    cases.update({case_name(0.1, 28, dt): (0.1, 28, dt) for dt in STUDY_T})
    return cases


def run(build, work, name, text):
    directory = os.path.join(work, name)
    if os.path.exists(os.path.join(directory, "summary.json")):
        return directory
    os.makedirs(work, exist_ok=True)
    path = os.path.join(work, name + ".toml")
    with open(path, "w") as f:
        f.write(text)
    subprocess.run([os.path.join(build, "softflow"), "run", path, "-o", directory, "-q",
                    "--overwrite"], check=False)
    return directory


def load(directory):
    summary_path = os.path.join(directory, "summary.json")
    if not os.path.exists(summary_path):
        return None
    summary = json.load(open(summary_path))
    rows = list(csv.DictReader(open(os.path.join(directory, "timeseries.csv"))))
    stress = list(csv.DictReader(open(os.path.join(directory, "stress.csv"))))
    t = [float(r["t"]) for r in rows]
    tail = [r for r in rows if float(r["t"]) >= t[-1] - WINDOW]
    stress_tail = [r for r in stress if float(r["t"]) >= t[-1] - WINDOW]
    mean = lambda rs, key: sum(float(r[key]) for r in rs) / len(rs)  # noqa: E731
    d_tail = [float(r["D"]) for r in tail]
    return {
        "t": t, "D": [float(r["D"]) for r in rows], "theta": [float(r["theta_deg"]) for r in rows],
        "D_steady": mean(tail, "D"), "D_amplitude": (max(d_tail) - min(d_tail)) / 2,
        "theta_steady": mean(tail, "theta_deg"),
        "stress": {k: mean(stress_tail, k) for k in ("tau_xx", "tau_yy", "tau_zz", "tau_xy", "N1",
                                                     "tau_1", "tau_2", "tau_3", "spread")},
        "deviation": float(rows[-1]["ellipsoid_dev"]),
        "volume_drift": float(rows[-1]["volume"]) / float(rows[0]["volume"]) - 1.0,
        "wall": summary["wall_seconds"], "unknowns": summary["unknowns"], "steps": summary["steps"],
        "status": summary["status"], "end": t[-1],
    }


def roscoe_d(ca_e):
    return 1.25 * ca_e


def roscoe_theta(ca_e):
    return math.degrees(math.pi / 4 - 0.75 * ca_e)


def report(work):
    os.makedirs(OUT, exist_ok=True)
    results = {name: load(os.path.join(work, name)) for name in all_cases()}
    md = ["# Neo-Hookean elastic particle in unbounded shear (thesis §2.5.4, Figs. 2.13-2.15)", "",
          "Unit sphere, no interfacial tension, Newtonian matrix (eta_m = 1, shear rate 1), box "
          "30 x 30 x 30 (15 diameters), periodic in x and z. Steady values: means over the last "
          "2 pi time units of each run (to the t shown in the status column); `D ampl.` is the "
          "half-amplitude of D over that window. Generated by `scripts/validation/elastic_particle.py`.", "",
          "## Steady D and theta vs Ca_e (28 equator nodes, dt = 0.02)", "",
          "| Ca_e | unknowns | D | D ampl. | Roscoe D = 5/4 Ca_e | D / Roscoe - 1 | theta [deg] | Roscoe theta [deg] | theta - Roscoe [deg] | ellipsoid dev. | volume drift | wall time [s] | status |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    csv_rows = []
    for c in STUDY_C:
        r = results[case_name(c, 28, 0.02)]
        if r is None:
            md.append(f"| {c:g} | | | | {roscoe_d(c):.4f} | | | {roscoe_theta(c):.2f} | | | | | not run |")
            continue
        md.append(f"| {c:g} | {r['unknowns']} | {r['D_steady']:.4f} | {r['D_amplitude']:.1e} | "
                  f"{roscoe_d(c):.4f} | {r['D_steady'] / roscoe_d(c) - 1:+.1%} | {r['theta_steady']:.2f} | "
                  f"{roscoe_theta(c):.2f} | {r['theta_steady'] - roscoe_theta(c):+.2f} | "
                  f"{r['deviation']:.1e} | {r['volume_drift']:+.1e} | {r['wall']:.0f} | {r['status']} (t = {r['end']:g}) |")
    md += ["", "## Stress inside the particle (Fig. 2.15), in units of eta_m gamma_dot", "",
           "Volume average of tau = G (B - I) over the particle, its principal values, and the "
           "spread sqrt(<|tau - <tau>|^2>) / |<tau>| (0 = uniform). As Ca_e -> 0 the particle "
           "acts as a rigid sphere, whose volume-averaged deviatoric stress is its stresslet over "
           "its volume, 5 eta_m E (Batchelor 1970): <tau_xy> -> 5/2 eta_m gamma_dot.", "",
           "| Ca_e | tau_xx | tau_yy | tau_zz | tau_xy | tau_xy / 2.5 - 1 | N1 | tau_1 | tau_2 | tau_3 | spread |",
           "|---|---|---|---|---|---|---|---|---|---|---|"]
    for c in STUDY_C:
        r = results[case_name(c, 28, 0.02)]
        if r is None:
            continue
        s = r["stress"]
        md.append(f"| {c:g} | " + " | ".join(f"{s[k]:.4f}" for k in ("tau_xx", "tau_yy", "tau_zz", "tau_xy")) +
                  f" | {s['tau_xy'] / 2.5 - 1:+.1%} | " +
                  " | ".join(f"{s[k]:.4f}" for k in ("N1", "tau_1", "tau_2", "tau_3")) +
                  f" | {s['spread']:.3f} |")
    for title, rows, key in (
            ("## Mesh study at Ca_e = 0.1 (dt = 0.02; equator nodes, far size and growth refined together)",
             [(case_name(0.1, n, 0.02), f"{n} / {MESHES[n][1]:g} / {MESHES[n][2]:g}") for n in STUDY_M],
             "equator nodes / far size / growth"),
            ("## Time-step study at Ca_e = 0.1 (28 equator nodes)",
             [(case_name(0.1, 28, dt), f"{dt:g}") for dt in STUDY_T], "dt")):
        md += ["", title, "", f"| {key} | unknowns | D | D ampl. | theta [deg] | spread | wall time [s] | status |",
               "|---|---|---|---|---|---|---|---|"]
        values = []
        for name, label in rows:
            r = results[name]
            if r is None:
                md.append(f"| {label} | | | | | | | not run |")
                continue
            values.append(r["D_steady"])
            md.append(f"| {label} | {r['unknowns']} | {r['D_steady']:.5f} | {r['D_amplitude']:.1e} | "
                      f"{r['theta_steady']:.3f} | {r['stress']['spread']:.3f} | {r['wall']:.0f} | {r['status']} |")
        if len(values) == 3 and values[1] != values[2] and (values[0] - values[1]) / (values[1] - values[2]) > 0:
            ratio = (values[0] - values[1]) / (values[1] - values[2])
            factor = 1.4 if "Mesh" in title else 2.0
            md += ["", f"Differences {values[0] - values[1]:+.2e}, {values[1] - values[2]:+.2e}: observed order "
                   f"{math.log(ratio) / math.log(factor):.2f} (refinement factor {factor:g})."]
    for name, (c, n, dt) in all_cases().items():
        r = results[name]
        if r:
            csv_rows.append([c, n, dt, r["unknowns"], r["D_steady"], r["D_amplitude"], r["theta_steady"],
                             r["stress"]["tau_xy"], r["stress"]["N1"], r["stress"]["spread"], r["volume_drift"],
                             r["wall"], r["status"]])
    with open(os.path.join(OUT, "elastic_particle.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["Ca_e", "equator_nodes", "dt", "unknowns", "D", "D_amplitude", "theta_deg", "tau_xy",
                    "N1", "stress_spread", "volume_drift", "wall_seconds", "status"])
        w.writerows(csv_rows)

    fig, axes = plt.subplots(1, 4, figsize=(19, 4.2))
    cs, ds, ths = [], [], []
    for c in STUDY_C:
        r = results[case_name(c, 28, 0.02)]
        if r is None:
            continue
        axes[0].plot(r["t"], r["D"], label=f"Ca_e = {c:g}")
        axes[1].plot(r["t"][1:], r["theta"][1:], label=f"Ca_e = {c:g}")
        cs.append(c)
        ds.append(r["D_steady"])
        ths.append(r["theta_steady"])
    axes[0].set(xlabel="t gamma_dot", ylabel="D", title="D(t) (Fig. 2.13a)")
    axes[1].set(xlabel="t gamma_dot", ylabel="theta [deg]", title="theta(t) (Fig. 2.13b)")
    grid = [i * 0.5 / 50 for i in range(51)]
    axes[2].plot(cs, ds, "o", label="softflow")
    axes[2].plot(grid, [roscoe_d(c) for c in grid], "--", color="gray", label="5/4 Ca_e (Roscoe, small Ca_e)")
    axes[2].set(xlabel="Ca_e", ylabel="steady D", title="D vs Ca_e (Fig. 2.14a)")
    axes[3].plot(cs, ths, "o", label="softflow")
    axes[3].plot(grid, [roscoe_theta(c) for c in grid], "--", color="gray", label="45 deg - 3/4 Ca_e rad")
    axes[3].set(xlabel="Ca_e", ylabel="steady theta [deg]", title="theta vs Ca_e (Fig. 2.14b)")
    for a in axes:
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "elastic_particle.png"), dpi=110)
    with open(os.path.join(OUT, "elastic_particle.md"), "w") as f:
        f.write("\n".join(md) + "\n\n![elastic particle](elastic_particle.png)\n")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    parser.add_argument("work", nargs="?", default=os.path.join(ROOT, "output", "validation_elastic_particle"))
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--report-only", action="store_true")
    args = parser.parse_args()
    if not args.report_only:
        jobs = [(name, case_text(name, *spec)) for name, spec in all_cases().items()]
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            list(pool.map(lambda j: run(args.build, args.work, *j), jobs))
    report(args.work)


if __name__ == "__main__":
    main()
