"""capsim under faults, end to end: kills inside the write windows, a file system that
fills up, a folder it may not write, and a damaged time series. Each run stops with one
clear message (exit 4), keeps a checkpoint it can resume from, and the resumed run equals
an uninterrupted one bit for bit (docs/reliability.md)."""

import os
import pathlib
import resource
import shutil
import signal
import subprocess
import sys
import tempfile

import h5py
import pytest

from pipeline.command_line import set_arguments

ROOT = pathlib.Path(__file__).resolve().parents[2]
CAPSIM = ROOT / "build" / "capsim"
sys.path.insert(0, str(ROOT / "tests" / "reliability"))
import kill_resume_soak  # noqa: E402

# Two capsules, a sample every step and a checkpoint every two steps: 78 rows, so the
# time series grows by a second chunk of rows near gammadot t = 3.7 (about 1 s).
CASE = {"method": "direct", "phi": 0.05, "capsules": 2, "mesh_level": 1, "t_end": 4.5,
        "t_avg_start": 1, "dt_safety": 0.5, "output.sample_interval": 0.02,
        "output.checkpoint_interval": 0.1, "threads": 1}
ARGS = set_arguments(CASE)


def capsim(*args, **kwargs):
    return subprocess.run([str(CAPSIM), *args], capture_output=True, text=True, **kwargs)


@pytest.fixture(scope="module")
def whole(tmp_path_factory):
    if not CAPSIM.exists():
        pytest.fail(f"{CAPSIM} is missing: build first (bash scripts/setup.sh)")
    out = tmp_path_factory.mktemp("whole") / "run"
    assert capsim("run", "-q", *ARGS, "-o", str(out)).returncode == 0
    return out


def files_of(folder):
    return {p.relative_to(folder): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


def assert_resumes_to(whole, folder):
    r = capsim("run", "-q", "--resume", str(folder))
    assert r.returncode == 0, r.stderr
    assert kill_resume_soak.differences(whole, folder) == []


def test_kills_inside_the_write_windows_resume_to_the_same_bits(whole, tmp_path):
    record = kill_resume_soak.soak(CAPSIM, tmp_path, kills=3, seed=3, case=CASE,
                                   points=["checkpoint_closed", "series_written"])
    assert record["kills_landed"] == 3
    assert record["windows"]["checkpoint_closed"] == 1
    assert record["windows"]["series_written"] == 1
    assert record["equal_to_uninterrupted"], record["differences"]
    assert record["tmp_files_left"] == []


def file_size_limit(size):
    """A full disk for one process: writes past `size` bytes fail with EFBIG."""
    def apply():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (size, size))
    return apply


def test_a_full_disk_stops_with_one_message_and_the_run_resumes(whole, tmp_path):
    run = tmp_path / "run"
    # The time series outgrows 45 kB when its second chunk of rows is allocated.
    r = capsim("run", "-q", *ARGS, "-o", str(run), preexec_fn=file_size_limit(45_000))
    assert r.returncode == 4
    message = r.stderr.strip()
    assert message.count("\n") == 0 and "HDF5-DIAG" not in message
    assert message.startswith(f"capsim: error: cannot write timeseries {run}/timeseries.h5")
    assert "File too large" in message
    assert "The last good checkpoint (gammadot*t = 3.6" in message
    assert f"capsim run --resume {run}" in message
    assert sorted(p.name for p in run.glob("*.tmp")) == []
    with h5py.File(run / "checkpoint.h5", "r") as f:
        assert f["step"][()] > 0
    assert_resumes_to(whole, run)


def killed_run(tmp_path):
    run = tmp_path / "run"
    env = dict(os.environ, CAPSIM_TEST_KILL_AT="checkpoint_closed:10")
    r = subprocess.run([str(CAPSIM), "run", "-q", *ARGS, "-o", str(run)], env=env)
    assert r.returncode == -signal.SIGKILL
    return run


def test_a_checkpoint_that_cannot_be_replaced_keeps_the_last_one(whole, tmp_path):
    run = killed_run(tmp_path)
    # checkpoint.h5.tmp taken by a folder: the next checkpoint cannot be written, also as
    # root, which ignores permissions.
    (run / "checkpoint.h5.tmp").unlink(missing_ok=True)
    (run / "checkpoint.h5.tmp").mkdir()
    (run / "checkpoint.h5.tmp" / "keep").touch()
    before = (run / "checkpoint.h5").read_bytes()
    r = capsim("run", "-q", "--resume", str(run))
    assert r.returncode == 4
    assert r.stderr.startswith(f"capsim: error: cannot write checkpoint {run}/checkpoint.h5")
    assert "The last good checkpoint" in r.stderr
    assert (run / "checkpoint.h5").read_bytes() == before
    shutil.rmtree(run / "checkpoint.h5.tmp")
    assert_resumes_to(whole, run)


def as_unprivileged_user():
    """Root writes anywhere; a read-only folder needs a user without that right."""
    if os.geteuid() == 0:
        os.setgid(65534)
        os.setuid(65534)


def test_a_read_only_folder_changes_nothing_and_the_run_resumes(whole):
    # Under a world-readable temp folder, so that the unprivileged user can read it.
    base = pathlib.Path(tempfile.mkdtemp(prefix="capsim_readonly_"))
    try:
        base.chmod(0o755)
        run = killed_run(base)
        for p in [run, *run.rglob("*")]:
            p.chmod(0o555 if p.is_dir() else 0o444)
        before = files_of(run)
        # A copy of capsim the unprivileged user can reach wherever the checkout lives.
        exe = shutil.copy2(CAPSIM, base / "capsim")
        r = subprocess.run([exe, "run", "-q", "--resume", str(run)], capture_output=True,
                           text=True, preexec_fn=as_unprivileged_user)
        assert r.returncode == 4
        assert "Permission denied" in r.stderr and "timeseries.h5" in r.stderr
        assert files_of(run) == before
        run.chmod(0o755)
        assert_resumes_to(whole, run)
    finally:
        shutil.rmtree(base)


def damage_truncate(path):
    os.truncate(path, path.stat().st_size // 2)


def damage_rows(path):
    """Flips 16 bytes inside the stored rows of /capsule/D."""
    with h5py.File(path, "r") as f:
        chunk = f["capsule/D"].id.get_chunk_info(0)
    with open(path, "r+b") as f:
        f.seek(chunk.byte_offset + 8)
        f.write(bytes(16))


@pytest.mark.parametrize("damage", [damage_truncate, damage_rows])
def test_a_damaged_time_series_is_refused_on_resume_naming_the_file(tmp_path, damage):
    run = killed_run(tmp_path)
    damage(run / "timeseries.h5")
    before = files_of(run)
    r = capsim("run", "-q", "--resume", str(run))
    assert r.returncode == 4
    message = r.stderr.strip()
    assert message.count("\n") == 0 and "HDF5-DIAG" not in message
    assert message.startswith(f"capsim: error: timeseries {run}/timeseries.h5 is corrupt")
    assert "Nothing was changed" in message
    assert files_of(run) == before
