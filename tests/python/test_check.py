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
