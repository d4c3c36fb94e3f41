"""The sensitivity study: its membrane codes, its plan, the change against the paper's
membrane and the smallest bending modulus on synthetic rows with known answers, the
membrane named in the figures' footers, and the study's small variant (config/ci.yaml)
end to end through the workflow."""

import importlib.util
import math
import sys

import numpy as np
import pandas as pd
import pytest
import yaml

from analysis import membrane
from analysis.tables import COLUMNS, run_row, stopped_row
from analysis.sensitivity import (Run, changes_against_paper, dilute_references,
                                  mark_smallest_eb, plan, run_names)
from pipeline import run_spec
from pipeline.command_line import set_arguments
from test_workflow_ci import ROOT, snakemake, pytestmark  # noqa: F401 (skips without capsim)

sys.path.insert(0, str(ROOT / "figures"))
import common  # noqa: E402 (figures/common.py, after its folder is on the path)


def config_block(name="config.yaml"):
    config = yaml.safe_load((ROOT / "config" / name).read_text())
    return config["sensitivity"], config["dilute"]


@pytest.mark.parametrize("code, options", [
    ("paper", []),
    ("wrinkling", ["membrane.wrinkling=true"]),
    ("eb0.05", ["membrane.bending=0.05"]),
    ("eb0.01+imex", ["membrane.bending=0.01", "time.scheme=imex", "time.tolerance=auto"]),
    ("imex1e-3+rep5+eb0.025", ["membrane.bending=0.025", "suspension.repulsion_force=5",
                               "time.scheme=imex", "time.tolerance=0.001"]),
    ("consistent+rep5", ["suspension.repulsion_force=5", "membrane.load=consistent",
                         "dt_safety=0.2"]),
    ("eb0.01+wrinkling", ["membrane.wrinkling=true", "membrane.bending=0.01"]),
    ("rep5+eb0.025", ["membrane.bending=0.025", "suspension.repulsion_force=5"]),
])
def test_membrane_codes_give_capsim_options(code, options):
    assert membrane.options(code) == options


def test_a_code_overrides_the_run_options():
    run = Run("suspension", 0.6, 0.4, 3, "eb0.025+rep5", 27, 1, 20.0, (10, 20))
    spec = run_spec.sensitivity(
        run, {"suspension.repulsion_force": 1, "membrane.wrinkling": True}, {})
    options = " ".join(set_arguments(spec.capsim_options(threads=2)))
    assert spec.folder == "results/sensitivity/" + run.name
    assert "--set suspension.repulsion_force=5" in options
    assert "repulsion_force=1" not in options
    # the code's membrane replaces run_options' (the paper's membrane keys are always set)
    assert "--set membrane.wrinkling=false" in options
    assert "--set membrane.bending=0.025" in options


@pytest.mark.parametrize("code", ["bending", "eb", "ebx", "eb0", "eb-0.1", "eb2",
                                  "paper+eb0.01", "wrinkling+wrinkling", "eb0.01+eb0.02",
                                  "Wrinkling", "", "rep", "rep0", "rep101", "rep5+rep1",
                                  "imex0", "imex0.2", "imexx", "imex+imex1e-3"])
def test_bad_membrane_codes_name_the_key_and_the_forms(code):
    with pytest.raises(ValueError, match=r"sensitivity\.membranes: .*allowed: paper"):
        membrane.options(code)


def test_canonical_spelling():
    assert membrane.canonical("eb0.050+wrinkling") == "wrinkling+eb0.05"
    assert membrane.membrane_part("eb0.01+imex") == "eb0.01"
    assert membrane.canonical("rep5.0+wrinkling") == "wrinkling+rep5"
    assert membrane.membrane_part("imex+rep5+eb0.025") == "eb0.025"
    assert membrane.canonical("imex1e-3+rep5.0+eb0.025") == "eb0.025+rep5+imex0.001"
    assert membrane.membrane_part("eb0.025+imex0.001") == "eb0.025"
    assert membrane.membrane_part("consistent+rep5") == "paper"


@pytest.mark.parametrize("parameters, code", [
    ({}, "paper"),  # a summary of a version without the keys
    ({"membrane.wrinkling": False, "membrane.bending": 0}, "paper"),
    ({"membrane.wrinkling": True, "membrane.bending": 0}, "wrinkling"),
    ({"membrane.wrinkling": False, "membrane.bending": 0.05}, "eb0.05"),
    ({"membrane.wrinkling": True, "membrane.bending": 0.01}, "wrinkling+eb0.01"),
])
def test_membrane_code_from_summary_parameters(parameters, code):
    assert membrane.code_from_parameters(parameters) == code


