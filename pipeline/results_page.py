"""The results page of a configuration (docs/results.md): what it computed and where its
runs are kept, a headline with the verdicts counted by class of claim, the largest
disagreements, every claim of the paper against ours (analysis.paper_comparison), Table 1,
figures 3-12 with the captions their scripts write, the averaging windows of the runs,
the viscosity-ratio study where the configuration shows it (beyond the paper), and the list of the
paper's statements with how each is counted. All from the workflow's
outputs under results/; the page is written where the docs are, with the figures' PNGs
beside it (reduced: half the pixels, 256 colours), so that it can be committed as the
project's published results.

Usage: python -m pipeline.results_page --results results --out docs/results.md
       --label config/quantitative.yaml [--archive archive/quantitative]
       [--numbers config/paper_numbers.yaml] [--figures fig03 fig04 ...]
"""

import argparse
import datetime
import json
import sys
from pathlib import Path

import pandas as pd
import yaml
from PIL import Image

from analysis import paper_comparison, viscosity_ratio
from analysis.tables import markdown_table
from pipeline import archive
from pipeline.run_spec import ROOT, physics_version

FIGURES = [f"fig{n:02d}" for n in range(3, 13)]  # the paper's results, figures 3-12
LARGEST = 5  # disagreements shown first
REDUCE = 2  # the committed PNGs keep 1 / REDUCE of the pixels in each direction
# (column title, average, its standard error) of the eb -> 0 table on the page
SHOWN_LIMITS = [("<D>", "D", "D_se"), ("theta_D", "theta_D_deg", "theta_D_se_deg"),
                ("mu_sp", "mu_sp", "mu_sp_se"), ("N1", "N1", "N1_se"), ("N2", "N2", "N2_se")]
# The claims of Table 1's N_E 1280 row (the paper's M 100 over [10, 100]), shown beside
# the reference study's runs: {column: claim id}
TABLE1_1280 = {"D": "table1-D-1280", "mu_sp": "table1-mu-1280"}
CLASS_NAMES = {"number": "numbers", "trend": "trends", "other-paper": "other papers",
               "analytic": "analytic"}


def archive_line(store):
    """One sentence on the results archive the runs came from."""
    s = archive.summary(archive.read_records([store]))
    store = Path(store).resolve()
    shown = store.relative_to(ROOT) if store.is_relative_to(ROOT) else store
    versions = ", ".join(sorted(s["physics_versions"])) or physics_version()
    return (f"Its runs are kept in the results archive `{shown}`: {s['records']} records "
            f"({s['finished']} finished), {s['bytes'] / 1e6:.1f} MB, "
            f"{s['cpu_seconds'] / 3600:.1f} CPU hours, solver physics version {versions}.")


def headline(table):
    """One line per class of claim: its verdicts counted."""
    counts = paper_comparison.verdict_counts(table)
    lines = []
    for cls, name in CLASS_NAMES.items():
        n = sum(counts[cls].values())
        if n:
            words = ", ".join(f"{counts[cls][w]} {w}" for w in paper_comparison.VERDICTS
                              if counts[cls].get(w))
            lines.append(f"- {name}: {words} (of {n})")
    return lines


def largest_disagreements(table, n=LARGEST):
    """The paper's claims that differ (numbers and trends; other papers' have their own
    class), the farthest in combined standard errors first."""
    differ = table[(table["this_verdict"] == paper_comparison.DIFFERS)
                   & table["class"].isin(["number", "trend"])]
    differ = differ.assign(off=differ["this_z"].abs()).sort_values("off", ascending=False)
    cells = differ.head(n)[["quantity", "paper", "this_run", "off", "this_reason"]]
    cells = cells.assign(off=cells["off"].map(lambda z: f"{z:.1f}"),
                         this_reason=cells["this_reason"].map(lambda r: r.split("; ")[0]))
    return markdown_table(cells.map(lambda v: str(v).replace("|", "/")),
                          headers=["claim", "paper", "ours", "off by (combined SE)",
                                   "how"])


