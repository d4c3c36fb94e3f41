"""The viscosity-ratio study (workflow/rules/viscosity_ratio.smk, analysis/viscosity_ratio.py,
figures/viscosity_ratio.py): which runs it plans (lambda 1 is the dilute study's run where
the settings match), its table on tiny real runs (level 2, a fraction of a strain) and a
stopped one, its figure, and its section of the results page, there where the
configuration shows it.
The runs and dry runs need build/capsim and snakemake and are skipped without them."""

import json
import math
import runpy
import shutil
import subprocess
import sys
from pathlib import Path

import matplotlib.pyplot as plt
import pandas as pd
import pytest
import yaml

from analysis import viscosity_ratio as vr
from analysis.read_run import read_summary
from pipeline import results_page, run_spec

ROOT = Path(__file__).resolve().parents[2]
CAPSIM = ROOT / "build" / "capsim"
SNAKEMAKE = Path(sys.executable).with_name("snakemake")
needs_capsim = pytest.mark.skipif(not CAPSIM.exists(),
                                  reason="build/capsim is missing (bash scripts/setup.sh)")
needs_snakemake = pytest.mark.skipif(not SNAKEMAKE.exists(), reason="snakemake is missing")

DILUTE = {"t_end": 20, "t_avg_start": 10, "options": {"quadrature.near_ratio": 1.5}}
BLOCK = {"ca": [0.2], "lambda": [0.2, 1, 5], "mesh_level": 3, "t_end": 20, "t_avg_start": 10}
T_END = 0.3  # the tiny runs' end; averages from T_START
T_START = 0.1


def test_lambda_1_at_the_dilute_t_end_is_the_dilute_study_s_own_run():
    assert run_spec.viscosity_ratio(0.2, 1, BLOCK, DILUTE) == run_spec.dilute(0.2, 3, DILUTE)
    other = run_spec.viscosity_ratio(0.2, 1, BLOCK | {"t_end": 30}, DILUTE)
    # Another t_end: a run of its own, lambda left at capsim's default (1).
    assert other.folder == "results/viscosity_ratio/ca0.2_level3_lambda1"
    assert "lambda" not in other.trajectory_options() and other.t_end == 30


def test_another_ratio_is_a_run_of_its_own_with_the_dilute_options():
    spec = run_spec.viscosity_ratio(0.05, 0.2, BLOCK, DILUTE)
    assert spec.folder == "results/viscosity_ratio/ca0.05_level3_lambda0.2"
    assert spec.trajectory_options() == {"ca": 0.05, "mesh_level": 3,
                                         "quadrature.near_ratio": 1.5, "lambda": 0.2}
    assert (spec.t_end, spec.t_avg_start, spec.stop_is_result) == (20, 10, True)
    # Its cost per strain: the benchmark's measured factor over lambda 1, at the level
    # and ratio measured, and doubled a level up.
    record = json.loads((ROOT / "benchmarks" / "records" /
                         "viscosity_ratio_cost.json").read_text())
    ratio = {(c["mesh_level"], c["lambda"]): c["cost_ratio"] for c in record["cases"]
             if all(v for k, v in c.items() if k.startswith("default_"))}  # defaults
    plain = run_spec.dilute(0.05, 3, DILUTE).seconds_per_strain()
    assert spec.seconds_per_strain() == pytest.approx(ratio[(3, 0.2)] * plain)
    five = run_spec.viscosity_ratio(0.05, 5, BLOCK | {"mesh_level": 2}, DILUTE)
    assert five.seconds_per_strain() == pytest.approx(
        ratio[(2, 5.0)] * run_spec.dilute(0.05, 2, DILUTE).seconds_per_strain())
    assert run_spec.lambda_cost_ratio(4, 8.0, dense=False) == 2 * ratio[(3, 10.0)]
    assert run_spec.lambda_cost_ratio(3, 1.0, dense=True) == 1.0


def dry_run(workdir, target, *configfiles):
    """snakemake -n of target (a word, or a tuple of words) in workdir."""
    target = [target] if isinstance(target, str) else list(target)
    cmd = [str(SNAKEMAKE), "-n", *target, "--snakefile", str(ROOT / "Snakefile"),
           "--directory", str(workdir), "--configfile",
           *[str(ROOT / "config" / "ci.yaml"), *map(str, configfiles)]]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return proc.stdout


