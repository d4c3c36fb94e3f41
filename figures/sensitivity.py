"""The sensitivity study: <D>, mu_sp and N1 of the folding points under each membrane
(top row, one category per point, one marker and colour per membrane, open at the coarser
mesh levels and filled at the finest), and the dilute limit, D, [mu] and [N1] against Ca
per membrane and level (bottom row). Runs that stopped before their end are not drawn:
the caption lists them, with when and how they stopped.

Usage: python figures/sensitivity.py --out results/figures/sensitivity \
           results/sensitivity/table.csv
Writes STEM.png, STEM.pdf and the plotted data STEM.csv.
"""

import common
import numpy as np
from common import plt

from analysis.sensitivity import PAPER, QUANTITIES

LABELS = {"D": r"$\langle D\rangle$", "mu_sp": r"$\mu_{sp}$", "N1": r"$N_1$"}
DILUTE_LABELS = {"D": "D (dilute)", "mu_sp": r"$[\mu]$", "N1": r"$[N_1]$"}
MARKERS = ("o", "s", "D", "^", "v", "P", "X", "<", ">")
# How a run can stop early (summary.json "ended"), as the caption says it.
HOW = {"numerical": "a numerical failure (numerical: a triangle inverted)",
       "contact": "contact (two membranes touched)"}


def membrane_styles(codes):
    """One (marker, colour) per membrane, the paper's first."""
    codes = sorted(set(codes), key=lambda c: (c != PAPER, c))
    return {c: (MARKERS[i % len(MARKERS)], f"C{i % 10}") for i, c in enumerate(codes)}


def point_label(row):
    return f"Ca {row['ca']:g}, phi {row['phi']:g}"


def series_label(code, level):
    return f"{code}, N_E {int(common.elements(level))}"


def top_row(axes, susp, finished, styles, levels):
    """The suspension points: categorical x, a small offset per (membrane, level)."""
    points = sorted({(r.ca, r.phi) for r in susp.itertuples()})
    x_of = {p: i for i, p in enumerate(points)}
    series = sorted({(r.membrane, int(r.mesh_level)) for r in susp.itertuples()},
                    key=lambda s: ((s[0] != PAPER, s[0]), s[1]))
    width = min(0.8 / max(1, len(series)), 0.15)
    plotted = []
    for j, (code, level) in enumerate(series):
        rows = finished[(finished["membrane"] == code) & (finished["mesh_level"] == level)]
        if rows.empty:
            continue
        x = np.array([x_of[(r.ca, r.phi)] for r in rows.itertuples()], float)
        x += (j - (len(series) - 1) / 2) * width
        marker, color = styles[code]
        filled = level == max(levels)
        for ax, q in zip(axes, QUANTITIES):
            common.points(ax, x, rows[q], yerr=rows[f"{q}_se"], fmt=marker, color=color,
                          mfc=color if filled else "none", label=series_label(code, level))
        plotted.append(rows.assign(x=x, panel="suspension"))
    for ax, q in zip(axes, QUANTITIES):
        ax.set_xticks(range(len(points)))
        ax.set_xticklabels([point_label({"ca": c, "phi": p}) for c, p in points],
                           rotation=30, ha="right", fontsize=7)
        ax.set_xlim(-0.5, len(points) - 0.5)
        ax.set_ylabel(LABELS[q])
    return plotted


def bottom_row(axes, finished, styles, levels):
    """The dilute limit against Ca, a line per membrane and level (dashed at the coarser
    levels), each shifted by a small step in Ca so that the markers do not overlap."""
    plotted = []
    groups = sorted(finished.groupby(["membrane", "mesh_level"]),
                    key=lambda g: ((g[0][0] != PAPER, g[0][0]), g[0][1]))
    cas = np.unique(finished["ca"])
    step = 0.04 * (np.diff(cas).min() if cas.size > 1 else 0.1)
    for j, ((code, level), rows) in enumerate(groups):
        rows = rows.sort_values("ca")
        x = rows["ca"] + (j - (len(groups) - 1) / 2) * step
        marker, color = styles[code]
        filled = level == max(levels)
        for ax, q in zip(axes, QUANTITIES):
            common.points(ax, x, rows[q], yerr=rows[f"{q}_se"], fmt=marker,
                          color=color, mfc=color if filled else "none",
                          ls="-" if filled else "--", label=series_label(code, level))
        plotted.append(rows.assign(x=x, panel="dilute"))
    for ax, q in zip(axes, QUANTITIES):
        ax.set(xlabel="Ca", ylabel=DILUTE_LABELS[q])
        if 0 < cas.size <= 3:  # label the Ca themselves, not the offsets around them
            ax.set_xticks(cas, [f"{ca:g}" for ca in cas])
    return plotted


