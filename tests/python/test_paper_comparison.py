"""analysis.paper_comparison: each computation and test on small synthetic tables, the
verdicts that can fail (and those that cannot tell), the claims file of the repository,
and the tables with a second results folder."""

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from analysis import paper_comparison as pc
from analysis.tables import write_table

ROOT = Path(__file__).resolve().parents[2]


def grid_rows():
    """A grid table: the dilute run and phi 0.1, 0.3 at Ca 0.1, phi 0.1 (stopped before
    its window) at Ca 0.4, and phi 0.1, 0.3 at Ca 0.2 where phi 0.3 carries bending."""
    def row(ca, phi, D, D_se, N1, theta, count=100, ended="t_end", t_end=12.0,
            membrane="paper"):
        return {"ca": ca, "phi": phi, "capsules": 1 if phi == 0 else 8, "seed": 1,
                "mesh_level": 2, "t_start": 6.0, "t_end": t_end, "count": count,
                "D": D, "D_se": D_se, "theta_D_deg": theta, "theta_D_se_deg": 0.1,
                "N1": N1, "N1_se": 0.01, "N2": -0.1 * N1, "N2_se": 0.01,
                "intrinsic": int(phi == 0), "membrane": membrane, "ended": ended}
    return [row(0.1, 0.0, 0.20, 0.001, 1.4, 34.0), row(0.1, 0.1, 0.22, 0.002, 0.20, 32.5),
            row(0.1, 0.3, 0.26, 0.002, 0.90, 30.0),
            row(0.4, 0.1, float("nan"), float("nan"), float("nan"), float("nan"), count=0,
                ended="contact", t_end=3.5),
            row(0.2, 0.0, 0.30, 0.001, 2.0, 30.0), row(0.2, 0.1, 0.31, 0.002, 0.3, 29.0),
            row(0.2, 0.3, 0.29, 0.002, 1.0, 27.0, membrane="eb0.025")]


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
        {"ca": 0.1, "phi_max": 0.1, "a1": 2.3, "a1_se": 0.01, "a2": 2.7, "a2_se": 0.2},
        {"ca": 0.3, "phi_max": 0.1, "a1": 1.9, "a1_se": 0.01, "a2": 3.0, "a2_se": 0.1}])
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


def claim(**kw):
    base = {"id": "x", "class": "number", "quantity": "q", "quote": "w", "stated": "s",
            "test": "value", "value": 0.0}
    return base | kw


def test_value_averages_the_matching_rows_and_skips_the_mean_row(results):
    spec = {"computation": "value", "file": "figures/table1.csv", "where": {"N_E": 320},
            "exclude": {"seed": "mean"}, "column": "D", "se_column": "D_se"}
    (p,) = pc.comp_value(results, spec)
    assert p.value == pytest.approx(0.375)
    assert p.se == pytest.approx(math.sqrt(2 * 0.002**2) / 2)  # the mean of two runs


def test_value_of_a_missing_grid_point_or_a_stopped_run_is_missing(results):
    with pytest.raises(pc.Missing, match="no grid/table.csv row"):
        pc.comp_value(results, {"file": "grid/table.csv", "where": {"ca": 0.5}, "column": "D"})
    with pytest.raises(pc.Missing, match="stopped at t = 3.5 \\(contact\\)"):
        pc.comp_value(results, {"file": "grid/table.csv", "where": {"ca": 0.4, "phi": 0.1},
                                "column": "D"})
    with pytest.raises(pc.Missing, match="no figures/fig99.csv"):
        pc.comp_value(results, {"file": "figures/fig99.csv", "column": "D"})


def test_a_point_of_another_membrane_is_another_condition(results):
    with pytest.raises(pc.OtherCondition, match="eb0.025"):
        pc.comp_change(results, {"where": {"ca": 0.2}, "from": "dilute", "to": 0.3,
                                 "column": "D", "se_column": "D_se"})
    n = claim(value=-0.1, ours={"computation": "change", "where": {"ca": 0.2},
                                "from": "dilute", "to": 0.3, "column": "D",
                                "se_column": "D_se"})
    row, _ = pc.compare_claim(n, results)
    assert row["verdict"] == pc.NOT_COMPARABLE and "eb0.025" in row["reason"]


