#!/usr/bin/env python3
"""`softflow converge` through the program.

Usage: converge.py SOFTFLOW CASE.toml WORK_DIR

The coarse regression drop (to t = 0.5) on three meshes, ratio 1.2, from 14
equator nodes:
1. The levels are 14, 17, 20 nodes with far size and growth scaled by
   14 / N (the whole mesh refined), each run's case.toml says so, and
   converge.csv holds each run's own final D and theta (summary.json).
2. The order and extrapolated value in converge.json are recomputed here
   from those values (bisection for p in (D2 - D1)/(D3 - D2) =
   (h1^p - h2^p)/(h2^p - h3^p), h = 1 / the equator nodes the mesh report of
   each run gives) and must agree.
3. Running it again skips the finished levels; bad options and cases are
   refused with exit code 1 and a message naming them.
4. With --order 3 two levels suffice: the finest two (the finished 14 and 17
   nodes, not run again) extrapolated with the order given, recomputed here.
"""
import csv
import json
import os
import shutil
import subprocess
import sys

from cli_support import fail, run




def order(h, q):
    d21, d32 = q[1] - q[0], q[2] - q[1]
    g = lambda p: (h[0] ** p - h[1] ** p) / (h[1] ** p - h[2] ** p)  # noqa: E731
    ratio = d21 / d32
    if not ratio > g(0.1):
        return None, None
    lo, hi = 0.1, 12.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if g(mid) < ratio else (lo, mid)
    p = 0.5 * (lo + hi)
    return p, q[2] - d32 * h[2] ** p / (h[2] ** p - h[1] ** p)


