#!/usr/bin/python3
"""The computational domain of an emulsion and its mesh (thesis Figs. 4.2 and
4.10, both at phi = 0.05): the configuration of
scripts/validation/emulsion_moduli_phi.py at phi = 0.05 (seed 1: drops of
R = 1 placed by random sequential addition in a centred core cube of side 8
of a 12^3 cell, gaps >= 0.1 R, 14 equator nodes, far size 1.5), meshed by
`softflow mesh -o` and read back with vtu_pieces.py. Fig. 4.2: the drops in
the cell; Fig. 4.10: the surface elements on the drops and on three faces of
the cell. Beside them, measured on the written mesh: the drops' count and
volume fraction (from the volumes their curved surfaces bound), their
surface triangles and node spacing against the thesis's
Delta x* = 2 pi / 16, and the element quality.
Writes docs/validation/emulsion_geometry.{md,png}.
Usage: scripts/validation/emulsion_geometry.py [build_dir] [work_dir] [--jobs N] [--report-only]"""
import glob
import json
import os
import subprocess

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection  # noqa: E402

import vtu_pieces  # noqa: E402
from case_runs import validation_main  # noqa: E402
from emulsion_moduli_phi import case_text, name  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "docs", "validation")
PHI, SEED, LAMBDA, NODES = 0.05, 1, 1.0, 14
CELL, CORE = 12.0, 8.0
THESIS_SPACING = 2 * np.pi / 16  # Fig. 4.10's caption: Delta x* of the drops' surface triangles
NAME = name(LAMBDA, PHI, SEED, NODES)  # the moduli study's own case


def jobs():
    return [(NAME, case_text(LAMBDA, PHI, SEED, NODES))]


def mesh_runner(build, work, name, text):
    """`softflow mesh -o`, unless the directory holds the mesh of this very case text."""
    os.makedirs(work, exist_ok=True)
    case = os.path.join(work, name + ".toml")
    out = os.path.join(work, name)
    if os.path.exists(os.path.join(out, "mesh.json")) and os.path.exists(case) and open(case).read() == text:
        return
    with open(case, "w") as f:
        f.write(text)
    subprocess.run([os.path.join(build, "softflow"), "mesh", case, "-o", out], check=True)


def surfaces(directory):
    """Each drop's piece: points, curved boundary faces, the flat triangles drawing them, areas, normals."""
    drops = []
    for path in sorted(glob.glob(os.path.join(directory, "object_*.vtu")),
                       key=lambda p: int(os.path.basename(p)[7:-4])):
        piece = vtu_pieces.read_piece(path)
        faces = vtu_pieces.boundary_faces(piece["cells"], piece["points"])
        flat = vtu_pieces.flat_triangles(faces)
        area, normal = vtu_pieces.triangle_geometry(piece["points"], flat)
        centroids = piece["points"][flat].mean(axis=1)
        volume = (area * np.einsum("ij,ij->i", centroids, normal)).sum() / 3.0
        centre = (area[:, None] * centroids).sum(axis=0) / area.sum()
        drops.append({"points": piece["points"], "faces": faces, "flat": flat, "normal": normal,
                      "volume": volume, "centre": centre, "quality": piece["cell_data"]["quality"]})
    return drops


def node_spacing(drop):
    """The chords from the surface triangles' vertices to their edge nodes (the
    distances between neighbouring P2 nodes): their mean and their largest."""
    p, f = drop["points"], drop["faces"]
    chords = np.concatenate([np.linalg.norm(p[f[:, a]] - p[f[:, e]], axis=1)
                             for a, e in ((0, 3), (1, 3), (1, 4), (2, 4), (2, 5), (0, 5))])
    return float(chords.mean()), float(chords.max())


# The view, and the cell's faces behind the drops from it (x = -L/2, y = +H/2, z = -W/2).
ELEVATION, AZIMUTH = 22, -58
BACK = ((0, -1), (1, +1), (2, -1))  # (axis, side)


def box_faces(matrix):
    """The matrix piece's boundary faces on the cell's faces behind the drops (BACK)."""
    faces = vtu_pieces.boundary_faces(matrix["cells"], matrix["points"])
    corners = matrix["points"][faces[:, :3]]
    on = np.zeros(len(faces), dtype=bool)
    for axis, side in BACK:
        on |= np.all(np.abs(corners[:, :, axis] - side * CELL / 2) < 1e-9, axis=1)
    return faces[on]


def cube_edges(side):
    h = side / 2
    corners = [np.array([x, y, z]) for x in (-h, h) for y in (-h, h) for z in (-h, h)]
    return [(a, b) for i, a in enumerate(corners) for b in corners[i + 1:] if np.sum(np.abs(a - b) > 1e-9) == 1]


