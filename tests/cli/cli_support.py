"""Helpers shared by the command-line tests: failing with a message, running
softflow with an expected exit code, reading a run's outputs."""
import csv
import json
import os
import subprocess
import sys


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def run(args, expect=0, launcher=()):
    """Runs `args` (after `launcher`), failing unless it exits with `expect`."""
    result = subprocess.run(list(launcher) + list(args), capture_output=True, text=True)
    if result.returncode != expect:
        fail(f"{' '.join(args)}: exit code {result.returncode}, expected {expect}\n"
             f"{result.stdout}\n{result.stderr}")
    return result


def rows(directory, name="timeseries.csv"):
    with open(os.path.join(directory, name)) as f:
        return list(csv.DictReader(f))


def read_json(directory, name="summary.json"):
    with open(os.path.join(directory, name)) as f:
        return json.load(f)
