#!/usr/bin/env python3
"""The validation scripts' archive of finished runs (scripts/validation/case_runs.py,
data/runs/): a study goes on on another machine where it stopped.

Usage: run_archive.py SOFTFLOW CASE WORK_DIR SCRIPTS_DIR

With the repository root of case_runs pointed at WORK_DIR:
1. run_case into output/study runs the case and keeps its tables, summary
   and case text in data/runs/study/NAME, not its checkpoint.
2. On a "fresh clone" (output/ deleted) run_case restores the run without
   running softflow (the binary given is one that does not exist): the same
   tables, byte for byte, and a report reads them.
3. A changed case text is not restored: run_case runs it (and here fails
   to, the binary being absent).
4. A finished run from before the archive is kept when its script meets it.
5. A work directory outside output/ (a test's scratch) is never kept.
6. A binary that cannot be executed yet (a rebuild relinking it) is waited
   for; one that stays so fails after the retries, naming the error.
"""
import filecmp
import os
import shutil
import sys
import threading

from cli_support import fail


def main():
    softflow, case, work, scripts = sys.argv[1:5]
    sys.dont_write_bytecode = True
    sys.path.insert(0, scripts)
    import case_runs

    shutil.rmtree(work, ignore_errors=True)
    root = os.path.abspath(work)
    case_runs.ROOT = root
    case_runs.ARCHIVE = os.path.join(root, "data", "runs")
    study = os.path.join(root, "output", "study")
    kept = os.path.join(case_runs.ARCHIVE, "study", "short")
    text = open(case).read()
    if "end = 1.0" not in text:
        fail(f"{case} no longer ends at t = 1.0: shorten it here another way")
    text = text.replace("end = 1.0", "end = 0.1")  # two steps
    absent = os.path.join(root, "no_build")  # no softflow here: running anything raises

    # 1. run and keep
    directory = case_runs.run_case(os.path.dirname(softflow), study, "short", text)
    if not case_runs.finished(directory):
        fail(f"the run did not finish: {os.listdir(directory)}")
    for name in ("summary.json", "timeseries.csv", case_runs.CASE_TEXT):
        if not os.path.exists(os.path.join(kept, name)):
            fail(f"the archive lacks {name}: {sorted(os.listdir(kept)) if os.path.exists(kept) else 'no folder'}")
    if open(os.path.join(kept, case_runs.CASE_TEXT)).read() != text:
        fail("the archive's case text is not the run's")
    heavy = [n for n in os.listdir(kept) if n.endswith((".h5", ".vtu", ".pvd"))]
    if heavy:
        fail(f"the archive keeps checkpoint or field files: {heavy}")
    series = open(os.path.join(directory, "timeseries.csv")).read()

    # 2. a fresh clone: restored, not run
    shutil.rmtree(os.path.join(root, "output"))
    try:
        directory = case_runs.run_case(absent, study, "short", text)
    except FileNotFoundError:
        fail("the archived run was run again instead of restored")
    if not case_runs.finished(directory) or open(os.path.join(directory, "timeseries.csv")).read() != series:
        fail("the restored run is not the archived one")
    if os.path.exists(os.path.join(directory, case_runs.CASE_TEXT)):
        fail("the archive's own case text was copied into the run")
    if case_runs.read_run(directory, 0.2) is None:
        fail("the restored run cannot be read")

    # 3. another case text: not restored
    try:
        case_runs.run_case(absent, study, "short", text + "# changed\n")
        fail("a run of another case text was restored")
    except FileNotFoundError:
        pass

    # 4. a finished run from before the archive is kept
    shutil.rmtree(os.path.join(root, "output"))
    shutil.copytree(kept, os.path.join(study, "short"), ignore=shutil.ignore_patterns(case_runs.CASE_TEXT))
    with open(os.path.join(study, "short.toml"), "w") as f:
        f.write(text)
    shutil.rmtree(case_runs.ARCHIVE)
    case_runs.run_case(absent, study, "short", text)
    if not filecmp.cmp(os.path.join(kept, "timeseries.csv"), os.path.join(study, "short", "timeseries.csv"),
                       shallow=False):
        fail("a finished run from before the archive was not kept")

    # 5. a scratch directory is not kept
    scratch = os.path.join(root, "scratch", "study")
    shutil.copytree(os.path.join(study, "short"), os.path.join(scratch, "other"))
    with open(os.path.join(scratch, "other.toml"), "w") as f:
        f.write(text)
    case_runs.run_case(absent, scratch, "other", text)
    if os.path.exists(os.path.join(case_runs.ARCHIVE, "study", "other")) or \
            os.path.exists(os.path.join(case_runs.ARCHIVE, "scratch")):
        fail("a work directory outside output/ was archived")

    # 6. a binary being relinked: waited for, then run
    rebuilt = os.path.join(root, "rebuilt")
    os.makedirs(rebuilt)
    wrapper = os.path.join(rebuilt, "softflow")
    with open(wrapper, "w") as f:
        f.write(f'#!/bin/sh\nexec "{os.path.abspath(softflow)}" "$@"\n')
    os.chmod(wrapper, 0o644)  # not executable, as while the linker writes it
    case_runs.LAUNCH_RETRY_INTERVAL = 0.1
    timer = threading.Timer(0.5, lambda: os.chmod(wrapper, 0o755))
    timer.start()
    directory = case_runs.run_case(rebuilt, study, "late", text)
    timer.join()
    if not case_runs.finished(directory):
        fail("a run whose binary became executable after a wait did not run")
    os.chmod(wrapper, 0o644)
    case_runs.LAUNCH_RETRY_SECONDS = 0.3
    try:
        case_runs.run_case(rebuilt, study, "never", text)
        fail("a binary that never became executable did not fail")
    except PermissionError:
        pass
    print("run archive: kept, restored without running, refused for another text, scratch not kept, "
          "a rebuilt binary waited for")


if __name__ == "__main__":
    main()
