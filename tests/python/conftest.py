"""Shared fixtures of the Python suite."""

import subprocess
from pathlib import Path

import pytest

CAPSIM = Path(__file__).resolve().parents[2] / "build" / "capsim"


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
