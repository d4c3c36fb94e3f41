"""The results page (pipeline/results_page.py) from a results folder: the comparison,
Table 1 and the chosen figures, copied beside the page; the archive it names."""

from pipeline import results_page
from pipeline.run_spec import ROOT


def test_page_holds_the_comparison_table1_and_the_figures(tmp_path):
    figures = tmp_path / "results" / "figures"
    figures.mkdir(parents=True)
    (figures / "paper_comparison.md").write_text("| quantity |\n|---|\n| <D> |\n")
    (figures / "table1.md").write_text("| N_E |\n|---|\n| 320 |\n")
    (figures / "fig03.png").write_bytes(b"png")
    text = results_page.page(tmp_path / "results", "config/x.yaml", ["fig03", "fig12"],
                             tmp_path / "docs" / "results", date="2026-12-04")
    assert "`config/x.yaml`, generated on 2026-12-04" in text
    assert text.index("| <D> |") < text.index("## Table 1") < text.index("| 320 |")
    assert "![Figure 3](results/fig03.png)" in text
    assert "Figure 12: not in this configuration." in text
    assert (tmp_path / "docs" / "results" / "fig03.png").read_bytes() == b"png"


def test_the_archive_is_named_within_the_repository_with_its_counts():
    store = ROOT / "archive" / "quantitative"
    records = len([p for p in store.rglob("record.json")])
    line = results_page.archive_line(store)
    assert line.startswith("Its runs are kept in the results archive "
                           "`archive/quantitative`: " + f"{records} records")
