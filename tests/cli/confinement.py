"""Confinement from the command line (thesis ch. 3, issue 35).

1. examples/confined_particle.toml (beta = 0.4, y_p0 = 0.27 H: a gap of 0.03 H
   to the upper wall) passes `softflow check`, whose resolved case states the
   blockage ratio and the height it sets.
2. `softflow mesh` meshes a small version of it (12 equator nodes, where the
   gap is a seventh of an interface element).
3. An object closer to a wall than the mesh resolves is refused by `check`
   before any meshing, exit 1, the message naming the keys that change it.
4. cell.height and cell.blockage_ratio together are refused as ambiguous.
5. A run from mesh.point_symmetric_start that remeshes says, once, that the
   remesh gives the symmetric mesh up and which key keeps it; without
   remeshing it says nothing.

usage: confinement.py SOFTFLOW EXAMPLE WORKDIR
"""
import os
import shutil
import sys

from cli_support import fail, run

softflow, example, work = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def write(name, text):
    path = os.path.join(work, name)
    with open(path, "w") as f:
        f.write(text)
    return path


# 1. The example.
checked = run([softflow, "check", example]).stdout
for expected in ("blockage_ratio = 0.4", "height H = 2R / blockage_ratio = 5.0", "gap_elements = 2"):
    if expected not in checked:
        fail(f"softflow check {example}: the resolved case lacks '{expected}':\n{checked}")
print("check accepts the example")

# 2. A small confined case meshes.
SMALL = """
[cell]
length = 6.0
width = 6.0
blockage_ratio = 0.4
[[objects]]
model = "neo_hookean"
elastic_capillary_number = 0.1
centre = [0.0, 1.35, 0.0]
[mesh]
equator_nodes = 12
far_size = 1.0
"""
small = write("small.toml", SMALL)
meshed = run([softflow, "mesh", small]).stdout
if "min quality" not in meshed:
    fail(f"softflow mesh: no report:\n{meshed}")
print(meshed.strip())

# 3. Too close for the mesh: gap 0.02 < g_min = 2 (4 pi / 16) / 64 = 0.0245.
close = write("too_close.toml", """
[cell]
blockage_ratio = 0.4
[[objects]]
centre = [0.0, 1.48, 0.0]
[mesh]
equator_nodes = 16
""")
refused = run([softflow, "check", close], expect=1).stderr
for expected in ("objects[1]: sphere at (0, 1.48, 0) with radius 1 is too close to the wall y = 2.5",
                 "gap 0.02 < g_min = 0.0245437", "objects[1].centre", "cell.blockage_ratio",
                 "mesh.equator_nodes ≥ 20", "mesh.gap_elements"):
    if expected not in refused:
        fail(f"softflow check {close}: the refusal lacks '{expected}':\n{refused}")
print("check refuses a gap the mesh cannot resolve:", refused.strip())

# 4. Height and blockage ratio together.
both = write("both.toml", "[cell]\nheight = 5.0\nblockage_ratio = 0.4\n[[objects]]\n")
refused = run([softflow, "check", both], expect=1).stderr
if "cell gives both height = 5.0 and blockage_ratio = 0.4: give only one" not in refused:
    fail(f"softflow check {both}: {refused}")
print("check refuses height with blockage_ratio:", refused.strip())

# 5. A remesh gives the point-symmetric start up: a note, once; none without remeshing.
symmetric = SMALL.replace("centre = [0.0, 1.35, 0.0]", "centre = [0.0, 0.1, 0.0]") + """point_symmetric_start = true
[time]
step = 0.05
end = 0.1
[output]
fields = false
"""
note = "gives up mesh.point_symmetric_start"
# remesh.quality above any mesh's, and an interval of one step: a remesh before every step.
remeshing = write("symmetric_remeshed.toml", symmetric + "[remesh]\nquality = 0.6\ninterval = 0.05\n")
stderr = run([softflow, "run", remeshing, "-o", os.path.join(work, "symmetric_remeshed"), "-q"]).stderr
if stderr.count(note) != 1 or "remesh.quality = 0 (now 0.6)" not in stderr:
    fail(f"a remeshed symmetric start: expected one note naming remesh.quality:\n{stderr}")
with open(os.path.join(work, "symmetric_remeshed", "remesh.csv")) as f:
    if len(f.readlines()) < 3:
        fail("the remeshed symmetric start remeshed fewer than twice: the note's 'once' is untested")
kept = write("symmetric_kept.toml", symmetric)
stderr = run([softflow, "run", kept, "-o", os.path.join(work, "symmetric_kept"), "-q"]).stderr
if note in stderr:
    fail(f"a symmetric start without remeshing: an unexpected note:\n{stderr}")
print("a remesh of a symmetric start is noted once:", note)