def windows(results):
    """The averaging windows of the runs of each study table (the grid's dilute runs
    apart), one line each, naming the runs that stopped early."""
    lines = []
    # (figure 11 states the initial runs' own)
    for study in ("grid", "mesh", "boxsize", "reference"):
        path = results / study / "table.csv"
        if not path.exists():
            continue
        table = pd.read_csv(path)
        parts = [("dilute limit", table[table["intrinsic"] == 1]),
                 ("suspensions", table[table["intrinsic"] == 0])] \
            if study == "grid" and "intrinsic" in table else [("", table)]
        for what, t in parts:
            spans = sorted({f"[{a:g}, {b:.3g}]" for a, b in zip(t["t_start"], t["t_end"])
                            if pd.notna(a) and pd.notna(b)})
            early = t[t["ended"].fillna("t_end") != "t_end"] if "ended" in t else t.iloc[:0]
            stops = "; ".join(f"Ca {r.ca:g} phi {r.phi:g} level {int(r.mesh_level)} "
                              f"seed {int(r.seed)} {r.ended} at {r.t_end:.3g}"
                              for r in early.itertuples())
            lines.append(f"- {study}{' (' + what + ')' if what else ''}: gammadot t in "
                         + ", ".join(spans) + (f" (stopped early: {stops})" if stops else ""))
    return lines


def paper_membrane_lines(results):
    """The points that carry bending by the paper's membrane (results/eblimit/table.csv,
    analysis.bending_limit): each average's limit eb -> 0 with its standard error and the
    correction from the grid's run with bending; none where the study is not there."""
    path = results / "eblimit" / "table.csv"
    if not path.exists():
        return []
    table = pd.read_csv(path)

    def cell(row, q, se):
        if pd.isna(row[q]):
            return f"none ({row['membrane']}: {row[q + '_eb']:.4g})"
        return (f"{row[q]:.4g} +- {row[se]:.2g} ({100 * row[q + '_correction']:+.1f} %)")

    cells = pd.DataFrame([{"Ca": f"{r['ca']:g}", "phi": f"{r['phi']:g}",
                           "runs (eb)": str(r["moduli"]),
                           "ended": str(r["short"]) if isinstance(r.get("short"), str)
                           and r["short"] else str(r["ended"]),
                           **{name: cell(r, q, se) for name, q, se in SHOWN_LIMITS}}
                          for r in table.to_dict("records")])
    return ["## The paper's membrane where it folds", "",
            "Where the paper's membrane folds at this mesh, the grid runs a bending "
            "membrane; each such point is run again at smaller moduli and every average "
            "extrapolated to eb -> 0 (`analysis/bending_limit.py`, `docs/suspensions.md`). "
            "Each cell: the limit +- its standard error (statistical and the "
            "extrapolation's own miss on one capsule, in quadrature), and in brackets the "
            "correction from the grid's run with bending; a point whose run at a smaller "
            "modulus stopped within the first half of the window has no limit and keeps "
            "its run with bending, left out of the claims.", "", markdown_table(cells), ""]


def reference_lines(results, numbers):
    """Table 1's point at the paper's scale (results/reference/table.csv, where the
    configuration puts the reference study on the page): each run's averages +- their
    standard errors beside the paper's N_E 1280 values (from the claims file `numbers`);
    none where the table is not there."""
    path = results / "reference" / "table.csv"
    if not path.exists():
        return []
    table = pd.read_csv(path)
    paper = {c["id"]: c.get("value") for c in paper_comparison.load_numbers(numbers)}

    def cell(row, q, se):
        return f"{row[q]:.4g} +- {row[se]:.2g}"

    cells = pd.DataFrame([{"seed": f"{int(r['seed'])}",
                           "window": f"[{r['t_start']:g}, {r['t_end']:.3g}]"
                           + ("" if r.get("ended", "t_end") == "t_end" else
                              f" ({r['ended']})"),
                           **{name: cell(r, q, se) for name, q, se in SHOWN_LIMITS}}
                          for r in table.to_dict("records")]
                         + [{"seed": "paper, N_E 1280", "window": "[10, 100]",
                             **{name: "" for name, _, _ in SHOWN_LIMITS},
                             "<D>": f"{paper[TABLE1_1280['D']]:g}",
                             "mu_sp": f"{paper[TABLE1_1280['mu_sp']]:g}"}])
    sizes = sorted({int(v) for v in table["capsules"]})
    return ["## Table 1's point at the paper's scale", "",
            f"Ca 0.2, phi 0.3 at the paper's M = {'/'.join(map(str, sizes))} and N_E "
            f"{20 * 4 ** int(table['mesh_level'].iloc[0])} to its t_e (`snakemake "
            "reference`), one run per initial position (seed); the claims above compare "
            "their mean with Table 1's N_E 1280 row.", "", markdown_table(cells), ""]


# The dense study's GMRES tolerance (config/quantitative.yaml, viscosity_ratio.dense), as
# the page writes it.
DENSE_TOLERANCE_TEXT = "1e-5"
DENSE_TOLERANCE = float(DENSE_TOLERANCE_TEXT)