def planned_runs(output):
    """The run folders a dry run's `run` jobs write summary.json into."""
    words = [line.split() for line in output.splitlines()]
    return sorted(w[1][: -len("/summary.json")] for w in words
                  if len(w) == 2 and w[0] == "output:" and w[1].endswith("/summary.json"))


@needs_capsim
@needs_snakemake
def test_the_ci_study_plans_its_runs_once_and_lambda_1_in_the_dilute_folder(tmp_path):
    runs = planned_runs(dry_run(tmp_path, "viscosity_ratio"))
    assert runs == ["results/dilute/ca0.2_level2", "results/dilute/ca0.4_level2",
                    "results/viscosity_ratio/ca0.2_level2_lambda0.2",
                    "results/viscosity_ratio/ca0.2_level2_lambda5",
                    "results/viscosity_ratio/ca0.4_level2_lambda0.2",
                    "results/viscosity_ratio/ca0.4_level2_lambda5"]
    # Another t_end than the dilute study's: lambda 1 is a run of the study's own.
    (tmp_path / "short.yaml").write_text("viscosity_ratio: {ca: [0.2], lambda: [1, 5], "
                                         "mesh_level: 2, t_end: 0.5, t_avg_start: 0.2}\n")
    runs = planned_runs(dry_run(tmp_path, "viscosity_ratio", tmp_path / "short.yaml"))
    assert runs == ["results/viscosity_ratio/ca0.2_level2_lambda1",
                    "results/viscosity_ratio/ca0.2_level2_lambda5"]


@needs_capsim
@needs_snakemake
def test_the_results_page_needs_the_study_only_where_the_configuration_shows_it(tmp_path):
    def jobs(output):
        return {line.split()[-1] for line in output.splitlines()
                if line.startswith(("rule ", "localrule "))}

    # --forcerun: the page (docs/results.md, in the repository) is scheduled whether or
    # not its file is newer than its code, so the jobs it needs are listed.
    page = ("results_page", "--forcerun", "results_page")
    assert "viscosity_ratio_table:" not in jobs(dry_run(tmp_path, page))
    (tmp_path / "page.yaml").write_text("viscosity_ratio: {ca: [0.2], lambda: [1, 5], "
                                        "mesh_level: 2, t_end: 1, t_avg_start: 0.5, "
                                        "on_page: true}\n")
    shown = dry_run(tmp_path, page, tmp_path / "page.yaml")
    assert {"viscosity_ratio_table:", "viscosity_ratio_figure:"} <= jobs(shown)


@pytest.fixture(scope="module")
def tiny_runs(capsim_run):
    """{lambda: run folder} of one capsule at Ca 0.2, level 2, to T_END."""
    if not CAPSIM.exists():
        pytest.skip("build/capsim is missing (bash scripts/setup.sh)")
    return {ratio: capsim_run(f"lambda{ratio}", "ca=0.2", "mesh_level=2", f"lambda={ratio}",
                              f"t_end={T_END}", f"t_avg_start={T_START}")
            for ratio in (1, 5)}


def entries(runs):
    return [{"ca": 0.2, "lambda": ratio, "folder": str(folder)}
            for ratio, folder in runs.items()]


def test_the_table_reads_the_dilute_reduction_and_the_gmres_counts(tiny_runs):
    table = vr.study_table(entries(tiny_runs), T_START)
    assert list(table.columns) == list(vr.COLUMNS)
    assert list(table["lambda"]) == [1, 5] and set(table["ended"]) == {"t_end"}
    for row in table.to_dict("records"):
        summary = read_summary(tiny_runs[row["lambda"]])
        # The window is the run's own, so the averages are capsim's summary values.
        assert row["D"] == pytest.approx(summary["taylor_D"], rel=1e-9)
        assert row["theta_D_deg"] == pytest.approx(summary["theta_D_deg"], rel=1e-9)
        assert row["mu_sp"] == pytest.approx(summary["mu_sp"], rel=1e-9)
        assert row["N1"] == pytest.approx(summary["N1"], rel=1e-9)
        assert row["N_E"] == 320 and row["count"] > 0 and row["mu_sp_se"] > 0
    one, five = table.to_dict("records")
    assert math.isnan(one["gmres_iterations_mean"])
    assert five["gmres_iterations_mean"] == read_summary(tiny_runs[5])["gmres_iterations_mean"]
    text = vr.markdown(table)
    assert "| 0.2 | 1 |" in text and "none (lambda 1)" in text and "| t_end |" in text
    assert "beyond it" in text and "Tank-treading frequency" in text


