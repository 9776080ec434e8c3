"""Running softflow cases for the validation scripts and reading their output.

run_case writes CASE.toml in `work` and runs `softflow run` into work/NAME
(run_response: `softflow response`),
unless that directory already holds the summary.json of a run that ended by
itself (scripts can be re-run to regenerate their reports), or the
repository's archive holds a run of that case text (data/runs/, below:
restored instead of run again); a run interrupted
(SIGTERM/SIGINT: its summary says "interrupted") or killed, with a checkpoint
of the same case text, is continued with `softflow restart`.
read_run reads summary.json and the time series, with steady values as the
means over the rows at t >= t_end - window. validation_main is the command
line the validation scripts share."""
import argparse
import concurrent.futures
import csv
import errno
import inspect
import json
import os
import shutil
import subprocess
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


# The conformation numerics of the results in docs/ from before the keys of
# `[conformation]`: the Stokes step's stress at the Euler prediction (eq. 2.37;
# the default `stress_prediction = "consistent"` is second order in dt:
# docs/viscoelastic.md, "The predicted stress and the transported one"), and
# for the particle figures also the thesis's steady SUPG parameter (the
# default `supg_tau = "auto"` limits it by the time step inside solids: "The
# SUPG parameter and the time step"). Their scripts append these tables so
# that they reproduce their documents.
EULER_PREDICTION = '[conformation]\nstress_prediction = "euler"\n'
PARTICLE_FIGURES_CONFORMATION = '[conformation]\nsupg_tau = "steady"\nstress_prediction = "euler"\n'


def finished(directory):
    """A run that ended by itself (an interrupted one writes its summary too)."""
    path = os.path.join(directory, "summary.json")
    return os.path.exists(path) and json.load(open(path)).get("status") != "interrupted"


# Finished runs are kept in the repository, under data/runs/WORK/NAME/: the
# case text and the run's tables and summary (not its checkpoint, fields or
# log). A script run again on a fresh clone, or on another machine, restores
# such a run instead of running it again, so that a study longer than one
# session goes on where the last one stopped. Only for work directories in
# output/ (a test's scratch directory is not kept). Delete a run's folder
# there to measure it again.
ARCHIVE = os.path.join(ROOT, "data", "runs")
KEPT_SUFFIXES = (".csv", ".json", ".md", ".toml")
CASE_TEXT = "case_text.toml"


def archive_of(work, name):
    """data/runs/WORK/NAME for a work directory in output/, else None."""
    work = os.path.abspath(work)
    if os.path.dirname(work) != os.path.join(ROOT, "output"):
        return None
    return os.path.join(ARCHIVE, os.path.basename(work), name)


def archived(work, name, text):
    """The kept run of this name, if it ran this very case text."""
    kept = archive_of(work, name)
    if kept is None or not os.path.exists(os.path.join(kept, "summary.json")):
        return None
    path = os.path.join(kept, CASE_TEXT)
    return kept if os.path.exists(path) and open(path).read() == text else None


def keep(work, name, text):
    """Copies a finished run's tables and summary, and its case text, to the archive."""
    kept = archive_of(work, name)
    directory = os.path.join(work, name)
    if kept is None or not finished(directory):
        return
    os.makedirs(kept, exist_ok=True)
    for entry in sorted(os.listdir(directory)):
        if entry.endswith(KEPT_SUFFIXES) and os.path.isfile(os.path.join(directory, entry)):
            shutil.copyfile(os.path.join(directory, entry), os.path.join(kept, entry))
    with open(os.path.join(kept, CASE_TEXT), "w") as f:
        f.write(text)


def restore(work, name, text):
    """Fills work/NAME from the archive; False when it holds no run of this case text."""
    kept = archived(work, name, text)
    if kept is None:
        return False
    directory = os.path.join(work, name)
    if os.path.exists(directory):
        shutil.rmtree(directory)
    shutil.copytree(kept, directory, ignore=shutil.ignore_patterns(CASE_TEXT))
    with open(os.path.join(work, name + ".toml"), "w") as f:
        f.write(text)
    return True


LAUNCH_RETRY_SECONDS, LAUNCH_RETRY_INTERVAL = 600, 10


