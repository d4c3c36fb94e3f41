"""The results archive and segmented runs (docs/workflow.md, "Runs, segments and the
results archive"), on a tiny study (the initial-position study: two seeds, M 2, level 1)
in temporary folders:

- a run stopped after two of its three segments and archived is continued in a fresh
  working directory from the archive alone (the new clone of a repository that holds
  the archive), which runs only the missing segments; its time series equal those of the
  same study run unsegmented and without an archive: to the last bit from the archived
  state on, and before it to the single precision that the archive keeps them in; the
  figure data agree to 1e-6 (the quantities are of order 0.01-10, which single precision
  rounds by about 1e-7 of themselves; a mean or a standard deviation of them moves by no
  more than that, and a standard deviation over two nearly equal seeds is where it shows);
- a third fresh working directory restores every run (its dry run lists no run job) and
  regenerates the same figure data;
- replaying the last segment from a record's state gives its archived rows to the last
  bit (same thread count, so the same reductions in the same order);
- a record whose file, record.json or format was changed is refused, naming it, by the
  archive and by the workflow.

About 30 s on 2 cores. Skipped when build/capsim or snakemake is missing."""

import hashlib
import json
import shutil
import subprocess

import h5py
import numpy as np
import pandas as pd
import pytest
import yaml

from pipeline import archive, run_spec
from pipeline.command_line import option_value
from pipeline.run_spec import RunSpec

from test_workflow_ci import CAPSIM, ROOT, SNAKEMAKE, pytestmark  # noqa: F401 (the skips)

# Three segments of 0.2 strain units (checkpoints every 0.1) to t_end 0.6, with a step
# small enough for several rows per segment.
STUDY = {
    "averages": {"t_start": 0.1},
    "resources": {"threads": 2},
    "run_options": {"output.checkpoint_interval": 0.1, "dt_safety": 0.1},
    "initial": {"ca": 0.4, "phi": 0.2, "capsules": 2, "mesh_level": 1, "seeds": [1, 2],
                "t_end": 0.6},
    "segments": {"strain": 0.2},
}
RUNS = ["results/initial/ca0.4_phi0.2_M2_level1_seed1",
        "results/initial/ca0.4_phi0.2_M2_level1_seed2"]
FIGURE = "results/figures/fig11.csv"


def snakemake(workdir, config, *targets, dry=False):
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "study.yaml").write_text(yaml.safe_dump(config))
    exe = str(SNAKEMAKE) if SNAKEMAKE.exists() else shutil.which("snakemake")
    cmd = [exe, "--cores", "2", "--snakefile", str(ROOT / "Snakefile"), "--directory",
           str(workdir), *(["-n"] if dry else []), *targets, "--configfile",
           str(workdir / "study.yaml")]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=300)


def run_jobs(dry_run_output):
    """The run and run_segment jobs a dry run lists: {rule: count}."""
    counts = {}
    for line in dry_run_output.splitlines():
        words = line.split()
        if len(words) == 2 and words[0] in ("run", "run_segment") and words[1].isdigit():
            counts[words[0]] = int(words[1])
    return counts


def series(run_dir):
    with h5py.File(run_dir / "timeseries.h5", "r") as f:
        out = {}
        f.visititems(lambda n, o: out.__setitem__(n, o[()])
                     if isinstance(o, h5py.Dataset) else None)
    return out


def assert_same_figure_data(workdir, reference):
    got, want = (pd.read_csv(w / FIGURE) for w in (workdir, reference))
    pd.testing.assert_frame_equal(got, want, check_exact=False, rtol=1e-6, atol=1e-6)


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """Runs the study three ways; returns their folders and the archive."""
    base = tmp_path_factory.mktemp("archive_study")
    store = base / "archive"
    with_archive = {**STUDY, "archive": str(store)}
    plain = snakemake(base / "plain", {**STUDY, "segments": {"strain": None,
                                                             "minutes": None}}, FIGURE)
    assert plain.returncode == 0, plain.stderr[-3000:]
    # Two segments of each run, recorded in the archive; then this folder is gone.
    first = snakemake(base / "first", with_archive,
                      *[f"{run}/segment2.done" for run in RUNS])
    assert first.returncode == 0, first.stderr[-3000:]
    partial = [archive.read_record(store / "initial" / r.split("/")[-1]) for r in RUNS]
    clone = snakemake(base / "clone", with_archive, FIGURE, dry=True)
    continued = snakemake(base / "clone", with_archive, FIGURE)
    assert continued.returncode == 0, continued.stderr[-3000:]
    restored_dry = snakemake(base / "restored", with_archive, FIGURE, dry=True)
    restored = snakemake(base / "restored", with_archive, FIGURE)
    assert restored.returncode == 0, restored.stderr[-3000:]
    return {"base": base, "store": store, "config": with_archive, "partial": partial,
            "clone_dry": clone.stdout + clone.stderr,
            "restored_dry": restored_dry.stdout + restored_dry.stderr}


