#!/usr/bin/env python3
"""Fuzzing `softflow check` with generated case files (issue 11).

Usage: fuzz_check.py SOFTFLOW WORK_DIR [COUNT] [SEED]

From a valid case that sets a key of every table, COUNT files (default 300,
seed 1: the same files every time) each get one to three random mutations:
a key deleted, a value replaced by one of another type or an extreme one
(0, -1, 2^63, 1e308, 1e-320, nan, inf, "", control characters, 10,000
characters, arrays, inline tables, nesting), an unknown key or table, a
duplicated key, the text cut short, random bytes inserted, or one of the
inputs of issue 33 (names too long for a directory or of only spaces,
PETSc option words PETSc would skip, extreme semi-axes and angles, relaxation
times shorter than the step, oscillation frequencies the step cannot resolve,
duplicated sweep values, slip coefficients beyond what the mesh resolves).
`softflow check`
must, for each: end within 20 s, by itself (no signal), valid or refused
with a message naming the file and a key (table.key, or objects[k].key) or
a line (file:N:), the process's exit code 1 if any file was refused. The
files go BATCH to a process (`softflow check A B ...`, one verdict per
file); a batch that crashes, hangs or leaves a file without a verdict is
checked again one process per file, which names the file. The first
failures are listed with their files kept in WORK_DIR.
"""
import os
import random
import re
import shutil
import subprocess
import sys

BASE = {
    "case": {"name": '"fuzz"'},
    "cell": {"length": "20.0", "height": "16.0", "width": "20.0", "periodic_x": "true"},
    "matrix": {"viscosity": "1.0"},
    "flow": {"type": '"steady"', "shear_rate": "1.0"},
    "mesh": {"equator_nodes": "20", "far_size": "4.0", "growth": "0.4"},
    "solver": {"type": '"direct"', "rtol": "1e-8"},
    "time": {"step": "0.05", "end": "1.0", "min_quality": "0.02", "steady_tolerance": "0"},
    "interface": {"redistribution_factor": "10.0", "semi_implicit_tension": "true"},
    "checkpoint": {"interval_steps": "0"},
    "output": {"fields": "false"},
}
OBJECTS = [
    {"shape": '"sphere"', "centre": "[-3.0, 0.0, 0.0]", "radius": "1.0", "viscosity_ratio": "1.0",
     "capillary_number": "0.1"},
    {"shape": '"ellipsoid"', "centre": "[3.0, 0.5, 0.0]", "semi_axes": "[1.2, 0.9, 0.8]",
     "model": '"oldroyd_b"', "solvent_viscosity": "0.5", "polymer_viscosity": "0.5",
     "relaxation_time": "0.1", "capillary_number": "0.05"},
]
EXTREMES = ["0", "-1", "9223372036854775808", "-9223372036854775809", "1e308", "1e400", "1e-320",
            "nan", "inf", "-inf", "0.0", "-0.0", '""', '"\\u0007"', '"\\n"', "true", "false",
            "[]", "[1, 2, 3]", '["a", 1]', "[[1.0, 2.0, 3.0], [1.0]]", "{}", "{ a = 1 }",
            "1979-05-27T07:32:00Z", "0x10", "1_000", '"sphere"', '"ucm"', '"neo_hookean"', "3.5",
            "[1.0, 2.0, 3.0]", "[0.5, 0.5]"]