def run_softflow(command):
    """subprocess.run(command) of softflow, retried every LAUNCH_RETRY_INTERVAL seconds for up to
    LAUNCH_RETRY_SECONDS while the binary cannot be executed (EACCES, ETXTBSY: a rebuild is
    relinking it). Without this a rebuild during a study failed, at once, every run the study had
    not started yet."""
    waited = 0
    while True:
        try:
            return subprocess.run(command, check=False)
        except OSError as e:
            if e.errno not in (errno.EACCES, errno.ETXTBSY) or waited >= LAUNCH_RETRY_SECONDS:
                raise
            if waited == 0:
                print(f"note: cannot execute {command[0]} ({e.strerror}; being rebuilt?): retrying every "
                      f"{LAUNCH_RETRY_INTERVAL:g} s for up to {LAUNCH_RETRY_SECONDS / 60:g} minutes", flush=True)
            time.sleep(LAUNCH_RETRY_INTERVAL)
            waited += LAUNCH_RETRY_INTERVAL


def run_case(build, work, name, text, rerun=False):
    directory = os.path.join(work, name)
    path = os.path.join(work, name + ".toml")
    # The run in work/NAME is this case's unless the case text beside it differs.
    here = not rerun and not (os.path.exists(path) and open(path).read() != text)
    if here and finished(directory):
        if archived(work, name, text) is None and os.path.exists(path):
            keep(work, name, text)  # a run from before the archive
        return directory
    os.makedirs(work, exist_ok=True)
    if not rerun and restore(work, name, text):
        return directory
    if here and os.path.exists(path) and os.path.exists(os.path.join(directory, "checkpoint.h5")):
        # Interrupted (a stop, a crash, a machine that went down): continue from the checkpoint.
        run_softflow([os.path.join(build, "softflow"), "restart", directory, "-q", "--force"])
        keep(work, name, text)
        return directory
    with open(path, "w") as f:
        f.write(text)
    run_softflow([os.path.join(build, "softflow"), "run", path, "-o", directory, "-q", "--overwrite"])
    keep(work, name, text)
    return directory


def run_linked(build, work, other_work, name, text, other_name=None):
    """run_case of `text` in the sibling work directory `other_work` (another script's, e.g.
    output/OTHER_WORK) under `other_name` (default `name`), linked here as work/NAME: one run shared
    by two studies, made or restored by whichever runs first."""
    other = os.path.join(os.path.dirname(os.path.abspath(work)), other_work)
    directory = run_case(build, other, other_name or name, text)
    link = os.path.join(work, name)
    os.makedirs(work, exist_ok=True)
    if not os.path.lexists(link):
        os.symlink(directory, link)
    return link


def run_response(build, work, name, text, frequencies=None, extra=()):
    """`softflow response` on the case `text` into work/NAME, unless its
    response.csv is there (the command writes its outputs only at its end);
    at `frequencies` (-f), or the case's own frequency when None; `extra`:
    more arguments (e.g. --cube-sides)."""
    directory = os.path.join(work, name)
    if os.path.exists(os.path.join(directory, "response.csv")):
        return directory
    os.makedirs(work, exist_ok=True)
    path = os.path.join(work, name + ".toml")
    with open(path, "w") as f:
        f.write(text)
    command = [os.path.join(build, "softflow"), "response", path, "-q", "-o", directory]
    if frequencies:
        command += ["-f", ",".join(f"{w:g}" for w in frequencies)]
    run_softflow(command + list(extra))
    return directory


def richardson(hs, values, bracket=(0.05, 12.0)):
    """Order p and limit v* of v = v* + c h^p through three levels (coarse to fine, sizes hs at
    any ratios): p solves (v0 - v1) / (v1 - v2) = (h0^p - h1^p) / (h1^p - h2^p) by bisection
    within `bracket`. None when the differences change sign or no p in the bracket fits."""
    (h0, h1, h2), (v0, v1, v2) = hs, values
    d1, d2 = v0 - v1, v1 - v2
    if d1 * d2 <= 0:
        return None

    def mismatch(p):
        return (h0 ** p - h1 ** p) / (h1 ** p - h2 ** p) - d1 / d2
    lo, hi = bracket
    if mismatch(lo) * mismatch(hi) > 0:
        return None
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if mismatch(lo) * mismatch(mid) <= 0 else (mid, hi)
    p = 0.5 * (lo + hi)
    return p, v2 - d2 * h2 ** p / (h1 ** p - h2 ** p)


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def summary_of(directory):
    """The run's summary.json, or {} while it has none."""
    path = os.path.join(directory, "summary.json")
    return json.load(open(path)) if os.path.exists(path) else {}


