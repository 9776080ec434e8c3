#!/usr/bin/env python3
"""What a user sees when gmsh is slow or fails (issue 11, item 3).

Usage: meshing_messages.py SOFTFLOW WORK_DIR

1. Fifty spheres in the cell keep gmsh's curved-element optimiser busy for
   more than ten minutes, silently until now. With the note's delay set to
   1 s (SOFTFLOW_SLOW_MESHING_NOTE_SECONDS), `softflow mesh` must print a
   note naming mesh.optimize_high_order within 30 s; the run is then stopped.
2. A prolate ellipsoid (3, 1, 1) in a 60 x 30 x 30 cell, which gmsh fails to
   mesh, ends fast (exit 2) with gmsh's error followed by the keys to
   change, not gmsh's error alone.
3. Meshing is reproducible from one process to the next: an ellipsoid and
   a sphere meshed five times, with OMP_NUM_THREADS 1, 4 and unset, from
   case files at paths of different lengths and with stdout a pipe or a
   file, give the same mesh fingerprint (a hash of every coordinate's bits
   and every element). Each of these used to change gmsh's heap, and with
   it the curved nodes of the ellipsoid, before gmsh ran in a
   DeterministicHeapScope.
"""
import os
import random
import shutil
import subprocess
import sys
import time

from cli_support import fail



def main(softflow, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)

    # 1. The note on a slow mesh.
    rng, centres = random.Random(3), []
    while len(centres) < 50:
        p = [rng.uniform(-12, 12), rng.uniform(-11, 11), rng.uniform(-12, 12)]
        if all(sum((a - b) ** 2 for a, b in zip(p, q)) > 12 for q in centres):
            centres.append(p)
    case = os.path.join(work, "fifty.toml")
    with open(case, "w") as f:
        f.write("[mesh]\nequator_nodes = 12\n")
        for c in centres:
            f.write("[[objects]]\ncentre = [%.3f, %.3f, %.3f]\ncapillary_number = 0.1\n" % tuple(c))
    env = dict(os.environ, SOFTFLOW_SLOW_MESHING_NOTE_SECONDS="1")
    process = subprocess.Popen([softflow, "mesh", case], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True, env=env)
    start, note = time.time(), ""
    while time.time() - start < 30 and process.poll() is None:
        line = process.stderr.readline()
        if "note: gmsh has been meshing" in line:
            note = line
            break
    process.kill()
    process.communicate()
    if not note:
        fail("no note within 30 s while gmsh meshed fifty spheres")
    for words in ("mesh.optimize_high_order = false", "mesh.equator_nodes (now 12; 16 or more)"):
        if words not in note:
            fail(f"the note does not say '{words}': {note}")
    print(f"note after {time.time() - start:.1f} s: {note.strip()[:100]}...")

    # 2. A failure says what to change.
    case = os.path.join(work, "prolate.toml")
    with open(case, "w") as f:
        f.write('[[objects]]\nshape = "ellipsoid"\nsemi_axes = [3.0, 1.0, 1.0]\ncapillary_number = 0.1\n'
                "[cell]\nlength = 60.0\n")
    start = time.time()
    r = subprocess.run([softflow, "mesh", case], capture_output=True, text=True, timeout=120)
    if r.returncode == 0:
        print("the prolate ellipsoid meshed (gmsh changed?): part 2 has nothing to check")
    else:
        if r.returncode != 2:
            fail(f"exit code {r.returncode}, expected 2: {r.stderr}")
        for words in ("gmsh failed while meshing", "What usually helps", "mesh.equator_nodes (now 40",
                      "mesh.far_size (now 3)"):
            if words not in r.stderr:
                fail(f"the message does not say '{words}': {r.stderr}")
        print(f"failure in {time.time() - start:.1f} s: {r.stderr.strip()[:120]}...")

    # 3. The same mesh in every process.
    case = os.path.join(work, "two.toml")
    with open(case, "w") as f:
        f.write('[[objects]]\nshape = "ellipsoid"\ncentre = [-1.5, 0.2, 0.0]\nsemi_axes = [1.2, 0.9, 0.8]\n'
                'rotation_deg = [10.0, 20.0, 30.0]\ncapillary_number = 0.1\n[[objects]]\n'
                'centre = [2.0, -0.5, 0.3]\nradius = 0.7\ncapillary_number = 0.1\n'
                '[cell]\nlength = 10.0\nheight = 8.0\nwidth = 8.0\n[mesh]\nequator_nodes = 16\n'
                'far_size = 2.0\n')
    prints = []
    runs = [("1", case, False), ("4", case, False), (None, case, False)]
    for depth, to_file in ((1, False), (5, True)):
        deeper = os.path.join(work, *(["a_longer_directory_name"] * depth))
        os.makedirs(deeper, exist_ok=True)
        shutil.copy(case, deeper)
        runs.append((None, os.path.join(deeper, "two.toml"), to_file))
    for threads, path, to_file in runs:
        env = dict(os.environ)
        env.pop("OMP_NUM_THREADS", None)
        if threads:
            env["OMP_NUM_THREADS"] = threads
        if to_file:
            with open(os.path.join(work, "mesh_stdout.txt"), "w+") as out:
                r = subprocess.run([softflow, "mesh", path], stdout=out, stderr=subprocess.PIPE, text=True,
                                   env=env, timeout=120)
                out.seek(0)
                r.stdout = out.read()
        else:
            r = subprocess.run([softflow, "mesh", path], capture_output=True, text=True, env=env, timeout=120)
        if r.returncode != 0 or "fingerprint " not in r.stdout:
            fail(f"softflow mesh: exit {r.returncode}, no fingerprint: {r.stdout}{r.stderr}")
        prints.append(r.stdout.split("fingerprint ")[1].split()[0])
    if len(set(prints)) != 1:
        fail(f"the same case meshed to different meshes: fingerprints {prints}")
    print(f"{len(prints)} processes, one mesh: fingerprint {prints[0]}")
    print("PASS")


if __name__ == "__main__":
    main(*sys.argv[1:3])