def main(softflow, case_source, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    out = os.path.join(work, "levels")
    with open(case_source) as f:
        text = f.read().replace("equator_nodes = 16", "equator_nodes = 14").replace("end = 1.0", "end = 0.5")
    text = text.replace("[output]", f'[output]\ndirectory = "{out}"')
    case = os.path.join(work, "converge.toml")
    with open(case, "w") as f:
        f.write(text)
    result = run([softflow, "converge", case, "--levels", "3", "--factor", "1.2", "-j", "2"])
    if "time.steady_tolerance = 0" not in result.stdout:
        fail("no note that the values are those at time.end:\n" + result.stdout)

    # 1. The levels and their values.
    with open(os.path.join(out, "converge.csv")) as f:
        rows = list(csv.DictReader(f))
    if [int(r["equator_nodes"]) for r in rows] != [14, 17, 20]:
        fail(f"levels {[r['equator_nodes'] for r in rows]}, expected 14, 17, 20")
    for r in rows:
        n = int(r["equator_nodes"])
        with open(os.path.join(out, f"N{n}", "case.toml")) as f:
            case_text = f.read()
        for key, base in (("far_size", 2.0), ("growth", 0.4)):
            value = float(r[key])
            if abs(value - base * 14 / n) > 1e-5 * base:
                fail(f"N{n}: {key} {value}, expected {base * 14 / n}")
            line = next(line for line in case_text.splitlines() if line.startswith(key + " ="))
            if abs(float(line.split("=")[1].split("#")[0]) - base * 14 / n) > 1e-12:
                fail(f"N{n}/case.toml: {line}")
        with open(os.path.join(out, f"N{n}", "summary.json")) as f:
            s = json.load(f)
        if s["status"] != "completed" or r["status"] != "completed":
            fail(f"N{n}: status {s['status']} / {r['status']}")
        if abs(float(r["D"]) - s["final"][0]["D"]) > 1e-7 or \
                abs(float(r["theta_deg"]) - s["final"][0]["theta_deg"]) > 1e-5:
            fail(f"N{n}: converge.csv D/theta {r['D']}/{r['theta_deg']} vs summary {s['final'][0]}")

    # 2. The extrapolation, recomputed.
    with open(os.path.join(out, "converge.json")) as f:
        extrapolation = {e["quantity"]: e for e in json.load(f)["extrapolation"]}
    h = [1.0 / int(r["meshed_equator_nodes"]) for r in rows]
    for r in rows:
        with open(os.path.join(out, f"N{r['equator_nodes']}", "summary.json")) as f:
            if int(r["meshed_equator_nodes"]) != json.load(f)["mesh"]["equator_nodes"]:
                fail(f"N{r['equator_nodes']}: meshed equator nodes differ from the run's mesh report")
    for key in ("D", "theta_deg"):
        q = [float(r[key]) for r in rows]
        p, limit = order(h, q)
        e = extrapolation[key]
        if p is None:
            if e["orders"] != [None] or e["extrapolated"] is not None:
                fail(f"{key}: differences {q} do not converge, yet converge.json has {e}")
            print(f"{key}: {q}: not monotone, no order (as reported)")
            continue
        if abs(e["orders"][0] - p) > 1e-4 * p or abs(e["extrapolated"] - limit) > 1e-6 * abs(limit):
            fail(f"{key}: converge.json {e}, recomputed order {p}, limit {limit}")
        print(f"{key}: {q}: order {p:.3f}, extrapolated {limit:.6g} (as reported)")
    for name in ("converge.md", "converge.png", "sweep.md"):
        if not os.path.exists(os.path.join(out, name)):
            fail(f"no {name}")

    # 3. Resume and refusals.
    again = run([softflow, "converge", case, "--levels", "3", "--factor", "1.2"])
    if again.stdout.count("completed earlier, skipped") != 3:
        fail("a second converge did not skip the three finished levels:\n" + again.stdout)
    for args, words in ((["--levels", "2"], "--levels 2"), (["--factor", "3"], "--factor 3")):
        r = run([softflow, "converge", case] + args, 1)
        if words not in r.stderr:
            fail(f"{args}: message does not name it: {r.stderr}")
    listed = os.path.join(work, "listed.toml")
    with open(listed, "w") as f:
        f.write(text.replace("capillary_number = 0.1", "capillary_number = [0.1, 0.2]"))
    if "is a sweep" not in run([softflow, "converge", listed], 1).stderr:
        fail("a case file with lists is not refused as a sweep")
    # 4. Two levels with the order known: the finest two extrapolated with it,
    #    the observed order absent; an order out of range refused.
    known = run([softflow, "converge", case, "--levels", "2", "--factor", "1.2", "--order", "3"])
    if known.stdout.count("completed earlier, skipped") != 2:
        fail("converge --levels 2 --order 3 did not reuse the two finished levels:\n" + known.stdout)
    with open(os.path.join(out, "converge.json")) as f:
        extrapolation = {e["quantity"]: e for e in json.load(f)["extrapolation"]}
    finals = []
    for r in rows[:2]:
        with open(os.path.join(out, f"N{r['equator_nodes']}", "summary.json")) as f:
            finals.append(json.load(f)["final"][0])  # full precision (converge.csv rounds)
    for key in ("D", "theta_deg"):
        q = [final[key] for final in finals]
        limit = q[1] + (q[1] - q[0]) * h[1] ** 3 / (h[0] ** 3 - h[1] ** 3)
        e = extrapolation[key]
        if e["order_given"] != 3 or e["orders"] != [] or abs(e["extrapolated"] - limit) > 1e-9 * abs(limit):
            fail(f"{key} with --order 3: converge.json {e}, recomputed limit {limit}")
        print(f"{key}: {q}: with order 3, extrapolated {limit:.6g} (as reported)")
    if "--order 20" not in run([softflow, "converge", case, "--levels", "2", "--order", "20"], 1).stderr:
        fail("--order 20 is not refused naming it")
    static = os.path.join(work, "static.toml")
    with open(static, "w") as f:
        f.write(text.replace("end = 0.5", "end = 0"))
    if "time.end = 0" not in run([softflow, "converge", static], 1).stderr:
        fail("a case without time is not refused naming time.end")
    print("PASS")


if __name__ == "__main__":
    main(*sys.argv[1:4])
