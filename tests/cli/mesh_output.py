#!/usr/bin/env python3
"""`softflow mesh CASE -o DIR`: the mesh written to look at before a run.

Usage: mesh_output.py SOFTFLOW CASE WORK_DIR SCRIPTS_DIR

1. The directory holds mesh.pvd, one piece per region, mesh.json and
   case.toml; the pieces' cells add up to the report's tetrahedra, their
   cell data "quality" has the report's min quality, and the mesh is the
   one `softflow mesh` reports without -o (same fingerprint).
2. The drop's piece, read by scripts/validation/vtu_pieces.py: its boundary
   surface (6-node triangles, drawn as four flat ones each) is the unit
   sphere's interface (every node at radius 1 to round-off), its normals
   point outwards, and it is closed: the volume it bounds equals, to
   round-off, that of the piece's tetrahedra each split into the eight
   straight ones through its edge nodes. Cut along its quadratic map into
   n^2 flat triangles per curved one (n = 2, 4, 8, 16), its area converges
   at second order (successive differences falling 4-fold), n = 2 being the
   drawing through the nodes.
3. A second call replaces its own earlier mesh, and an empty directory is
   filled; a run's output directory is refused (exit 1, naming --output)
   and left as it was; an empty -o is refused.
"""
import json
import os
import shutil
import sys

import numpy as np

from cli_support import fail, run


def eight_tets(cell):
    """The quadratic tetrahedron's eight straight ones through its edge nodes
    (4..9 on (0,1), (1,2), (0,2), (0,3), (1,3), (2,3)): the four at its
    corners and the inner octahedron cut along (0,2)-(1,3)."""
    v0, v1, v2, v3, e01, e12, e02, e03, e13, e23 = cell
    return [(v0, e01, e02, e03), (v1, e01, e12, e13), (v2, e02, e12, e23), (v3, e03, e13, e23),
            (e02, e13, e01, e12), (e02, e13, e12, e23), (e02, e13, e23, e03), (e02, e13, e03, e01)]


def tet_volume(p):
    return np.dot(np.cross(p[1] - p[0], p[2] - p[0]), p[3] - p[0]) / 6.0


def main(softflow, case, work, scripts):
    sys.path.insert(0, scripts)
    import vtu_pieces

    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    out = os.path.join(work, "mesh")

    # 1. The files and the report.
    plain = run([softflow, "mesh", case]).stdout
    written = run([softflow, "mesh", case, "-o", out]).stdout
    for name in ("mesh.pvd", "matrix.vtu", "object_1.vtu", "mesh.json", "case.toml"):
        if not os.path.exists(os.path.join(out, name)):
            fail(f"mesh -o wrote no {name}: {sorted(os.listdir(out))}")
    with open(os.path.join(out, "mesh.json")) as f:
        report = json.load(f)
    if f"fingerprint {report['fingerprint']}" not in plain or f"fingerprint {report['fingerprint']}" not in written:
        fail(f"mesh -o meshed another mesh than softflow mesh: {report['fingerprint']}\n{plain}\n{written}")
    pieces = [vtu_pieces.read_piece(os.path.join(out, n)) for n in ("matrix.vtu", "object_1.vtu")]
    cells = sum(len(p["cells"]) for p in pieces)
    if cells != report["tetrahedra"]:
        fail(f"the pieces have {cells} cells, the report {report['tetrahedra']} tetrahedra")
    worst = min(p["cell_data"]["quality"].min() for p in pieces)
    if abs(worst - report["min_quality"]) > 1e-12:
        fail(f"the pieces' worst quality {worst} is not the report's {report['min_quality']}")
    print(f"1. {cells} cells in 2 pieces, worst quality {worst:.4f}, fingerprint {report['fingerprint']}: ok")

    # 2. The drop's surface from its piece (the case's drop: radius 1 at the origin).
    drop = pieces[1]
    points = drop["points"]
    faces = vtu_pieces.boundary_faces(drop["cells"], points)
    radius_error = np.abs(np.linalg.norm(points[faces], axis=2) - 1.0).max()
    if radius_error > 1e-12:
        fail(f"the drop's boundary has nodes off its sphere by {radius_error:.2e}")
    triangles = vtu_pieces.flat_triangles(faces)
    area, normal = vtu_pieces.triangle_geometry(points, triangles)
    centroids = points[triangles].mean(axis=1)
    inward = (np.einsum("ij,ij->i", normal, centroids) <= 0).sum()
    if inward:
        fail(f"{inward} of {len(triangles)} surface triangles point inwards")
    bounded = (area * np.einsum("ij,ij->i", centroids, normal)).sum() / 3.0
    split = sum(abs(tet_volume(points[list(t)])) for cell in drop["cells"] for t in eight_tets(cell))
    if abs(bounded / split - 1) > 1e-12:
        fail(f"the drop's surface bounds {bounded!r}, its tetrahedra fill {split!r}: not its closed boundary")
    areas = [vtu_pieces.corner_geometry(vtu_pieces.subdivided_triangles(points, faces, n))[0].sum()
             for n in (2, 4, 8, 16)]
    if abs(areas[0] / area.sum() - 1) > 1e-12:
        fail(f"n = 2 along the map: area {areas[0]!r}, through the nodes {area.sum()!r}")
    ratios = [(areas[k + 1] - areas[k]) / (areas[k + 2] - areas[k + 1]) for k in range(2)]
    if not all(3.5 < r < 4.5 for r in ratios):
        fail(f"the curved surface's area does not converge at second order: {areas}, ratios {ratios}")
    print(f"2. drop surface: {len(faces)} curved triangles on the sphere to {radius_error:.1e}, all outward, "
          f"closed (volume {bounded:.6f} = its {len(drop['cells'])} tetrahedra's to {abs(bounded / split - 1):.1e}), "
          f"area along the map converging 4-fold ({ratios[0]:.2f}, {ratios[1]:.2f}): ok")

    # 3. Replacing, refusing.
    run([softflow, "mesh", case, "-o", out, "-q"])
    run_dir = os.path.join(work, "run")
    os.makedirs(run_dir)
    with open(os.path.join(run_dir, "summary.json"), "w") as f:
        f.write("{}\n")
    refused = run([softflow, "mesh", case, "-o", run_dir], expect=1)
    if "--output" not in refused.stderr or sorted(os.listdir(run_dir)) != ["summary.json"]:
        fail(f"a run's directory: {refused.stderr!r}, left {sorted(os.listdir(run_dir))}")
    new_dir = os.path.join(work, "made_by_hand")
    os.makedirs(new_dir)
    run([softflow, "mesh", case, "-o", new_dir, "-q"])
    if "mesh.pvd" not in os.listdir(new_dir):
        fail(f"an empty directory was not filled: {os.listdir(new_dir)}")
    empty = run([softflow, "mesh", case, "-o", ""], expect=1)
    if "-o/--output" not in empty.stderr:
        fail(f"an empty -o: {empty.stderr!r}")
    print("3. an earlier mesh and an empty directory replaced, a run's directory and an empty -o refused: ok")


if __name__ == "__main__":
    main(*sys.argv[1:5])
