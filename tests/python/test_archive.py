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
  archive and by the workflow;
- the eight ways of issue 45 to make the archive present old or foreign results as
  current, each refused with a message naming the record or folder, or handled: a dry run
  writes nothing and rewrites no record of another physics version or other options; a
  folder or record of another run is not recorded or used; concurrent restores leave
  every run equal to the archive; only the files a record lists are restored; a folder of
  the archive without record.json is named; the key follows the solver's own defaults;
  an archive path with a space, an archive that cannot be written and an empty
  summary.json; a killed attempt's CPU time in the segments.

The archive of these runs lies in a folder whose path holds a space. About a minute on 2
cores. Skipped when build/capsim or snakemake is missing."""

import json
import shutil
import subprocess
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import h5py
import numpy as np
import pandas as pd
import pytest
import yaml

from pipeline import archive, job, run_spec
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


def written_outside_snakemake(workdir):
    """The files under a working directory but for snakemake's own bookkeeping
    (.snakemake/): what the workflow wrote."""
    return [p for p in Path(workdir).rglob("*")
            if p.is_file() and ".snakemake" not in p.relative_to(workdir).parts]


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
    store = base / "the archive"  # a space: every job's command must quote it
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
    assert "2 run(s) to restore whole" in study["restored_dry"]
    assert_same_figure_data(study["base"] / "restored", study["base"] / "plain")
    # A second invocation in the restored folder has nothing to do: the restored runs
    # were made by rule restore, and a provenance trigger would run them again
    # (profiles/default: reruns by modification time).
    again = snakemake(study["base"] / "restored", study["config"], FIGURE, dry=True)
    assert "Nothing to be done" in again.stdout + again.stderr, again.stdout[-3000:]


def test_a_raised_t_end_continues_a_run_from_a_state_before_its_first_pause(study,
                                                                            tmp_path):
    """A finished record keeps the start of its last segment (0.4); with t_end raised to
    0.7 in one segment, the run continues from that state ("after segment 0"), to the
    same bits as the plain run up to 0.6, instead of starting again."""
    store = tmp_path / "store"
    shutil.copytree(study["store"], store)
    config = {**study["config"], "archive": str(store), "segments": {"strain": 5.0},
              "initial": {**STUDY["initial"], "t_end": 0.7}}
    dry = snakemake(tmp_path / "work", config, FIGURE, dry=True)
    assert "2 run(s) to restore and continue" in dry.stderr, dry.stderr[-3000:]
    assert "restore_segment" in dry.stdout and run_jobs(dry.stdout) == {"run": 2}
    done = snakemake(tmp_path / "work", config, FIGURE)
    assert done.returncode == 0, done.stderr[-3000:]
    for run in RUNS:
        start = archive.read_record(study["store"] / "initial" / run.split("/")[-1])
        segments = json.loads((tmp_path / "work" / run / "segments.json").read_text())
        assert segments[-1]["t_from"] == pytest.approx(start["state_time"])
        assert archive.read_record(store / "initial" / run.split("/")[-1])["t_reached"] >= 0.7
        plain, longer = series(study["base"] / "plain" / run), series(tmp_path / "work" / run)
        after = (plain["time"] > start["state_time"])
        for name in plain:
            np.testing.assert_array_equal(plain[name][after],
                                          longer[name][: len(after)][after], err_msg=name)


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
    assert archive.orphans(store) == []
    records = [archive.read_record(path) for path in archive._records([store])]
    # The studies run by their own targets (reference, viscosity_ratio:
    # workflow/rules/common.smk, ON_DEMAND_RUNS) join the archive run by run, finished or
    # not; the main studies' runs must all be there, finished: the grid's and the other
    # studies', and with eblimit.in_grid the limit eb -> 0's 12 suspensions and 10
    # capsules.
    main = [r for r in records if r["study"] not in ("reference", "viscosity_ratio")]
    finished = sum(r["finished"] for r in main)
    assert len(main) == finished == 44 + 21 + 22, "archive/quantitative is incomplete"
    exe = str(SNAKEMAKE) if SNAKEMAKE.exists() else shutil.which("snakemake")
    dry = subprocess.run([exe, "--snakefile", str(ROOT / "Snakefile"), "--directory",
                          str(tmp_path), "-n", "all", "check", "--configfile",
                          str(ROOT / "config" / "quantitative.yaml")],
                         capture_output=True, text=True, timeout=600)
    assert dry.returncode == 0, dry.stdout[-3000:] + dry.stderr[-3000:]
    assert "physics version" not in dry.stderr and "other options" not in dry.stderr
    assert run_jobs(dry.stdout).get("run", 0) == 0
    assert "main studies: 0 of 87 runs to compute" in dry.stderr
    assert written_outside_snakemake(tmp_path) == [], "a dry run wrote files"
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
    assert candidates, "no record of archive/quantitative keeps a state before its end"
    rows, difference = archive.replay(min(candidates)[1], CAPSIM, span=0.1)
    assert rows >= 1 and difference <= archive.ROUNDING_UNITS


def test_a_run_is_recorded_only_once_it_has_left_its_start(tmp_path, monkeypatch):
    # A folder holding only the checkpoint of t = 0 (a run started, then stopped at
    # once) has nothing to keep; one past it is recorded by its next job.
    spec = RunSpec(study="initial", ca=0.4, level=1, t_end=0.6, t_avg_start=0.1, phi=0.2,
                   M=2)
    for t, want in ((0.0, []), (0.2, [spec.folder])):
        monkeypatch.setattr(archive, "reached", lambda run_dir, t=t: (False, t))
        plan = archive.plan([spec], tmp_path / "archive", lambda s: {},
                            lambda s: [s.t_end], workdir=tmp_path)
        assert plan["ahead"] == want


# Issue 45: the ways to make the archive present old or foreign results as current.

def tree(folder):
    """{path: bytes} of every file under a folder."""
    return {str(p.relative_to(folder)): p.read_bytes()
            for p in sorted(Path(folder).rglob("*")) if p.is_file()}


def copied_store(study, tmp_path):
    store = tmp_path / "archive"
    shutil.copytree(study["store"], store)
    return store


def record_dir_of(store, k):
    return store / "initial" / RUNS[k].split("/")[-1]


def forge(record_dir, change):
    """Edits record.json as a careful hand would: `change(record)`, then the key, the
    files' sha256 and the checksum made to agree."""
    record = json.loads((record_dir / "record.json").read_text())
    change(record)
    record["key"] = run_spec.options_key(record["options"], record["physics_version"])
    record["files"] = {name: archive.sha256(record_dir / name) for name in record["files"]}
    record["checksum"] = archive._content_checksum(record)
    (record_dir / "record.json").write_text(json.dumps(record, indent=1, sort_keys=True))


