#!/usr/bin/env python3
"""Damaged checkpoints that passed (issue 33, defect 3), through the program.

Usage: corrupt_checkpoint.py SOFTFLOW CASE.toml WORK_DIR   (CASE: the coarse drop_short case)

Fletcher32 checks each chunk HDF5 finds, not that its chunk index finds the
right one. A run stopped by SIGTERM at step 4 leaves a checkpoint whose
/state/time_loop/nodes (the moved mesh) and previous_nodes (the step before)
are chunks of one size. Two damages, each in a copy of the run:

1. the chunk index: the entry of nodes' chunk points at previous_nodes'
   chunk (its 8-byte address, wherever the format keeps it);
2. the chunk: nodes' values replaced by previous_nodes' through HDF5 (a
   valid chunk, Fletcher32 and all, that is not what was written).

Both passed before (format 4): the restart read the wrong nodes without a
word and exited 0. Now `softflow restart` must exit 1 saying "corrupt checkpoint"
and naming the file, and print no "HDF5: infinite loop closing library".
An intact copy restarts (exit 0).

HDF5 is reached through ctypes (the library softflow links), for chunk
addresses and the rewrite; nothing else is needed.
"""
import ctypes
import ctypes.util
import os
import shutil
import signal
import subprocess
import sys

import cli_support as support
from cli_support import fail

INTERRUPTED = 5
NODES = b"/state/time_loop/nodes"
PREVIOUS = b"/state/time_loop/previous_nodes"


def hdf5_library(softflow):
    """The HDF5 library softflow is linked with (another one could clash)."""
    linked = subprocess.run(["ldd", softflow], capture_output=True, text=True).stdout
    for line in linked.splitlines():
        if "libhdf5" in line and "=>" in line:
            path = line.split("=>")[1].split("(")[0].strip()
            break
    else:
        path = ctypes.util.find_library("hdf5_openmpi") or ctypes.util.find_library("hdf5")
    if not path:
        fail("cannot find the HDF5 library softflow uses")
    lib = ctypes.CDLL(path)
    hid = ctypes.c_int64
    for name, args in [("H5Fopen", [ctypes.c_char_p, ctypes.c_uint, hid]),
                       ("H5Dopen2", [hid, ctypes.c_char_p, hid]),
                       ("H5Dget_space", [hid])]:
        getattr(lib, name).restype = hid
        getattr(lib, name).argtypes = args
    for name in ("H5Fclose", "H5Dclose", "H5Sclose"):
        getattr(lib, name).argtypes = [hid]
    lib.H5Dget_chunk_info.argtypes = [hid, hid, ctypes.c_uint64, ctypes.c_void_p,
                                      ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]
    lib.H5Dread.argtypes = [hid, hid, hid, hid, hid, ctypes.c_void_p]
    lib.H5Dwrite.argtypes = [hid, hid, hid, hid, hid, ctypes.c_void_p]
    lib.H5open()
    return lib


def first_chunk(lib, path, dataset):
    """(address, size) of the dataset's first chunk."""
    file = lib.H5Fopen(path.encode(), 0, 0)  # H5F_ACC_RDONLY, H5P_DEFAULT
    dset = lib.H5Dopen2(file, dataset, 0)
    space = lib.H5Dget_space(dset)
    if min(file, dset, space) < 0:
        fail(f"{path}: cannot open {dataset.decode()}")
    offset = (ctypes.c_uint64 * 2)()
    mask, address, size = ctypes.c_uint(), ctypes.c_uint64(), ctypes.c_uint64()
    status = lib.H5Dget_chunk_info(dset, space, 0, offset, ctypes.byref(mask),
                                   ctypes.byref(address), ctypes.byref(size))
    lib.H5Sclose(space)
    lib.H5Dclose(dset)
    lib.H5Fclose(file)
    if status < 0:
        fail(f"{path}: no chunk information for {dataset.decode()}")
    return address.value, size.value


