"""The dilute-table helpers on synthetic summaries with known answers."""

import json
import math
import subprocess
import sys
from pathlib import Path

from analysis.fits import observed_order

ROOT = Path(__file__).resolve().parents[2]


def test_observed_order_of_a_second_order_sequence():
    # f(h) = 1 + 3 h^2 with h = 0.4, 0.2, 0.1
    f = [1 + 3 * h * h for h in (0.4, 0.2, 0.1)]
    assert math.isclose(observed_order(*f), 2.0, rel_tol=1e-12)


def test_table_end_to_end(tmp_path):
    paths = []
    for level, h in ((2, 0.4), (3, 0.2), (4, 0.1)):
        d = tmp_path / f"run{level}"
        d.mkdir()
        s = {"taylor_D": 0.1 + h * h, "theta_D_deg": 40 + h, "mu_sp": 2.5 - h * h,
             "N1": 1.0, "N2": -0.2, "parameters": {"ca": 0.05, "mesh_level": level}}
        (d / "summary.json").write_text(json.dumps(s))
        paths.append(str(d / "summary.json"))
    md, csv_path = tmp_path / "t.md", tmp_path / "t.csv"
    subprocess.run([sys.executable, str(ROOT / "figures/dilute_table.py"), "--out-md", str(md),
                    "--out-csv", str(csv_path)] + paths, check=True, capture_output=True)
    text = md.read_text()
    assert "| 0.05 | D | 0.26 | 0.14 | 0.11 | 2.00 |" in text
    assert "| 0.05 | theta_D (deg) |" in text and "1.00 |" in text
    assert "(25/12) Ca = 0.10417" in text