def test_relative_rise_from_the_dilute_limit(results):
    spec = {"where": {"ca": 0.1}, "from": "dilute", "to": 0.3, "relative": True,
            "column": "D", "se_column": "D_se"}
    (p,) = pc.comp_change(results, spec)
    assert p.value == pytest.approx(0.26 / 0.20 - 1)
    # first order: d(y1/y0) = sqrt((s1/y0)^2 + (y1 s0 / y0^2)^2)
    assert p.se == pytest.approx(math.hypot(0.002 / 0.2, 0.26 * 0.001 / 0.04), rel=1e-4)
    assert p.context.startswith("phi 0 (dilute) to 0.3") and "N_E 320" in p.context


def test_series_per_ca_leave_out_another_membrane(results):
    series = pc.comp_series(results, {"file": "grid/table.csv", "x": "phi", "group": "ca",
                                      "y": "D", "se": "D_se", "dilute": True})
    by = {s.label: s for s in series}
    assert list(by["ca 0.1"].x) == [0.0, 0.1, 0.3]
    assert list(by["ca 0.2"].x) == [0.0, 0.1] and by["ca 0.2"].left_out == ["phi 0.3 (eb0.025)"]


def test_spread_of_the_cases(results):
    (p,) = pc.comp_spread(results, {"file": "figures/fig11.csv", "column": "D"})
    assert p.value == pytest.approx(0.005 / 0.375)
    assert p.se == pytest.approx(p.value / 2)  # 1/sqrt(2 (3 - 1))
    assert "3 cases at t_e = 12" in p.context
    (p,) = pc.comp_spread(results, {"file": "figures/table1.csv", "column": "D"})
    assert p.value == pytest.approx(0.005 / 0.375) and p.context == "2 cases"


def test_mesh_error_against_the_finest_mesh(results):
    (p,) = pc.comp_mesh_error(results, {"file": "figures/table1.csv", "N_E": 80,
                                        "quantity": "D"})
    assert p.value == pytest.approx(0.025 / 0.375) and p.se > 0
    with pytest.raises(pc.Missing, match="reference"):
        pc.comp_mesh_error(results, {"file": "figures/table1.csv", "N_E": 320,
                                     "quantity": "D"})


def test_dilute_takes_the_finest_level_with_a_value(results):
    (p,) = pc.comp_dilute(results, {"where": {"ca": 0.6, "quantity": "D"}})
    assert (p.value, p.se) == (0.520, 2e-4) and p.context == "level 3 (N_E 1280)"


def test_value_verdicts_use_only_the_stated_error_and_ours():
    n = claim(value=0.38)  # no error stated: 2 of our standard errors only
    assert pc.point_verdict(n, 0.39, 0.006).word == "agrees"
    assert pc.point_verdict(n, 0.39, 0.004).word == "differs"  # 0.01 > 2 * 0.004
    assert "combined SE" in pc.point_verdict(n, 0.28, 0.02).how
    t1 = claim(value=0.81762, error=0.0014, error_is="Table 1")
    v = pc.point_verdict(t1, 0.8444, 0.012)
    assert v.word == "differs" and v.z == pytest.approx(0.0268 / math.hypot(0.012, 0.0014),
                                                         rel=1e-3)


def test_a_range_is_not_widened_beyond_two_of_our_errors():
    n = claim(test="range", low=-4.0, high=-3.0)
    assert pc.point_verdict(n, -4.73, 0.61).word == "agrees"   # 0.73 <= 1.22
    assert pc.point_verdict(n, -4.39, 0.31).word == "agrees"   # 0.39 <= 0.62
    assert pc.point_verdict(n, -4.73, 0.30).word == "differs"  # 0.73 > 0.60
    assert pc.point_verdict(n, -3.5, 0.1).word == "agrees"


def test_an_error_too_large_to_tell_is_inconclusive_with_what_it_needs():
    n = claim(value=0.0033)  # eps at N_E 1280: SE 0.0097 cannot tell 0.33 % from 0
    v = pc.point_verdict(n, 0.0094, 0.0097)
    assert v.word.startswith("inconclusive: needs a standard error below 0.00082")
    assert pc.point_verdict(claim(test="max", value=0.01), 0.007, 0.0).word == "agrees"
    assert pc.point_verdict(claim(test="max", value=0.01), 0.012, 0.0).word == "differs"
    assert pc.point_verdict(n, 0.0034, math.nan).word.startswith("inconclusive")


