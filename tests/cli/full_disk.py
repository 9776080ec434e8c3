#!/usr/bin/env python3
"""A run whose disk fills up (issue 11, item 6).

Usage: full_disk.py SOFTFLOW CASE.toml WORK_DIR

The regression case runs into a 200 kB tmpfs: the small files fit, the
checkpoint does not. softflow must stop with exit code 4 and say that the
disk is full (it crashed with a segmentation fault in HDF5's clean-up, after
a message blaming [checkpoint] interval_steps). Needs permission to mount a
tmpfs (root); skipped (exit 77) where there is none.
"""
import os
import shutil
import subprocess
import sys

from cli_support import fail

SKIP = 77


def main(softflow, case, work):
    shutil.rmtree(work, ignore_errors=True)
    mount_point = os.path.join(work, "small_disk")
    os.makedirs(mount_point)
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=200k", "tmpfs", mount_point],
                      capture_output=True).returncode != 0:
        print("cannot mount a tmpfs here: skipped")
        sys.exit(SKIP)
    try:
        r = subprocess.run([softflow, "run", case, "-o", os.path.join(mount_point, "out")],
                           capture_output=True, text=True, timeout=300)
    finally:
        subprocess.run(["umount", mount_point], capture_output=True)
    if r.returncode != 4:
        fail(f"exit code {r.returncode} (expected 4: a file-system error):\n{r.stderr}")
    for words in ("the disk is full", "MB free in"):
        if words not in r.stderr:
            fail(f"the message does not say '{words}':\n{r.stderr}")
    if "interval_steps" in r.stderr:
        fail(f"the message blames [checkpoint] interval_steps:\n{r.stderr}")
    if "\nwrote " in "\n" + r.stdout:
        fail(f"the failed run says 'wrote ...' before its error:\n{r.stdout[-300:]}")
    print(r.stderr.strip())
    print("PASS")


if __name__ == "__main__":
    main(*sys.argv[1:4])
