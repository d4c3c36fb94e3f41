"""analysis.paper_comparison: each computation and verdict on small synthetic tables, the
numbers file of the repository, and the table with a second results folder."""

import math
from pathlib import Path

import pandas as pd
import pytest

from analysis import paper_comparison as pc
from analysis.tables import write_table

ROOT = Path(__file__).resolve().parents[2]


def grid_rows():
    """A grid table: the dilute run and phi 0.1, 0.3 at Ca 0.1, and phi 0.1 (stopped before
    its window) at Ca 0.4."""
    def row(ca, phi, D, D_se, N1, theta, count=100, ended="t_end", t_end=12.0):
        return {"ca": ca, "phi": phi, "capsules": 1 if phi == 0 else 8, "seed": 1,
                "mesh_level": 2, "t_start": 6.0, "t_end": t_end, "count": count,
                "D": D, "D_se": D_se, "theta_D_deg": theta, "theta_D_se_deg": 0.1,
                "N1": N1, "N1_se": 0.01, "N2": -0.1 * N1, "N2_se": 0.01,
                "intrinsic": int(phi == 0), "ended": ended}
    return [row(0.1, 0.0, 0.20, 0.001, 1.4, 34.0), row(0.1, 0.1, 0.22, 0.002, 0.20, 32.5),
            row(0.1, 0.3, 0.26, 0.002, 0.90, 30.0),
            row(0.4, 0.1, float("nan"), float("nan"), float("nan"), float("nan"), count=0,
                ended="contact", t_end=3.5)]


@pytest.fixture
def results(tmp_path):
    write_table(tmp_path / "grid" / "table.csv", grid_rows())
    write_table(tmp_path / "figures" / "table1.csv", [
        {"N_E": 80, "label": "80", "seed": 1, "D": 0.35, "D_se": 0.002, "mu_sp": 0.78,
         "mu_sp_se": 0.01},
        {"N_E": 320, "label": "320 (case 1)", "seed": 1, "D": 0.37, "D_se": 0.002,
         "mu_sp": 0.80, "mu_sp_se": 0.01},
        {"N_E": 320, "label": "320 (case 2)", "seed": 2, "D": 0.38, "D_se": 0.002,
         "mu_sp": 0.82, "mu_sp_se": 0.01},
        {"N_E": 320, "label": "320 (average): reference", "seed": "mean", "D": 0.375,
         "D_se": 0.0014, "D_std": 0.005, "mu_sp": 0.81, "mu_sp_se": 0.007, "mu_sp_std": 0.01}])
    write_table(tmp_path / "mesh" / "table.csv", [{"ca": 0.2, "phi": 0.3, "seed": 1}])
    write_table(tmp_path / "grid" / "fits.csv", [
        {"ca": 0.6, "phi_max": 0.1, "a1": 1.6, "a1_se": 0.01, "a2": 0.1, "a2_se": 0.2},
        {"ca": 0.1, "phi_max": 0.1, "a1": 2.3, "a1_se": 0.01, "a2": 2.7, "a2_se": 0.2}])
    write_table(tmp_path / "figures" / "fig11.csv", [
        {"seed": 1, "t_e": 12.0, "D": 0.37}, {"seed": 2, "t_e": 12.0, "D": 0.38},
        {"seed": "mean", "t_e": 12.0, "D": 0.375, "D_std": 0.005, "D_se": 0.002, "cases": 3},
        {"seed": "mean", "t_e": 12.0, "mu_sp": 0.8, "mu_sp_std": 0.02, "mu_sp_se": 0.01,
         "cases": 3}])
    write_table(tmp_path / "dilute" / "table.csv", [
        {"ca": 0.6, "quantity": "D", "level_2": 0.512, "level_3": 0.520,
         "level_4": float("nan"), "level_2_se": 1e-4, "level_3_se": 2e-4,
         "level_4_se": float("nan")}])
    return pc.Results(tmp_path)


def number(**kw):
    base = {"id": "x", "quantity": "q", "stated": "s", "kind": "value", "value": 0.0,
            "error": 0.0}
    return base | kw


def test_value_averages_the_matching_rows_and_skips_the_mean_row(results):
    spec = {"computation": "value", "file": "figures/table1.csv", "where": {"N_E": 320},
            "exclude": {"seed": "mean"}, "column": "D", "se_column": "D_se"}
    value, se, _ = pc.comp_value(results, spec)
    assert value == pytest.approx(0.375)
    assert se == pytest.approx(math.sqrt(2 * 0.002**2) / 2)  # the mean of two runs


