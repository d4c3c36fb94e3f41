"""The accuracy study: which settings buy which accuracy at which cost.

Each setting changes one parameter of a base run (mesh level, Ewald tolerance, time
scheme and step, capsules M, averaging window); the relative error of <D>, mu_sp and N1
of every setting is split into four parts, each measured on its own:

- discretisation: against the finest mesh level of the study; the finest level's own
  error from the observed order of the three finest levels (Richardson);
- Ewald: against a tight tolerance, over an early window in which the trajectories of
  both runs still coincide (a suspension is chaotic, so later windows differ by more
  than the Ewald error);
- time step: against a small step, over the same early window (the dilute limit, which is
  steady, over its averaging window), at the run's own sample times: a fixed step
  samples at the step nearest each sample time, so the finely sampled reference is
  interpolated there;
- statistics: the standard error of the time average (analysis.statistics).

The total is their root sum of squares. The cost of a setting is the CPU seconds per
unit strain of its run (summary.json's cpu_seconds: all threads, its last invocation). The study's plan
(plan()) is shared by the workflow, which runs it, and by main(), which reads it back.
"""

import argparse
import json
import math
import re
import sys
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pandas as pd

from analysis.fits import observed_order
from analysis.read_run import read_summary, read_timeseries
from analysis.rheology import stress_factor
from analysis.tables import run_row, write_table

QUANTITIES = ("D", "mu_sp", "N1")
PARTS = ("disc", "ewald", "time", "stat")
TIME_CODE = re.compile(r"^(heun|imexrms|imex)([0-9.eE+-]+)$")
NOMINAL_ORDER = 2.0  # P1 elements: used where the observed order cannot be measured


@dataclass(frozen=True)
class Setting:
    """One point of the study: a run and the window its averages are taken over."""
    case: str  # "suspension" or "dilute_ca<Ca>"
    family: str  # base, mesh, ewald, time, capsules, window, or a configuration's name
    ca: float
    phi: float  # 0: one capsule in unbounded shear
    level: int
    capsules: int
    ewald: float  # 0 for the dilute limit
    time: str  # "heun<dt_safety>" (fixed step), "imex<time.tolerance>" (adaptive) or
    #            "imexrms<time.tolerance>" (adaptive, time.error_norm rms)
    t_end: float
    window: tuple
    seed: int = 1
    sample_interval: float = 0  # 0: the study's; a reference samples finer


    @property
    def run(self):
        """The run's folder name: all that distinguishes its run."""
        sampled = f"_s{self.sample_interval:g}" if self.sample_interval else ""
        if self.phi == 0:
            return (f"ca{self.ca:g}_phi0_level{self.level}_{self.time}_t{self.t_end:g}"
                    + sampled)
        return (f"ca{self.ca:g}_phi{self.phi:g}_M{self.capsules}_level{self.level}"
                f"_seed{self.seed}_ewald{self.ewald:g}_{self.time}_t{self.t_end:g}"
                + sampled)

    @property
    def label(self):
        changed = {"mesh": f"level {self.level}", "ewald": f"Ewald {self.ewald:g}",
                   "time": self.time, "capsules": f"M {self.capsules}",
                   "window": f"[{self.window[0]:g}, {self.window[1]:g}]"}
        return changed.get(self.family, self.family)


def time_options(code):
    """capsim --set options of a time code: heun<dt_safety>, imex<tolerance> (the max
    norm) or imexrms<tolerance> (the rms norm)."""
    match = TIME_CODE.match(code)
    if not match:
        raise ValueError(f"accuracy: time setting '{code}' is not heun<dt_safety>, "
                         "imex<tolerance> or imexrms<tolerance> (e.g. heun0.5, imex0.001, "
                         "imexrms0.01)")
    scheme, value = match.group(1), float(match.group(2))
    if scheme == "heun":
        return ["time.scheme=heun", "time.tolerance=0", f"dt_safety={value:g}"]
    norm = ["time.error_norm=rms"] if scheme == "imexrms" else []  # max: the default
    return ["time.scheme=imex", f"time.tolerance={value:g}"] + norm


