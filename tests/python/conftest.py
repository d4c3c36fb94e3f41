"""Shared fixtures of the Python suite."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
CAPSIM = ROOT / "build" / "capsim"
SNAKEMAKE = Path(sys.executable).with_name("snakemake")


@pytest.fixture(scope="package")
def capsim_run(tmp_path_factory):
    """A function run(name, *settings) that runs capsim to its end in a new folder with
    the given `key=value` settings and returns the folder; it fails the test where the
    solver has not been built."""
    def run(name, *settings):
        if not CAPSIM.exists():
            pytest.fail(f"{CAPSIM} is missing: build first (bash scripts/setup.sh)")
        out = tmp_path_factory.mktemp(name) / "run"
        sets = [arg for setting in settings for arg in ("--set", setting)]
        subprocess.run([str(CAPSIM), "run", "-q", *sets, "-o", str(out)], check=True)
        return out
    return run


def run_snakemake(workdir, *targets, configfile="ci.yaml", extra=(), timeout=600):
    """Snakemake with the local executor on 2 cores in `workdir` on config/<configfile>
    (and `extra` arguments); returns the finished process, its output captured."""
    exe = str(SNAKEMAKE) if SNAKEMAKE.exists() else shutil.which("snakemake")
    cmd = [exe, "--cores", "2", "--snakefile", str(ROOT / "Snakefile"), "--directory",
           str(workdir), *targets, "--configfile", str(ROOT / "config" / configfile),
           *extra]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)


@pytest.fixture(scope="package")
def ci_workflow(tmp_path_factory):
    """The whole workflow on the ci configuration (`all check`) in a new working
    directory, made once for the tests that read it (test_workflow_ci.py, and
    test_slurm.py as the reference of the SLURM profile's outputs): returns (working
    directory, finished process). About 1.5 minutes on 2 cores."""
    workdir = tmp_path_factory.mktemp("ci_workflow")
    return workdir, run_snakemake(workdir, "all", "check", timeout=900)
