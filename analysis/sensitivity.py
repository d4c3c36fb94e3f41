"""The sensitivity study: the folding points under each membrane.

At Ca 0.4-0.6 and phi 0.3-0.4 the paper's membrane (neo-Hookean, no bending) folds at the
element scale and its runs stop early (docs/suspensions.md, "Hard cases"). Two
regularisers exist, the relaxed (tension-field) membrane and a hinge bending modulus
eb; each changes the model, so the question is how far each moves <D>, mu_sp and N1. The
study runs every point of `sensitivity.points` with every membrane of its mesh level
(`sensitivity.membranes`, codes of analysis.membrane), and one capsule in unbounded shear
(the dilute limit, where the paper's membrane does not fold and the change is the
regulariser's alone) at `sensitivity.dilute`'s Ca and levels, against the dilute study's
runs of the paper's membrane.

main() writes one row per run: its averages over the study's window (a run that stopped
inside the window averages up to its stop and is marked by `ended`; one that stopped
before it has count 0 and no averages), and the relative change of each quantity against
the paper's membrane at the same point and level with its standard error (NaN where
either run did not reach its end: only runs that did count as results), and
`smallest_eb_to_end`: the smallest pure bending modulus that carried a point to the end.
The plan (plan()) is shared by the workflow, which runs it, and by main(), which reads it
back (the accuracy study's pattern, analysis/accuracy.py).
"""

import argparse
import json
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from analysis import membrane
from analysis.read_run import read_summary, read_timeseries
from analysis.statistics import propagated_standard_error
from analysis.tables import markdown_table, run_row, stopped_row, write_table

QUANTITIES = ("D", "mu_sp", "N1")
PAPER = membrane.PAPER
COLUMNS = ("case", "ca", "phi", "capsules", "seed", "mesh_level", "N_E", "membrane",
           "ended", "t_stop", "t_start", "t_end", "count", "intrinsic",
           "D", "D_se", "mu_sp", "mu_sp_se", "N1", "N1_se",
           "D_change", "D_change_se", "mu_sp_change", "mu_sp_change_se",
           "N1_change", "N1_change_se", "smallest_eb_to_end", "run")


@dataclass(frozen=True)
class Run:
    """One run of the study (or the dilute study's run of the paper's membrane that the
    dilute runs are compared with) and the window its averages are taken over."""
    case: str  # "suspension" or "dilute"
    ca: float
    phi: float  # 0: one capsule in unbounded shear
    level: int
    membrane: str  # a canonical code (analysis.membrane)
    capsules: int  # 1 in the dilute limit
    seed: int
    t_end: float
    window: tuple

    @property
    def name(self):
        """The run's folder name: every setting that distinguishes it (its t_end is not:
        raising it extends the run, as in every study)."""
        if self.case == "dilute":
            return f"dilute_ca{self.ca:g}_level{self.level}_{self.membrane}"
        return (f"ca{self.ca:g}_phi{self.phi:g}_M{self.capsules}_level{self.level}"
                f"_seed{self.seed}_{self.membrane}")


def _error(key, why):
    return ValueError(f"sensitivity.{key}: {why}")


def _codes(codes, key=membrane.CONFIG_KEY):
    """The canonical codes of a list, each once (a bad code raises, naming `key`,
    sensitivity.membranes, and the allowed forms)."""
    return list(dict.fromkeys(membrane.canonical(code, key) for code in codes))


def levels_and_membranes(block):
    """{mesh level: [canonical codes]} from `sensitivity.membranes`: a list of
    {mesh_level, codes}, not a map keyed by level, because --configfile merges maps
    (config/ci.yaml's level 1 would be added to config.yaml's levels)."""
    out = {}
    for entry in block["membranes"]:
        level = int(entry["mesh_level"])
        if level in out:
            raise _error("membranes", f"mesh level {level} is listed twice")
        out[level] = _codes(entry["codes"])
    return out


def plan(block, dilute_block):
    """The runs the study makes: every point x every membrane of each mesh level, and the
    dilute limit at every Ca x level x membrane of `block["dilute"]` (its paper runs are
    the dilute study's: dilute_references). The dilute runs take t_end and t_avg_start of
    `dilute_block` (config["dilute"]), so they compare with the dilute study's runs.
    Raises ValueError for a bad membrane code or window, before any run."""
    t_end = float(block["t_end"])
    window = tuple(float(t) for t in block["window"])
    if not 0 <= window[0] < window[1] <= t_end:
        raise _error("window", f"{list(window)} is not within [0, t_end = {t_end:g}]")
    capsules, seed = int(block["capsules"]), int(block.get("seed", 1))
    runs = []
    points = list(dict.fromkeys((float(ca), float(phi)) for ca, phi in block["points"]))
    for level, codes in levels_and_membranes(block).items():
        for ca, phi in points:
            runs += [Run("suspension", ca, phi, level, code, capsules, seed, t_end, window)
                     for code in codes]
    for ca, level in _dilute_cases(block):
        for code in _codes(block["dilute"]["membranes"], "sensitivity.dilute.membranes"):
            if code != PAPER:  # the dilute study's run
                runs.append(_dilute_run(ca, level, code, dilute_block))
    return runs


