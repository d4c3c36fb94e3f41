"""analysis.tables: the markdown writer and the row selection, on small tables."""

import pandas as pd

from analysis.tables import markdown_table, read_table, select, write_table


def test_markdown_table_formats_columns_and_missing_values():
    table = pd.DataFrame({"label": ["80", "320 (average)"], "D": [0.1015204, 0.1083370],
                          "eps_D": [0.0629204, float("nan")]})
    text = markdown_table(table, {"D": ".5f", "eps_D": ".4f"}, ["N_E", "<D>", "eps_D"],
                          na_rep="-")
    assert text.splitlines() == ["| N_E | <D> | eps_D |", "|---|---|---|",
                                 "| 80 | 0.10152 | 0.0629 |",
                                 "| 320 (average) | 0.10834 | - |"]


def test_markdown_table_prints_standard_errors_beside_values():
    table = pd.DataFrame({"label": ["80", "320"], "D": [0.37441, float("nan")]})
    text = markdown_table(table, {"D": ".4f"}, errors={"D": [0.002638, 0.001]}, na_rep="-")
    assert text.splitlines()[2:] == ["| 80 | 0.3744 +- 0.0026 |", "| 320 | - |"]
    text = markdown_table(table.iloc[:1], {"D": ".4f"}, errors={"D": [float("nan")]})
    assert text.splitlines()[2] == "| 80 | 0.3744 |"


def test_select_numbers_to_1e9_and_text_exactly(tmp_path):
    # A seed column holding numbers and "mean" (Table 1) is read back as text.
    rows = [{"N_E": 80, "seed": 1, "mu_sp": 0.8}, {"N_E": 320, "seed": 1, "mu_sp": 0.81},
            {"N_E": 320, "seed": "mean", "mu_sp": 0.82}]
    write_table(tmp_path / "t.csv", rows)
    table = read_table(tmp_path / "t.csv")
    assert list(select(table, N_E=320)["mu_sp"]) == [0.81, 0.82]
    assert list(select(table, N_E=320 * (1 + 5e-10), seed=1)["mu_sp"]) == [0.81]
    assert list(select(table, seed="mean")["mu_sp"]) == [0.82]
    assert select(table, N_E=320.001).empty and select(table, no_such_column=1).empty