def test_signs_rounding_and_approximations():
    s = claim(test="sign", sign="-")
    assert pc.point_verdict(s, -0.5, 0.1).word == "agrees"
    assert pc.point_verdict(s, 0.5, 0.1).word == "differs"
    assert pc.point_verdict(s, -0.1, 0.1).word.startswith("inconclusive")
    r = claim(test="rounded", value=0.5, precision=0.1)
    assert pc.point_verdict(r, 0.5327, 0.0).word == "agrees"
    assert pc.point_verdict({**r, "precision": 0.01}, 0.5327, 0.0).word == "differs"
    a = claim(test="approx", value=1.0)  # no tolerance stated: never agrees or differs
    assert pc.point_verdict(a, 0.97, 0.001).word.startswith("inconclusive: needs the tolerance")


def series(y, se=0.01, x=None):
    x = np.arange(len(y), dtype=float) if x is None else np.asarray(x, dtype=float)
    return pc.Series("ca 0.1", x, np.asarray(y, dtype=float), np.full(len(y), se))


def test_a_trend_is_tested_on_every_step_not_only_its_ends():
    rises = claim(class_="trend", test="rises")
    assert pc.series_verdict(rises, series([0.1, 0.2, 0.3, 0.4])).word == "agrees"
    # The ends rise by 30 SE, but one step falls by 5 combined SE: the claim differs.
    v = pc.series_verdict(rises, series([0.1, 0.3, 0.23, 0.4]))
    assert v.word == "differs" and "1 to 2" in v.how and v.z == pytest.approx(
        0.07 / math.hypot(0.01, 0.01))
    assert pc.series_verdict(rises, series([0.1, 0.1, 0.1005])).word.startswith(
        "inconclusive")
    falls = claim(test="falls")
    assert pc.series_verdict(falls, series([0.4, 0.3, 0.2])).word == "agrees"


def test_flat_and_linearity():
    flat = claim(test="flat", needs_se_below=0.05)
    assert pc.series_verdict(flat, series([0.37, 0.371, 0.369])).word == "agrees"
    assert pc.series_verdict(flat, series([0.37, 0.40, 0.43])).word == "differs"
    assert pc.series_verdict(flat, series([0.37, 0.371, 0.369], se=0.3)).word.startswith(
        "inconclusive")
    x = [0.0, 0.1, 0.2, 0.3, 0.4]
    straight = [series([0.2 + v for v in x], x=x)]
    curved = [series([0.2 + 3 * v * v for v in x], x=x)]
    assert pc.judge(claim(test="linear"), straight)[0] == "agrees"
    assert pc.judge(claim(test="linear"), curved)[0] == "differs"
    assert pc.judge(claim(test="nonlinear"), curved)[0] == "agrees"


def test_a_claim_over_several_points_differs_when_one_does(results):
    n = claim(test="range", low=-4.0, high=-3.0, each_ca=[0.1, 0.2],
              ours={"computation": "change", "where": {"ca": "{ca}"}, "from": "dilute",
                    "to": 0.3, "column": "theta_D_deg", "se_column": "theta_D_se_deg"})
    row, data = pc.compare_claim(n, results)
    # Ca 0.1: -4.0 (within); Ca 0.2: another membrane, left out and named.
    assert row["verdict"] == "agrees" and "another membrane" in row["reason"]
    assert [d["datum"] for d in data] == ["Ca 0.1"]
    row, _ = pc.compare_claim({**n, "low": -3.5, "high": -3.0}, results)
    assert row["verdict"] == "differs"  # 0.5 beyond, 2 SE = 0.28


def test_each_ca_expands_over_the_grid_or_a_list(results):
    template = claim(id="fall", each_ca="grid",
                     ours={"computation": "value", "file": "grid/table.csv",
                           "where": {"ca": "{ca}"}, "column": "D"})
    specs = pc.point_specs(template, results)
    assert [label for label, _ in specs] == ["Ca 0.1", "Ca 0.2", "Ca 0.4"]
    assert specs[0][1]["where"] == {"ca": 0.1}
    specs = pc.point_specs({**template, "each_ca": [0.5]}, results)
    assert specs[0][1]["where"] == {"ca": 0.5}


