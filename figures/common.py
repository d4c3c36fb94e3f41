"""Shared plumbing of the figure scripts: style, arguments, the grid table split into
dilute and suspension rows, the section 4.2 coefficients per Ca read from their table,
markers with error bars, and saving a figure with its data (PNG, PDF, CSV) and a footer
that states the reductions of the runs it shows."""

import argparse
from pathlib import Path

import matplotlib

matplotlib.rc_file(str(Path(__file__).with_name("matplotlibrc")))
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402,F401 (after the style and backend are set)
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from analysis import coefficients, fits  # noqa: E402
from analysis.membrane import PAPER as PAPER_MEMBRANE  # noqa: E402
from analysis.tables import read_table, write_table  # noqa: E402

# The line of a caption that says what the error bars are (docs/workflow.md).
ERROR_BARS = ("Bars: standard error of the time average, from the integrated "
              "autocorrelation time (docs/conventions.md)")


def parse_args(description):
    """Arguments every figure script accepts (the workflow passes them all)."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--out", required=True, help="output stem: writes STEM.png/.pdf/.csv")
    ap.add_argument("--t-start", type=float, default=10.0,
                    help="start t_s of the time averages (paper: 10)")
    ap.add_argument("--phi-m", type=float, default=fits.PHI_RANDOM_CLOSE,
                    help="maximum packing of the Krieger-Dougherty curve (paper: 0.63)")
    ap.add_argument("--images", default="xy", choices=["none", "xy", "all"],
                    help="periodic images drawn in figure 2")
    ap.add_argument("inputs", nargs="+", help="tables or run summaries")
    return ap.parse_args()


def parse_table_args(description):
    """The arguments of a figure drawn from one study table (--out STEM TABLE): the output
    stem and the table as a DataFrame."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--out", required=True, help="output stem: writes STEM.png/.pdf/.csv")
    ap.add_argument("table")
    args = ap.parse_args()
    return args.out, read_table(args.table)


def elements(level):
    """N_E of an icosphere level (or of each of an array of levels): 20 * 4^level."""
    return 20 * 4 ** np.asarray(level, dtype=int)


def _span(values, fmt="{:g}"):
    values = sorted(set(values))
    return fmt.format(values[0]) if len(values) == 1 else ", ".join(fmt.format(v) for v in values)


def _rounded(values):
    return [round(v, 1) for v in values]


def membranes(rows):
    """The footer's part that says which membrane the runs carry (a run table's column
    `membrane`, analysis.membrane's codes): the paper's when every row does (a table
    without the column, or a cell left empty, is of the paper's membrane); otherwise
    which (Ca, phi) carry which."""
    if "membrane" in rows:
        codes = rows["membrane"].astype(object)
        codes = codes.where(codes.notna(), PAPER_MEMBRANE).astype(str)
    else:
        codes = pd.Series(PAPER_MEMBRANE, rows.index, dtype=str)
    if (codes == PAPER_MEMBRANE).all():
        return "membrane: the paper's (no bending)"
    if codes.nunique() == 1:
        return f"membrane: {codes.iloc[0]} (every run)"
    parts = []
    for code in sorted(set(codes), key=lambda c: (c != PAPER_MEMBRANE, c)):
        mine = rows[codes == code].sort_values(["ca", "phi"], kind="stable")
        phi = mine["phi"].astype(float)
        where = list(dict.fromkeys(f"Ca {r.ca:g} phi {r.phi:g}"
                                   for r in mine[phi > 0].itertuples()))
        if (phi == 0).any():
            where.append("the dilute limit at Ca " + ", ".join(
                dict.fromkeys(f"{ca:g}" for ca in mine.loc[phi == 0, "ca"])))
        name = "the paper's" if code == PAPER_MEMBRANE else code
        parts.append(f"{name} at {', '.join(where)}")
    return "membrane: " + "; ".join(parts)


