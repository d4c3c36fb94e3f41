"""One row of averages per run, and the CSV tables the figures read.

A row holds the run's parameters (from summary.json), its averages over
[t_start, t_end] (analysis.averages), the rheology (analysis.rheology) and both sides of
the stresslet decomposition (analysis.stresslet). Figures read only these tables, as
pandas DataFrames; markdown_table is the one writer of the markdown tables.
"""

import numbers
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from analysis.averages import run_averages
from analysis.membrane import code_from_parameters
from analysis.read_run import read_summary, read_timeseries
from analysis.rheology import rheology, stress_factor
from analysis.stresslet import decomposition

PARAMETERS = ("ca", "phi", "capsules", "seed", "mesh_level")
COLUMNS = (PARAMETERS + ("t_start", "t_end", "count", "D", "D_std", "D_se", "D_std_se",
                         "theta_D_deg", "theta_D_std_deg", "theta_D_se_deg",
                         "theta_D_std_se_deg",
                         "principal_diff", "principal_diff_se", "theta_S_deg",
                         "theta_S_se_deg", "S_xx", "S_xy", "S_yy", "S_zz",
                         "mu_sp", "mu_sp_se", "N1", "N1_se", "N2", "N2_se", "S12", "S12_se",
                         "S12_principal", "S12_principal_se", "S11_S22", "S11_S22_se",
                         "S11_S22_principal", "S11_S22_principal_se", "sin2theta_S",
                         "sin2theta_S_se", "cos2theta_S", "cos2theta_S_se",
                         "volume_error_max", "intrinsic", "membrane", "ended", "run"))


def rheology_standard_errors(avg, phi, ca):
    """mu_sp_se, N1_se, N2_se from a run's averages (analysis.averages.run_averages). The
    rheology is linear in the stresslet (eqs. 4.5, 4.9, 4.10), so are its errors; for
    phi = 0 they are those of the intrinsic values."""
    factor = stress_factor(phi, ca)
    n1, n2 = (factor * float(e) for e in avg["normal_differences_se"])
    return {"mu_sp_se": factor * float(avg["stresslet_se"][0, 1]), "N1_se": n1, "N2_se": n2}


def run_row(run_dir, t_start=None, t_end=None):
    """The averages of one run directory as a flat dict (keys: COLUMNS).

    t_start None: the run's own t_avg_start (summary.json). t_end None: the last sample.
    For phi = 0, mu_sp, N1, N2 are intrinsic values per unit phi (intrinsic = 1).
    """
    summary = read_summary(run_dir)
    p = summary["parameters"]
    t_start = float(summary["t_avg_start"]) if t_start is None else float(t_start)
    avg = run_averages(read_timeseries(run_dir), t_start, t_end)
    phi, ca = float(p["phi"]), float(p["ca"])
    s = avg["stresslet"]
    row = {"ca": ca, "phi": phi, "capsules": int(p["capsules"]), "seed": int(p["seed"]),
           "mesh_level": int(p["mesh_level"]), "t_start": avg["t_start"],
           "t_end": avg["t_end"], "count": avg["count"]}
    for key in ("D", "D_std", "D_se", "D_std_se", "theta_D_deg", "theta_D_std_deg",
                "theta_D_se_deg", "theta_D_std_se_deg", "principal_diff",
                "principal_diff_se", "theta_S_deg", "theta_S_se_deg"):
        row[key] = float(avg[key])
    row.update({"S_xx": s[0, 0], "S_xy": s[0, 1], "S_yy": s[1, 1], "S_zz": s[2, 2]})
    row.update(rheology(s, phi, ca))
    row.update(rheology_standard_errors(avg, phi, ca))
    row.update(decomposition(s, avg["principal_diff"], avg["theta_S_deg"]))
    row["S12_se"] = float(avg["stresslet_se"][0, 1])
    row["S11_S22_se"] = float(avg["normal_differences_se"][0])
    row.update({f"{name}_se": float(se) for name, se in avg["decomposition_se"].items()})
    # The largest relative volume error of the stored states (the paper's section 3 bound).
    row["volume_error_max"] = float(summary.get("volume_error_max", float("nan")))
    row["intrinsic"] = int(phi == 0)
    # The membrane the run carried (analysis.membrane: "paper", "wrinkling", "eb0.05"):
    # the figures' footers say which points carry which.
    row["membrane"] = code_from_parameters(p)
    # "t_end", or how a run stopped early ("contact", "numerical"); such a row averages
    # up to its last good sample, and the figures name it in their footers.
    row["ended"] = summary.get("ended", "t_end")
    row["run"] = str(run_dir)
    return row