def study_spec():
    """The RunSpec of the first run, as the workflow makes it (config/config.yaml's
    run_options under the study's)."""
    return run_spec.suspension("initial", {"ca": 0.4, "phi": 0.2, "M": 2, "level": 1,
                                           "seed": 1}, STUDY["initial"], 0.1,
                               {"ewald.tolerance": "auto", **STUDY["run_options"]})


def stored_options(study, k=0):
    """The resolved options of run k: those of this configuration."""
    return archive.read_record(record_dir_of(study["store"], k))["options"]


def verify(*paths):
    return subprocess.run([sys.executable, "-m", "pipeline.archive", "verify",
                           *map(str, paths)], capture_output=True, text=True, cwd=ROOT)


def test_case1_a_dry_run_writes_nothing_and_keeps_records_of_another_run(study, tmp_path):
    store = copied_store(study, tmp_path)
    old = record_dir_of(store, 0)
    forge(old, lambda r: r.update(physics_version="0"))
    before = tree(store)
    config = {**study["config"], "archive": str(store),
              "run_options": {**STUDY["run_options"], "dt_safety": 0.05}}
    dry = snakemake(tmp_path / "work", config, FIGURE, dry=True)
    out = dry.stdout + dry.stderr
    assert dry.returncode == 0, out[-3000:]
    assert "1 record(s) of another physics version" in out
    assert "1 record(s) with other options than this configuration's" in out
    assert "git rm -r" in out
    assert run_jobs(dry.stdout) == {"run_segment": 4, "run": 2}  # both computed anew
    assert tree(store) == before, "a dry run changed the archive"
    # Nothing but study.yaml, written by the test itself.
    assert [p.name for p in written_outside_snakemake(tmp_path / "work")] == ["study.yaml"]
    # Recording over it is refused, naming the record and what to do; it stays as it is.
    with pytest.raises(archive.ArchiveError, match=r"physics version 0.*git rm -r"):
        archive.collect(study["base"] / "restored" / RUNS[0], old, stored_options(study))
    assert tree(store) == before