def _dilute_cases(block):
    d = block.get("dilute") or {}
    return [(float(ca), int(level)) for level in d.get("mesh_levels", [])
            for ca in d.get("ca", [])]


def _dilute_run(ca, level, code, dilute_block):
    t_end = float(dilute_block["t_end"])
    return Run("dilute", ca, 0.0, level, code, 1, 1, t_end,
               (float(dilute_block["t_avg_start"]), t_end))


def dilute_references(block, dilute_block):
    """The dilute study's runs of the paper's membrane that the study's dilute runs are
    compared with: one per Ca and level of `block["dilute"]`."""
    return [_dilute_run(ca, level, PAPER, dilute_block) for ca, level in _dilute_cases(block)]


def run_folders(block, dilute_block, results, references):
    """(Run, folder) of every run the table reads: the study's own in
    results/sensitivity/<name>, then each of dilute_references() in the folder given for
    it (`references`, in its order: the workflow names the dilute study's folders,
    pipeline.run_spec, so that no name is spelt twice)."""
    refs = dilute_references(block, dilute_block)
    if len(refs) != len(references):
        raise ValueError(f"sensitivity: {len(references)} reference folders given for "
                         f"{len(refs)} dilute references")
    return ([(run, Path(results) / run.name) for run in plan(block, dilute_block)] +
            list(zip(refs, map(Path, references))))


def run_names(block, dilute_block):
    """{folder name: Run} of every run the study makes."""
    return {run.name: run for run in plan(block, dilute_block)}


def _check_membrane(run, summary, path):
    """The membrane a run's summary says it carried must be its code's (imex aside): a
    folder made by other options would otherwise be read as this run."""
    planned = membrane.membrane_part(run.membrane)
    carried = membrane.code_from_parameters(summary.get("parameters", {}))
    if planned != carried:
        raise ValueError(f"sensitivity: {path} carries the membrane '{carried}' but its "
                         f"plan says '{planned}': delete the folder to run it again")


def run_values(run, path):
    """One row of the table: the run's settings, how it ended, its last sample time
    (t_stop) and its averages over its window (analysis.tables.run_row), or the row of a
    run that stopped before its window (stopped_row: count 0, NaN averages)."""
    summary = read_summary(path)
    _check_membrane(run, summary, path)
    times = read_timeseries(path)["time"]
    try:
        row = run_row(path, run.window[0], run.window[1])
    except ValueError:  # no samples in the window: a run that stopped before it
        if summary.get("ended", "t_end") == "t_end":
            raise
        row = stopped_row(path, run.window[0])
    out = {"case": run.case, "ca": run.ca, "phi": run.phi, "capsules": run.capsules,
           "seed": run.seed, "mesh_level": run.level, "N_E": 20 * 4**run.level,
           "membrane": run.membrane, "ended": summary.get("ended", "t_end"),
           "t_stop": float(times.max()) if times.size else 0.0,
           "t_start": row["t_start"], "t_end": row["t_end"], "count": int(row["count"]),
           "intrinsic": int(run.phi == 0), "run": str(path)}
    for q in QUANTITIES:
        out[q], out[f"{q}_se"] = float(row[q]), float(row[f"{q}_se"])
    return out


def _key(row):
    return (row["case"], float(row["ca"]), float(row["phi"]), int(row["mesh_level"]))


def relative_change(value, se, reference, reference_se):
    """value / reference - 1 and its standard error from both (independent) errors, to
    first order (analysis.statistics.propagated_standard_error)."""
    def change(v):
        return v[0] / v[1] - 1.0

    return (change([value, reference]),
            propagated_standard_error(change, [value, reference], [se, reference_se]))


def changes_against_paper(table):
    """Adds <q>_change and <q>_change_se: each row's relative change against the paper's
    membrane at the same case, point and level. NaN for the paper's rows themselves, and
    wherever either run did not reach its end (ended != "t_end"): a stopped run's
    averages cover a shorter, earlier window."""
    table = table.copy()
    reached = table["ended"].fillna("t_end") == "t_end"
    references = {_key(row): row for _, row in table[reached & (table["membrane"] == PAPER)]
                  .iterrows()}
    for q in QUANTITIES:
        table[f"{q}_change"] = math.nan
        table[f"{q}_change_se"] = math.nan
    for i, row in table[reached & (table["membrane"] != PAPER)].iterrows():
        ref = references.get(_key(row))
        if ref is None:
            continue
        for q in QUANTITIES:
            value, se = relative_change(row[q], row[f"{q}_se"], ref[q], ref[f"{q}_se"])
            table.loc[i, f"{q}_change"] = value
            table.loc[i, f"{q}_change_se"] = se
    return table


def mark_smallest_eb(table):
    """Adds smallest_eb_to_end: True on the row of the smallest eb among the pure bending
    membranes (eb<value> alone) of a case, point and level that reached their end."""
    table = table.copy()
    table["smallest_eb_to_end"] = False
    reached = table["ended"].fillna("t_end") == "t_end"
    pure = table["membrane"].map(membrane.is_pure_bending)
    candidates = table[reached & pure]
    if candidates.empty:
        return table
    eb = candidates["membrane"].map(membrane.bending)
    for _, group in candidates.groupby(["case", "ca", "phi", "mesh_level"]):
        table.loc[eb[group.index].idxmin(), "smallest_eb_to_end"] = True
    return table