def test_run_tables_say_which_membrane_a_run_carried(capsim_run):
    run = capsim_run("membrane", "ca=0.2", "mesh_level=1", "t_end=0.2", "t_avg_start=0.1",
                     "membrane.bending=0.01", "membrane.wrinkling=true", "threads=1")
    assert run_row(run)["membrane"] == "wrinkling+eb0.01"
    assert stopped_row(run)["membrane"] == "wrinkling+eb0.01"
    assert "membrane" in COLUMNS


def test_plan_of_the_default_configuration():
    block, dilute = config_block()
    runs = plan(block, dilute)
    suspension = [r for r in runs if r.case == "suspension"]
    diluted = [r for r in runs if r.case == "dilute"]
    assert len(suspension) == 5 * 3 * 2 and len(diluted) == 7 * 2 * 2
    assert len(run_names(block, dilute)) == 58  # every name distinct
    names = {r.name for r in runs}
    assert "ca0.6_phi0.4_M8_level2_seed1_eb0.05" in names
    assert "ca0.6_phi0.4_M8_level3_seed1_eb0.025" in names
    assert "dilute_ca0.2_level2_wrinkling" in names
    # The dilute runs are compared with the dilute study's, over its window.
    references = dilute_references(block, dilute)
    assert len(references) == 14 and all(r.membrane == "paper" for r in references)
    assert {r.window for r in diluted} == {(dilute["t_avg_start"], dilute["t_end"])}


def test_plan_refuses_a_bad_code_and_a_level_listed_twice():
    block, dilute = config_block()
    bad = block | {"membranes": [{"mesh_level": 2, "codes": ["paper", "eb0"]}]}
    with pytest.raises(ValueError, match=r"sensitivity\.membranes: membrane 'eb0'"):
        plan(bad, dilute)
    twice = block | {"membranes": [{"mesh_level": 2, "codes": ["paper"]}] * 2}
    with pytest.raises(ValueError, match="mesh level 2 is listed twice"):
        plan(twice, dilute)
    bad_dilute = block | {"dilute": {"ca": [0.2], "mesh_levels": [2], "membranes": ["x"]}}
    with pytest.raises(ValueError, match=r"sensitivity\.dilute\.membranes"):
        plan(bad_dilute, dilute)


def synthetic(rows):
    base = {"case": "suspension", "ca": 0.6, "phi": 0.4, "mesh_level": 2, "ended": "t_end"}
    table = pd.DataFrame([base | r for r in rows])
    for q in ("mu_sp", "N1"):
        table[q], table[f"{q}_se"] = table["D"], table["D_se"]
    return table


def test_change_against_the_paper_membrane():
    table = synthetic([
        {"membrane": "paper", "D": 0.5, "D_se": 0.01},
        {"membrane": "eb0.05", "D": 0.45, "D_se": 0.02},
        {"membrane": "wrinkling", "D": 0.6, "D_se": 0.0, "ended": "numerical"},
        {"membrane": "eb0.05", "D": 0.4, "D_se": 0.01, "mesh_level": 3},  # no paper there
    ])
    out = changes_against_paper(table)
    # 0.45 / 0.5 - 1, and the first-order error of a ratio of independent estimates.
    assert out.loc[1, "D_change"] == pytest.approx(-0.1, rel=1e-12)
    want = math.hypot(0.02 / 0.5, 0.45 * 0.01 / 0.5**2)
    assert out.loc[1, "D_change_se"] == pytest.approx(want, rel=1e-3)
    assert math.isnan(out.loc[0, "D_change"])  # the reference itself
    assert math.isnan(out.loc[2, "D_change"])  # stopped early: not a result
    assert math.isnan(out.loc[3, "D_change"])  # no paper run at its level


def test_no_change_where_the_paper_membrane_stopped():
    table = synthetic([
        {"membrane": "paper", "D": 0.5, "D_se": 0.01, "ended": "numerical"},
        {"membrane": "eb0.05", "D": 0.45, "D_se": 0.02},
    ])
    assert changes_against_paper(table)["D_change"].isna().all()