# The dense study's cost measured at its own scale, one record per machine kind (the
# ratio to lambda 1 differs between them by about a third).
DENSE_COST_RECORDS = ("viscosity_ratio_cost_dense_M27.json",
                      "viscosity_ratio_cost_dense_M27_epyc.json")


def dense_cost_ratios(ratio):
    """The dense study's cost a strain at viscosity ratio `ratio` over lambda 1's at its
    GMRES tolerance, (least, largest) over the machines of DENSE_COST_RECORDS."""
    measured = [case["cost_ratio"] for name in DENSE_COST_RECORDS
                for case in json.loads((ROOT / "benchmarks" / "records" / name)
                                       .read_text())["cases"]
                if case["mesh_level"] == 3 and case["lambda"] == ratio
                and case["gmres_tolerance"] == DENSE_TOLERANCE]
    return min(measured), max(measured)


def viscosity_ratio_lines(results, figure_dir):
    """The viscosity-ratio study (results/viscosity_ratio/table.csv, analysis.
    viscosity_ratio): its table and its figure (reduced, copied into figure_dir). Shown
    where the configuration puts it on the page (viscosity_ratio.on_page: the rule
    passes --viscosity-ratio and depends on both)."""
    path = results / "viscosity_ratio" / "table.csv"
    lines = ["## Beyond the paper: the viscosity ratio", "",
             "The paper's capsules have the viscosity of the suspending fluid inside "
             "(lambda = 1). One capsule in unbounded shear at other viscosity ratios "
             "(`snakemake viscosity_ratio`, `docs/workflow.md`): the rows with lambda != 1 "
             "are beyond the paper and have nothing of it to compare with; those at "
             "lambda = 1 are the paper's capsule.", "",
             viscosity_ratio.markdown(pd.read_csv(path)), ""]
    lines += one_figure(results / "figures" / "viscosity_ratio.png", figure_dir,
                        "The viscosity ratio")
    dense = results / "viscosity_ratio" / "dense.csv"
    if not dense.exists():
        (fast5, slow5), (fast02, slow02) = dense_cost_ratios(5.0), dense_cost_ratios(0.2)
        return lines + [
            "The dense suspension at other viscosity ratios (Ca 0.2, phi 0.1-0.3, M = 27) "
            "is computed on demand (`snakemake viscosity_ratio_dense`) and shown here once "
            "all its runs are archived (`docs/suspensions.md` has those that are): at "
            f"lambda 5 it costs {fast5:.0f} to {slow5:.0f} times and at lambda 0.2 "
            f"{fast02:.0f} to {slow02:.0f} times lambda = 1 a strain, by machine (M = 27, "
            f"level 3, phi 0.3, gmres.tolerance {DENSE_TOLERANCE_TEXT}, over 0.3 strain "
            "from rest: `benchmarks/records/viscosity_ratio_cost_dense_M27.json` and "
            "`viscosity_ratio_cost_dense_M27_epyc.json`, `docs/method.md`).", ""]
    return lines + [
        "### The suspension at other viscosity ratios", "",
        "The grid's suspension at the Table 1 point's Ca with interior viscosity lambda "
        "(`snakemake viscosity_ratio_dense`): no code of this field reports the dense, "
        "sheared rheology of capsules against lambda; the rows at lambda = 1 are the "
        "paper's suspension.", "",
        viscosity_ratio.dense_markdown(pd.read_csv(dense)), ""] + one_figure(
        results / "figures" / "viscosity_ratio_dense.png", figure_dir,
        "The suspension's viscosity ratio")


def one_figure(png, figure_dir, alt):
    """A figure (reduced, copied into figure_dir) and its caption, where it exists."""
    if not png.exists():
        return []
    copy_reduced(png, figure_dir / png.name)
    lines = [f"![{alt}]({figure_dir.name}/{png.name})", ""]
    if png.with_suffix(".txt").exists():
        lines += [png.with_suffix(".txt").read_text(encoding="utf-8").strip(), ""]
    return lines


def claims_list(numbers):
    """Every claim with its class, test and the paper's words, then the statements not
    compared and why."""
    claims = paper_comparison.load_numbers(numbers)
    cells = pd.DataFrame([{"id": c["id"], "class": c["class"], "test": c["test"],
                           "stated": c["stated"], "quote": c["quote"]} for c in claims])
    lines = [markdown_table(cells.map(lambda v: str(v).replace("|", "/")),
                            headers=["claim", "class", "test", "where", "the paper's words"])]
    data = yaml.safe_load(Path(numbers).read_text(encoding="utf-8"))
    skipped = pd.DataFrame(data.get("not_compared", []), columns=["stated", "quote", "why"])
    if not skipped.empty:
        lines += ["", "Statements not compared, and why:", "",
                  markdown_table(skipped.map(lambda v: str(v).replace("|", "/")),
                                 headers=["where", "the paper's words", "why"])]
    return lines