def _suspension_plan(block):
    s = block["suspension"]
    b = block["base"]
    base = Setting("suspension", "base", s["ca"], s["phi"], b["mesh_level"], b["capsules"],
                   b["ewald_tolerance"], b["time"], b["t_end"], tuple(b["window"]),
                   s.get("seed", 1))
    configurations = block.get("configurations", {})

    def values(key, own):  # a family's values, the base's, and those of configurations
        return list(dict.fromkeys([b[own]] + list(block[key]) +
                                  [c[own] for c in configurations.values()]))

    points = [base]
    points += [replace(base, family="mesh", level=v) for v in values("mesh_levels",
                                                                      "mesh_level")]
    points += [replace(base, family="ewald", ewald=v)
               for v in values("ewald_tolerances", "ewald_tolerance")]
    points += [replace(base, family="time", time=v) for v in values("times", "time")]
    points += [replace(base, family="capsules", capsules=v) for v in block["capsules"]]
    # A window is a part of the base run: it costs no run of its own.
    points += [replace(base, family="window", window=tuple(w)) for w in block["windows"]]
    for name, c in configurations.items():
        points.append(replace(base, family=name, level=c["mesh_level"],
                              capsules=c["capsules"], ewald=c["ewald_tolerance"],
                              time=c["time"], t_end=c["window"][1],
                              window=tuple(c["window"])))
    return points


def _dilute_plan(block):
    d = block["dilute"]
    points = []
    for ca in d["ca"]:
        base = Setting(f"dilute_ca{ca:g}", "base", ca, 0.0, d["mesh_level"], 1, 0.0,
                       block["base"]["time"], d["t_end"], tuple(d["window"]))
        points += [base] + [replace(base, family="mesh", level=v) for v in d["mesh_levels"]]
        points += [replace(base, family="time", time=v)
                   for v in dict.fromkeys([base.time] + list(block["times"]))]
    return points


def references(block):
    """The reference runs of the Ewald and time parts: the suspension's base over the
    early window with a tight Ewald tolerance, or with a small step; the dilute base with
    the small step over its own window. The small-step references sample finely: a
    fixed step samples at the step nearest each sample time, so a run is compared with
    the reference interpolated at its own sample times (time_errors)."""
    base = _suspension_plan(block)[0]
    ref = block["reference"]
    short = replace(base, family="reference", t_end=block["short_window"][1],
                    window=tuple(block["short_window"]))
    fine = {"time": ref["time"], "sample_interval": ref["sample_interval"]}
    refs = {("suspension", "ewald"): replace(short, ewald=ref["ewald_tolerance"]),
            ("suspension", "time"): replace(short, **fine)}
    for point in _dilute_plan(block):
        if point.family == "base":
            refs[(point.case, "time")] = replace(point, family="reference", **fine)
    return refs


def plan(block):
    """Every setting of the study (a setting may appear in more than one family: the base
    is also a mesh level, a tolerance, a time setting, an M and a window)."""
    points = _suspension_plan(block) + _dilute_plan(block)
    for point in points:
        time_options(point.time)  # a readable error for a bad time code, before any run
    return points


def run_names(block):
    """The folder names of every run the study needs (settings and references)."""
    names = {}
    for point in plan(block) + list(references(block).values()):
        names.setdefault(point.run, point)  # the first (the base) sets t_avg_start
    return names


def run_values(results, setting, window=None):
    """<D>, mu_sp, N1 and their standard errors of a setting's run over `window`
    (default: the setting's own); NaN for a run that stopped before the window."""
    t0, t1 = window or setting.window
    try:
        row = run_row(Path(results) / setting.run, t0, t1)
    except ValueError:  # no samples in the window (capsim's exit 3, summary "ended")
        row = {f"{q}{end}": math.nan for q in QUANTITIES for end in ("", "_se")}
    return {q: row[q] for q in QUANTITIES} | {f"{q}_se": row[f"{q}_se"] for q in QUANTITIES}


