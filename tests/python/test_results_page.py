"""The results page (pipeline/results_page.py) from a results folder: the headline counted
by class, the largest disagreements first, the comparison, Table 1, the averaging
windows, the figures (reduced, copied beside the page) with their captions, the list of
claims; the archive it names."""

import pandas as pd
from PIL import Image

from analysis import paper_comparison as pc
from analysis.tables import write_table
from pipeline import results_page
from pipeline.run_spec import ROOT


def comparison(rows):
    base = {"quantity": "q", "quote": "w", "stated": "s", "test": "value", "paper": "1",
            "this_run": "1.1 +- 0.01", "this_reason": "off by +0.1; N_E 1280", "this_z": 0.0}
    return pd.DataFrame([base | r for r in rows])


def test_page_holds_headline_disagreements_comparison_table1_and_figures(tmp_path):
    figures = tmp_path / "results" / "figures"
    figures.mkdir(parents=True)
    table = comparison([
        {"id": "a", "class": "number", "this_verdict": "differs", "this_z": 3.0,
         "quantity": "mu_sp three"},
        {"id": "b", "class": "number", "this_verdict": "differs", "this_z": -7.0,
         "quantity": "D seven"},
        {"id": "c", "class": "trend", "this_verdict": "agrees"},
        {"id": "d", "class": "trend", "this_verdict": "inconclusive: needs a standard "
         "error below 0.1"},
        {"id": "e", "class": "analytic", "this_verdict": "agrees"}])
    table.to_csv(figures / "paper_comparison.csv", index=False)
    (figures / "paper_comparison.md").write_text("| claim |\n|---|\n| <D> |\n")
    (figures / "table1.md").write_text("| N_E |\n|---|\n| 320 |\n")
    Image.new("RGB", (40, 20), "white").save(figures / "fig03.png")
    (figures / "fig03.txt").write_text("Figure 3. What the script plots.\n")
    write_table(tmp_path / "results" / "grid" / "table.csv", [
        {"ca": 0.1, "phi": 0.1, "mesh_level": 3, "seed": 1, "t_start": 10.0, "t_end": 30.0,
         "ended": "t_end", "intrinsic": 0},
        {"ca": 0.5, "phi": 0.4, "mesh_level": 3, "seed": 1, "t_start": 10.0, "t_end": 27.5,
         "ended": "numerical", "intrinsic": 0},
        {"ca": 0.5, "phi": 0.0, "mesh_level": 3, "seed": 1, "t_start": 10.0, "t_end": 20.0,
         "ended": "t_end", "intrinsic": 1}])
    text = results_page.page(tmp_path / "results", "config/x.yaml", ["fig03", "fig12"],
                             tmp_path / "docs" / "results", date="2026-12-05")
    assert "`config/x.yaml`, generated on 2026-12-05" in text
    assert "- numbers: 2 differs (of 2)" in text
    assert "- trends: 1 agrees, 1 inconclusive (of 2)" in text and "- analytic: 1 agrees" in text
    # The largest disagreement first, by its distance in combined standard errors.
    assert text.index("D seven") < text.index("mu_sp three") < text.index("## Every claim")
    assert text.index("| <D> |") < text.index("## Table 1") < text.index("| 320 |")
    assert "- grid (dilute limit): gammadot t in [10, 20]\n" in text
    assert "- grid (suspensions): gammadot t in [10, 27.5], [10, 30] (stopped early: " \
           "Ca 0.5 phi 0.4 level 3 seed 1 numerical at 27.5)" in text
    assert "![Figure 3](results/fig03.png)\n\nFigure 3. What the script plots." in text
    assert "Figure 12: not in this configuration." in text
    assert Image.open(tmp_path / "docs" / "results" / "fig03.png").size == (20, 10)
    assert "## The claims and how they are counted" in text and "Statements not compared" in text


def test_every_figure_of_the_paper_3_to_12_is_on_the_page():
    assert results_page.FIGURES == [f"fig{n:02d}" for n in range(3, 13)]


def test_the_archive_is_named_within_the_repository_with_its_counts():
    store = ROOT / "archive" / "quantitative"
    records = len([p for p in store.rglob("record.json")])
    line = results_page.archive_line(store)
    assert line.startswith("Its runs are kept in the results archive "
                           "`archive/quantitative`: " + f"{records} records")


def test_the_headline_counts_the_verdicts_of_the_committed_page():
    text = (ROOT / "docs" / "results.md").read_text()
    assert "## Headline" in text and "- trends:" in text and "- other papers:" in text
    assert set(pc.CLASSES) == set(results_page.CLASS_NAMES)


def test_the_points_by_the_paper_s_membrane_show_limit_error_and_correction(tmp_path):
    import pandas as pd
    from pipeline import results_page

    (tmp_path / "eblimit").mkdir()
    row = {"ca": 0.5, "phi": 0.1, "membrane": "eb0.025", "moduli": "0.0125 0.025",
           "ended": "t_end t_end", "short": ""}
    for name, q, se in results_page.SHOWN_LIMITS:
        row.update({q: 0.5, se: 0.004, f"{q}_correction": 0.078, f"{q}_eb": 0.4638})
    stopped = {**row, "phi": 0.4, "D": float("nan"), "short": "eb 0.0125 stopped at 11.1"}
    pd.DataFrame([row, stopped]).to_csv(tmp_path / "eblimit" / "table.csv", index=False)
    text = "\n".join(results_page.paper_membrane_lines(tmp_path))
    assert "| 0.5 | 0.1 | 0.0125 0.025 | t_end t_end | 0.5 +- 0.004 (+7.8 %) |" in text
    assert "eb 0.0125 stopped at 11.1" in text and "none (eb0.025: 0.4638)" in text
    assert results_page.paper_membrane_lines(tmp_path / "nothing") == []


def test_the_reference_runs_stand_beside_table_1_s_n_e_1280_row(tmp_path):
    (tmp_path / "reference").mkdir()
    row = {"ca": 0.2, "phi": 0.3, "capsules": 100, "mesh_level": 3, "seed": 1,
           "t_start": 10.0, "t_end": 100.04, "ended": "t_end"}
    for name, q, se in results_page.SHOWN_LIMITS:
        row.update({q: 0.84, se: 0.0038})
    stopped = {**row, "seed": 2, "t_end": 20.81, "ended": "contact"}
    pd.DataFrame([row, stopped]).to_csv(tmp_path / "reference" / "table.csv", index=False)
    numbers = ROOT / "config" / "paper_numbers.yaml"
    text = "\n".join(results_page.reference_lines(tmp_path, numbers))
    assert "M = 100 and N_E 1280" in text
    assert "| 1 | [10, 100] | 0.84 +- 0.0038 |" in text
    assert "| 2 | [10, 20.8] (contact) |" in text
    # The paper's values come from the claims file, not a copy.
    claims = {c["id"]: c.get("value") for c in pc.load_numbers(numbers)}
    assert f"| paper, N_E 1280 | [10, 100] | {claims['table1-D-1280']:g} |" in text
    assert f"| {claims['table1-mu-1280']:g} |" in text
    assert results_page.reference_lines(tmp_path / "nothing", numbers) == []
