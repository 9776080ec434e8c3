#!/usr/bin/env python3
"""The repo's scripts against the current softflow: every validation,
theory and benchmark script imports (its names from the modules it shares
resolve), every validation script's jobs() builds its case texts (their
assert-guarded edits of a shared base case still find what they edit), and
`softflow check` finds every one of those cases valid. A key renamed in the
library, or a base case edited under a script that derives from it, fails
here instead of hours into a validation run.

Usage: script_cases.py SOFTFLOW WORK_DIR REPO_ROOT
"""
import glob
import importlib
import inspect
import os
import shutil
import subprocess
import sys

from cli_support import fail

sys.dont_write_bytecode = True  # the scripts are imported from the source tree: leave it as it is

# The directories whose top-level scripts are importable modules (each
# keeps `main` behind `if __name__ == "__main__"`).
SCRIPT_DIRECTORIES = ["scripts/validation", "scripts/theory", "bench"]
# A floor well below today's count (268 cases from 28 scripts), so that a
# glob or import path that silently finds nothing fails.
MIN_CASES = 200


def import_all(root):
    modules, broken = {}, []
    for directory in SCRIPT_DIRECTORIES:
        path = os.path.join(root, directory)
        sys.path.insert(0, path)
        for script in sorted(glob.glob(os.path.join(path, "*.py"))):
            name = os.path.splitext(os.path.basename(script))[0]
            if name.startswith("test_"):
                continue
            try:
                modules[f"{directory}/{name}.py"] = importlib.import_module(name)
            except Exception as error:  # noqa: BLE001 -- every failure is reported by script
                broken.append(f"{directory}/{name}.py: {type(error).__name__}: {error}")
    return modules, broken


def case_files(modules, work):
    files, broken = [], []
    for script, module in modules.items():
        jobs = getattr(module, "jobs", None)
        if not script.startswith("scripts/validation/") or not callable(jobs) or inspect.signature(jobs).parameters:
            continue
        try:
            cases = [job for job in jobs() if isinstance(job, tuple)]
        except Exception as error:  # noqa: BLE001
            broken.append(f"{script}: jobs(): {type(error).__name__}: {error}")
            continue
        stem = os.path.splitext(os.path.basename(script))[0]
        for name, text in cases:
            path = os.path.join(work, f"{stem}__{name}.toml")
            if path in files:
                broken.append(f"{script}: two jobs named {name}")
            with open(path, "w") as f:
                f.write(text)
            files.append(path)
    return files, broken


def main(softflow, work, root):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    os.environ.setdefault("MPLBACKEND", "Agg")
    modules, broken = import_all(root)
    files, broken_jobs = case_files(modules, work)
    broken += broken_jobs
    if broken:
        fail("scripts that no longer build:\n" + "\n".join(broken))
    if len(files) < MIN_CASES:
        fail(f"only {len(files)} validation cases found (expected at least {MIN_CASES}): is the repo root right?")
    result = subprocess.run([softflow, "check", *files], capture_output=True, text=True)
    verdicts = [line for line in result.stdout.splitlines() if line.endswith(": valid") or ": valid," in line]
    if result.returncode != 0 or len(verdicts) != len(files):
        fail(f"softflow check: exit code {result.returncode}, {len(verdicts)} of {len(files)} validation cases "
             f"valid; the refusals:\n{result.stderr}")
    print(f"{len(modules)} scripts import; {len(files)} validation cases valid")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