def sampled_values(results, setting):
    """The capsule means of D, mu_sp and N1 at every sample of a setting's run, and the
    sample times."""
    run_dir = Path(results) / setting.run
    ts = read_timeseries(run_dir)
    s = np.asarray(ts["stresslet"], float).mean(axis=1)
    factor = stress_factor(setting.phi, setting.ca)
    return {"time": np.asarray(ts["time"], float), "D": np.asarray(ts["D"]).mean(axis=1),
            "mu_sp": factor * s[:, 0, 1], "N1": factor * (s[:, 0, 0] - s[:, 1, 1])}


def time_errors(got, ref, window):
    """Relative error of the window mean of each quantity of `got` against the reference
    interpolated (finely sampled) at got's own sample times."""
    t = got["time"]
    inside = (t >= window[0]) & (t <= window[1])
    errors = {}
    for q in QUANTITIES:
        want = np.interp(t[inside], ref["time"], ref[q]).mean()
        errors[q] = abs(got[q][inside].mean() - want) / abs(want)
    return errors


def convergent_order(values_by_level):
    """The observed order (analysis.fits.observed_order) of the three finest levels (h
    halves per level) where it shows convergence (p > 0); NaN where it cannot be
    observed (fewer levels, or the differences do not shrink)."""
    levels = sorted(values_by_level)[-3:]
    if len(levels) < 3:
        return math.nan
    p = observed_order(*(values_by_level[level] for level in levels))
    return p if p > 0 else math.nan


def discretisation_errors(values_by_level):
    """Relative error of each level against the finest, and of the finest from the
    observed order (the nominal order where none is observed). Returns (errors, p)."""
    levels = sorted(values_by_level)
    finest = values_by_level[levels[-1]]
    p = convergent_order(values_by_level)
    errors = {level: abs(values_by_level[level] - finest) / abs(finest) for level in levels}
    if len(levels) > 1:
        order = p if math.isfinite(p) else NOMINAL_ORDER
        errors[levels[-1]] = errors[levels[-2]] / (2.0**order - 1.0)
    else:
        errors[levels[-1]] = math.nan
    return errors, p


def run_facts(run_dir):
    """How a run ended, its wall and CPU seconds and its CPU seconds per unit strain: the
    sums over its segments (segments.json, one entry per job that ended well, each from
    the checkpoint it resumed to the last it wrote) when they follow each other from the
    start; else NaN (a job was killed, and its time is lost)."""
    summary = read_summary(run_dir)
    facts = {"ended": summary.get("ended", "t_end")}
    path = Path(run_dir) / "segments.json"
    segments = json.loads(path.read_text()) if path.exists() else []
    reached = 0.0
    for segment in segments:
        if not math.isclose(segment["t_from"], reached, abs_tol=1e-9):
            segments = []
            break
        reached = segment["t_to"]
    if not segments:
        print(f"accuracy: the segments of {run_dir} do not cover it from the start, so "
              "its cost is unknown: run it again from the start (delete its folder) to "
              "time it", file=sys.stderr)
        return facts | {"wall_s": math.nan, "cpu_s": math.nan, "cpu_s_per_strain": math.nan}
    cpu = sum(float(s["cpu_seconds"]) for s in segments)
    return facts | {"wall_s": sum(float(s["wall_seconds"]) for s in segments), "cpu_s": cpu,
                    "cpu_s_per_strain": cpu / float(summary["t_end"])}


def pareto_front(cost_values, errors):
    """True where no other point is at most as costly and as wrong, and better in one
    (never for a point whose cost or error is unknown)."""
    c, e = np.asarray(cost_values, float), np.asarray(errors, float)
    dominated = [(c <= ci) & (e <= ei) & ((c < ci) | (e < ei)) for ci, ei in zip(c, e)]
    known = np.isfinite(c) & np.isfinite(e)
    return np.array([k and not d.any() for k, d in zip(known, dominated)])