def test_a_folder_of_another_ratio_is_refused(tiny_runs):
    wrong = [{"ca": 0.2, "lambda": 0.2, "folder": str(tiny_runs[5])}]
    with pytest.raises(ValueError, match="carries lambda 5, not 0.2"):
        vr.study_table(wrong, T_START)


def stopped_copy(folder, tmp_path):
    """A copy of a run whose summary says it stopped on a numerical failure (a fold)."""
    copy = tmp_path / "stopped"
    shutil.copytree(folder, copy)
    summary = read_summary(copy) | {"ended": "numerical", "end_message": "inverted"}
    (copy / "summary.json").write_text(json.dumps(summary))
    return copy


def test_a_run_that_stopped_before_the_window_is_a_row_without_averages(tiny_runs, tmp_path):
    runs = {5: stopped_copy(tiny_runs[5], tmp_path)}
    table = vr.study_table(entries(runs), T_END + 1)  # the window starts after its end
    stopped = table.iloc[0]
    assert stopped["ended"] == "numerical" and stopped["count"] == 0
    assert math.isnan(stopped["D"]) and stopped["t_stop"] == pytest.approx(T_END, abs=0.1)
    assert f"numerical at {stopped['t_stop']:.3g}" in vr.markdown(table)
    with pytest.raises(ValueError):  # one that ran to its end must have its window
        vr.study_table(entries({1: tiny_runs[1]}), T_END + 1)


def run_figure(*args, name="viscosity_ratio"):
    """figures/<name>.py as its command line runs it, in this process."""
    script = ROOT / "figures" / f"{name}.py"
    argv, path = sys.argv, list(sys.path)
    sys.argv, sys.path[:0] = [str(script), *map(str, args)], [str(script.parent)]
    try:
        runpy.run_path(str(script), run_name="__main__")
    finally:
        sys.argv, sys.path[:] = argv, path
        plt.close("all")


@pytest.fixture(scope="module")
def results(tiny_runs, tmp_path_factory):
    """A results folder with the study's table (a run at lambda 5 stopped) and figure."""
    out = tmp_path_factory.mktemp("results")
    runs = {1: tiny_runs[1], 5: stopped_copy(tiny_runs[5], out)}
    table = vr.study_table(entries(runs), T_START)
    (out / "viscosity_ratio").mkdir()
    table.to_csv(out / "viscosity_ratio" / "table.csv", index=False)
    run_figure("--out", out / "figures" / "viscosity_ratio",
               out / "viscosity_ratio" / "table.csv")
    return out


def test_the_figure_draws_the_runs_that_ended_and_names_the_stopped(results):
    data = pd.read_csv(results / "figures" / "viscosity_ratio.csv")
    assert list(data["lambda"]) == [1]  # the stopped run is not drawn
    caption = (results / "figures" / "viscosity_ratio.txt").read_text()
    assert "Not drawn, stopped before their end: Ca 0.2, lambda 5: numerical at" in caption
    assert (results / "figures" / "viscosity_ratio.png").stat().st_size > 0


def test_the_results_page_section(results, tmp_path):
    lines = results_page.viscosity_ratio_lines(results, tmp_path)
    text = "\n".join(lines)
    assert lines[0] == "## Beyond the paper: the viscosity ratio"
    assert "the rows with lambda != 1 are beyond the paper" in text
    assert "| 0.2 | 5 |" in text and "numerical at" in text
    assert "![The viscosity ratio](" in text and (tmp_path / "viscosity_ratio.png").exists()
    dense = [line for line in lines if "once all its runs are archived" in line]
    assert len(dense) == 1 and "Ca 0.2, phi 0.1-0.3, M = 27" in dense[0]
    # The study's cost from the benchmark at its own scale and tolerance, the range over
    # the machines measured.
    measured = [{c["lambda"]: c["cost_ratio"] for c in json.loads(
        (ROOT / "benchmarks" / "records" / name).read_text())["cases"]
        if c["mesh_level"] == 3 and c["gmres_tolerance"] == 1e-5}
        for name in ("viscosity_ratio_cost_dense_M27.json",
                     "viscosity_ratio_cost_dense_M27_epyc.json")]
    at = {ratio: sorted(m[ratio] for m in measured) for ratio in (5.0, 0.2)}
    assert f"costs {at[5.0][0]:.0f} to {at[5.0][1]:.0f} times and at lambda 0.2 " \
        f"{at[0.2][0]:.0f} to {at[0.2][1]:.0f} times lambda = 1" in dense[0]


