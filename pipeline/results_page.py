"""The results page of a configuration (docs/results.md): what it computed and where its
runs are kept, the paper's numbers against ours with a verdict for each, Table 1 and a
small set of its figures, all from the workflow's outputs under results/ (the comparison
of analysis.paper_comparison, the figures of figures/). The page is written where the
docs are, with the figures' PNGs beside it, so that it can be committed as the project's
published results.

Usage: python -m pipeline.results_page --results results --out docs/results.md
       --label config/quantitative.yaml [--archive archive/quantitative]
       [--figures fig03 fig05 ...]
"""

import argparse
import datetime
import shutil
import sys
from pathlib import Path

from pipeline import archive
from pipeline.run_spec import ROOT, physics_version

# The figures a reader of the paper looks for first: deformation and viscosity against
# phi (3, 5), the normal stress differences (7), the stresslet relations (9), the initial
# positions and the box size (11, 12).
FIGURES = ["fig03", "fig05", "fig07", "fig09", "fig11", "fig12"]


def archive_line(store):
    """One sentence on the results archive the runs came from."""
    s = archive.summary(archive.read_records([store]))
    store = Path(store).resolve()
    shown = store.relative_to(ROOT) if store.is_relative_to(ROOT) else store
    versions = ", ".join(sorted(s["physics_versions"])) or physics_version()
    return (f"Its runs are kept in the results archive `{shown}`: {s['records']} records "
            f"({s['finished']} finished), {s['bytes'] / 1e6:.1f} MB, "
            f"{s['cpu_seconds'] / 3600:.1f} CPU hours, solver physics version {versions}.")


def page(results, label, figures, figure_dir, store=None, date=None):
    """The page's Markdown; copies the figures' PNGs into `figure_dir`."""
    results, figure_dir = Path(results), Path(figure_dir)
    date = date or datetime.date.today().isoformat()
    lines = ["# Results", "",
             f"The paper's numbers against those of `{label}`, generated on {date} by "
             "`pipeline/results_page.py` from the workflow's outputs (`docs/workflow.md`).",
             ""]
    if store:
        lines += [archive_line(store), ""]
    lines += ["## The paper's numbers against ours", "",
              "Where a number differs, its reason says what differs between the paper's "
              "runs and ours and what was measured to be, or not to be, the cause "
              "(`config/paper_numbers.yaml`; the measurements: `docs/suspensions.md`, "
              "`docs/dilute_limit.md`).", "",
              (results / "figures" / "paper_comparison.md").read_text().strip(), "",
              "## Table 1", "", (results / "figures" / "table1.md").read_text().strip(),
              "", "## Figures", ""]
    figure_dir.mkdir(parents=True, exist_ok=True)
    for name in figures:
        png, number = results / "figures" / f"{name}.png", name[3:].lstrip("0")
        if not png.exists():
            lines += [f"Figure {number}: not in this configuration.", ""]
            continue
        shutil.copyfile(png, figure_dir / png.name)
        lines += [f"![Figure {number}]({figure_dir.name}/{png.name})", ""]
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--results", default="results", help="the workflow's results folder")
    ap.add_argument("--out", required=True, help="the page (its figures go to a folder "
                    "named after it: docs/results.md -> docs/results/)")
    ap.add_argument("--label", required=True, help="the configuration, as the page names it")
    ap.add_argument("--archive", help="the results archive the runs came from")
    ap.add_argument("--figures", nargs="+", default=FIGURES, help="figures to show")
    args = ap.parse_args(argv)
    out = Path(args.out)
    try:
        text = page(args.results, args.label, args.figures, out.with_suffix(""),
                    args.archive)
    except (FileNotFoundError, archive.ArchiveError) as e:
        print(f"results_page: error: {e}", file=sys.stderr)
        return 2
    out.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