def test_value_of_a_missing_grid_point_or_a_stopped_run_is_missing(results):
    with pytest.raises(pc.Missing, match="no grid/table.csv row"):
        pc.comp_value(results, {"file": "grid/table.csv", "where": {"ca": 0.5}, "column": "D"})
    with pytest.raises(pc.Missing, match="stopped at t = 3.5 \\(contact\\)"):
        pc.comp_value(results, {"file": "grid/table.csv", "where": {"ca": 0.4, "phi": 0.1},
                                "column": "D"})
    with pytest.raises(pc.Missing, match="no figures/fig99.csv"):
        pc.comp_value(results, {"file": "figures/fig99.csv", "column": "D"})


def test_relative_rise_from_the_dilute_limit(results):
    spec = {"where": {"ca": 0.1}, "from": "dilute", "to": 0.3, "relative": True,
            "column": "D", "se_column": "D_se"}
    value, se, context = pc.comp_change(results, spec)
    assert value == pytest.approx(0.26 / 0.20 - 1)
    # first order: d(y1/y0) = sqrt((s1/y0)^2 + (y1 s0 / y0^2)^2)
    assert se == pytest.approx(math.hypot(0.002 / 0.2, 0.26 * 0.001 / 0.04), rel=1e-4)
    assert context.startswith("phi 0 (dilute) to 0.3") and "N_E 320" in context


def test_change_between_the_smallest_and_largest_phi(results):
    value, se, _ = pc.comp_change(results, {"where": {"ca": 0.1}, "from": "min", "to": "max",
                                            "column": "N1", "se_column": "N1_se"})
    assert value == pytest.approx(0.70) and se == pytest.approx(math.hypot(0.01, 0.01))
    value, _, _ = pc.comp_change(results, {"where": {"ca": 0.1}, "from": "dilute", "to": 0.3,
                                           "column": "theta_D_deg",
                                           "se_column": "theta_D_se_deg"})
    assert value == pytest.approx(-4.0)
    with pytest.raises(pc.Missing):  # Ca 0.5 is not in this grid
        pc.comp_change(results, {"where": {"ca": 0.5}, "from": "dilute", "to": 0.3,
                                 "column": "D"})


def test_coefficients_along_ca(results):
    # From the smallest to the largest Ca, whatever the table's order.
    value, se, context = pc.comp_ca_change(results, {"file": "grid/fits.csv",
                                                     "column": "a1"})
    assert context == "Ca 0.1 to 0.6"
    assert value == pytest.approx(-0.7) and se == pytest.approx(math.hypot(0.01, 0.01))
    fall, fall_se, _ = pc.comp_faster_fall(
        results, {"file": "grid/fits.csv", "column": "a2", "than": "a1"})
    assert fall == pytest.approx((0.1 / 2.7 - 1) - (1.6 / 2.3 - 1))
    assert fall_se > 0


def test_spread_of_the_cases(results):
    value, se, context = pc.comp_spread(results, {"file": "figures/fig11.csv", "column": "D"})
    assert value == pytest.approx(0.005 / 0.375)
    assert se == pytest.approx(value / 2)  # 1/sqrt(2 (3 - 1))
    assert "3 cases at t_e = 12" in context
    value, _, _ = pc.comp_spread(results, {"file": "figures/fig11.csv", "column": "mu_sp"})
    assert value == pytest.approx(0.025)
    value, se, context = pc.comp_spread(results, {"file": "figures/table1.csv",
                                                  "column": "D"})
    assert value == pytest.approx(0.005 / 0.375) and context == "2 cases"


def test_mesh_error_against_the_finest_mesh(results):
    value, se, _ = pc.comp_mesh_error(results, {"file": "figures/table1.csv", "N_E": 80,
                                                "quantity": "D"})
    assert value == pytest.approx(0.025 / 0.375) and se > 0
    with pytest.raises(pc.Missing, match="reference"):
        pc.comp_mesh_error(results, {"file": "figures/table1.csv", "N_E": 320,
                                     "quantity": "D"})
    with pytest.raises(pc.Missing, match="no N_E 5120"):
        pc.comp_mesh_error(results, {"file": "figures/table1.csv", "N_E": 5120,
                                     "quantity": "D"})


def test_dilute_takes_the_finest_level_with_a_value(results):
    value, se, context = pc.comp_dilute(results, {"where": {"ca": 0.6, "quantity": "D"}})
    assert (value, se) == (0.520, 2e-4) and context == "level 3 (N_E 1280)"