def test_a_stopped_segmented_run_continues_from_the_archive_to_the_same_bits(study):
    for record in study["partial"]:
        assert not record["finished"] and 0.4 <= record["state_time"] < 0.6
    # The fresh directory runs the last segment of each run, not the first two.
    assert run_jobs(study["clone_dry"]) == {"run": 2}
    for run, record in zip(RUNS, study["partial"]):
        plain, continued = series(study["base"] / "plain" / run), series(
            study["base"] / "clone" / run)
        assert plain.keys() == continued.keys()
        after = plain["time"] > record["state_time"]
        assert 2 <= after.sum() < len(after)
        for name in plain:
            np.testing.assert_array_equal(plain[name][after], continued[name][after],
                                          err_msg=name)
            np.testing.assert_array_equal(plain[name].astype(np.float32),
                                          continued[name].astype(np.float32), err_msg=name)
    assert_same_figure_data(study["base"] / "clone", study["base"] / "plain")


def test_a_fresh_directory_restores_every_run_and_the_same_figure_data(study):
    assert run_jobs(study["restored_dry"]) == {}
    assert "2 run(s) restored whole" in study["restored_dry"]
    assert_same_figure_data(study["base"] / "restored", study["base"] / "plain")


def test_a_record_replays_its_last_segment_to_the_last_bit(study):
    record_dir = study["store"] / "initial" / RUNS[0].split("/")[-1]
    record = archive.read_record(record_dir)
    assert record["finished"] and record["state_time"] < record["t_reached"]
    rows, difference = archive.replay(record_dir, CAPSIM)
    assert rows >= 2 and difference == 0.0


