#!/usr/bin/python3
"""G' and G'' of an emulsion against its volume fraction at omega* = 0.4 (thesis
Figs. 4.11-4.15: lambda = 0.1, 0.5, 1, 5, 100), from the frequency domain
(`softflow response`, one complex Stokes solve per configuration; issue 32).

Each point: random configurations (seeds) of monodisperse drops (R = 1,
Gamma = 1, eta_m = 1) packed by random sequential addition in a centred core
cube of side 8 of a 12^3 cell (the thesis's frame layout), at least 0.1 R
apart, 14 equator nodes, the moduli averaged over the core cube (eq. 4.1)
with drops counted by their centre; G' R / Gamma and G'' / (eta_m omega),
mean and sample standard deviation over the seeds, beside Oldroyd's
emulsion (appendix A) at the cube's mean phi. The core cube of side 8 jams
near phi = 0.24 at gaps of 0.1 R with the drops wholly inside it: the
thesis's densest points, 0.26 and 0.28, run in its own frame layout
(CENTRES: the drops' centres in the cube, the drops crossing its faces).

Beside Fig. 4.15: one drop at lambda = 100 (dilute_drop_moduli.py's drop and
cell) on 14, 20, 28 and 40 equator nodes against the dilute limit of
Oldroyd's emulsion: what the emulsion's 14-node drops can resolve of G' and
G'' when the drops are nearly rigid.

Runs lambda = 1 first (Fig. 4.13), then 5, 0.1, 0.5, 100; every configuration
is its own run (kept; a second call only reports), so the script can be
stopped and called again. Each configuration's result is also kept in the
repository (docs/validation/emulsion_moduli_phi_configurations.csv), and a
configuration found there is not run again, so that a later call on another
machine, whose work directory is empty, goes on where the last one stopped;
the points made before that record existed (lambda = 1, 5, 0.1) are carried
over from the document's own csv and table. Writes
docs/validation/emulsion_moduli_phi{.md,.csv,.png,_configurations.csv}.
Usage: scripts/validation/emulsion_moduli_phi.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import csv
import json
import os
import statistics

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import dilute_drop_moduli  # noqa: E402
from case_runs import run_response, validation_main  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
OMEGA = 0.4
LAMBDAS = [1.0, 5.0, 0.1, 0.5, 100.0]  # the order they run in
FIGURE = {0.1: "4.11", 0.5: "4.12", 1.0: "4.13", 5.0: "4.14", 100.0: "4.15"}
PHIS = [0.05, 0.10, 0.15, 0.20]
SEEDS = [1, 2, 3]
ONE_DROP_NODES = [14, 20, 28, 40]  # one drop at lambda = 100, for Fig. 4.15's resolution


# Points also run with finer drops, the same configurations (the packing's
# gaps are in drop radii, so a seed packs the same drops on any mesh):
# (lambda, phi asked, equator nodes).
FINER = [(100.0, 0.05, 20), (1.0, 0.05, 20), (5.0, 0.05, 20)]
# Points in the thesis's own frame layout ([emulsion] core_layout =
# "centres": the drops whose centres lie in the core cube, crossing its
# faces), which packs the densest points the "inside" layout above cannot:
# (lambda, phi asked), in the order they run; phi = 0.20 again beside the
# "inside" layout's point, for what the layout itself changes.
CENTRES = [(1.0, 0.28), (1.0, 0.20), (5.0, 0.28), (1.0, 0.26)]
# ... and with finer drops, the same configurations: (lambda, phi asked, equator nodes).
CENTRES_FINER = [(1.0, 0.28, 20)]


def name(lam, phi, seed, nodes=14, layout="inside"):
    suffix = ("" if nodes == 14 else f"_N{nodes}") + ("" if layout == "inside" else f"_{layout}")
    return f"lambda{lam:g}_phi{phi:.2f}_seed{seed}{suffix}"


def case_text(lam, phi, seed, nodes=14, layout="inside"):
    return f"""[case]