def test_repository_claims_file_is_valid_and_every_claim_has_its_words():
    claims = pc.load_numbers(ROOT / "config" / "paper_numbers.yaml")
    assert len({c["id"] for c in claims}) == len(claims)
    assert {c["class"] for c in claims} == set(pc.CLASSES)
    for c in claims:
        assert c["stated"] and c["quantity"] and c["quote"], c["id"]
        # An error only where the paper states one (Table 1's cases): none is invented.
        if c.get("error") or any(p.get("error") for p in c.get("points", [])):
            assert "Table 1" in c["error_is"] or "three" in c["error_is"], c["id"]
    ids = {c["id"] for c in claims}
    assert {"table1-D-5120-cases", "share-mu-phi0.4-every-ca", "D-rises-with-phi",
            "D-linear-in-phi", "a1-falls-with-ca", "S1S2-follows-dilute-relation",
            "no-dependence-on-M", "table1-eps-1280", "volume-error",
            "lit-ramanujan1998-D", "kd-a2"} <= ids


def test_load_numbers_rejects_an_error_without_its_source(tmp_path):
    path = tmp_path / "n.yaml"
    path.write_text("claims:\n  - {id: a, class: number, quantity: q, quote: w, stated: s,\n"
                    "     test: value, value: 1, error: 0.1, ours: {computation: value}}\n")
    with pytest.raises(pc.NumbersError, match="needs 'error_is'"):
        pc.load_numbers(path)


def test_tables_with_a_missing_grid_point_and_another_folder(results):
    claims = pc.load_numbers(ROOT / "config" / "paper_numbers.yaml")
    table = pc.comparison_table(claims, results, other=results)
    row = table.set_index("id").loc["rise-D-ca0.5-phi0.3"]
    assert row["this_verdict"] == pc.NOT_HERE and row["other_verdict"] == pc.NOT_HERE
    row = table.set_index("id").loc["rise-D-ca0.1-phi0.3"]
    assert row["this_verdict"] in ("agrees", "differs") and row["this_run"].startswith("0.3")
    row = table.set_index("id").loc["lit-doddi2008-D"]
    assert row["this_run"] == "0.52 +- 0.0002" and row["this_verdict"] == "differs"
    assert row["class"] == "other-paper"
    text = pc.markdown(table, "ci.yaml", "quantitative.yaml")
    assert "this run (ci.yaml)" in text and "other (quantitative.yaml)" in text
    assert "Rule (analysis/paper_comparison.py)" in text and "other papers:" in text


def test_main_writes_markdown_and_both_tables(results, tmp_path):
    out = tmp_path / "out" / "cmp"
    out.parent.mkdir()
    assert pc.main(["--results", str(results.folder), "--numbers",
                    str(ROOT / "config" / "paper_numbers.yaml"), "--out", str(out),
                    "--label", "synthetic"]) == 0
    table = pd.read_csv(out.with_suffix(".csv"))
    assert {"class", "quote", "paper", "this_run", "this_verdict", "this_z"} <= set(table)
    data = pd.read_csv(out.parent / "cmp_points.csv")
    assert list(data.columns) == ["id", "datum", "value", "se", "datum_verdict",
                                  "claim_verdict"]
    assert out.with_suffix(".md").read_text().startswith("| claim |")


def test_the_paper_s_side_of_a_claim_of_points_is_their_own_values():
    # Table 1's cases inherit the N_E 320 value from their anchor; each point states its own.
    claims = {c["id"]: c for c in pc.load_numbers(ROOT / "config" / "paper_numbers.yaml")}
    assert pc.paper_text(claims["table1-D-5120-cases"]) == \
        "3 points, 0.37927 to 0.38009 +- 0.00034"
    assert pc.paper_text(claims["table1-spread"]) == "2 points, 0.00089 to 0.00167"
    assert pc.paper_text(claims["table1-D-1280"]) == "0.37837 +- 0.00034"


def test_a_row_without_a_window_names_none():
    # Table 1's mean row has no window of its own: no "t nan-nan" in the context.
    rows = pd.DataFrame([{"mesh_level": 4, "t_start": np.nan, "t_end": np.nan}])
    assert pc._context(rows) == "N_E 5120"
    rows = pd.DataFrame([{"mesh_level": 3, "t_start": 10.0, "t_end": 30.02}])
    assert pc._context(rows) == "N_E 1280, t 10-30"