def copy_reduced(png, target):
    """The figure's PNG at 1 / REDUCE of its pixels in each direction and 256 colours."""
    with Image.open(png) as image:
        small = image.convert("RGB").resize((max(1, image.width // REDUCE),
                                             max(1, image.height // REDUCE)),
                                            Image.LANCZOS)
        small.quantize(256).save(target, optimize=True)


def figure_lines(results, figures, figure_dir):
    lines = []
    for name in figures:
        png, number = results / "figures" / f"{name}.png", name[3:].lstrip("0")
        if not png.exists():
            lines += [f"Figure {number}: not in this configuration.", ""]
            continue
        lines += one_figure(png, figure_dir, f"Figure {number}")
    return lines


def page(results, label, figures, figure_dir, store=None, date=None, numbers=None,
         viscosity_ratio=False):
    """The page's Markdown; copies the figures' PNGs (reduced) into `figure_dir`; with
    viscosity_ratio, the section of that study."""
    results, figure_dir = Path(results), Path(figure_dir)
    numbers = Path(numbers or ROOT / "config" / "paper_numbers.yaml")
    date = date or datetime.date.today().isoformat()
    table = pd.read_csv(results / "figures" / "paper_comparison.csv")
    lines = ["# Results", "",
             f"Every checkable statement of the paper against `{label}`, generated on "
             f"{date} by `pipeline/results_page.py` from the workflow's outputs "
             "(`snakemake --cores 2 results_page`, `docs/workflow.md`).", ""]
    if store:
        lines += [archive_line(store), ""]
    lines += ["## Headline", "",
              "The paper's claims, counted apart by what they are: its numbers (values, "
              "ranges, bounds), its trends over Ca and phi (each one claim over every "
              "point it covers), other papers' numbers and the paper's own arithmetic "
              "(`config/paper_numbers.yaml`; the list below).", ""]
    lines += headline(table) + [""]
    lines += [f"## The {LARGEST} largest disagreements", "",
              "The paper's numbers and trends that differ, the farthest in combined "
              "standard errors first (a trend's: its worst step, or its linearity test "
              "as standard deviations).", "",
              largest_disagreements(table), "",
              "## Every claim against ours", "",
              "Where a claim differs, its reason says what differs between the paper's "
              "runs and ours and what was measured to be, or not to be, the cause "
              "(`docs/suspensions.md`, `docs/dilute_limit.md`).", "",
              (results / "figures" / "paper_comparison.md").read_text().strip(), "",
              "## Table 1", "", (results / "figures" / "table1.md").read_text().strip(),
              ""] + reference_lines(results, numbers) + paper_membrane_lines(results) + [
              "## Averaging windows", ""] + windows(results) + [
              "", "## Figures", "",
              f"Reduced to 1/{REDUCE} of their pixels in each direction; full size in "
              "`results/figures/`.", ""]
    figure_dir.mkdir(parents=True, exist_ok=True)
    lines += figure_lines(results, figures, figure_dir)
    if viscosity_ratio:
        lines += viscosity_ratio_lines(results, figure_dir)
    lines += ["## The claims and how they are counted", ""] + claims_list(numbers)
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--results", default="results", help="the workflow's results folder")
    ap.add_argument("--out", required=True, help="the page (its figures go to a folder "
                    "named after it: docs/results.md -> docs/results/)")
    ap.add_argument("--label", required=True, help="the configuration, as the page names it")
    ap.add_argument("--archive", help="the results archive the runs came from")
    ap.add_argument("--numbers", help="the claims file (default config/paper_numbers.yaml)")
    ap.add_argument("--figures", nargs="+", default=FIGURES, help="figures to show")
    ap.add_argument("--viscosity-ratio", action="store_true",
                    help="add the viscosity-ratio study's section (its table and figure)")
    args = ap.parse_args(argv)
    out = Path(args.out)
    try:
        text = page(args.results, args.label, args.figures, out.with_suffix(""),
                    args.archive, numbers=args.numbers,
                    viscosity_ratio=args.viscosity_ratio)
    except (FileNotFoundError, archive.ArchiveError) as e:
        print(f"results_page: error: {e}", file=sys.stderr)
        return 2
    out.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