def test_smallest_bending_modulus_that_reached_the_end():
    table = synthetic([
        {"membrane": "paper", "D": 0.5, "D_se": 0.01, "ended": "numerical"},
        {"membrane": "eb0.01", "D": 0.5, "D_se": 0.01, "ended": "numerical"},
        {"membrane": "eb0.03", "D": 0.5, "D_se": 0.01},
        {"membrane": "eb0.05", "D": 0.5, "D_se": 0.01},
        {"membrane": "eb0.02+imex", "D": 0.5, "D_se": 0.01},  # not a pure bending code
        {"membrane": "wrinkling+eb0.001", "D": 0.5, "D_se": 0.01},
        {"membrane": "eb0.05", "D": 0.5, "D_se": 0.01, "mesh_level": 3},
    ])
    marked = mark_smallest_eb(table)["smallest_eb_to_end"].tolist()
    assert marked == [False, False, True, False, False, False, True]


def test_footer_names_the_membranes():
    rows = pd.DataFrame({"ca": [0.2, 0.6, 0.6], "phi": [0.3, 0.4, 0.4],
                         "capsules": 8, "seed": 1, "mesh_level": 2, "t_start": 6.0,
                         "t_end": 12.0, "count": 100, "intrinsic": 0, "ended": "t_end",
                         "membrane": ["paper", "paper", "eb0.05"]})
    text = common.footer(rows)
    assert "membrane: the paper's at Ca 0.2 phi 0.3, Ca 0.6 phi 0.4;" in text
    assert "eb0.05 at Ca 0.6 phi 0.4" in text
    only_paper = rows.assign(membrane="paper")
    assert "membrane: the paper's (no bending)" in common.footer(only_paper)
    # An older table without the column, or with empty cells, is of the paper's membrane.
    assert "membrane: the paper's (no bending)" in common.footer(rows.drop(columns="membrane"))
    assert "membrane: the paper's (no bending)" in common.footer(
        rows.assign(membrane=np.nan))
    assert "membrane: wrinkling (every run)" in common.footer(rows.assign(membrane="wrinkling"))
    dilute = pd.concat([rows, rows.iloc[:2].assign(phi=0.0, intrinsic=1, ca=[0.1, 0.2])])
    assert ("the paper's at Ca 0.1 phi 0, " not in common.footer(dilute)
            and "the paper's at Ca 0.2 phi 0.3, Ca 0.6 phi 0.4, the dilute limit at Ca 0.1, 0.2"
            in common.footer(dilute))


