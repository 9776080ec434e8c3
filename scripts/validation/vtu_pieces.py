"""Reading softflow's VTU pieces (matrix.vtu, object_k.vtu: quadratic
tetrahedra, inline base64 binary with a UInt32 header) and their boundary
surfaces, for the scripts that draw meshes and shapes (thesis Figs. 3.7,
4.2, 4.10). numpy only; ParaView reads the same files."""
import base64
import xml.etree.ElementTree as ElementTree

import numpy as np

TYPES = {"Float64": np.float64, "Int32": np.int32, "UInt8": np.uint8}
# The quadratic tetrahedron's edge nodes 4..9 sit on these vertex pairs
# (mesh::kTetEdges, VTK_QUADRATIC_TETRA's order).
TET_EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
EDGE_NODE = {frozenset(e): 4 + k for k, e in enumerate(TET_EDGES)}
FACES = [(1, 2, 3, 0), (0, 2, 3, 1), (0, 1, 3, 2), (0, 1, 2, 3)]  # three vertices, then the opposite one


def decode(array):
    """A DataArray's values: base64 of a UInt32 byte count, then the bytes."""
    raw = base64.b64decode(array.text.strip())
    n = int(np.frombuffer(raw[:4], dtype=np.uint32)[0])
    values = np.frombuffer(raw[4:4 + n], dtype=TYPES[array.get("type")])
    components = int(array.get("NumberOfComponents", "1"))
    return values.reshape(-1, components) if components > 1 else values


def read_piece(path):
    """{'points': (n, 3), 'cells': (m, 10), 'point_data': {name: values}, 'cell_data': {name: values}}."""
    piece = ElementTree.parse(path).getroot().find("UnstructuredGrid/Piece")
    arrays = {a.get("Name"): a for a in piece.find("Cells")}
    cells = decode(arrays["connectivity"]).reshape(-1, 10)
    out = {"points": decode(piece.find("Points/DataArray")), "cells": cells, "point_data": {}, "cell_data": {}}
    for section, key in (("PointData", "point_data"), ("CellData", "cell_data")):
        block = piece.find(section)
        if block is not None:
            out[key] = {a.get("Name"): decode(a) for a in block}
    return out


def boundary_faces(cells, points):
    """The faces of a piece's tetrahedra that belong to one of them only, as
    6-node triangles (three vertices, then the edge nodes on (0,1), (1,2),
    (2,0)), turned so that the vertices' normal points out of the piece."""
    count = {}
    for t, cell in enumerate(cells):
        for a, b, c, d in FACES:
            key = frozenset((cell[a], cell[b], cell[c]))
            count[key] = (count[key][0] + 1, t, (a, b, c, d)) if key in count else (1, t, (a, b, c, d))
    faces = []
    for n, t, (a, b, c, d) in count.values():
        if n != 1:
            continue
        cell = cells[t]
        p = points[[cell[a], cell[b], cell[c], cell[d]]]
        if np.dot(np.cross(p[1] - p[0], p[2] - p[0]), p[3] - p[0]) > 0:
            b, c = c, b  # the opposite vertex must lie behind the face
        local = [a, b, c]
        edges = [EDGE_NODE[frozenset((local[i], local[(i + 1) % 3]))] for i in range(3)]
        faces.append([cell[k] for k in local + edges])
    return np.array(faces, dtype=np.int64).reshape(-1, 6)


def flat_triangles(faces):
    """Each 6-node triangle as four flat ones through its edge nodes
    (vertex indices into the piece's points): the curved surface drawn to
    the resolution of its nodes."""
    out = []
    for v0, v1, v2, e01, e12, e20 in faces:
        out += [(v0, e01, e20), (e01, v1, e12), (e20, e12, v2), (e01, e12, e20)]
    return np.array(out, dtype=np.int64).reshape(-1, 3)


def triangle_geometry(points, triangles):
    """Areas and unit normals of flat triangles given by indices into `points`."""
    return corner_geometry(points[triangles])


def p2_shape(l0, l1, l2):
    """The 6-node triangle's shape functions at barycentric (l0, l1, l2):
    vertices, then the edge nodes on (0,1), (1,2), (2,0)."""
    return np.array([l0 * (2 * l0 - 1), l1 * (2 * l1 - 1), l2 * (2 * l2 - 1), 4 * l0 * l1, 4 * l1 * l2, 4 * l2 * l0])


def subdivided_triangles(points, faces, n):
    """Each 6-node triangle's quadratic surface cut into n^2 flat triangles
    through points of its map on a barycentric lattice: (m n^2, 3, 3)
    corners. n = 2 gives flat_triangles' four; larger n converges to the
    curved surface (area error O(1 / n^2))."""
    lattice = {(i, j): p2_shape(1 - (i + j) / n, i / n, j / n) for i in range(n + 1) for j in range(n + 1 - i)}
    small = []
    for i in range(n):
        for j in range(n - i):
            small.append(((i, j), (i + 1, j), (i, j + 1)))
            if i + j < n - 1:
                small.append(((i + 1, j), (i + 1, j + 1), (i, j + 1)))
    nodes = points[faces]  # (m, 6, 3)
    at = {key: np.einsum("k,mkd->md", weights, nodes) for key, weights in lattice.items()}
    return np.stack([np.stack([at[a], at[b], at[c]], axis=1) for a, b, c in small], axis=1).reshape(-1, 3, 3)


def corner_geometry(corners):
    """Areas and unit normals of flat triangles given by their corners (m, 3, 3)."""
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    area = 0.5 * np.linalg.norm(cross, axis=1)
    return area, cross / (2.0 * area[:, None])
