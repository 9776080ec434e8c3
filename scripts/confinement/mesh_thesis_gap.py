#!/usr/bin/env python3
"""Meshes the thesis's closest start (ch. 3, Fig. 3.5: beta = 0.4, y_p0 = 0.27 H,
a gap of 0.03 H to the upper wall) at several equator-node counts and gaps,
and prints a Markdown table: nodes, tetrahedra, minimum quality, meshing
time, and how the gap was meshed (elements across it, tetrahedra crossed).

usage: mesh_thesis_gap.py SOFTFLOW [--nodes 16,20,24,28] [--gaps 0.03]
                          [--wall-size 0.5] [--work DIR]

Lengths are in R = 1 (H = 2R / beta = 5), so y_p0 = 0.27 H is y = 1.35;
--gaps are in units of H (y_p0 = 0.5 - beta / 2 - gap). The box is 10
particle diameters long and wide (thesis §3.1). Each mesh is a fresh
`softflow mesh` process (meshes are reproducible per process).
"""
import argparse
import os
import re
import subprocess
import sys

parser = argparse.ArgumentParser()
parser.add_argument("softflow")
parser.add_argument("--nodes", default="16,20,24,28")
parser.add_argument("--gaps", default="0.03")
parser.add_argument("--beta", type=float, default=0.4)
parser.add_argument("--gap-elements", type=int, default=2)
parser.add_argument("--wall-size", type=float, default=None)
parser.add_argument("--far-size", type=float, default=2.0)
parser.add_argument("--work", default="/tmp/softflow_confinement_meshes")
args = parser.parse_args()
os.makedirs(args.work, exist_ok=True)

height = 2.0 / args.beta
print("| N | gap / H | y_p0 / H | nodes | tetrahedra | min quality | seconds | elements across | "
      "tetrahedra crossed |")
print("|---|---|---|---|---|---|---|---|---|")
for gap in (float(g) for g in args.gaps.split(",")):
    y_p0 = 0.5 - args.beta / 2 - gap
    for n in (int(x) for x in args.nodes.split(",")):
        text = f"""[cell]
length = 20.0
width = 20.0
blockage_ratio = {args.beta}
[[objects]]
model = "neo_hookean"
elastic_capillary_number = 0.1
centre = [0.0, {y_p0 * height!r}, 0.0]
[mesh]
equator_nodes = {n}
far_size = {args.far_size}
gap_elements = {args.gap_elements}
"""
        if args.wall_size:
            text += f"wall_size = {args.wall_size}\n"
        path = os.path.join(args.work, f"n{n}_gap{gap}.toml")
        with open(path, "w") as f:
            f.write(text)
        r = subprocess.run([args.softflow, "mesh", path], capture_output=True, text=True)
        if r.returncode != 0:
            print(f"| {n} | {gap:g} | {y_p0:.4g} | refused or failed: {r.stderr.strip()} |||||")
            continue
        m = re.search(r"mesh: (\d+) nodes, (\d+) tetrahedra.*min quality ([\d.]+), ([\d.]+) s", r.stdout)
        g = re.search(r"([\d.]+) elements across .* (\d+) tetrahedra crossed", r.stdout)
        across, crossed = (g.group(1), g.group(2)) if g else ("(not refined)", "")
        print(f"| {n} | {gap:g} | {y_p0:.4g} | {m.group(1)} | {m.group(2)} | {m.group(3)} | "
              f"{m.group(4)} | {across} | {crossed} |")
        sys.stdout.flush()