@pytest.mark.parametrize("damage", ["series", "record", "format"])
def test_a_damaged_record_is_refused_naming_it(study, tmp_path, damage):
    store = tmp_path / "archive"
    shutil.copytree(study["store"], store)
    record_dir = store / "initial" / RUNS[1].split("/")[-1]
    if damage == "series":
        data = bytearray((record_dir / "timeseries.h5").read_bytes())
        data[len(data) // 2] ^= 1
        (record_dir / "timeseries.h5").write_bytes(bytes(data))
    else:
        record = json.loads((record_dir / "record.json").read_text())
        if damage == "record":
            record["t_end"] = 0.5
        else:
            record["format"] = 99
        (record_dir / "record.json").write_text(json.dumps(record))
    with pytest.raises(archive.ArchiveError, match=str(record_dir)):
        archive.read_record(record_dir)
    dry = snakemake(tmp_path / "work", {**study["config"], "archive": str(store)}, FIGURE,
                    dry=True)
    assert dry.returncode != 0 and f"{record_dir}: " in dry.stdout + dry.stderr


def test_the_quantitative_archive_is_sound_and_restores_its_runs(tmp_path):
    """Every record of archive/quantitative is sound, of this physics version and of the
    configuration's options: a fresh directory restores each finished run (no run job for
    it) and continues each unfinished one. Once every run is there, the quantitative
    figure data regenerate from the archive and pass their check against the paper."""
    store = ROOT / "archive" / "quantitative"
    records = [archive.read_record(path) for path in archive._records([store])] \
        if store.exists() else []
    if not records:
        pytest.skip("archive/quantitative holds no record yet")
    exe = str(SNAKEMAKE) if SNAKEMAKE.exists() else shutil.which("snakemake")
    dry = subprocess.run([exe, "--snakefile", str(ROOT / "Snakefile"), "--directory",
                          str(tmp_path), "-n", "all", "check", "--configfile",
                          str(ROOT / "config" / "quantitative.yaml")],
                         capture_output=True, text=True, timeout=600)
    assert dry.returncode == 0, dry.stdout[-3000:] + dry.stderr[-3000:]
    assert "stale" not in dry.stderr and "other options" not in dry.stderr
    finished = sum(r["finished"] for r in records)
    assert run_jobs(dry.stdout).get("run", 0) == 45 + 21 - finished
    if finished < 45 + 21:
        return
    # Complete: the figures, Table 1, the comparison with the paper and the check come
    # from the archive alone, and the check (config/expected/paper.yaml) passes.
    full = subprocess.run([exe, "--cores", "2", "--snakefile", str(ROOT / "Snakefile"),
                           "--directory", str(tmp_path), "all", "check", "--configfile",
                           str(ROOT / "config" / "quantitative.yaml")],
                          capture_output=True, text=True, timeout=1200)
    assert full.returncode == 0, full.stdout[-3000:] + full.stderr[-3000:]
    assert "0 failed" in (tmp_path / "results" / "check" / "report.md").read_text()


def test_a_quantitative_record_replays_a_stretch_to_its_rounding():
    """The cheapest record of archive/quantitative that keeps a state before its last
    row (a run of several segments keeps the start of its last one) replays 0.1 strain
    units from it to the archived rows within one unit in their last place: the record's
    own thread count, but not its build, whose sums the present one may order otherwise
    (archive.ROUNDING_UNITS)."""
    store = ROOT / "archive" / "quantitative"
    candidates = []
    for path in (archive._records([store]) if store.exists() else []):
        record = archive.read_record(path)
        if record["state_time"] is not None and record["state_time"] < record["t_reached"]:
            options = record["options"]
            candidates.append((options["capsules"] * 4 ** options["mesh_level"], path))
    if not candidates:
        pytest.skip("no record of archive/quantitative keeps a state before its end yet")
    rows, difference = archive.replay(min(candidates)[1], CAPSIM, span=0.1)
    assert rows >= 1 and difference <= archive.ROUNDING_UNITS


def test_a_run_recorded_only_once_it_has_left_its_start(tmp_path, monkeypatch):
    # A folder holding only the checkpoint of t = 0 (a run started, then stopped at
    # once) has nothing to keep; one past it is recorded.
    spec = RunSpec(study="initial", ca=0.4, level=1, t_end=0.6, t_avg_start=0.1, phi=0.2,
                   M=2)
    recorded = []
    monkeypatch.setattr(archive, "collect", lambda run_dir, *a, **k: recorded.append(run_dir))
    for t, want in ((0.0, []), (0.2, [spec.folder])):
        monkeypatch.setattr(archive, "reached", lambda run_dir, t=t: (False, t))
        report = archive.sync([spec], tmp_path / "archive", lambda s: [s.t_end],
                              workdir=tmp_path)
        assert report["recorded"] == want
    assert len(recorded) == 1


def test_changed_defaults_are_capsim_s_present_ones():
    # CHANGED_DEFAULTS says what capsim's defaults are now: `capsim params` agrees.
    listed = subprocess.run([str(CAPSIM), "params"], capture_output=True, text=True,
                            check=True).stdout
    defaults = {row.split("|")[1].strip(" `"): row.split("|")[2].strip()
                for row in listed.splitlines() if row.startswith("| `")}
    for name, (_, now, _) in run_spec.CHANGED_DEFAULTS.items():
        assert run_spec._same_value(defaults[name], now), name


def test_a_run_that_pins_the_old_defaults_keeps_its_key():
    # The key of a run as it was before the defaults changed (every option as given, none
    # of CHANGED_DEFAULTS among them) is that of the same run pinning the old values; a
    # run that takes the new defaults, or other values, has another key.
    def key_before(spec):
        options = {k: option_value(v) for k, v in sorted(spec.trajectory_options().items())}
        text = json.dumps({"physics_version": run_spec.physics_version(),
                           "options": options}, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()

    base = {"study": "grid", "ca": 0.2, "level": 3, "t_end": 30, "t_avg_start": 10,
            "phi": 0.3, "M": 27}
    given = (("ewald.tolerance", "auto"),)
    old = tuple(sorted({**dict(given), **{name: then for name, (then, _, _)
                                         in run_spec.CHANGED_DEFAULTS.items()}}.items()))
    before = key_before(RunSpec(**base, options=given))
    assert RunSpec(**base, options=old).key() == before
    assert RunSpec(**base, options=given).key() != before
    assert RunSpec(**base, options=old + (("quadrature.max_depth", 7),)).key() != before
    single = tuple(sorted({**dict(old), "ewald.precision": "single"}.items()))
    assert RunSpec(**base, options=single).key() != before
    # A dilute run has no grids: the precision is not in its key; the quadrature is.
    dilute = {"study": "dilute", "ca": 0.2, "level": 3, "t_end": 20, "t_avg_start": 10}
    quadrature = (("quadrature.far_ratio", 2), ("quadrature.near_ratio", 1.5))
    assert RunSpec(**dilute, options=quadrature).key() == key_before(RunSpec(**dilute))
    assert RunSpec(**dilute).key() != key_before(RunSpec(**dilute))