def point_index_elsewhere(lib, path):
    """Damage 1: nodes' chunk address, in the index, becomes previous_nodes'."""
    nodes, nodes_size = first_chunk(lib, path, NODES)
    previous, previous_size = first_chunk(lib, path, PREVIOUS)
    with open(path, "rb") as f:
        data = bytearray(f.read())
    if nodes_size != previous_size or data[nodes:nodes + nodes_size] == \
            data[previous:previous + previous_size]:
        fail("nodes and previous_nodes: not two different chunks of one size")
    entry = nodes.to_bytes(8, "little")
    if data.count(entry) != 1:
        fail(f"the address {nodes} of nodes' chunk is {data.count(entry)} times in the file")
    at = data.find(entry)
    data[at:at + 8] = previous.to_bytes(8, "little")
    with open(path, "wb") as f:
        f.write(data)
    return at


def replace_chunk(lib, path):
    """Damage 2: nodes' values become previous_nodes', written through HDF5."""
    _, size = first_chunk(lib, path, PREVIOUS)  # one chunk: the values and their Fletcher32
    values = ctypes.create_string_buffer(size)
    file = lib.H5Fopen(path.encode(), 1, 0)  # H5F_ACC_RDWR
    nodes, previous = lib.H5Dopen2(file, NODES, 0), lib.H5Dopen2(file, PREVIOUS, 0)
    double = ctypes.c_int64.in_dll(lib, "H5T_NATIVE_DOUBLE_g")
    if min(file, nodes, previous) < 0 or lib.H5Dread(previous, double, 0, 0, 0, values) < 0 or \
            lib.H5Dwrite(nodes, double, 0, 0, 0, values) < 0:  # H5S_ALL, H5P_DEFAULT
        fail(f"{path}: cannot rewrite {NODES.decode()}")
    lib.H5Dclose(previous)
    lib.H5Dclose(nodes)
    lib.H5Fclose(file)


def restart_refuses(softflow, directory, what, names=""):
    result = subprocess.run([softflow, "restart", directory, "-q"], capture_output=True, text=True)
    message = result.stderr.strip()
    if result.returncode != 1 or "corrupt checkpoint" not in message or \
            os.path.join(directory, "checkpoint.h5") not in message or names not in message:
        fail(f"{what}: exit code {result.returncode}, expected 1 with 'corrupt checkpoint', the "
             f"file{' and ' + names if names else ''}:\n{result.stdout[-2000:]}\n{message}")
    if "infinite loop" in result.stderr:
        fail(f"{what}: HDF5's exit report follows the message:\n{message}")
    print(f"{what}: exit 1, {message.splitlines()[0][:200]}")


def main(softflow, case_source, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    with open(case_source) as f:
        text = f.read()
    case = os.path.join(work, "case.toml")
    with open(case, "w") as f:
        f.write(text)
    stopped = os.path.join(work, "stopped")
    code, output = support.stop_when_past([softflow, "run", case, "-o", stopped, "-q"], stopped, 4,
                                          signal.SIGTERM)
    if code != INTERRUPTED:
        fail(f"SIGTERM: exit code {code}, expected {INTERRUPTED}\n{output}")
    lib = hdf5_library(softflow)

    index = os.path.join(work, "index")
    shutil.copytree(stopped, index)
    at = point_index_elsewhere(lib, os.path.join(index, "checkpoint.h5"))
    print(f"chunk index: nodes' chunk address at byte {at} now points at previous_nodes' chunk")
    restart_refuses(softflow, index, "a chunk index pointing at another chunk")

    chunk = os.path.join(work, "chunk")
    shutil.copytree(stopped, chunk)
    replace_chunk(lib, os.path.join(chunk, "checkpoint.h5"))
    restart_refuses(softflow, chunk, "a valid chunk that is not what was written", NODES.decode())

    support.run([softflow, "restart", stopped, "-q"], 0)
    print("the intact checkpoint restarts (exit 0)")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