# Issue 33: (table or "objects", {key: value}, keys removed): values that
# passed `check` and failed later, or were ignored. Only refusals and values
# `check` answers without PETSc, so that the test's run time stays.
ISSUE_33 = [
    ("case", {"name": '"' + "n" * 250 + '"'}, ()),
    ("case", {"name": '"' + "n" * 239 + '"'}, ()),
    ("case", {"name": '"' + "\u00e9" * 130 + '"'}, ()),
    ("case", {"name": '"   "'}, ()),
    ("case", {"name": '" "'}, ()),
    ("output", {"directory": '"out/' + "d" * 250 + '"'}, ()),
    ("output", {"directory": '"' + "p" * 300 + '/x"'}, ()),
    ("output", {"directory": '"out/.."'}, ()),
    ("solver", {"petsc_options": '"ksp_monitor"'}, ()),
    ("solver", {"petsc_options": '"-stokes_ksp_type gmres restart"'}, ()),
    ("solver", {"petsc_options": '"-1 -a"'}, ()),
    ("solver", {"petsc_options": '"-a\\t1"'}, ()),
    ("solver", {"petsc_options": '"-a\t1"'}, ()),
    ("objects", {"shape": '"ellipsoid"', "semi_axes": "[1e-3, 1.0, 1.0]"}, ("radius",)),
    ("objects", {"shape": '"ellipsoid"', "semi_axes": "[1e300, 1e-300, 1.0]"}, ("radius",)),
    ("objects", {"shape": '"ellipsoid"', "semi_axes": "[0.25, 1.0, 1.0]"}, ("radius",)),
    ("objects", {"shape": '"ellipsoid"', "semi_axes": "[1.2, 1.0, 1.0]", "rotation_deg": "[1e300, 0.0, 0.0]"},
     ("radius",)),
    ("objects", {"shape": '"ellipsoid"', "semi_axes": "[1.2, 1.0, 1.0]", "rotation_deg": "[-360.0, 360.0, 720.0]"},
     ("radius",)),
    ("objects", {"model": '"ucm"', "polymer_viscosity": "1.0", "relaxation_time": "1e-300"},
     ("viscosity_ratio", "solvent_viscosity")),
    ("matrix", {"model": '"oldroyd_b"', "solvent_viscosity": "0.5", "polymer_viscosity": "0.5",
                "relaxation_time": "1e-300"}, ("viscosity",)),
    ("matrix", {"model": '"giesekus"', "solvent_viscosity": "0.5", "polymer_viscosity": "0.5",
                "relaxation_time": "0.01", "mobility": "0.2"}, ("viscosity",)),
    ("flow", {"type": '"oscillatory"', "strain_amplitude": "0.5", "frequency": "1000.0"}, ("shear_rate",)),
    ("flow", {"type": '"oscillatory"', "strain_amplitude": "0.5", "frequency": "1e300"}, ("shear_rate",)),
    ("time", {"step": "[0.05, 0.05]"}, ()),
    ("objects", {"capillary_number": "[0.1, 0.2, 0.1]"}, ("interfacial_tension",)),
    ("case", {"name": '["a", "b"]'}, ()),
    # defect 2: slip beyond what the interface mesh resolves, and free slip
    ("objects", {"slip": "1e6"}, ()),
    ("objects", {"slip": "1e3", "viscosity_ratio": "100.0"}, ()),
    ("objects", {"slip": "inf"}, ()),
    ("objects", {"slip": "1e308"}, ()),
]


def issue_33(rng, tables, objects):
    table, values, removed = rng.choice(ISSUE_33)
    if table == "objects":
        if not objects:
            return
        target = rng.choice(objects)
    else:
        target = tables.setdefault(table, {})
    for key in removed:
        target.pop(key, None)
    target.update(values)


def random_value(rng):
    kind = rng.randrange(6)
    if kind == 0:
        return rng.choice(EXTREMES)
    if kind == 1:
        return repr(rng.uniform(-100, 100))
    if kind == 2:
        return str(rng.randrange(-5, 200))
    if kind == 3:
        depth = rng.randrange(1, 120)
        return "[" * depth + "1" + "]" * depth
    if kind == 4:
        return '"' + "".join(rng.choice("abcxyz _-./") for _ in range(rng.choice([1, 10, 10000]))) + '"'
    return "[" + ", ".join(repr(rng.uniform(0, 2)) for _ in range(rng.randrange(1, 6))) + "]"


def render(tables, objects, extra_lines):
    lines = []
    for name, keys in tables.items():
        lines.append(f"[{name}]")
        lines += [f"{k} = {v}" for k, v in keys.items()]
    for o in objects:
        lines.append("[[objects]]")
        lines += [f"{k} = {v}" for k, v in o.items()]
    lines += extra_lines
    return "\n".join(lines) + "\n"