def footer(rows, t_start=None):
    """One line: mesh, capsules per box, end time and averaging window of these rows (a
    run table), the membrane of each point, and the runs that stopped early (averaged up
    to their stop, or without data)."""
    # A table without the column (or a cell left empty) means the runs ran to their end.
    # (an all-empty column reads as float, hence the cast before the text fill).
    ended = (rows["ended"].astype(object).fillna("t_end") if "ended" in rows
             else pd.Series("t_end", rows.index))
    finished = rows[ended == "t_end"]
    if finished.empty:
        finished = rows
    susp = finished[finished["intrinsic"] == 0]
    use = finished if susp.empty else susp
    parts = [f"N_E = {_span(elements(use['mesh_level']), '{:d}')}"]
    if not susp.empty:
        parts.append(f"M = {_span(susp['capsules'].astype(int), '{:d}')}")
    parts.append(f"gammadot t_e = {_span(_rounded(use['t_end']))}")
    ts = t_start if t_start is not None else _span(use["t_start"])
    parts.append(f"t_s = {ts}")
    dil = finished[finished["intrinsic"] != 0]
    if not dil.empty and not susp.empty:
        parts.append(f"dilute limit: N_E = {_span(elements(dil['mesh_level']), '{:d}')}, "
                     f"average over [{_span(dil['t_start'])}, "
                     f"{_span(_rounded(dil['t_end']))}]")
    parts.append(membranes(rows))
    early = rows[ended != "t_end"]
    if not early.empty:
        parts.append("stopped early: " + ", ".join(
            f"Ca {r.ca:g} phi {r.phi:g} seed {int(r.seed)} at {r.t_end:.2f} "
            f"({r.ended}{'' if r.count > 0 else ', no data in the window'})"
            for r in early.itertuples()))
    return "Runs: " + "; ".join(parts)


def save(fig, out, rows, caption):
    """Write OUT.png, OUT.pdf with `caption` under the axes, the plotted data OUT.csv
    (a DataFrame or dict rows; the columns in the order they first appear) and the caption
    as text, OUT.txt (the results page prints it under the figure)."""
    fig.text(0.01, -0.02, caption, ha="left", va="top", fontsize=7, wrap=True)
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out.with_suffix(".png"))
    fig.savefig(out.with_suffix(".pdf"))
    write_table(out.with_suffix(".csv"), rows)
    out.with_suffix(".txt").write_text(caption + "\n", encoding="utf-8")


def grid_rows(path):
    """The grid table (a DataFrame) and its rows with data split: (all rows, dilute row by
    Ca, suspension rows by Ca sorted by phi)."""
    rows = read_table(path)
    return (rows, *coefficients.split_grid(rows))


def coefficient_inputs(args, key):
    """The grid table and the section 4.2 coefficients of `key` (results/grid/fits.csv,
    analysis.coefficients) of a figure given both (inputs: TABLE FITS): (rows, dilute,
    susp, {ca: (c1, c2)}, {ca: (c1_se, c2_se)}, the fitting range)."""
    if len(args.inputs) != 2:
        raise SystemExit("usage: the grid table and its coefficient table "
                         "(results/grid/table.csv results/grid/fits.csv)")
    return (*grid_rows(args.inputs[0]),
            *coefficients.read_coefficients(args.inputs[1], key))


def points(ax, x, y, yerr=None, xerr=None, fmt="o", **style):
    """Markers (and lines, by `fmt`) with error bars: the standard errors `yerr`, `xerr`
    (none where an error is missing or smaller than the marker). `style` goes to
    errorbar and may override the thin, capped bars."""
    return ax.errorbar(x, y, yerr=yerr, xerr=xerr, fmt=fmt,
                       **({"capsize": 2, "elinewidth": 0.8} | style))


def colors(keys):
    """One colour per key (Ca or phi), dark to light as in the paper's series."""
    keys = sorted(keys)
    cmap = plt.get_cmap("viridis")
    return {k: cmap(0.85 * i / max(1, len(keys) - 1)) for i, k in enumerate(keys)}


def phi_with_dilute(dilute_row, rows, key, dilute_value=None):
    """phi and values of one Ca (rows: its suspension rows) with the dilute limit at
    phi = 0 first."""
    first = dilute_row[key] if dilute_value is None else dilute_value
    return (np.concatenate([[0.0], rows["phi"]]),
            np.concatenate([[first], rows[key]]))