def test_case2_a_folder_or_record_of_another_run_is_refused(study, tmp_path):
    want = stored_options(study)
    store = copied_store(study, tmp_path)
    record_dir = record_dir_of(store, 0)
    before = tree(store)
    # A run made with another mesh in this run's folder: neither recorded nor used.
    run_dir = tmp_path / RUNS[0]
    shutil.copytree(study["base"] / "restored" / RUNS[0], run_dir)
    (run_dir / "run.yaml").write_text(
        (run_dir / "run.yaml").read_text().replace("mesh_level: 1", "mesh_level: 2"))
    with pytest.raises(archive.ArchiveError, match=rf"{run_dir} holds another run.*mesh_lev"):
        archive.collect(run_dir, record_dir, want)
    spec = study_spec()
    with pytest.raises(archive.ArchiveError, match=rf"{run_dir} holds another run"):
        archive.plan([spec], store, lambda s: want, lambda s: [0.2, 0.4, 0.6],
                     workdir=tmp_path)
    assert tree(store) == before
    # Another run's files copied into the record, its checksums made to agree.
    other = record_dir_of(store, 1)
    for name in ("run.yaml", "timeseries.h5", "summary.json"):
        shutil.copyfile(other / name, record_dir / name)
    forge(record_dir, lambda r: None)
    with pytest.raises(archive.ArchiveError, match=rf"{record_dir}: run.yaml is not the"):
        archive.read_record(record_dir)
    # ... and its options too: the state is still this run's.
    forge(record_dir, lambda r: r.update(options=archive.read_record(other)["options"]))
    with pytest.raises(archive.ArchiveError,
                       match=rf"{record_dir}: state.h5 is of another run.*seed"):
        archive.read_record(record_dir)


def _restore(args):
    return archive.restore_run(*args)


def test_case3_concurrent_restores_leave_every_run_equal_to_the_archive(study, tmp_path):
    record_dir, want = record_dir_of(study["store"], 0), stored_options(study)
    run_dir = tmp_path / RUNS[0]
    with ProcessPoolExecutor(4) as pool:
        done = list(pool.map(_restore, [(record_dir, run_dir, want)] * 4))
    assert sum(done) == 1  # one restored it, the others found it whole
    reference = series(study["base"] / "restored" / RUNS[0])
    restored = series(run_dir)
    assert reference.keys() == restored.keys()
    for name in reference:
        np.testing.assert_array_equal(reference[name], restored[name], err_msg=name)
    archive.check_folder(run_dir, want)
    assert [p.name for p in run_dir.parent.iterdir()] == [run_dir.name]  # no leftovers
    # A restored file damaged later: the folder does not count as finished.
    (run_dir / "timeseries.h5").write_bytes(b"")
    with pytest.raises(archive.ArchiveError,
                       match=rf"{run_dir}: timeseries.h5 is not as restored.*rm -r"):
        archive.check_folder(run_dir, want)
    # A folder left with summary.json alone: named, with what to do.
    alone = tmp_path / "alone"
    alone.mkdir()
    shutil.copyfile(study["base"] / "restored" / RUNS[0] / "summary.json",
                    alone / "summary.json")
    with pytest.raises(archive.ArchiveError, match=rf"{alone} is damaged.*missing.*rm -r"):
        archive.reached(alone)


def test_case4_only_the_files_a_record_lists_are_restored(study, tmp_path):
    store = copied_store(study, tmp_path)
    record_dir = record_dir_of(store, 0)
    (record_dir / "snapshot_000099.h5").write_bytes(b"xx")
    with pytest.raises(archive.ArchiveError,
                       match=rf"{record_dir}: holds snapshot_000099.h5, which record.json"):
        archive.read_record(record_dir)
    checked = verify(store)
    assert checked.returncode == 1 and "snapshot_000099.h5" in checked.stderr
    (record_dir / "snapshot_000099.h5").unlink()
    run_dir = tmp_path / "run"
    archive.restore(record_dir, run_dir, archive.read_record(record_dir), full=True)
    assert sorted(p.name for p in run_dir.iterdir()) == [
        "checkpoint.h5", "restored.json", "run.yaml", "segments.json", "summary.json",
        "timeseries.h5"]


