"""analysis.check on synthetic CSVs: a correct expectation passes, a deliberately
corrupted one fails with a readable message, a malformed file is refused; the paper
comparison's datum table against the committed one, where a perturbed datum or verdict
fails the check."""

import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest
import yaml

from analysis import check
from analysis import paper_comparison as pc
from analysis.tables import write_table

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def results(tmp_path):
    rows = [{"N_E": 320, "D": 0.37181, "mu_sp": 0.80256},
            {"N_E": 1280, "D": 0.37837, "mu_sp": 0.81597}]
    write_table(tmp_path / "figures" / "table1.csv", rows)
    return tmp_path


def expectation(**change):
    e = {"id": "mu-1280", "file": "figures/table1.csv", "where": {"N_E": 1280},
         "column": "mu_sp", "value": 0.81762, "rel_tol": 0.01, "source": "reference-run",
         "provenance": "Table 1 point of a reference run, N_E = 5120 average"}
    e.update(change)
    return e


def write_expected(path, *items):
    path.write_text(yaml.safe_dump({"expectations": list(items)}))
    return path


def test_met_expectations_pass(results, tmp_path):
    f = write_expected(tmp_path / "e.yaml", expectation(),
                       expectation(id="D-range", column="D", value=None, min=0.3, max=0.4))
    failed, lines = check.run_checks([f], results)
    assert failed == 0, lines
    assert lines[0].startswith("ok")