def write_csv(path, fieldnames, rows):
    """Rows (dicts keyed by fieldnames) to a csv at path, creating its folder:
    floats to 6 significant digits, None as an empty cell."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fieldnames)
        w.writeheader()
        for x in rows:
            w.writerow({k: ("" if v is None else (f"{v:.6g}" if isinstance(v, float) else v)) for k, v in x.items()})


def read_run(directory, window):
    """None if the run has no summary; else its series and steady values (D, theta)."""
    summary_path = os.path.join(directory, "summary.json")
    if not os.path.exists(summary_path):
        return None
    summary = json.load(open(summary_path))
    rows = read_csv(os.path.join(directory, "timeseries.csv"))
    t = [float(r["t"]) for r in rows]
    tail = [r for r in rows if float(r["t"]) >= t[-1] - window]
    mean = lambda key: sum(float(r[key]) for r in tail) / len(tail)  # noqa: E731
    d_tail = [float(r["D"]) for r in tail]
    return {
        "summary": summary, "rows": rows, "tail_from": t[-1] - window,
        "t": t, "D": [float(r["D"]) for r in rows], "theta": [float(r["theta_deg"]) for r in rows],
        "D_steady": mean("D"), "D_amplitude": (max(d_tail) - min(d_tail)) / 2,
        "theta_steady": mean("theta_deg"),
        "deviation": float(rows[-1]["ellipsoid_dev"]),
        "volume_drift": float(rows[-1]["volume"]) / float(rows[0]["volume"]) - 1.0,
        "wall": summary["wall_seconds"], "unknowns": summary["unknowns"], "steps": summary["steps"],
        "status": summary["status"], "end": t[-1],
    }


def remesh_overhead(rows, remesh_rows):
    """(remesh seconds, first-step seconds, median step seconds) of a run from its
    timeseries rows and remesh.csv rows: what the remeshes cost it, the remeshes
    themselves and the first step on each new mesh above the run's median step
    (it factors a new matrix)."""
    step_seconds = sorted(float(row["step_seconds"]) for row in rows[1:])
    median = step_seconds[len(step_seconds) // 2]
    by_step = {int(row["step"]): float(row["step_seconds"]) for row in rows[1:]}
    remeshes = sum(float(row["seconds"]) for row in remesh_rows)
    first_steps = sum(max(0.0, by_step.get(int(row["step"]) + 1, median) - median) for row in remesh_rows)
    return remeshes, first_steps, median


def meshed_size(r):
    """1 / (equator nodes the mesher made) of a read_run result: the element size
    a whole-mesh study refines (the mesher rounds the asked count unevenly)."""
    return 1.0 / r["summary"]["mesh"]["equator_nodes"]


def validation_main(work_name, jobs, report, runner=run_case):
    """`SCRIPT [build_dir] [work_dir] [--jobs N] [--report-only]`: runs every
    (name, case text) of jobs() with `runner` (two at a time by default),
    unless --report-only, then report(work_dir), or report(work_dir, build_dir)
    when report takes two arguments (it runs softflow itself). work_dir
    defaults to output/WORK_NAME."""
    parser = argparse.ArgumentParser()
    parser.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    parser.add_argument("work", nargs="?", default=os.path.join(ROOT, "output", work_name))
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--report-only", action="store_true")
    args = parser.parse_args()
    if not args.report_only:
        with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
            list(pool.map(lambda j: runner(args.build, args.work, *j), jobs()))
    names = [name for name, _ in jobs()]
    absent = [name for name in names if not finished(os.path.join(args.work, name))
              and not os.path.exists(os.path.join(args.work, name, "response.csv"))]
    if absent:
        # On a fresh clone the runs from before the archive (data/runs/) are
        # not here: the report then covers fewer runs than the committed one.
        print(f"note: {len(absent)} of {len(names)} runs have not finished in {args.work} "
              f"(the report leaves them out): {', '.join(absent[:8])}{' ...' if len(absent) > 8 else ''}")
    if len(inspect.signature(report).parameters) >= 2:
        report(args.work, args.build)
    else:
        report(args.work)