# The dense part: the grid's suspension at other ratios.

def test_a_dense_run_is_the_grid_s_suspension_with_lambda_and_the_block_s_options():
    keys = dict(ca=0.2, phi=0.3, M=27, level=3, seed=1)
    grid = {"t_end": 30}
    spec = run_spec.viscosity_ratio_dense(keys, 5, grid, 10, {"ewald.tolerance": "auto"},
                                          {"gmres.tolerance": 1e-5})
    assert spec.folder == "results/viscosity_ratio/ca0.2_phi0.3_M27_level3_seed1_lambda5"
    assert spec.trajectory_options().items() >= {"lambda": 5, "gmres.tolerance": 1e-5,
                                                 "ewald.tolerance": "auto"}.items()
    assert (spec.M, spec.t_end, spec.t_avg_start) == (27, 30, 10)
    with pytest.raises(ValueError, match="lambda 1 is the grid's own run"):
        run_spec.viscosity_ratio_dense(keys, 1, grid, 10, {})


def test_a_dense_run_keeps_the_grid_s_t_end_where_the_grid_s_point_runs_longer():
    # grid.t_end_at lengthens the lambda = 1 run for the O(phi^3) shares; the dense
    # study's runs at other ratios stay at the grid's t_end (and so their records).
    keys = dict(ca=0.2, phi=0.1, M=27, level=3, seed=1)
    grid = {"t_end": 30, "ca": [0.2], "phi": [0.1, 0.3],
            "t_end_at": [{"ca": 0.2, "phi": 0.1, "t_end": 150}]}
    assert run_spec.suspension("grid", keys, grid, 10, {}).t_end == 150
    spec = run_spec.viscosity_ratio_dense(keys, 0.2, grid, 10, {})
    assert (spec.t_end, spec.t_avg_start) == (30, 10)


def test_a_dense_run_s_cost_is_the_benchmark_s_at_its_scale_and_tolerance():
    # The benchmark's M 27, level 3 cases at gmres.tolerance 1e-5 price the dense study's
    # runs; a run at the default tolerance takes the M 8, level 2 cases at the defaults.
    keys = dict(ca=0.2, phi=0.3, M=27, level=3, seed=1)
    record = json.loads((ROOT / "benchmarks" / "records" /
                         "viscosity_ratio_cost_dense_M27.json").read_text())
    at_1e5 = {c["lambda"]: c["cost_ratio"] for c in record["cases"]
              if c["gmres_tolerance"] == 1e-5 and c.get("default_guess")}
    small = json.loads((ROOT / "benchmarks" / "records" /
                        "viscosity_ratio_cost_dense.json").read_text())
    defaults = {c["lambda"]: c["cost_ratio"] for c in small["cases"]
                if c.get("default_tolerance") and c.get("default_guess")}
    for ratio in (0.2, 5.0):
        assert run_spec.lambda_cost_ratio(3, ratio, dense=True, tolerance=1e-5) == \
            pytest.approx(at_1e5[ratio])
        assert run_spec.lambda_cost_ratio(3, ratio, dense=True) == \
            pytest.approx(defaults[ratio])
    study = run_spec.viscosity_ratio_dense(keys, 5, {"t_end": 30}, 10, {},
                                           {"gmres.tolerance": 1e-5})
    unsolved = run_spec.viscosity_ratio_dense(keys, 5, {"t_end": 30}, 10, {}, {})
    assert study.seconds_per_strain() / unsolved.seconds_per_strain() == pytest.approx(
        at_1e5[5.0] / defaults[5.0])


def test_the_page_s_dense_tolerance_is_the_configuration_s():
    config = yaml.safe_load((ROOT / "config" / "quantitative.yaml").read_text())
    options = config["viscosity_ratio"]["dense"]["options"]
    assert float(options["gmres.tolerance"]) == results_page.DENSE_TOLERANCE