def mutate(rng):
    tables = {k: dict(v) for k, v in BASE.items()}
    objects = [dict(o) for o in OBJECTS[:rng.randrange(0, 3)]]
    extra = []
    text_mutations = []
    for _ in range(rng.randrange(1, 4)):
        op = rng.randrange(10)
        pool = list(tables.values()) + objects
        target = rng.choice(pool)
        if op in (0, 1, 2) and target:  # a value of another type or an extreme one
            target[rng.choice(list(target))] = random_value(rng)
        elif op == 3 and target:  # a key deleted
            del target[rng.choice(list(target))]
        elif op == 4:  # an unknown key
            target["".join(rng.choice("abcdefghij_") for _ in range(rng.randrange(1, 12)))] = random_value(rng)
        elif op == 5:  # an unknown or repeated table
            extra += [f"[{rng.choice(['mesh', 'cells', 'objects', 'x.y', 'time'])}]", "a = 1"]
        elif op == 9:  # an input of issue 33
            issue_33(rng, tables, objects)
        elif op == 6 and target:  # a key given twice
            key = rng.choice(list(target))
            extra_key = (key, target[key])
            target[key + " = 1\n" + key] = extra_key[1]
        else:
            text_mutations.append(rng.randrange(3))
    text = render(tables, objects, extra).encode()
    for m in text_mutations:
        if m == 0 and len(text) > 2:  # cut short
            text = text[:rng.randrange(1, len(text))]
        elif m == 1:  # random bytes
            at = rng.randrange(len(text) + 1)
            text = text[:at] + bytes(rng.randrange(256) for _ in range(rng.randrange(1, 8))) + text[at:]
        else:  # a line duplicated elsewhere
            lines = text.split(b"\n")
            lines.insert(rng.randrange(len(lines) + 1), rng.choice(lines))
            text = b"\n".join(lines)
    return text


NAMED = re.compile(r"([a-z_]+(\[\d+\])?\.[a-z_0-9]+|:\d+:|unknown key|unknown table|objects\[\d+\]"
                   r"|\.toml( \[sweep case [^\]]*\])?: [a-z_]+ = )")


BATCH = 30  # files per `softflow check` process (one process per file: 0.25 s each of start-up)


def verdicts(softflow, paths):
    """(exit code, {path: (code, message)}) of one `softflow check` of `paths`,
    or None when the process ran out of time or ended by a signal. A refused
    file's message is the stderr chunk from a "softflow: " line naming it."""
    try:
        # Far less than 20 s per file: a batch with a hanging file must time out
        # well before the test's own limit, so that the files can be run singly.
        r = subprocess.run([softflow, "check"] + paths, capture_output=True, timeout=20 + 2 * len(paths))
    except subprocess.TimeoutExpired:
        return None
    if r.returncode < 0:
        return None
    found = {}
    for line in r.stdout.decode(errors="replace").splitlines():
        for p in paths:
            if line == f"{p}: valid" or line.startswith(f"{p}: valid, a sweep"):
                found[p] = (0, "")
    chunks = re.split(r"(?m)^(?=softflow: )", r.stderr.decode(errors="replace"))
    for chunk in filter(None, chunks):
        first = chunk.split("\n", 1)[0]
        if ": warning: " in first:
            continue  # a valid case's warning (it will not run well) is not a verdict
        named = [p for p in paths if os.path.basename(p) + ":" in first or
                 os.path.basename(p) + " [sweep case" in first]
        for p in named:
            found[p] = (1, chunk)
    return r.returncode, found


def judge(path, code, message):
    """The failure of one file's verdict, or None."""
    if code not in (0, 1):
        return f"{path}: exit code {code}: {message[:300]}"
    if code == 1 and not NAMED.search(message):
        return f"{path}: the message names no key or line: {message[:300]}"
    return None


def main(softflow, work, count=300, seed=1):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    rng = random.Random(seed)
    paths = []
    for i in range(count):
        paths.append(os.path.join(work, f"fuzz_{i}.toml"))
        with open(paths[-1], "wb") as f:
            f.write(mutate(rng))
    failures, codes = [], {}
    for first in range(0, count, BATCH):
        batch = paths[first:first + BATCH]
        result = verdicts(softflow, batch)
        if result is None or any(p not in result[1] for p in batch) or \
                result[0] != max(c for c, _ in result[1].values()):
            # One process per file: which file kills, hangs, or goes unanswered.
            result = (None, {})
            for p in batch:
                one = verdicts(softflow, [p])
                if one is None:
                    failures.append(f"{p}: killed, or no answer within 20 s")
                elif one[0] not in (0, 1):
                    failures.append(f"{p}: exit code {one[0]}")
                elif p not in one[1]:
                    failures.append(f"{p}: exit code {one[0]}, but no verdict naming the file")
                else:
                    result[1][p] = one[1][p]
        for p, (code, message) in result[1].items():
            codes[code] = codes.get(code, 0) + 1
            failure = judge(p, code, message)
            if failure:
                failures.append(failure)
            else:
                os.remove(p)
    print(f"{count} files (seed {seed}, {BATCH} per process): exit codes {dict(sorted(codes.items()))}")
    if failures:
        print(f"FAIL: {len(failures)} files")
        for line in failures[:15]:
            print("  " + line)
        sys.exit(1)
    print("PASS")


if __name__ == "__main__":
    args = sys.argv[1:]
    main(args[0], args[1], *(int(a) for a in args[2:4]))