def _case_parts(block, results, points):
    """The error parts of one case: {part: {key: {quantity: relative error}}}, keyed by
    the level, the Ewald tolerance, the time code; and the observed orders."""
    refs = references(block)
    case = points[0].case
    base = points[0]
    own = {p: run_values(results, p) for p in points}
    by_level = {p.level: own[p] for p in points if p.family == "mesh"}
    disc, orders = {}, {}
    for q in QUANTITIES:
        errors, orders[q] = discretisation_errors({k: v[q] for k, v in by_level.items()})
        for level, e in errors.items():
            disc.setdefault(level, {})[q] = e
    parts = {"disc": disc, "ewald": {}, "time": {}}
    ewald_ref = refs.get((case, "ewald"))
    if ewald_ref is None:  # no Ewald sums in unbounded shear
        parts["ewald"][base.ewald] = {q: 0.0 for q in QUANTITIES}
    else:  # the same (exact) sample times in every run of the family
        want = run_values(results, ewald_ref)
        for p in (p for p in points if p.family == "ewald"):
            got = run_values(results, p, ewald_ref.window)
            parts["ewald"][p.ewald] = {q: abs(got[q] - want[q]) / abs(want[q])
                                       for q in QUANTITIES}
    time_ref = refs[(case, "time")]
    fine = sampled_values(results, time_ref)
    for p in (p for p in points if p.family == "time"):
        parts["time"][p.time] = time_errors(sampled_values(results, p), fine,
                                            time_ref.window)
    return parts, orders, own


def error_table(block, results):
    """One row per setting of the study: its parameters, cost, values, error parts and
    total for each quantity, whether it is on the Pareto front (per case and quantity),
    and the observed mesh order of its case. A DataFrame."""
    rows = []
    points = plan(block)
    for case in dict.fromkeys(p.case for p in points):
        mine = [p for p in points if p.case == case]
        parts, orders, own = _case_parts(block, results, mine)
        seen = {}
        for p in mine:
            key = (p.run, p.window)
            if key in seen:
                seen[key]["families"] += f";{p.family}"
                continue
            row = {"case": case, "family": p.family, "families": p.family, "label": p.label,
                   "ca": p.ca, "phi": p.phi, "mesh_level": p.level, "capsules": p.capsules,
                   "ewald_tolerance": p.ewald, "time": p.time, "t_end": p.t_end,
                   "window_start": p.window[0], "window_end": p.window[1], "run": p.run}
            row |= run_facts(Path(results) / p.run)
            for q in QUANTITIES:
                value = own[p]
                split = {"disc": parts["disc"].get(p.level, {}).get(q, math.nan),
                         "ewald": parts["ewald"].get(p.ewald, {}).get(q, math.nan),
                         "time": parts["time"].get(p.time, {}).get(q, math.nan),
                         "stat": value[f"{q}_se"] / abs(value[q])}
                row |= {q: value[q], f"{q}_se": value[f"{q}_se"], f"{q}_order": orders[q]}
                row |= {f"{q}_{part}": split[part] for part in PARTS}
                row[f"{q}_total"] = math.sqrt(sum(e * e for e in split.values()))
            seen[key] = row
            rows.append(row)
    table = pd.DataFrame(rows)
    for q in QUANTITIES:
        table[f"{q}_pareto"] = False
        for case, group in table.groupby("case"):
            front = pareto_front(group["cpu_s_per_strain"], group[f"{q}_total"])
            table.loc[group.index, f"{q}_pareto"] = front
    return table


def main(argv=None):
    """CLI: python -m analysis.accuracy --plan JSON --results DIR --out CSV."""
    ap = argparse.ArgumentParser(description="The accuracy study's error table.")
    ap.add_argument("--plan", required=True, help="the accuracy block of the config (JSON)")
    ap.add_argument("--results", required=True, help="the folder of the study's runs")
    ap.add_argument("--out", required=True)
    args = ap.parse_args(argv)
    write_table(args.out, error_table(json.loads(args.plan), args.results))


if __name__ == "__main__":
    main()