def _membrane_order(code):
    return (code != PAPER, code)


def sort_rows(table):
    """Suspension points first, then the dilute limit; by Ca, phi, level and membrane
    (the paper's first)."""
    order = table.assign(_case=table["case"] != "suspension",
                         _membrane=table["membrane"].map(_membrane_order))
    order = order.sort_values(["_case", "ca", "phi", "mesh_level", "_membrane"],
                              kind="stable")
    return table.loc[order.index].reset_index(drop=True)


def study_table(block, dilute_block, results, references):
    """The study's table (a DataFrame, COLUMNS): one row per run and per dilute
    reference (its folder in `references`, run_folders()), sorted (sort_rows)."""
    rows = [run_values(run, folder)
            for run, folder in run_folders(block, dilute_block, results, references)]
    table = pd.DataFrame(rows, columns=[c for c in COLUMNS
                                        if c not in ("smallest_eb_to_end",)
                                        and not c.endswith(("_change", "_change_se"))])
    table = mark_smallest_eb(changes_against_paper(table))
    return sort_rows(table).reindex(columns=list(COLUMNS))


def markdown(table):
    """The table as markdown: values +- their standard errors, the changes in percent."""
    shown = pd.DataFrame({
        "point": [f"Ca {r.ca:g}, phi {r.phi:g}" if r.case == "suspension"
                  else f"dilute, Ca {r.ca:g}" for r in table.itertuples()],
        "N_E": [f"{int(r.N_E)} (level {int(r.mesh_level)})" for r in table.itertuples()],
        "membrane": table["membrane"],
        "ended": [r.ended if r.ended == "t_end" else
                  f"{r.ended} at {r.t_stop:.2f}"
                  + ("" if r.count > 0 else ", before its window")
                  for r in table.itertuples()],
    })
    errors = {}
    for q in QUANTITIES:
        shown[q] = table[q]
        errors[q] = table[f"{q}_se"]
    for q in QUANTITIES:
        shown[f"{q} change %"] = 100 * table[f"{q}_change"]
        errors[f"{q} change %"] = 100 * table[f"{q}_change_se"]
    shown["smallest eb to end"] = table["smallest_eb_to_end"].map({True: "yes", False: ""})
    formats = {q: ".4g" for q in QUANTITIES} | {f"{q} change %": "+.1f" for q in QUANTITIES}
    headers = (["point", "N_E", "membrane", "ended", "<D>", "mu_sp", "N1"] +
               [f"{name} change %" for name in ("<D>", "mu_sp", "N1")] +
               ["smallest eb to end"])
    t0 = sorted(set(table.loc[table["case"] == "suspension", "t_start"].dropna()))
    lines = ["# The sensitivity study: the folding points under each membrane", "",
             "Averages over the study's window (suspensions from gammadot t = "
             f"{', '.join(f'{t:g}' for t in t0) or '-'}; the dilute limit over its own "
             "window), +- one standard error of the time average. In the dilute rows "
             "mu_sp and N1 are the intrinsic [mu] and [N1]. The change is relative to the "
             "paper's membrane at the same point and level, only where both runs reached "
             "their end; a run that stopped inside its window averages up to its stop. "
             "Membranes: paper (no bending), wrinkling (the relaxed membrane), "
             "eb<value> (bending modulus kb / (Gs a^2)), imex (the time scheme), joined "
             "by + (docs/workflow.md).", "",
             markdown_table(shown, formats=formats, headers=headers, errors=errors,
                            na_rep="-"), ""]
    return "\n".join(lines)


def main(argv=None):
    """CLI: python -m analysis.sensitivity --plan JSON --dilute JSON --results DIR
    --references JSON --out-csv CSV --out-md MD."""
    ap = argparse.ArgumentParser(description="The sensitivity study's table.")
    ap.add_argument("--plan", required=True, help="the sensitivity block of the config (JSON)")
    ap.add_argument("--dilute", required=True, help="the dilute block of the config (JSON)")
    ap.add_argument("--results", required=True, help="the folder of the study's runs")
    ap.add_argument("--references", required=True,
                    help="the folders of the dilute study's runs of the paper's membrane, "
                    "one per dilute reference in its order (a JSON list)")
    ap.add_argument("--out-csv", required=True)
    ap.add_argument("--out-md", required=True)
    args = ap.parse_args(argv)
    table = study_table(json.loads(args.plan), json.loads(args.dilute), args.results,
                        json.loads(args.references))
    for r in table[table["ended"] != "t_end"].itertuples():
        print(f"sensitivity: {r.run} stopped early ({r.ended} at {r.t_stop:.2f})",
              file=sys.stderr)
    write_table(args.out_csv, table, COLUMNS)
    Path(args.out_md).write_text(markdown(table), encoding="utf-8")


if __name__ == "__main__":
    main()