def stopped_text(rows):
    """The runs not drawn: where, at which mesh and with which membrane, when and how
    (grouped by how they stopped)."""
    ended = rows["ended"].fillna("t_end")
    if (ended == "t_end").all():
        return "Every run reached its end."
    groups = []
    stopped = rows[ended != "t_end"].groupby(ended[ended != "t_end"])
    for how, early in sorted(stopped, key=lambda g: (g[0] != "numerical", g[0])):
        items = [(f"Ca {r.ca:g}, phi {r.phi:g}" if r.case == "suspension"
                  else f"dilute Ca {r.ca:g}")
                 + f", N_E {int(r.N_E)}, {r.membrane} at {r.t_stop:.2f}"
                 for r in early.itertuples()]
        groups.append(f"{HOW.get(how, how)}: " + "; ".join(items))
    return ("Not drawn, stopped before their end (at gammadot t) by " + ". By ".join(groups)
            + ".")


def main():
    out, table = common.parse_table_args(__doc__.splitlines()[0])
    table["ended"] = table["ended"].fillna("t_end")
    finished = table[table["ended"] == "t_end"]
    susp = table[table["case"] == "suspension"]
    dilute = table[table["case"] == "dilute"]
    styles = membrane_styles(table["membrane"])
    rows_of_panels = 1 + (not dilute.empty)
    fig, axes = plt.subplots(rows_of_panels, len(QUANTITIES), squeeze=False,
                             figsize=(7.5, 2.9 * rows_of_panels))
    plotted = top_row(axes[0], susp, finished[finished["case"] == "suspension"], styles,
                      sorted(set(susp["mesh_level"])) or [0])
    if not dilute.empty:
        plotted += bottom_row(axes[1], finished[finished["case"] == "dilute"], styles,
                              sorted(set(dilute["mesh_level"])))
    titles = ("suspensions", "dilute limit (one capsule)")
    for row_axes, title in zip(axes, titles):
        row_axes[1].set_title(title)
        if row_axes[0].get_legend_handles_labels()[0]:
            row_axes[-1].legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    fig.tight_layout()
    levels = sorted(set(table["mesh_level"].astype(int)))
    caption = ("Sensitivity of the folding points to the membrane (docs/workflow.md, the "
               "sensitivity study). Membranes: paper (no bending), wrinkling (the relaxed "
               "membrane), eb<value> (bending modulus kb / (Gs a^2)), imex (the time "
               "scheme). "
               + (f"Open markers: N_E {', '.join(str(common.elements(v)) for v in levels[:-1])}; "
                  f"filled: N_E {common.elements(levels[-1])}. " if len(levels) > 1 else "")
               + "Bottom row: one capsule in unbounded shear, intrinsic [mu] and [N1]. "
               + stopped_text(table) + " " + common.ERROR_BARS + ". "
               + common.footer(finished if not finished.empty else table))
    data = (common.pd.concat(plotted, ignore_index=True) if plotted
            else table.iloc[:0].assign(x=[], panel=[]))
    columns = ["panel", "x", "case", "ca", "phi", "mesh_level", "N_E", "membrane", "ended"]
    columns += [c for q in QUANTITIES for c in (q, f"{q}_se", f"{q}_change",
                                                 f"{q}_change_se")]
    common.save(fig, out, data[columns], caption)


if __name__ == "__main__":
    main()