def stopped_row(run_dir, t_start=None):
    """The row of a run that stopped before its averaging window: its parameters, how it
    ended and when (t_end: its last sample), count 0 and NaN for every average."""
    summary = read_summary(run_dir)
    p = summary["parameters"]
    times = read_timeseries(run_dir)["time"]
    row = {key: float("nan") for key in COLUMNS}
    row.update({"ca": float(p["ca"]), "phi": float(p["phi"]), "capsules": int(p["capsules"]),
                "seed": int(p["seed"]), "mesh_level": int(p["mesh_level"]),
                "t_start": float(summary["t_avg_start"] if t_start is None else t_start),
                "t_end": float(times.max()) if times.size else 0.0, "count": 0,
                "intrinsic": int(float(p["phi"]) == 0), "membrane": code_from_parameters(p),
                "ended": summary.get("ended", "t_end"), "run": str(run_dir)})
    return row


def with_data(table):
    """The rows that hold averages (count > 0): not those of runs stopped too early."""
    return table[table["count"] > 0]


def write_table(path, rows, columns=None):
    """Write a DataFrame, or dict rows, as CSV; `columns` picks and orders the columns
    (default: all, in the order they first appear). Missing values are left empty."""
    table = pd.DataFrame(rows)
    if columns is not None:
        table = table.reindex(columns=list(columns))
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    table.to_csv(path, index=False)


def read_yaml_list(path, key, error):
    """(the whole mapping, its non-empty list under `key`) of a YAML file; raises
    `error` (an exception class) naming the file and the key otherwise."""
    with open(path, encoding="utf-8") as f:
        data = yaml.safe_load(f) or {}
    items = data.get(key) if isinstance(data, dict) else None
    if not isinstance(items, list) or not items:
        raise error(f"{path}: needs a non-empty list '{key}'")
    return data, items


def read_table(path):
    """A CSV table as a DataFrame."""
    return pd.read_csv(path)


def select(table, **match):
    """The rows whose fields equal every given value: numbers to 1e-9 relative (a value
    read back from CSV is not always the one written), anything else as text (a column
    such as seed holds numbers and "mean")."""
    keep = np.ones(len(table), dtype=bool)
    for key, want in match.items():
        if key not in table:
            return table.iloc[:0]
        if isinstance(want, numbers.Real) and not isinstance(want, bool):
            got = pd.to_numeric(table[key], errors="coerce").to_numpy(dtype=float)
            keep &= np.abs(got - want) <= 1e-9 * max(1.0, abs(want))
        else:
            keep &= (table[key].astype(str) == str(want)).to_numpy()
    return table[keep]


def markdown_table(table, formats=None, headers=None, na_rep="nan", errors=None):
    """A DataFrame as a markdown table: a header line, a rule, one line per row.

    formats: column -> format spec of its values (default: str); headers: the names shown
    (default: the columns); na_rep: the text of a missing value; errors: column -> the
    standard errors of its values (a sequence in row order), printed after a value as
    "0.3744 +- 0.0026" (two significant digits; nothing where the error is missing). The
    cells are not padded, so a changed value changes one line of a committed table, not
    its layout.
    """
    formats = formats or {}
    errors = {column: list(values) for column, values in (errors or {}).items()}
    names = list(table.columns) if headers is None else list(headers)
    lines = ["| " + " | ".join(names) + " |", "|" + "---|" * len(names)]
    for i, row in enumerate(table.itertuples(index=False)):
        cells = []
        for column, value in zip(table.columns, row):
            cell = na_rep if pd.isna(value) else format(value, formats.get(column, ""))
            error = errors[column][i] if column in errors else None
            if not pd.isna(value) and error is not None and not pd.isna(error):
                cell += f" +- {error:.2g}"
            cells.append(cell)
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _run_dir(path):
    return Path(path).parent if str(path).endswith(".json") else Path(path)


def main(argv=None):
    """CLI: python -m analysis.tables --out T.csv [--t-start T] RUN_DIR_OR_SUMMARY ..."""
    import argparse
    ap = argparse.ArgumentParser(description="Average runs into one CSV table.")
    ap.add_argument("--out", required=True)
    ap.add_argument("--t-start", type=float, default=None,
                    help="start of the averages (default: each run's t_avg_start)")
    ap.add_argument("runs", nargs="*", help="run directories or their summary.json")
    ap.add_argument("--own-window", nargs="*", default=[],
                    help="runs averaged over their own t_avg_start (the dilute limit)")
    args = ap.parse_args(argv)
    runs = [(run, None) for run in args.own_window] + [(run, args.t_start) for run in args.runs]
    rows = []
    for run, t_start in runs:
        try:
            rows.append(run_row(_run_dir(run), t_start))
        except ValueError as e:  # a run that stopped before its averaging window
            summary = read_summary(_run_dir(run))
            if summary.get("ended", "t_end") == "t_end":
                raise
            print(f"tables: no averages for {_run_dir(run)}: it stopped early "
                  f"({summary['ended']}: {summary.get('end_message', '')}) and {e}",
                  file=sys.stderr)
            rows.append(stopped_row(_run_dir(run), t_start))
    write_table(args.out, rows, COLUMNS)


if __name__ == "__main__":
    main()
