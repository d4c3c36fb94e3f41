"""analysis.check on synthetic CSVs: a correct expectation passes, a deliberately
corrupted one fails with a readable message, a malformed file is refused."""

import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from analysis import check
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
         "column": "mu_sp", "value": 0.81762, "rel_tol": 0.01, "source": "paper",
         "provenance": "Table 1, N_E = 5120 average"}
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
