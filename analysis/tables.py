"""One row of averages per run, and the CSV tables the figures read.

A row holds the run's parameters (from summary.json), its averages over
[t_start, t_end] (analysis.averages), the rheology (analysis.rheology) and both sides of
the stresslet decomposition (analysis.stresslet). Figures read only these tables.
"""

import csv
import sys
from pathlib import Path

from analysis.averages import run_averages
from analysis.read_run import read_summary, read_timeseries
from analysis.rheology import rheology
from analysis.stresslet import decomposition

PARAMETERS = ("ca", "phi", "capsules", "seed", "mesh_level")
COLUMNS = (PARAMETERS + ("t_start", "t_end", "count", "D", "D_std", "theta_D_deg",
                         "theta_D_std_deg", "principal_diff", "theta_S_deg", "S_xx",
                         "S_xy", "S_yy", "S_zz", "mu_sp", "N1", "N2", "S12",
                         "S12_principal", "S11_S22", "S11_S22_principal", "sin2theta_S",
                         "cos2theta_S", "intrinsic", "ended", "run"))


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
    for key in ("D", "D_std", "theta_D_deg", "theta_D_std_deg", "principal_diff",
                "theta_S_deg"):
        row[key] = float(avg[key])
    row.update({"S_xx": s[0, 0], "S_xy": s[0, 1], "S_yy": s[1, 1], "S_zz": s[2, 2]})
    row.update(rheology(s, phi, ca))
    row.update(decomposition(s, avg["principal_diff"], avg["theta_S_deg"]))
    row["intrinsic"] = int(phi == 0)
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
                "intrinsic": int(float(p["phi"]) == 0),
                "ended": summary.get("ended", "t_end"), "run": str(run_dir)})
    return row


def with_data(rows):
    """The rows that hold averages (count > 0): not those of runs stopped too early."""
    return [r for r in rows if r["count"] > 0]


def write_table(path, rows, columns=None):
    """Write dict rows as CSV with the given column order (default: the first row's)."""
    columns = list(columns or rows[0].keys())
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, fieldnames=columns, extrasaction="ignore")
        w.writeheader()
        for row in rows:
            w.writerow(row)


def read_table(path):
    """Read a CSV table; values that parse as numbers become floats."""
    with open(path, newline="", encoding="utf-8") as f:
        return [{k: _number(v) for k, v in row.items()} for row in csv.DictReader(f)]


def _number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return text


def select(rows, **match):
    """Rows whose fields equal every given value (numbers compared to 1e-9)."""
    def same(a, b):
        if isinstance(a, float) or isinstance(b, float):
            try:
                return abs(float(a) - float(b)) <= 1e-9 * max(1.0, abs(float(b)))
            except (TypeError, ValueError):
                return False
        return a == b
    return [r for r in rows if all(same(r.get(k), v) for k, v in match.items())]


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