def plot(drops, back, matrix_points, path):
    fig = plt.figure(figsize=(13, 6.2))
    light = np.array([0.4, 0.3, 0.85]) / np.linalg.norm([0.4, 0.3, 0.85])
    for panel in (1, 2):
        ax = fig.add_subplot(1, 2, panel, projection="3d", computed_zorder=False)  # drawn in the order added
        if panel == 2:  # the back faces first, so that the drops cover them
            ax.add_collection3d(Poly3DCollection(matrix_points[back[:, :3]], facecolors=(0.95, 0.95, 0.95),
                                                 edgecolors="0.3", linewidths=0.15))
        ax.add_collection3d(Line3DCollection(cube_edges(CELL), colors="k", linewidths=0.8))
        ax.add_collection3d(Line3DCollection(cube_edges(CORE), colors="0.5", linewidths=0.6, linestyles="--"))
        for d in drops:
            if panel == 1:  # Fig. 4.2: the drops, shaded
                shade = 0.35 + 0.6 * np.clip(d["normal"] @ light, 0, 1)
                colours = np.outer(shade, [0.35, 0.55, 0.9])
                ax.add_collection3d(Poly3DCollection(d["points"][d["flat"]], facecolors=colours, linewidths=0))
            else:  # Fig. 4.10: the surface elements (their vertex triangles)
                ax.add_collection3d(Poly3DCollection(d["points"][d["faces"][:, :3]], facecolors=(0.8, 0.85, 1.0),
                                                     edgecolors="k", linewidths=0.15))
        h = CELL / 2
        ax.set(xlim=(-h, h), ylim=(-h, h), zlim=(-h, h), xlabel="x", ylabel="y", zlabel="z")
        ax.set_box_aspect((1, 1, 1))
        ax.view_init(elev=ELEVATION, azim=AZIMUTH)
        ax.set_title("Fig. 4.2: the drops in the cell (dashed: the core cube)" if panel == 1 else
                     "Fig. 4.10: surface elements on the drops and three faces of the cell")
    fig.suptitle(f"emulsion, phi = {PHI} in the core cube (seed {SEED}), {NODES} equator nodes: softflow mesh -o")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def report(work):
    directory = os.path.join(work, NAME)
    if not os.path.exists(os.path.join(directory, "mesh.json")):
        print("no mesh to report")
        return
    mesh = json.load(open(os.path.join(directory, "mesh.json")))
    drops = surfaces(directory)
    matrix = vtu_pieces.read_piece(os.path.join(directory, "matrix.vtu"))
    back = box_faces(matrix)
    os.makedirs(OUT, exist_ok=True)
    plot(drops, back, matrix["points"], os.path.join(OUT, "emulsion_geometry.png"))
    in_core = [d for d in drops if np.all(np.abs(d["centre"]) < CORE / 2)]
    volumes = np.array([d["volume"] for d in drops])
    triangles = np.array([len(d["faces"]) for d in drops])
    spacing = np.array([node_spacing(d) for d in drops])  # (mean, largest) per drop
    quality = np.concatenate([matrix["cell_data"]["quality"]] + [d["quality"] for d in drops])
    lines = ["# The computational domain of an emulsion and its mesh (thesis Figs. 4.2, 4.10)", "",
             f"Generated by `scripts/validation/emulsion_geometry.py`: the configuration of "
             f"`emulsion_moduli_phi.py` at phi = {PHI} (seed {SEED}; drops of R = 1 by random sequential "
             f"addition in a centred core cube of side {CORE:g} of a {CELL:g}^3 cell, gaps >= 0.1 R, "
             f"{NODES} equator nodes, far size 1.5), meshed by `softflow mesh -o` and read back by "
             "`scripts/validation/vtu_pieces.py`. Volumes from the drops' curved surfaces (each 6-node "
             "triangle drawn as four flat ones through its edge nodes).", "",
             "![domain and mesh](emulsion_geometry.png)", "",
             "| quantity | softflow | thesis |", "|---|---|---|",
             f"| drops (centres in the core cube) | {len(drops)} ({len(in_core)}) | |",
             f"| phi in the core cube (drops counted by their centre): spheres, meshed surfaces | "
             f"{len(in_core) * 4 / 3 * np.pi / CORE ** 3:.4f}, {sum(d['volume'] for d in in_core) / CORE ** 3:.4f} "
             f"(asked {PHI}) | {PHI} |",
             f"| phi in the whole cell | {volumes.sum() / CELL ** 3:.4f} | |",
             f"| drop volume / (4/3 pi R^3) | {volumes.min() / (4 / 3 * np.pi):.4f} ... "
             f"{volumes.max() / (4 / 3 * np.pi):.4f} | |",
             f"| surface triangles per drop (6-node) | {triangles.min()} ... {triangles.max()} (median "
             f"{int(np.median(triangles))}) | |",
             f"| distance between neighbouring surface nodes / R: each drop's mean; the largest | "
             f"{spacing[:, 0].min():.3f} ... {spacing[:, 0].max():.3f}; {spacing[:, 1].max():.3f} "
             f"(2 pi / {NODES} = {2 * np.pi / NODES:.3f}) | Delta x* = 2 pi / 16 = {THESIS_SPACING:.3f} |",
             f"| tetrahedra, nodes | {mesh['tetrahedra']}, {mesh['nodes']} | |",
             f"| element quality: min, 1st percentile, median | {quality.min():.3f}, "
             f"{np.percentile(quality, 1):.3f}, {np.median(quality):.3f} | |",
             f"| mesh fingerprint | {mesh['fingerprint']} | |", "",
             "Every drop here is meshed finer than its 14 equator nodes say (their node spacing would be "
             f"2 pi / 14 = {2 * np.pi / NODES:.3f}): the mesher refines the surface towards the nearest drop, "
             "and each has one within half a radius, the closest pair 0.1 R apart (docs/emulsions.md); the "
             "largest spacing is on the drops' far sides. The thesis's single Delta x* is its drops' base "
             "size. The meshed volumes, drawn flat between the nodes, are 1-3 % below the spheres', most "
             "on the drops with the coarsest far sides.", ""]
    with open(os.path.join(OUT, "emulsion_geometry.md"), "w") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    validation_main("validation_emulsion_geometry", jobs, report, runner=mesh_runner)