name = "{name(lam, phi, seed, nodes, layout)}"
[cell]
length = 12.0
height = 12.0
width = 12.0
[flow]
type = "oscillatory"
strain_amplitude = 0.05
frequency = {OMEGA}
[[objects]]
radius = 1.0
viscosity_ratio = {lam:g}
interfacial_tension = 1.0
[emulsion]
volume_fraction = {phi:.2f}
seed = {seed}
core_side = 8.0
min_gap = 0.1
core_layout = "{layout}"
[bulk_stress]
box_side = 8.0
[mesh]
equator_nodes = {nodes}
far_size = 1.5
"""


RECORD = os.path.join(OUT, "emulsion_moduli_phi_configurations.csv")
KEYS = ("box_phi", "box_G_storage_R_over_Gamma", "box_G_loss_over_eta_m_omega", "oldroyd_box_G_storage",
        "oldroyd_box_G_loss", "seconds", "iterations")


def recorded(path=None):
    """The results kept in the repository (RECORD unless `path`), by run name."""
    path = path or RECORD
    if not os.path.exists(path):
        return {}
    return {row["run"]: row for row in csv.DictReader(open(path))}


def earlier_points():
    """The points of the document made before the per-configuration record
    (their runs are gone): the csv's values with the table's wall time and
    iterations, by (lambda, phi asked)."""
    table = os.path.join(OUT, "emulsion_moduli_phi.md")
    if not os.path.exists(RECORD.replace("_configurations", "")) or not os.path.exists(table):
        return {}
    cost = {}
    for line in open(table):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 13 and cells[1].replace(".", "").isdigit():
            cost[(float(cells[1]), float(cells[2]))] = (float(cells[11]), float(cells[12]))
    points = {}
    for row in csv.DictReader(open(RECORD.replace("_configurations", ""))):
        key = (float(row["lambda"]), float(row["phi_asked"]))
        if key in cost:
            points[key] = dict(lam=key[0], phi=key[1], n=int(row["configurations"]),
                               box_phi=(float(row["box_phi"]), 0.0),
                               storage=(float(row["G_storage_R_over_Gamma"]), float(row["G_storage_std"])),
                               loss=(float(row["G_loss_over_eta_m_omega"]), float(row["G_loss_std"])),
                               oldroyd=(float(row["oldroyd_G_storage"]), float(row["oldroyd_G_loss"])),
                               seconds=cost[key][0], iterations=cost[key][1])
    return points


# The points of the earlier document that are complete (every seed) need no runs.
CARRIED = {key for key, p in earlier_points().items() if p["n"] == len(SEEDS)}


def one_drop_name(n):
    return f"one_drop_lambda100_N{n}"


def one_drop_text(n):
    text = dilute_drop_moduli.case_text(one_drop_name(n), 100.0, OMEGA, n)
    return text.replace("[bulk_stress]\nbox_side = 4.0\nfit_periods = 2\n", "")


ONE_DROP_RECORD = os.path.join(OUT, "emulsion_moduli_phi_one_drop.csv")
ONE_DROP_KEYS = ("meshed_equator_nodes", "unknowns", "c_real", "c_imag", "oldroyd_c_real", "oldroyd_c_imag", "seconds")


def one_drop_rows(work):
    """The one-drop runs: each run's own output, else its recorded row."""
    recorded_rows = recorded(ONE_DROP_RECORD)
    rows = []
    for n in ONE_DROP_NODES:
        directory = os.path.join(work, one_drop_name(n))
        if os.path.exists(os.path.join(directory, "response.csv")):
            response = next(csv.DictReader(open(os.path.join(directory, "response.csv"))))
            summary = json.load(open(os.path.join(directory, "summary.json")))
            rows.append(dict(response, run=one_drop_name(n), meshed_equator_nodes=summary["mesh"]["equator_nodes"],
                             unknowns=summary["unknowns"]))
        elif one_drop_name(n) in recorded_rows:
            rows.append(recorded_rows[one_drop_name(n)])
    return rows


