"""The docs' generated tables (benchmarks/doc_tables.py) equal what their records give,
and a changed record makes the check fail."""

import json
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "benchmarks" / "doc_tables.py"


def check(*pages):
    return subprocess.run([sys.executable, str(SCRIPT), "--check", *map(str, pages)],
                          capture_output=True, text=True, cwd=ROOT)


def test_every_generated_table_of_the_docs_is_current():
    pages = sorted((ROOT / "docs").glob("*.md"))
    assert any("<!-- table " in p.read_text() for p in pages)
    result = check(*pages)
    assert result.returncode == 0, result.stderr


def test_a_changed_record_makes_its_table_stale(tmp_path):
    sys.path.insert(0, str(ROOT / "benchmarks"))
    import doc_tables

    record = tmp_path / "near.json"
    shutil.copy(ROOT / "benchmarks" / "records" / "near_corrections.json", record)
    page = tmp_path / "page.md"
    page.write_text(f"text\n<!-- table near_corrections {record} "
                    "benchmarks/records/peak_flops.json -->\n<!-- end table -->\nmore\n")
    # An absolute record path stays as it is (ROOT / an absolute path is that path).
    fresh = doc_tables.regenerate(page.read_text())
    assert "| 3 | 38.3 |" in fresh and fresh.endswith("<!-- end table -->\nmore\n")
    data = json.loads(record.read_text())
    data["levels"]["3"]["near_triangles_per_node"] = 40.0
    record.write_text(json.dumps(data))
    assert doc_tables.regenerate(fresh) != fresh