@needs_snakemake
def test_the_ci_dense_study_plans_its_run_and_the_grid_s_at_lambda_1(tmp_path):
    runs = planned_runs(dry_run(tmp_path, "viscosity_ratio_dense"))
    assert runs == ["results/grid/ca0.2_phi0.1_M2_level1_seed1",
                    "results/viscosity_ratio/ca0.2_phi0.1_M2_level1_seed1_lambda5"]


@pytest.fixture(scope="module")
def tiny_dense(capsim_run):
    """{lambda: run folder} of two capsules at phi 0.1, Ca 0.2, level 1, to T_END."""
    return {ratio: capsim_run(f"dense{ratio}", "ca=0.2", "phi=0.1", "capsules=2",
                              "mesh_level=1", f"lambda={ratio}", f"t_end={T_END}",
                              f"t_avg_start={T_START}", "output.snapshot_interval=0")
            for ratio in (1, 5)}


def test_the_dense_table_and_figure(tiny_dense, tmp_path):
    entries = [{"ca": 0.2, "phi": 0.1, "lambda": ratio, "folder": str(folder)}
               for ratio, folder in tiny_dense.items()]
    table = vr.dense_table(entries, T_START)
    assert list(table.columns) == list(vr.DENSE_COLUMNS)
    for row in table.to_dict("records"):
        summary = read_summary(tiny_dense[row["lambda"]])
        assert row["mu_sp"] == pytest.approx(summary["mu_sp"], rel=1e-9)
        assert row["D"] == pytest.approx(summary["taylor_D"], rel=1e-9)
        assert (row["phi"], row["capsules"], row["intrinsic"]) == (0.1, 2, 0)
    assert math.isnan(table["gmres_iterations_mean"][0])
    assert table["gmres_iterations_mean"][1] > 0
    assert list(table["t_planned"]) == [T_END, T_END]
    text = vr.dense_markdown(table)
    assert "| 0.1 | 5 |" in text and "Ca 0.2, M 2, N_E 80" in text
    (tmp_path / "viscosity_ratio").mkdir()
    table.to_csv(tmp_path / "viscosity_ratio" / "dense.csv", index=False)
    run_figure("--out", tmp_path / "figures" / "viscosity_ratio_dense",
               tmp_path / "viscosity_ratio" / "dense.csv", name="viscosity_ratio_dense")
    data = pd.read_csv(tmp_path / "figures" / "viscosity_ratio_dense.csv")
    assert list(data["lambda"]) == [1, 5]
    caption = (tmp_path / "figures" / "viscosity_ratio_dense.txt").read_text()
    assert "Every run reached its end." in caption
    # The page shows the dense table where there is one.
    (tmp_path / "viscosity_ratio" / "table.csv").write_text(
        ",".join(vr.COLUMNS) + "\n")
    (tmp_path / "page").mkdir()
    page = "\n".join(results_page.viscosity_ratio_lines(tmp_path, tmp_path / "page"))
    assert "### The suspension at other viscosity ratios" in page
    assert "| 0.1 | 5 |" in page and "once all its runs are archived" not in page


@pytest.mark.parametrize("stop, drawn", [(0.21, True), (0.19, False)])
def test_the_dense_figure_draws_a_stopped_run_hollow_where_its_window_holds_half(
        tiny_dense, tmp_path, stop, drawn):
    # The lambda 5 run as if it had stopped at `stop`: its window [0.1, stop] holds more
    # than half the planned [0.1, 0.3] at 0.21 (drawn hollow, averaged to its stop), less
    # at 0.19.
    entries = [{"ca": 0.2, "phi": 0.1, "lambda": ratio, "folder": str(folder)}
               for ratio, folder in tiny_dense.items()]
    table = vr.dense_table(entries, T_START)
    table.loc[table["lambda"] == 5, ["ended", "t_stop"]] = ["numerical", stop]
    table.to_csv(tmp_path / "dense.csv", index=False)
    run_figure("--out", tmp_path / "figure", tmp_path / "dense.csv",
               name="viscosity_ratio_dense")
    data = pd.read_csv(tmp_path / "figure.csv")
    assert list(data["lambda"]) == ([1, 5] if drawn else [1])
    caption = (tmp_path / "figure.txt").read_text()
    stopped = "phi 0.1, lambda 5: numerical at gammadot t = " + f"{stop:.3g}"
    assert ("Drawn hollow, stopped before their end and averaged to their stop: "
            if drawn else "Not drawn, stopped before their end: ") + stopped in caption