def test_case5_a_folder_of_the_archive_without_record_json_is_named(study, tmp_path):
    store = copied_store(study, tmp_path)
    record_dir = record_dir_of(store, 1)
    (record_dir / "record.json").unlink()
    checked = verify(store)
    assert checked.returncode == 1
    assert f"{record_dir} holds no record.json" in checked.stderr
    dry = snakemake(tmp_path / "work", {**study["config"], "archive": str(store)}, FIGURE,
                    dry=True)
    assert dry.returncode != 0
    assert f"{record_dir} holds no record.json" in dry.stdout + dry.stderr


def test_case6_the_key_follows_the_solver_s_own_defaults(study):
    record = archive.read_record(record_dir_of(study["store"], 0))
    spec = study_spec()
    resolved = spec.resolved_options(CAPSIM)
    assert spec.key(CAPSIM) == record["key"] and archive.usable(record, resolved) == "full"
    # `capsim params --json` is the solver's table of defaults, as `capsim params` shows.
    table = subprocess.run([str(CAPSIM), "params"], capture_output=True, text=True,
                           check=True).stdout
    shown = {row.split("|")[1].strip(" `"): row.split("|")[2].strip()
             for row in table.splitlines() if row.startswith("| `")}
    assert run_spec.resolved_options(CAPSIM, []) == shown
    # A default changed in the solver: the record is no longer this run's.
    assert archive.usable(record, {**resolved, "quadrature.max_depth": "7"}) == "changed"
    # One spelling; an option added since is read at the value runs took before it.
    assert run_spec.options_key({**resolved, "dt_safety": "0.10"}, "1") == \
        run_spec.options_key({**resolved, "dt_safety": 0.1}, "1")
    before = {k: v for k, v in resolved.items() if k != "time.stages"}
    assert run_spec.options_key(before, "1") == run_spec.options_key(resolved, "1")
    # lambda and membrane.law (issue 49) are out of the key at 1 and neo_hookean, the
    # values of every earlier run (which they leave bit for bit), so the records keep
    # their keys; any other value is in it.
    for key, other in (("lambda", "5"), ("membrane.law", "drop")):
        without = {k: v for k, v in resolved.items() if k != key}
        assert run_spec.options_key(without, "1") == run_spec.options_key(resolved, "1")
        assert run_spec.options_key({**resolved, key: other}, "1") != \
            run_spec.options_key(resolved, "1")
    # dt_lambda_max (the automatic step's growth above lambda 1) keys a run only where
    # it acts, at lambda > 1, and there not at 1, the step every earlier run took.
    for ratio in ("1", "0.2"):
        at = {**resolved, "lambda": ratio}
        assert run_spec.options_key({**at, "dt_lambda_max": "3"}, "1") == \
            run_spec.options_key({k: v for k, v in at.items() if k != "dt_lambda_max"}, "1")
    above = {k: v for k, v in resolved.items() if k != "dt_lambda_max"} | {"lambda": "5"}
    assert run_spec.options_key({**above, "dt_lambda_max": "1"}, "1") == \
        run_spec.options_key(above, "1")
    assert run_spec.options_key({**above, "dt_lambda_max": "2"}, "1") != \
        run_spec.options_key(above, "1")
    # A dilute run does not use the periodic sums: they are not in its key.
    dilute = run_spec.resolved_options(CAPSIM, [])
    assert run_spec.options_key({**dilute, "ewald.precision": "single"}, "1") == \
        run_spec.options_key(dilute, "1")


def test_case7_a_space_in_the_path_an_unwritable_archive_an_empty_summary(
        study, tmp_path, monkeypatch):
    # Every job recorded into the fixture's archive, whose path holds a space.
    assert " " in str(study["store"]) and len(archive.read_records([study["store"]])) == 2
    # An archive that cannot be written: the job says so and succeeds (the run is kept).
    spec = study_spec()
    run_dir = tmp_path / spec.folder
    shutil.copytree(study["base"] / "restored" / RUNS[0], run_dir)
    monkeypatch.chdir(tmp_path)

    def unwritable(*args, **kwargs):
        raise PermissionError(13, "Permission denied", str(study["store"]))

    monkeypatch.setattr(archive, "collect", unwritable)
    log = tmp_path / "job.log"
    status = job.main(["--capsim", str(CAPSIM), "--log", str(log), "--spec", spec.to_json(),
                       "--pause-at", "0.2", "--segment", "1", "--archive",
                       str(study["store"])])
    assert status == 0 and "NOT RECORDED" in log.read_text()
    assert "Permission denied" in log.read_text()
    # An empty summary.json: named, with what to do.
    (run_dir / "summary.json").write_text("")
    with pytest.raises(archive.ArchiveError, match=rf"{run_dir} is damaged.*rm -r"):
        archive.reached(run_dir)