def load_figure_script():
    spec = importlib.util.spec_from_file_location("sensitivity_figure",
                                                  ROOT / "figures" / "sensitivity.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_figure_lists_the_runs_that_stopped():
    figure = load_figure_script()
    rows = pd.DataFrame({"case": ["suspension", "suspension", "dilute"],
                         "ca": [0.6, 0.4, 0.6], "phi": [0.4, 0.3, 0.0], "N_E": [320, 1280, 320],
                         "membrane": ["paper", "wrinkling", "eb0.05"],
                         "ended": ["numerical", "contact", "t_end"],
                         "t_stop": [4.851, 9.2, 12.0]})
    text = figure.stopped_text(rows)
    assert ("by a numerical failure (numerical: a triangle inverted): Ca 0.6, phi 0.4, "
            "N_E 320, paper at 4.85") in text
    assert ("By contact (two membranes touched): Ca 0.4, phi 0.3, N_E 1280, wrinkling "
            "at 9.20") in text
    assert "eb0.05" not in text
    assert figure.stopped_text(rows.assign(ended="t_end")) == "Every run reached its end."


def test_ci_replaces_the_levels_of_the_default(tmp_path):
    # The levels are a list, so config/ci.yaml's replaces config.yaml's (a map keyed by
    # level would be merged: ci would run levels 1, 2 and 3).
    proc = snakemake(tmp_path, "sensitivity", "-n")
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    counts = dict(line.split()[:2] for line in proc.stdout.splitlines()
                  if line.split()[:1] == ["run"])
    # one point x four membranes at level 1, one dilute run of the relaxed membrane, and the
    # dilute study's run of the paper's membrane it is compared with.
    assert int(counts["run"]) == 4 + 1 + 1


def test_default_configuration_plans_the_study(tmp_path):
    proc = snakemake(tmp_path, "sensitivity", "-n", configfile="config.yaml")
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    counts = dict(line.split()[:2] for line in proc.stdout.splitlines()
                  if line.split()[:1] == ["run"])
    # 58 runs of the study, and 14 dilute references, shared with the dilute study.
    assert int(counts["run"]) == 58 + 14


def test_a_bad_code_stops_the_workflow_before_any_run(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("sensitivity:\n  points: [[0.4, 0.2]]\n  capsules: 2\n  t_end: 0.3\n"
                   "  window: [0.1, 0.3]\n"
                   "  membranes: [{mesh_level: 1, codes: [paper, bending0.01]}]\n")
    proc = snakemake(tmp_path, "sensitivity", "-n", configfile=str(bad))
    assert proc.returncode != 0
    assert "sensitivity.membranes: membrane 'bending0.01'" in proc.stdout + proc.stderr


def test_ci_sensitivity_study(tmp_path):
    proc = snakemake(tmp_path, "sensitivity")
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    table = pd.read_csv(tmp_path / "results" / "sensitivity" / "table.csv")
    suspension = table[table["case"] == "suspension"]
    assert suspension["membrane"].tolist() == ["paper", "eb0.01", "eb0.01+imex", "wrinkling"]
    assert (suspension["mesh_level"] == 1).all() and (suspension["N_E"] == 80).all()
    assert (table["ended"] == "t_end").all()
    others = table[table["membrane"] != "paper"]
    for q in ("D", "mu_sp", "N1"):
        assert table[q].notna().all()
        assert others[f"{q}_change"].notna().all()
        assert table.loc[table["membrane"] == "paper", f"{q}_change"].isna().all()
    assert suspension["smallest_eb_to_end"].tolist() == [False, True, False, False]
    dilute = table[table["case"] == "dilute"]
    assert dilute["membrane"].tolist() == ["paper", "wrinkling"]
    assert "results/dilute/ca0.2_level1" in dilute["run"].iloc[0]
    assert "| Ca 0.4, phi 0.2 | 80 (level 1) | eb0.01 |" in (
        tmp_path / "results" / "sensitivity" / "table.md").read_text()
    for ext in ("png", "pdf", "csv"):
        assert (tmp_path / "results" / "figures" / f"sensitivity.{ext}").stat().st_size > 0


def test_grid_points_with_another_membrane_are_checked():
    points = membrane.point_membranes([{"ca": 0.6, "phi": 0.40, "membrane": "eb0.050"}],
                                      [0.2, 0.6], [0.3, 0.4], "grid.membranes")
    assert points == {(0.6, 0.4): "eb0.05"}
    with pytest.raises(ValueError, match=r"grid.membranes: Ca 0.5, phi 0.4 is not a point"):
        membrane.point_membranes([{"ca": 0.5, "phi": 0.4, "membrane": "eb0.05"}],
                                 [0.2, 0.6], [0.3, 0.4], "grid.membranes")
    with pytest.raises(ValueError, match="listed twice"):
        membrane.point_membranes([{"ca": 0.6, "phi": 0.4, "membrane": "eb0.05"}] * 2,
                                 [0.6], [0.4], "grid.membranes")
    with pytest.raises(ValueError, match="grid.membranes: membrane 'bend'"):
        membrane.point_membranes([{"ca": 0.6, "phi": 0.4, "membrane": "bend"}],
                                 [0.6], [0.4], "grid.membranes")


def test_a_grid_point_with_another_membrane_has_its_own_run(tmp_path):
    # The point's folder names its membrane (the mesh study's run of the same keys, with
    # the paper's membrane, is then its own); a bad point stops the workflow at once.
    config = yaml.safe_load((ROOT / "config" / "ci.yaml").read_text())
    extra = tmp_path / "membranes.yaml"

    def dry_run(point):
        config["grid"]["membranes"] = [point]
        extra.write_text(yaml.safe_dump(config))
        return snakemake(tmp_path, "all", "-n", configfile=str(extra))

    proc = dry_run({"ca": 0.4, "phi": 0.2, "membrane": "rep5+wrinkling+eb0.01"})
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    assert "grid/ca0.4_phi0.2_M2_level1_seed1_wrinkling+eb0.01+rep5/summary.json" in proc.stdout
    assert "mesh/ca0.4_phi0.2_M2_level1_seed1/summary.json" in proc.stdout
    proc = dry_run({"ca": 0.5, "phi": 0.2, "membrane": "eb0.01"})
    assert proc.returncode != 0
    assert "grid.membranes: Ca 0.5, phi 0.2 is not a point" in proc.stdout + proc.stderr