def test_requires_names_what_the_study_is_at(results):
    n = number(requires=[{"file": "mesh/table.csv", "where": {"ca": 0.4, "phi": 0.2}}],
               ours={"computation": "dilute", "where": {"ca": 0.6, "quantity": "D"}})
    with pytest.raises(pc.Missing, match="it has ca 0.2; phi 0.3"):
        pc.evaluate(n, results)


def test_verdicts():
    n = number(value=0.38, error=0.005)
    assert pc.verdict(n, 0.39, 0.004)[0] == "agrees"  # 0.01 <= 2 * 0.0064
    assert pc.verdict(n, 0.28, 0.02)[0] == "differs"
    assert "combined SE" in pc.verdict(n, 0.28, 0.02)[1]
    s = number(kind="sign", sign="-")
    assert pc.verdict(s, -0.5, 0.1)[0] == "agrees"
    assert pc.verdict(s, 0.5, 0.1)[0] == "differs"
    assert pc.verdict(s, -0.1, 0.1)[0] == "inconclusive"
    assert pc.verdict(s, -0.1, float("nan"))[0] == "agrees"  # no error: the sign alone
    m = number(kind="max", value=0.01)
    assert pc.verdict(m, 0.004, float("nan"))[0] == "agrees"
    assert pc.verdict(m, 0.02, 0.001)[0] == "differs"


def test_each_ca_expands_over_the_grid_or_a_list(results):
    template = number(id="fall-ca{ca}", quantity="at Ca {ca}", each_ca="grid",
                      ours={"computation": "value", "file": "grid/table.csv",
                            "where": {"ca": "{ca}"}, "column": "D"})
    rows = pc.expand([template], results)
    assert [r["id"] for r in rows] == ["fall-ca0.1", "fall-ca0.4"]
    assert rows[0]["ours"]["where"] == {"ca": 0.1} and rows[1]["quantity"] == "at Ca 0.4"
    rows = pc.expand([{**template, "each_ca": [0.5]}], results)
    assert rows[0]["ours"]["where"] == {"ca": 0.5}


def test_repository_numbers_file_is_valid_and_every_number_has_its_source():
    numbers = pc.load_numbers(ROOT / "config" / "paper_numbers.yaml")
    assert len({n["id"] for n in numbers}) == len(numbers)
    for n in numbers:
        assert n["stated"] and n["quantity"]
        if n["kind"] == "value":
            assert n["error_is"], n["id"]
    ids = {n["id"] for n in numbers}
    assert {"table1-D-5120", "rise-D-ca0.1-phi0.3", "share-N1-ca0.1-phi0.4",
            "lit-ramanujan1998-D", "lit-doddi2008-D"} <= ids


def test_load_numbers_rejects_a_number_without_an_error(tmp_path):
    path = tmp_path / "n.yaml"
    path.write_text("numbers:\n  - {id: a, quantity: q, stated: s, kind: value, value: 1,\n"
                    "     ours: {computation: value}}\n")
    with pytest.raises(pc.NumbersError, match="needs 'error'"):
        pc.load_numbers(path)


def test_table_and_markdown_with_a_missing_grid_point_and_another_folder(results, tmp_path):
    numbers = pc.load_numbers(ROOT / "config" / "paper_numbers.yaml")
    table = pc.comparison_table(numbers, results, other=results)
    row = table.set_index("id").loc["rise-D-ca0.5-phi0.3"]
    assert row["this_verdict"] == pc.NOT_HERE and row["other_verdict"] == pc.NOT_HERE
    row = table.set_index("id").loc["rise-D-ca0.1-phi0.3"]
    assert row["this_verdict"] in ("agrees", "differs") and row["this_run"].startswith("0.3")
    row = table.set_index("id").loc["lit-doddi2008-D"]
    assert row["this_run"] == "0.52 +- 0.0002" and row["this_verdict"] == "differs"
    assert "level 3 (N_E 1280)" in row["this_reason"]
    text = pc.markdown(table, "ci.yaml", "quantitative.yaml")
    assert "this run (ci.yaml)" in text and "other (quantitative.yaml)" in text
    assert "Rule: a value agrees when" in text


def test_main_writes_markdown_and_csv(results, tmp_path):
    out = tmp_path / "out" / "cmp"
    out.parent.mkdir()
    assert pc.main(["--results", str(results.folder), "--numbers",
                    str(ROOT / "config" / "paper_numbers.yaml"), "--out", str(out),
                    "--label", "synthetic"]) == 0
    table = pd.read_csv(out.with_suffix(".csv"))
    assert {"paper", "this_run", "this_verdict", "this_reason"} <= set(table.columns)
    assert out.with_suffix(".md").read_text().startswith("| quantity |")