def test_case8_a_killed_attempt_s_cpu_time_is_in_the_segments(tmp_path, monkeypatch):
    fake = tmp_path / "capsim"
    fake.write_text(f"#!{sys.executable}\n"
                    "import os, signal, time\n"
                    "start = time.process_time()\n"
                    "while time.process_time() - start < 0.3:\n"
                    "    pass\n"
                    "os.kill(os.getpid(), signal.SIGKILL)\n")
    fake.chmod(0o755)
    spec = study_spec()
    run_dir = tmp_path / spec.folder
    run_dir.mkdir(parents=True)
    monkeypatch.chdir(tmp_path)
    status = job.run_job(str(fake), spec, tmp_path / "run.log", threads=1)
    assert status == 128 + 9
    segments = json.loads((run_dir / "segments.json").read_text())
    assert len(segments) == 1 and segments[0]["cpu_seconds"] >= 0.25
    assert segments[0]["ended"] == "killed by signal 9 (SIGKILL)"


def test_a_longer_run_s_series_repeats_the_shorter_s_complete_chunks(tmp_path):
    # A run recorded again further on (a raised t_end, the next segment) keeps its
    # earlier rows, and the record's compressed chunks of them stay the same bytes, which
    # git's packs then store once (archive.CHUNK_ROWS).
    rows, capsules = 3 * archive.CHUNK_ROWS + 40, 3
    rng = np.random.default_rng(1)
    with h5py.File(tmp_path / "capsim.h5", "w") as f:
        f["time"] = 0.05 * np.arange(rows)
        f["step"] = np.arange(rows, dtype=np.int64)
        f["capsule/stresslet"] = rng.normal(size=(rows, capsules, 3, 3))
    full, short = tmp_path / "full.h5", tmp_path / "short.h5"
    archive.compact_series(tmp_path / "capsim.h5", full)
    with h5py.File(tmp_path / "capsim.h5", "r") as f, \
            h5py.File(tmp_path / "prefix.h5", "w") as g:
        for name in ("time", "step", "capsule/stresslet"):
            g[name] = f[name][: 2 * archive.CHUNK_ROWS + 7]
    archive.compact_series(tmp_path / "prefix.h5", short)
    with h5py.File(full, "r") as a, h5py.File(short, "r") as b:
        for name in ("time", "capsule/stresslet"):
            zeros = (0,) * (a[name].ndim - 1)
            for k in range(2):  # the two chunks the shorter series fills
                at = (k * archive.CHUNK_ROWS,) + zeros
                assert a[name].id.read_direct_chunk(at) == b[name].id.read_direct_chunk(at)
            at = (2 * archive.CHUNK_ROWS,) + zeros  # its last, partial one differs
            assert a[name].id.read_direct_chunk(at) != b[name].id.read_direct_chunk(at)


def test_a_lengthened_record_without_a_state_keeps_its_end(tmp_path):
    """A run of one segment keeps no state; raised to a longer t_end it is computed again
    from the start, in segments, and its progress is no record's until it passes the old
    end. The longer record keeps its end instead, so that a second raise continues from
    there rather than computing the run a third time."""
    store = tmp_path / "store"
    one = {**STUDY, "archive": str(store), "segments": {"strain": None, "minutes": None},
           "initial": {**STUDY["initial"], "seeds": [1], "t_end": 0.4}}
    summary = f"{RUNS[0]}/summary.json"  # the run alone: no figure to draw
    assert snakemake(tmp_path / "a", one, summary).returncode == 0
    record_dir = store / "initial" / RUNS[0].split("/")[-1]
    assert archive.read_record(record_dir)["state_time"] is None
    # Two segments, the first ending before the old end (nothing new to record there).
    longer = {**one, "segments": {"strain": 0.3}, "initial": {**one["initial"], "t_end": 0.5}}
    done = snakemake(tmp_path / "b", longer, summary)
    assert done.returncode == 0, done.stderr[-3000:]
    record = archive.read_record(record_dir)
    assert record["finished"] and record["state_time"] == pytest.approx(record["t_reached"])
    again = {**longer, "initial": {**longer["initial"], "t_end": 0.6}}
    dry = snakemake(tmp_path / "c", again, summary, dry=True)
    assert "1 run(s) to restore and continue" in dry.stderr, dry.stderr[-3000:]
