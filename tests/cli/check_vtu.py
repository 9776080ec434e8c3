#!/usr/bin/env python3
"""Checks that fields.pvd and the VTU pieces it lists are well formed:
XML parses, every inline base64 array decodes to the size its header states,
points/velocity/pressure/connectivity sizes agree, cells are quadratic tets
(type 24) with in-range indices, and values are finite."""
import base64
import math
import os
import struct
import sys
import xml.etree.ElementTree as ET

TYPES = {"Float64": "d", "Int32": "i", "UInt8": "B"}


def decode(array):
    raw = base64.b64decode(array.text.strip())
    (nbytes,) = struct.unpack("<I", raw[:4])
    code = TYPES[array.get("type")]
    size = struct.calcsize(code)
    assert len(raw) - 4 == nbytes, f"{array.get('Name')}: header says {nbytes} bytes, has {len(raw) - 4}"
    return struct.unpack("<" + code * (nbytes // size), raw[4:])


def check_piece(path):
    piece = ET.parse(path).getroot().find("UnstructuredGrid/Piece")
    n_points, n_cells = int(piece.get("NumberOfPoints")), int(piece.get("NumberOfCells"))
    arrays = {a.get("Name"): decode(a) for a in piece.iter("DataArray")}
    assert len(arrays["Points"]) == 3 * n_points
    assert len(arrays["velocity"]) == 3 * n_points
    assert len(arrays["pressure"]) == n_points
    assert len(arrays["connectivity"]) == 10 * n_cells
    assert arrays["offsets"][-1] == 10 * n_cells
    assert set(arrays["types"]) == {24}
    assert 0 <= min(arrays["connectivity"]) and max(arrays["connectivity"]) < n_points
    for name in ("Points", "velocity", "pressure"):
        assert all(math.isfinite(v) for v in arrays[name]), f"{name} has NaN/Inf"
    return n_points, n_cells


def main(directory):
    pvd = ET.parse(os.path.join(directory, "fields.pvd")).getroot()
    files = [d.get("file") for d in pvd.iter("DataSet")]
    assert files, "fields.pvd lists no data sets"
    for f in files:
        n_points, n_cells = check_piece(os.path.join(directory, f))
        print(f"{f}: {n_points} points, {n_cells} quadratic tetrahedra: ok")


if __name__ == "__main__":
    main(sys.argv[1])
