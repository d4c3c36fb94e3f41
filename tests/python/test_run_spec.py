"""The one description of a run (pipeline.run_spec.RunSpec): its folder name, its capsim
command lines (fresh, resumed, one segment), its JSON form (what the job receives) and
its archive record and key, which must be those the archives already hold. The key
checks need build/capsim (`capsim params --json`) and are skipped without it."""

import dataclasses
import json
import re
from pathlib import Path

import pytest
import yaml

from pipeline import archive, run_spec
from pipeline.run_spec import RunSpec

ROOT = Path(__file__).resolve().parents[2]
CAPSIM = ROOT / "build" / "capsim"
QUANTITATIVE = ROOT / "archive" / "quantitative"
needs_capsim = pytest.mark.skipif(not CAPSIM.exists(),
                                  reason="build/capsim is missing (bash scripts/setup.sh)")

GRID_RUN = RunSpec(study="grid", ca=0.2, phi=0.3, M=27, level=3, seed=1, t_end=30,
                   t_avg_start=10,
                   options=(("dt_safety", 0.5), ("membrane.wrinkling", True)))


def merged(base, update):
    """A configuration merged as snakemake's --configfile merges it (maps recursively)."""
    out = dict(base)
    for key, value in update.items():
        out[key] = (merged(out[key], value) if isinstance(value, dict)
                    and isinstance(out.get(key), dict) else value)
    return out


def quantitative_config():
    def read(name):
        return yaml.safe_load((ROOT / "config" / name).read_text())
    return merged(read("config.yaml"), read("quantitative.yaml"))


@pytest.mark.parametrize("value, text", [(0.05, "0.05"), (0.0125, "0.0125"), (1.0, "1"),
                                         (1, "1"), (1e-05, "1e-05"), (0.3, "0.3")])
def test_a_number_is_spelt_one_way(value, text):
    # 1.0 and 1 are one run (ca1); every name the archives hold is unchanged.
    assert run_spec.number(value) == text


def test_the_folder_names_are_those_the_archive_holds():
    assert GRID_RUN.folder == "results/grid/ca0.2_phi0.3_M27_level3_seed1"
    assert dataclasses.replace(GRID_RUN, ca=0.5, phi=0.1, membrane="eb0.025").name == \
        "ca0.5_phi0.1_M27_level3_seed1_eb0.025"
    dilute = run_spec.dilute(0.05, 2, {"t_end": 20, "t_avg_start": 10})
    assert dilute.folder == "results/dilute/ca0.05_level2"
    bending = dataclasses.replace(run_spec.dilute(0.3, 3, {"t_end": 20, "t_avg_start": 10}),
                                  study="eblimit", membrane="eb0.0125")
    assert bending.folder == "results/eblimit/dilute_ca0.3_level3_eb0.0125"
    # Ca 1 given as an integer or a float is one folder.
    assert run_spec.dilute(1, 2, {"t_end": 1, "t_avg_start": 0}).name == \
        run_spec.dilute(1.0, 2, {"t_end": 1, "t_avg_start": 0}).name == "ca1_level2"
    for spec in (GRID_RUN, dilute, bending):
        assert spec.record("archive/x") == Path("archive/x") / spec.study / spec.name


def test_the_json_the_job_receives_gives_the_same_spec():
    labelled = dataclasses.replace(GRID_RUN, label="own_name", snapshot_interval=2)
    for spec in (GRID_RUN, labelled):
        text = spec.to_json()
        assert RunSpec.from_json(text) == spec
        assert RunSpec.from_json(json.loads(text)) == spec
        assert RunSpec.from_json(text).folder == spec.folder