def test_corrupted_value_fails_readably(results, tmp_path):
    f = write_expected(tmp_path / "e.yaml", expectation(value=0.9))  # corrupted: 0.81762
    proc = subprocess.run([sys.executable, "-m", "analysis.check", "--results", str(results),
                           str(f)], cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 1
    msg = proc.stderr
    assert "FAIL mu-1280" in msg
    assert "mu_sp = 0.81597, expected 0.9 +- 0.009" in msg
    assert "Table 1" in msg and "0 of 1 expectations met, 1 failed" in msg


def test_missing_row_and_file_fail(results, tmp_path):
    f = write_expected(tmp_path / "e.yaml", expectation(where={"N_E": 5120}),
                       expectation(id="nofile", file="figures/none.csv"))
    failed, lines = check.run_checks([f], results)
    assert failed == 2
    assert "0 rows" in lines[0] and "does not exist" in lines[1]


def test_expectation_without_provenance_is_refused(results, tmp_path):
    f = write_expected(tmp_path / "e.yaml", expectation(provenance=""))
    with pytest.raises(check.ExpectationError, match="missing 'provenance'"):
        check.run_checks([f], results)
    f = write_expected(tmp_path / "e.yaml", expectation(source="same-run"))
    with pytest.raises(check.ExpectationError, match="source must be one of"):
        check.run_checks([f], results)
    # The paper's numbers are claims of the paper comparison, not expectations.
    f = write_expected(tmp_path / "e.yaml", expectation(source="paper"))
    with pytest.raises(check.ExpectationError, match="config/paper_numbers.yaml"):
        check.run_checks([f], results)


def test_committed_expectation_files_are_well_formed():
    files = sorted((ROOT / "config" / "expected").glob("*.yaml"))
    assert files
    for f in files:
        assert check.load_expectations(f)


@pytest.fixture
def grid_results(tmp_path):
    # A run row with the standard error of its time average (analysis.tables).
    write_table(tmp_path / "grid" / "table.csv",
                [{"ca": 0.2, "phi": 0.3, "mu_sp": 0.80, "mu_sp_se": 0.01}])
    return tmp_path


def run_grid(tmp_path, results, k=None, **change):
    e = expectation(file="grid/table.csv", where={"ca": 0.2, "phi": 0.3},
                    source="reference-run", provenance="a reference run", **change)
    body = {"expectations": [e]} | ({} if k is None else {"k": k})
    f = tmp_path / "s.yaml"
    f.write_text(yaml.safe_dump(body))
    return check.run_checks([f], results)


@pytest.mark.parametrize("value, ok", [(0.8295, True), (0.7705, True),
                                       (0.8305, False), (0.7695, False)])
def test_within_k_standard_errors_passes_outside_fails(grid_results, tmp_path, value, ok):
    # 3 SE = 0.03 is wider than the relative tolerance (0.1 %): it sets the bound.
    failed, lines = run_grid(tmp_path, grid_results, value=value, rel_tol=0.001,
                             se_column="mu_sp_se")
    assert failed == (0 if ok else 1), lines
    assert "expected" in lines[0] and "3 SE = 0.03" in lines[0]


def test_reference_standard_error_adds_in_quadrature_and_k_is_read(grid_results, tmp_path):
    # SE of the difference: hypot(0.01, 0.02) = 0.02236; 2 SE = 0.0447.
    assert run_grid(tmp_path, grid_results, k=2, value=0.844, rel_tol=0.001,
                    se_column="mu_sp_se", value_se=0.02)[0] == 0
    assert run_grid(tmp_path, grid_results, k=2, value=0.846, rel_tol=0.001,
                    se_column="mu_sp_se", value_se=0.02)[0] == 1
    with pytest.raises(check.ExpectationError, match="'k'"):
        run_grid(tmp_path, grid_results, k=0, value=0.8, rel_tol=0.001)


def test_a_wider_tolerance_stays_the_bound(grid_results, tmp_path):
    # rel_tol 10 % (0.08) is wider than 3 SE (0.03): a value 0.07 off still passes, and a
    # tight tolerance with no standard error given is not widened.
    failed, lines = run_grid(tmp_path, grid_results, value=0.87, rel_tol=0.1,
                             se_column="mu_sp_se")
    assert failed == 0 and "+- 0.087" in lines[0]
    assert run_grid(tmp_path, grid_results, value=0.805, rel_tol=0.001)[0] == 1


def test_a_missing_standard_error_fails(grid_results, tmp_path):
    failed, lines = run_grid(tmp_path, grid_results, value=0.8, rel_tol=0.01,
                             se_column="N1_se")
    assert failed == 1 and "standard-error column 'N1_se'" in lines[0]


# ---------------------------------------------------------------- the paper comparison


def comparison_results(folder, d_at_phi03=0.26):
    """A results folder for the repository's claims: a small grid at Ca 0.1."""
    rows = [{"ca": 0.1, "phi": phi, "capsules": 1 if phi == 0 else 8, "seed": 1,
             "mesh_level": 2, "t_start": 6.0, "t_end": 12.0, "count": 100, "D": d,
             "D_se": 0.002, "theta_D_deg": 34.0 - 10 * phi, "theta_D_se_deg": 0.1,
             "intrinsic": int(phi == 0), "membrane": "paper", "ended": "t_end"}
            for phi, d in ((0.0, 0.20), (0.1, 0.22), (0.2, 0.24), (0.3, d_at_phi03))]
    write_table(folder / "grid" / "table.csv", rows)
    return folder


def regenerate(results, stem):
    claims = pc.load_numbers(ROOT / "config" / "paper_numbers.yaml")
    _, data = pc.comparison_tables(claims, pc.Results(results))
    write_table(stem, data)
    return stem


def test_the_regenerated_comparison_passes_as_committed(tmp_path):
    results = comparison_results(tmp_path / "results")
    committed = regenerate(results, tmp_path / "committed.csv")
    failed, lines = check.check_comparison(regenerate(results, tmp_path / "new.csv"),
                                           committed)
    assert failed == 0, lines
    assert lines[-1].startswith("ok   comparison:")


def test_a_perturbed_datum_or_verdict_fails_the_check(tmp_path):
    results = comparison_results(tmp_path / "results")
    committed = regenerate(results, tmp_path / "committed.csv")
    # One figure datum changed (<D> at phi 0.3 by 1e-6, far below any standard error):
    # the verdicts stay, the check fails on the values the datum enters.
    comparison_results(results, d_at_phi03=0.260001)
    failed, lines = check.check_comparison(regenerate(results, tmp_path / "new.csv"),
                                           committed)
    assert failed > 0
    assert any(line.startswith("FAIL comparison rise-D-ca0.1-phi0.3") and "value" in line
               for line in lines), lines
    # A change of agreement: the same data, one verdict edited in the committed table.
    table = pd.read_csv(committed)
    i = table.index[table["id"] == "D-rises-with-phi"][0]
    table.loc[i, "claim_verdict"] = "differs"
    table.to_csv(tmp_path / "edited.csv", index=False)
    comparison_results(results)
    failed, lines = check.check_comparison(regenerate(results, tmp_path / "new.csv"),
                                           tmp_path / "edited.csv")
    assert failed == 1 and "claim_verdict 'agrees', committed 'differs'" in lines[0]


def test_round_off_passes_and_a_missing_datum_fails(tmp_path):
    table = pd.DataFrame([{"id": "a", "datum": "Ca 0.1", "value": 0.3, "se": 0.01,
                           "datum_verdict": "agrees", "claim_verdict": "agrees"},
                          {"id": "b", "datum": "", "value": 1.0, "se": 0.0,
                           "datum_verdict": "agrees", "claim_verdict": "agrees"}])
    table.to_csv(tmp_path / "old.csv", index=False)
    table.assign(value=table["value"] * (1 + 1e-12)).to_csv(tmp_path / "new.csv",
                                                             index=False)
    assert check.check_comparison(tmp_path / "new.csv", tmp_path / "old.csv")[0] == 0
    table.iloc[:1].to_csv(tmp_path / "new.csv", index=False)
    failed, lines = check.check_comparison(tmp_path / "new.csv", tmp_path / "old.csv")
    assert failed == 1 and "not regenerated" in lines[0]


def test_check_main_holds_the_committed_folder(tmp_path):
    results = comparison_results(tmp_path / "results")
    committed = tmp_path / "committed"
    committed.mkdir()
    regenerate(results, committed / check.COMPARISON)
    regenerate(results, results / "figures" / check.COMPARISON)
    write_table(committed / "fig03.csv", [{"ca": 0.1, "phi": 0.3, "D": 0.26, "series": None}])
    write_table(results / "figures" / "fig03.csv",
                [{"ca": 0.1, "phi": 0.3, "D": 0.26, "series": None}])
    assert check.main(["--results", str(results), "--committed", str(committed)]) == 0
    # One figure datum perturbed: the figure data and the comparison resting on it fail.
    comparison_results(results, d_at_phi03=0.30)
    regenerate(results, results / "figures" / check.COMPARISON)
    write_table(results / "figures" / "fig03.csv",
                [{"ca": 0.1, "phi": 0.3, "D": 0.30, "series": None}])
    report = tmp_path / "report.md"
    assert check.main(["--results", str(results), "--report", str(report),
                       "--committed", str(committed)]) == 1
    text = report.read_text()
    assert "FAIL figure data fig03.csv: 1 cells differ: row 0 D 0.3, committed 0.26" in text
    assert "the paper comparison differs as committed" in text


def test_committed_figure_data_are_those_the_configurations_name():
    claims = {c["id"] for c in pc.load_numbers(ROOT / "config" / "paper_numbers.yaml")}
    for name in ("ci", "quantitative"):
        config = yaml.safe_load((ROOT / "config" / f"{name}.yaml").read_text())
        folder = ROOT / config["check"]["committed"]
        table = pd.read_csv(folder / check.COMPARISON)
        assert list(table.columns) == ["id", "datum", "value", "se", "datum_verdict",
                                       "claim_verdict"]
        assert set(table["id"]) <= claims, folder
        names = {p.name for p in folder.glob("*.csv")}
        assert {"table1.csv"} | {f"fig{n:02d}.csv" for n in range(1, 13)} <= names