def jobs():
    done = recorded()
    emulsions = [(name(lam, phi, s), case_text(lam, phi, s)) for lam in LAMBDAS for phi in PHIS for s in SEEDS
                 if (lam, phi) not in CARRIED and name(lam, phi, s) not in done]
    one_drop_done = recorded(ONE_DROP_RECORD)
    finer = [(name(lam, phi, s, n), case_text(lam, phi, s, n)) for lam, phi, n in FINER for s in SEEDS
             if name(lam, phi, s, n) not in done]
    centres = [(name(lam, phi, s, layout="centres"), case_text(lam, phi, s, layout="centres"))
               for lam, phi in CENTRES for s in SEEDS if name(lam, phi, s, layout="centres") not in done]
    centres += [(name(lam, phi, s, n, "centres"), case_text(lam, phi, s, n, "centres"))
                for lam, phi, n in CENTRES_FINER for s in SEEDS if name(lam, phi, s, n, "centres") not in done]
    return emulsions + finer + [(one_drop_name(n), one_drop_text(n)) for n in ONE_DROP_NODES
                                if one_drop_name(n) not in one_drop_done] + centres


def mean_std(values):
    return statistics.mean(values), (statistics.stdev(values) if len(values) > 1 else 0.0)


def write_record(path, keys, rows):
    """Each configuration's row (run name, then `keys`), as recorded() reads them back."""
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(("run",) + keys)
        for row in rows:
            w.writerow([row["run"]] + [row[key] for key in keys])


def read_point(work, lam, phi, record, nodes=14, layout="inside"):
    """The configurations of one point: each run's response.csv, else its recorded row."""
    rows = []
    for s in SEEDS:
        run = name(lam, phi, s, nodes, layout)
        path = os.path.join(work, run, "response.csv")
        if os.path.exists(path):
            rows.append(dict(next(csv.DictReader(open(path))), run=run))
        elif run in record:
            rows.append(record[run])
    return rows


def point(lam, phi, rows):
    """One point's mean and spread over its configurations' rows."""
    value = {key: [float(r[key]) for r in rows] for key in KEYS}
    return dict(lam=lam, phi=phi, n=len(rows), box_phi=mean_std(value["box_phi"]),
                storage=mean_std(value["box_G_storage_R_over_Gamma"]),
                loss=mean_std(value["box_G_loss_over_eta_m_omega"]),
                oldroyd=(statistics.mean(value["oldroyd_box_G_storage"]),
                         statistics.mean(value["oldroyd_box_G_loss"])),
                seconds=statistics.median(value["seconds"]), iterations=max(value["iterations"]))


def modulus(x):
    """Four decimals, or three significant digits below 0.01 (lambda = 100's G' is ~1e-4)."""
    return f"{x:.4f}" if abs(x) >= 0.01 or x == 0 else f"{x:.3g}"