def test_fresh_resumed_and_segment_commands(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    cmd, resumed = GRID_RUN.command("capsim", threads=2)
    assert not resumed
    assert cmd[:3] == ["capsim", "run", "-q"] and cmd[-2:] == ["-o", GRID_RUN.folder]
    assert "membrane.wrinkling=true" in cmd and "threads=2" in cmd and "ca=0.2" in cmd
    # A folder with a checkpoint is resumed with the keys capsim lets change, and a
    # segment pauses at its end.
    (tmp_path / GRID_RUN.folder).mkdir(parents=True)
    (tmp_path / GRID_RUN.folder / "checkpoint.h5").write_bytes(b"")
    cmd, resumed = GRID_RUN.command("capsim", threads=1, pause_at=4.0)
    assert resumed
    assert cmd == ["capsim", "run", "-q", "--pause-at", "4.0", "--resume", GRID_RUN.folder,
                   "--set", "t_end=30", "--set", "t_avg_start=10", "--set", "threads=1"]
    cmd, _ = GRID_RUN.command("capsim", threads=1, root="/elsewhere")
    assert "-o" in cmd and cmd[-1] == f"/elsewhere/{GRID_RUN.folder}"
    # The configuration's backend goes with every stretch: a segmented run (or a record
    # continued) on a GPU partition keeps to the GPU, whichever backend began it.
    on_gpu = dataclasses.replace(
        GRID_RUN, options=tuple(sorted(GRID_RUN.options + (("backend", "cuda"),))))
    cmd, resumed = on_gpu.command("capsim", threads=4)
    assert resumed and cmd[-2:] == ["--set", "backend=cuda"]
    fresh, _ = on_gpu.command("capsim", threads=4, root="/elsewhere")
    assert fresh.count("backend=cuda") == 1


def quantitative_specs():
    """A suspension, a dilute and a bending dilute run of config/quantitative.yaml, made
    as the workflow makes them."""
    config = quantitative_config()
    grid = config["grid"]
    keys = {"ca": 0.2, "phi": 0.3, "M": grid["capsules"], "level": grid["mesh_level"],
            "seed": 1}
    suspension = run_spec.suspension("grid", keys, grid, config["averages"]["t_start"],
                                     {**config["run_options"], **grid.get("options", {})})
    dilute = run_spec.dilute(0.2, 3, config["dilute"])
    bending = dataclasses.replace(run_spec.dilute(0.3, 3, config["dilute"]),
                                  study="eblimit", membrane="eb0.0125")
    return [suspension, dilute, bending]


@needs_capsim
@pytest.mark.parametrize("k", range(3))
def test_a_spec_finds_its_record_and_has_its_key(k):
    spec = quantitative_specs()[k]
    record = archive.read_record(spec.record(QUANTITATIVE))
    assert (record["study"], record["name"]) == (spec.study, spec.name)
    assert spec.key(CAPSIM) == record["key"]
    assert archive.usable(record, spec.resolved_options(CAPSIM)) == "full"


def test_a_grid_point_of_t_end_at_runs_longer_in_every_study_that_runs_it():
    grid = {"ca": [0.1, 0.2], "phi": [0.1, 0.4], "t_end": 30,
            "t_end_at": [{"ca": 0.1, "phi": 0.4, "t_end": 70}]}
    keys = {"ca": 0.1, "phi": 0.4, "M": 27, "level": 3, "seed": 1}
    longer = run_spec.suspension("grid", keys, grid, 10, {})
    assert longer.t_end == 70 and longer.t_avg_start == 10
    # The same run (name, key) as at the study's t_end: it continues that record.
    plain = run_spec.suspension("grid", keys, {**grid, "t_end_at": []}, 10, {})
    assert plain.t_end == 30 and plain.name == longer.name
    assert dataclasses.replace(plain, t_end=70) == longer
    # eblimit's runs of the point take the grid block, so its t_end too.
    assert run_spec.suspension("eblimit", {**keys, "membrane": "eb0.0125"}, grid, 10,
                               {}).t_end == 70
    assert run_spec.suspension("grid", {**keys, "ca": 0.2}, grid, 10, {}).t_end == 30
    assert run_spec.point_t_ends(grid, "grid.t_end_at") == {(0.1, 0.4): 70.0}
    for bad, says in [({"ca": 0.3, "phi": 0.4, "t_end": 70}, "not a point of the study"),
                      ({"ca": 0.1, "phi": 0.4, "t_end": 20}, "below the study's 30"),
                      ({"ca": 0.2, "phi": 0.1, "t_end": 50}, "listed twice")]:
        entries = [bad] + ([bad] if says == "listed twice" else [])
        with pytest.raises(ValueError, match=f"grid.t_end_at: .*{says}"):
            run_spec.point_t_ends({**grid, "t_end_at": entries}, "grid.t_end_at")


def test_eblimit_t_end_at_lengthens_the_limit_s_runs_of_a_point_and_not_the_grid_s():
    grid = {"ca": [0.3, 0.4], "phi": [0.1, 0.4], "t_end": 30,
            "membranes": [{"ca": 0.3, "phi": 0.4, "membrane": "eb0.025+rep5"}],
            "t_end_at": [{"ca": 0.3, "phi": 0.4, "t_end": 55},
                         {"ca": 0.3, "phi": 0.1, "t_end": 110}]}
    keys = {"ca": 0.3, "phi": 0.4, "M": 27, "level": 3, "seed": 1}
    limit = run_spec.eblimit_grid_block(
        grid, {"eb": [0.0125], "t_end_at": [{"ca": 0.3, "phi": 0.4, "t_end": 110}]})
    half = {**keys, "membrane": "eb0.0125+rep5"}
    assert run_spec.suspension("eblimit", half, limit, 10, {}).t_end == 110
    assert run_spec.suspension("grid", {**keys, "membrane": "eb0.025+rep5"}, grid, 10,
                               {}).t_end == 55
    # The grid's other points keep theirs; without the key the grid block is the limit's.
    assert run_spec.point_t_ends(limit, "t_end_at")[(0.3, 0.1)] == 110
    assert run_spec.eblimit_grid_block(grid, {"eb": [0.0125]}) is grid
    for bad, says in [({"ca": 0.3, "phi": 0.1, "t_end": 70}, "carries no bending"),
                      ({"ca": 0.5, "phi": 0.4, "t_end": 70}, "not a point of the study"),
                      ({"ca": 0.3, "phi": 0.4, "t_end": 20}, "below the study's 30")]:
        with pytest.raises(ValueError, match=f"eblimit.t_end_at: .*{says}"):
            run_spec.eblimit_grid_block(grid, {"eb": [0.0125], "t_end_at": [bad]})


@needs_capsim
def test_eblimit_t_end_at_in_the_quantitative_plan_runs_only_the_limit_s_run(tmp_path):
    # The workflow takes it: over the archive, only the run at half the modulus of the
    # point is planned, to the longer t_end, and the grid's run of the point is restored.
    from conftest import run_snakemake
    point = {"ca": 0.3, "phi": 0.4, "t_end": 400}
    longer = {"eblimit": {"t_end_at": [point]}}
    (tmp_path / "longer.yaml").write_text(yaml.safe_dump(longer))
    proc = run_snakemake(tmp_path, "all", "-n", configfile="quantitative.yaml",
                         extra=["--configfile", str(ROOT / "config" / "quantitative.yaml"),
                                str(tmp_path / "longer.yaml")])
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert "main studies: 1 of 87 runs to compute" in proc.stderr
    planned = set(re.findall(r"wildcards: study=(\w+), run=([\w.+]+)", proc.stdout))
    assert planned == {("eblimit", "ca0.3_phi0.4_M27_level3_seed1_eb0.0125+rep5")}


def test_the_cost_model_s_imex_at_the_bending_points_against_their_measurement():
    """At the two developed dense bending points of
    benchmarks/records/time_schemes_developed.json (Ca 0.3 and 0.4, phi 0.4, eb 0.025)
    the model's ratio of Heun's cost to imex's at 1e-3 (Heun's step shortened by
    bending's stability limit, imex's not) is within 10 % of the measured wall-time
    ratio (the machine drifts by 15-20 % within minutes; the two differ by 3 % and 1 %),
    and imex at time.tolerance auto is estimated as Heun."""
    rows = json.loads((ROOT / "benchmarks" / "records"
                       / "time_schemes_developed.json").read_text())["rows"]
    options = tuple(sorted(quantitative_config()["run_options"].items()))

    def cost(ca, code):
        return RunSpec(study="grid", ca=ca, phi=0.4, M=27, level=3, t_end=30,
                       t_avg_start=10, membrane=code, options=options).seconds_per_strain()

    for ca in (0.3, 0.4):
        wall = {row["variant"]: row["wall_s"] for row in rows
                if row["case"] == f"developed_Ca{ca}"}
        modelled = cost(ca, "eb0.025+rep5") / cost(ca, "eb0.025+rep5+imex0.001")
        assert modelled == pytest.approx(wall["heun_1"] / wall["imex"], rel=0.1)
        assert cost(ca, "eb0.025+rep5+imex") == cost(ca, "eb0.025+rep5")


def test_the_cost_model_s_longer_step_at_lambda_5_against_its_measurement():
    """The dense lambda 5 branches of benchmarks/records/viscosity_step_developed.json
    (Ca 0.2, phi 0.1 and 0.2, 27 capsules of level 3) at 2 and 3 times lambda 1's step
    (dt_lambda_max): the model's saving over lambda 1's step, g^0.65 (fitted at phi 0.1),
    is within 15 % of the measured wall-time ratio at both phi (the machine drifts by
    15-20 % within minutes), and the saving is no saving below lambda 1."""
    rows = json.loads((ROOT / "benchmarks" / "records"
                       / "viscosity_step_developed.json").read_text())["rows"]

    def cost(phi, ratio, **options):
        options = {"lambda": ratio, "gmres.tolerance": 1e-5, **options}
        return RunSpec(study="viscosity_ratio", ca=0.2, phi=phi, M=27, level=3, t_end=30,
                       t_avg_start=10,
                       options=tuple(sorted(options.items()))).seconds_per_strain()

    for phi in (0.1, 0.2):
        wall = {row["variant"]: row["wall_s"] for row in rows
                if row["case"] == f"viscosity_step_phi{phi}"}
        for growth, variant in ((2, "dt_2"), (3, "dt_3")):
            modelled = cost(phi, 5) / cost(phi, 5, dt_lambda_max=growth)
            assert modelled == pytest.approx(wall["heun_1"] / wall[variant], rel=0.15)
    assert cost(0.1, 0.2, dt_lambda_max=3) == cost(0.1, 0.2)