def report(work):
    table, points, record, earlier = [], {}, recorded(), earlier_points()
    kept, from_runs = [], {}
    for lam in LAMBDAS:
        for phi in PHIS:
            rows = read_point(work, lam, phi, record)
            kept += rows
            if not rows:
                if (lam, phi) in earlier:
                    points.setdefault(lam, []).append(earlier[(lam, phi)])
                    table.append(earlier[(lam, phi)])
                continue
            p = from_runs[(lam, phi)] = point(lam, phi, rows)
            points.setdefault(lam, []).append(p)
            table.append(p)
    if not table:
        print("no runs to report")
        return
    lines = ["# G', G'' against the volume fraction at omega* = 0.4 (thesis Figs. 4.11-4.15)", "",
             "Generated by `scripts/validation/emulsion_moduli_phi.py`: `softflow response` (the frequency domain) on "
             "random configurations of drops (R = 1, Gamma = 1, eta_m = 1) in a core cube of side 8 of a 12^3 cell, "
             "gaps >= 0.1 R, 14 equator nodes asked (the mesher refines the drops further near gaps and faces); moduli over the core cube, mean ± sample standard deviation over the "
             "configurations; Oldroyd's emulsion (appendix A) at each configuration's cube phi, averaged. phi asked is "
             "the packing's in the core cube; the cube counts drops by their centre.", "",
             "| Fig. | lambda | phi asked | configurations | phi (cube) | G' R/Gamma | Oldroyd | ratio | "
             "G''/(eta_m omega) | Oldroyd | ratio | s per configuration (median) | FGMRES iterations (most) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for p in table:
        lines.append(f"| {FIGURE[p['lam']]} | {p['lam']:g} | {p['phi']:.2f} | {p['n']} | {p['box_phi'][0]:.4f} | "
                     f"{modulus(p['storage'][0])} ± {modulus(p['storage'][1])} | {modulus(p['oldroyd'][0])} | "
                     f"{p['storage'][0] / p['oldroyd'][0]:.3f} | {p['loss'][0]:.4f} ± {p['loss'][1]:.4f} | "
                     f"{p['oldroyd'][1]:.4f} | {p['loss'][0] / p['oldroyd'][1]:.3f} | {p['seconds']:.0f} | "
                     f"{p['iterations']:.0f} |")
    finer_lines = []
    for lam, phi, n in FINER:
        fine = read_point(work, lam, phi, record, n)
        kept += fine
        # The 14-node point only where its configurations' runs are known (not carried over).
        for nodes, p in ((14, from_runs.get((lam, phi))), (n, point(lam, phi, fine) if fine else None)):
            if p:
                finer_lines.append(
                    f"| {lam:g} | {phi:.2f} | {nodes} | {p['n']} | {modulus(p['storage'][0])} ± "
                    f"{modulus(p['storage'][1])} | {modulus(p['oldroyd'][0])} | "
                    f"{p['storage'][0] / p['oldroyd'][0]:.3f} | {p['loss'][0]:.4f} ± "
                    f"{p['loss'][1]:.4f} | {p['oldroyd'][1]:.4f} | {p['loss'][0] / p['oldroyd'][1]:.3f} | "
                    f"{p['seconds']:.0f} |")
    if finer_lines:
        lines += ["", "## Finer drops at one point", "",
                  "The same configurations (seeds) with finer drops (equator nodes; far size and the rest of the mesh "
                  "as above).", "",
                  "| lambda | phi asked | equator nodes | configurations | G' R/Gamma | Oldroyd | ratio | G''/(eta_m omega) | "
                  "Oldroyd | ratio | s per configuration |", "|---|---|---|---|---|---|---|---|---|---|---|"] + finer_lines
    centres_points = []
    for lam, phi, n in [(lam, phi, 14) for lam, phi in CENTRES] + CENTRES_FINER:
        rows = read_point(work, lam, phi, record, n, "centres")
        kept += rows
        if rows:
            centres_points.append(dict(point(lam, phi, rows), nodes=n))
    if centres_points:
        lines += ["", "## The thesis's frame layout: drops counted by their centre", "",
                  "`[emulsion] core_layout = \"centres\"`: the drops whose centres lie in the core cube (side 8), "
                  "crossing its faces, one interface element from the cell's (the thesis, ch. 4: a whole-cell "
                  "packing without the drops whose centres lie outside the cube where the moduli are computed); "
                  "phi counts the drops by their centre. It packs phi = 0.26 and 0.28, where the layout above "
                  "jams; phi = 0.20 is the layouts' comparison. The rest as above (14 equator nodes asked, "
                  "unless the row says 20: the same configurations with finer drops).", "",
                  "| Fig. | lambda | phi asked | equator nodes | configurations | phi (cube) | G' R/Gamma | Oldroyd | ratio | "
                  "G''/(eta_m omega) | Oldroyd | ratio | s per configuration (median) | FGMRES iterations (most) |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for p in centres_points:
            lines.append(f"| {FIGURE[p['lam']]} | {p['lam']:g} | {p['phi']:.2f} | {p['nodes']} | {p['n']} | {p['box_phi'][0]:.4f} | "
                         f"{modulus(p['storage'][0])} ± {modulus(p['storage'][1])} | {modulus(p['oldroyd'][0])} | "
                         f"{p['storage'][0] / p['oldroyd'][0]:.3f} | {p['loss'][0]:.4f} ± {p['loss'][1]:.4f} | "
                         f"{p['oldroyd'][1]:.4f} | {p['loss'][0] / p['oldroyd'][1]:.3f} | {p['seconds']:.0f} | "
                         f"{p['iterations']:.0f} |")
    drops = one_drop_rows(work)
    if drops:
        with open(ONE_DROP_RECORD, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(("run",) + ONE_DROP_KEYS)
            for row in drops:
                w.writerow([row["run"]] + [row[key] for key in ONE_DROP_KEYS])
        lines += ["", "## One drop at lambda = 100 on refined meshes", "",
                  "`softflow response` at omega* = 0.4 on one drop (R = Gamma = eta_m = 1, cell 24 x 16 x 24, "
                  "scripts/validation/dilute_drop_moduli.py's) against the dilute limit of Oldroyd's emulsion: "
                  "c = c' + i c'' its complex intrinsic viscosity (per unit volume fraction: G'' / (eta_m omega) = "
                  "1 + phi c', G' R / Gamma = -phi omega* c'').", "",
                  "| equator nodes (asked / meshed) | unknowns | c' | Oldroyd | c' error | -c'' | Oldroyd | -c'' error "
                  "| solve s |", "|---|---|---|---|---|---|---|---|---|"]
        for row in drops:
            cr, ci, ocr, oci = (float(row[k]) for k in ("c_real", "c_imag", "oldroyd_c_real", "oldroyd_c_imag"))
            n = row["run"].rsplit("_N", 1)[1]
            lines.append(f"| {n} / {row['meshed_equator_nodes']} | {row['unknowns']} | {cr:.4f} | {ocr:.4f} | "
                         f"{100 * (cr / ocr - 1):+.1f} % | {-ci:.3e} | {-oci:.3e} | {100 * (ci / oci - 1):+.0f} % | "
                         f"{float(row['seconds']):.0f} |")
    lines += ["", "The thesis (§4.3): lambda = 0.1 and 0.5 within 5 % of Oldroyd for G' and G'' over its phi range; "
              "lambda = 1, G' on the theory except at phi = 0.28 (17 % above), G'' on it throughout; lambda = 5, G' "
              "above the theory beyond the dilute regime by up to 25 % (phi = 0.28), G'' 5 % above there; lambda = 100, "
              "G' qualitatively like the theory only, with wide error bars."]
    os.makedirs(OUT, exist_ok=True)
    write_record(RECORD, KEYS, kept)
    with open(os.path.join(OUT, "emulsion_moduli_phi.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(OUT, "emulsion_moduli_phi.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["lambda", "phi_asked", "configurations", "box_phi", "G_storage_R_over_Gamma", "G_storage_std",
                    "oldroyd_G_storage", "G_loss_over_eta_m_omega", "G_loss_std", "oldroyd_G_loss"])
        for p in table:
            w.writerow([p["lam"], p["phi"], p["n"], f"{p['box_phi'][0]:.6g}", f"{p['storage'][0]:.6g}",
                        f"{p['storage'][1]:.3g}", f"{p['oldroyd'][0]:.6g}", f"{p['loss'][0]:.6g}",
                        f"{p['loss'][1]:.3g}", f"{p['oldroyd'][1]:.6g}"])
    print("\n".join(lines))
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.4))
    for k, (lam, ps) in enumerate(points.items()):
        x = [p["box_phi"][0] for p in ps]
        for a, key, theory in ((ax[0], "storage", 0), (ax[1], "loss", 1)):
            a.errorbar(x, [p[key][0] for p in ps], yerr=[p[key][1] for p in ps], fmt="o", color=f"C{k}", capsize=3,
                       label=f"lambda = {lam:g} (Fig. {FIGURE[lam]})")
            a.plot(x, [p["oldroyd"][theory] for p in ps], "--", color=f"C{k}", lw=0.9)
    colour = {lam: f"C{k}" for k, lam in enumerate(points)}
    for p in (p for p in centres_points if p["nodes"] == 14):
        for a, key in ((ax[0], "storage"), (ax[1], "loss")):
            a.errorbar([p["box_phi"][0]], [p[key][0]], yerr=[p[key][1]], fmt="s", mfc="none", capsize=3,
                       color=colour.get(p["lam"], "k"))
    if centres_points:
        ax[0].plot([], [], "ks", mfc="none", label="frame layout: centres in the cube")
    ax[0].plot([], [], "k--", lw=0.9, label="Oldroyd (appendix A)")
    ax[0].set(xlabel="phi (cube)", ylabel="G' R / Gamma", title=f"storage, omega* = {OMEGA:g}")
    ax[1].set(xlabel="phi (cube)", ylabel="G'' / (eta_m omega)", title=f"loss, omega* = {OMEGA:g}")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "emulsion_moduli_phi.png"), dpi=120)


if __name__ == "__main__":
    validation_main("validation_emulsion_moduli_phi", jobs, report, runner=run_response)
