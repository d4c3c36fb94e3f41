"""The docs' tables of measurements, generated from the benchmarks' JSON records
(benchmarks/records/), so that a measured number is typed nowhere. In a Markdown page a
generated table sits between two comments:

    <!-- table KIND RECORD [RECORD ...] -->
    | ... |
    <!-- end table -->

KIND names a renderer below; each RECORD is a JSON file, relative to the repository root,
as a benchmark wrote it (its command is in the renderer's docstring and the page's text).

    .venv/bin/python benchmarks/doc_tables.py --write docs/performance.md  # regenerate
    .venv/bin/python benchmarks/doc_tables.py --check docs/*.md            # 1 if stale
"""

import argparse
import json
import re
import sys
from pathlib import Path

import pandas as pd

from analysis.tables import markdown_table

ROOT = Path(__file__).resolve().parents[1]
BLOCK = re.compile(r"(<!-- table (\S+)((?: \S+)+) -->\n)(.*?)(<!-- end table -->)", re.S)

# Rows of the step profile: the stages of `capsim run --profile` (run/run_profile.hpp).
STEP_ROWS = [
    ("membrane load (and repulsion), two per step", ["membrane_load"]),
    ("Ewald set-up (cell lists, rule points)", ["ewald_setup"]),
    ("near corrections (singular and near-singular quadrature)", ["near_corrections"]),
    ("real-space sum", ["real_space"]),
    ("reciprocal (Spectral Ewald)", ["reciprocal"]),
    ("of which spreading", ["spreading"]),
    ("of which FFT", ["fft"]),
    ("of which gathering", ["gathering"]),
    ("two evaluations (all of the above)", ["evaluations"]),
    ("volume constraint, state checks", ["volume_constraint", "state_checks"]),
    ("Lees-Edwards remapping and contact check", ["box_and_contact"]),
    ("sampling (one row every 0.05 strain)", ["sampling"]),
    ("checkpoints", ["checkpoints"]),
    ("whole step", ["loop"]),
]


def step_profile(profile):
    """`benchmarks/step_profile.py --out FILE`: seconds per step of every stage at levels
    3 and 4, its share of the step and its growth from level 3 to 4."""
    l3, l4 = (profile["levels"][k] for k in ("3", "4"))

    def seconds(level, keys):
        return sum(level["seconds_per_step"][k] for k in keys)

    whole3, whole4 = seconds(l3, ["loop"]), seconds(l4, ["loop"])
    grids = ", ".join("x".join(map(str, lv["rates"]["grid"])) for lv in (l3, l4))
    rows = []
    for label, keys in STEP_ROWS:
        s3, s4 = seconds(l3, keys), seconds(l4, keys)
        rows.append({"stage": label + (f" (grid {grids})" if keys == ["fft"] else ""),
                     "s3": s3, "p3": 100 * s3 / whole3, "s4": s4, "p4": 100 * s4 / whole4,
                     "growth": s4 / s3 if s3 > 0 else float("nan")})
    return markdown_table(
        pd.DataFrame(rows), formats={"s3": ".3f", "p3": ".1f", "s4": ".3f", "p4": ".1f",
                                     "growth": ".1f"},
        headers=["stage", f"level 3: s/step ({l3['steps']} steps)", "share %",
                 f"level 4: s/step ({l4['steps']} steps)", "share %", "growth"])


def step_rates(profile):
    """`benchmarks/step_profile.py --out FILE`: each stage's rate against its bound, and
    the wall seconds per capsule-strain. The FMA peak is measured in double; a stage in
    single precision (as the record's level 3 says) has twice that peak."""
    peak, copy = profile["fma_peak_gflops"], profile["memory_gbytes_per_s"]
    l3, l4 = (profile["levels"][k] for k in ("3", "4"))

    def peak_of(key):
        return peak * (2 if l3["rates"].get(key, "double") == "single" else 1)

    rows = [("real-space sum, GFLOP/s (145 flops per pair)", "real_space_gflops",
             peak_of("real_space_precision")),
            ("FFT, GFLOP/s (2.5 N log2 N per transform)", "fft_gflops",
             peak_of("grid_precision")),
            ("spreading, GB/s of grid values", "spreading_gbytes_per_s", copy),
            ("gathering, GB/s of grid values", "gathering_gbytes_per_s", copy)]
    table = [{"what": label, "l3": l3["rates"][key], "f3": 100 * l3["rates"][key] / bound,
              "l4": l4["rates"][key], "f4": 100 * l4["rates"][key] / bound,
              "bound": bound} for label, key, bound in rows]
    table.append({"what": "wall s per capsule-strain", "l3": l3["seconds_per_capsule_strain"],
                  "f3": float("nan"), "l4": l4["seconds_per_capsule_strain"],
                  "f4": float("nan"), "bound": float("nan")})
    return markdown_table(
        pd.DataFrame(table), formats={k: ".3g" for k in ("l3", "l4", "bound")}
        | {"f3": ".0f", "f4": ".0f"}, na_rep="",
        headers=["", "level 3", "% of bound", "level 4", "% of bound",
                 "bound (FMA peak in the stage's precision, GFLOP/s; copy, GB/s)"])


def near_corrections(bench, peak):
    """`build/bench_near_corrections` and `build/peak_flops`: correction points per node
    and nanoseconds per point on one thread, against the 27 flops of a point at the FMA
    peak of one thread."""
    bound_ns = bench["flops_per_point"] / peak["gflops"]["1"]
    rows = []
    for level, r in bench["levels"].items():
        p, ns = r["points_per_node"], r["ns_per_point"]
        rows.append({"level": level, "triangles": r["near_triangles_per_node"],
                     "polar": p["polar"], "adaptive": p["adaptive"],
                     "subtracted": p["subtracted"], "all": p["all"],
                     "generate": ns["generate"], "sum": ns["sum"],
                     "times": (ns["generate"] + ns["sum"]) / bound_ns})
    return markdown_table(
        pd.DataFrame(rows), formats={"triangles": ".1f", "polar": ".0f", "adaptive": ".0f",
                                     "subtracted": ".0f", "all": ".0f", "generate": ".2f",
                                     "sum": ".2f", "times": ".0f"},
        headers=["level", "near triangles per node", "polar points", "adaptive points",
                 "3-point points subtracted", "all points", "ns per point: generate",
                 "push and sum", f"times the bound ({bound_ns:.2f} ns)"])


def setting_compare(result):
    """`benchmarks/precision_compare.py --out FILE [--baseline ..] [--candidate ..]`: two
    settings side by side on the Table 1 point: cost, the averages, and for the grid
    precision the velocity error."""
    rows = []
    for level, e in result["levels"].items():
        d, s = e["runs"]["baseline"], e["runs"]["candidate"]
        err = e.get("velocity_error")
        rows.append({
            "case": f"level {level}, {e['strain']:g} strain units",
            "tolerance": f"{d['tolerance']:.2g}",
            "wall": f"{d['wall_s_per_capsule_strain']:.3g} / "
                    f"{s['wall_s_per_capsule_strain']:.3g}",
            "ratio": e["wall_ratio"], "cpu": e["cpu_ratio"],
            "error": f"{err['baseline']:.4g} / {err['candidate']:.4g}" if err else "",
            "D": f"{d['D']:.6f} / {s['D']:.6f} ({d['D_se']:.2g})",
            "mu": f"{d['mu_sp']:.5f} / {s['mu_sp']:.5f} ({d['mu_sp_se']:.2g})"})
    names = {w: ", ".join(f"{k} {v}" for k, v in o.items())
             for w, o in result["settings"].items()}
    pair = f"{names['baseline']} / {names['candidate']}"
    table = pd.DataFrame(rows)
    if not table["error"].any():
        table = table.drop(columns="error")
    headers = ["case", "tolerance", f"wall s per capsule-strain, {pair}", "ratio",
               "CPU ratio"] + (["velocity error"] if "error" in table else []) + [
        "<D> (SE)", "mu_sp (SE)"]
    return markdown_table(table, formats={"ratio": ".3f", "cpu": ".3f"}, headers=headers)


def near_settings(bench):
    """`build/bench_near_corrections`: the free-space single layer of one capsule with a
    few quadrature settings, its velocity error against a tight reference and the seconds
    of its near corrections on one thread, against far_ratio 2, near_ratio 1.5 (the
    defaults of physics version 1, pipeline/run_spec.py)."""
    rows = []
    for level, settings in bench["settings"].items():
        old = next(r for r in settings if r["far_ratio"] == 2 and r["near_ratio"] == 1.5)
        rows += [{"level": level, "far": r["far_ratio"], "near": r["near_ratio"],
                  "max": r["max_error"], "rms": r["rms_error"], "s": r["near_seconds"],
                  "ratio": r["near_seconds"] / old["near_seconds"]} for r in settings]
    return markdown_table(
        pd.DataFrame(rows), formats={"far": "g", "near": "g", "max": ".2e", "rms": ".2e",
                                     "s": ".4f", "ratio": ".2f"},
        headers=["level", "far_ratio", "near_ratio", "largest error", "rms error",
                 "near corrections, s", "of 2 and 1.5's"])


BUILD_ROWS = [("membrane load (and repulsion), s/step", "membrane_load"),
              ("remapping and contact check, s/step", "box_and_contact"),
              ("sampling, s/step", "sampling"),
              ("two evaluations, s/step", "evaluations"),
              ("time loop, s/step", "loop")]


def build_compare(result):
    """`benchmarks/build_compare.py --old OLD --out FILE`: two builds side by side on the
    Table 1 point (old, new, new, old): stages per step, cost per capsule-strain, whether
    the time series are the same, and the averages over the second half (SE)."""
    levels = result["levels"]

    def cells(get):
        return {f"{w}{lv}": get(e, w) for lv, e in levels.items() for w in ("old", "new")}

    rows = [{"what": label, **cells(lambda e, w, k=key: f"{e['seconds_per_step'][w][k]:.3f}")}
            for label, key in BUILD_ROWS]
    for label, key in (("wall s per capsule-strain (mean of two runs)",
                        "wall_s_per_capsule_strain"),
                       ("CPU s per capsule-strain", "cpu_s_per_capsule_strain")):
        rows.append({"what": label, **cells(lambda e, w, k=key: f"{e['builds'][w][k]:.3g}")})
    for label, key in (("ratio old / new, wall", "wall_ratio"),
                       ("ratio old / new, CPU", "cpu_ratio")):
        rows.append({"what": label, **cells(
            lambda e, w, k=key: f"{e[k]:.3f}" if w == "new" else "")})
    def series(e):
        d = e["difference"]
        most = max(d[k] for k in ("D", "stresslet"))
        if d.get("interpolated"):
            return f"differ by {most:.1e} (interpolated to the old's times)"
        return "identical" if most == 0 else f"differ by {most:.1e}"

    rows.append({"what": "time series",
                 **cells(lambda e, w: series(e) if w == "new" else "")})
    for label, key in (("<D> (SE)", "D"), ("mu_sp (SE)", "mu_sp")):
        rows.append({"what": label, **cells(
            lambda e, w, k=key: f"{e['averages'][w][k]:.6f} ({e['averages'][w][k + '_se']:.2g})")})
    headers = [""] + [f"level {lv} ({e['strain']:g} strain units): {w}"
                      for lv, e in levels.items() for w in ("old", "new")]
    return markdown_table(pd.DataFrame(rows), headers=headers)


def ewald_accuracy(rows):
    """`benchmarks/ewald_report.py accuracy --capsules 27 --mesh-level 2`: the RMS relative
    error of each method against the requested tolerance, at lattice strains 0 and 0.5."""
    table = pd.DataFrame(rows).pivot(index="tolerance", columns=["method", "strain"],
                                     values="rel_error")
    columns = [(m, s) for m in ("spectral", "direct", "patches") for s in (0.0, 0.5)
               if (m, s) in table]
    names = [f"{m}, strain {s:g}" for m, s in columns]
    table = table[columns].set_axis(names, axis=1).sort_index(ascending=False).reset_index()
    return markdown_table(table, formats={"tolerance": ".0e"} | {c: ".2e" for c in names})


# The stages of one evaluation that `capsim bench` times ("seconds"), in table order.
EWALD_STAGES = ["real_space", "near", "spreading", "fft", "gathering"]


def stage_seconds(rows):
    """The seconds of each stage of `capsim bench` outputs, one row per output (NaN for a
    stage not timed: only Spectral Ewald spreads, transforms and gathers)."""
    return pd.DataFrame([r["seconds"] for r in rows]).reindex(columns=EWALD_STAGES)


def grid_text(r):
    """The spectral grid of a `capsim bench` output as M_x x M_y x M_z, '-' for the other
    methods."""
    return "x".join(str(int(m)) for m in r["grid"]) if "grid" in r else "-"


def ewald_speed(rows):
    """`benchmarks/ewald_report.py speed --capsules M --mesh-level 3`: seconds per
    evaluation and per stage against the achieved error, per method and tolerance ('-'
    for the stages a method does not have)."""
    table = pd.DataFrame(rows)[["method", "tolerance", "rel_error", "seconds_per_eval"]]
    table = pd.concat([table, stage_seconds(rows)], axis=1).assign(
        grid=[grid_text(r) for r in rows], r_cut=[r["r_cut"] for r in rows])
    return markdown_table(table, {"tolerance": ".0e", "rel_error": ".2e", "r_cut": ".2f"}
                          | {k: ".3f" for k in ["seconds_per_eval"] + EWALD_STAGES},
                          ["method", "tolerance", "rel. error", "s/eval", "real space", "near",
                           "spreading", "FFT", "gathering", "grid", "r_cut"], na_rep="-")


def xi_table(rows):
    """`benchmarks/ewald_report.py xi --capsules 27 --mesh-level L --tolerance T`: Spectral
    Ewald at its automatic xi and around it, seconds per evaluation and the error."""
    table = pd.DataFrame(rows)
    table = table.assign(
        xi=[f"{r['xi']:.2f}" + (" automatic" if r["automatic"] else "") for r in rows],
        grid=[grid_text(r) for r in rows],
        real=[r["seconds"]["real_space"] for r in rows],
        reciprocal=[r["seconds"]["reciprocal"] for r in rows])
    return markdown_table(
        table[["xi", "r_cut", "grid", "seconds_per_eval", "real", "reciprocal", "rel_error"]],
        {"r_cut": ".2f", "seconds_per_eval": ".3f", "real": ".3f", "reciprocal": ".3f",
         "rel_error": ".2e"},
        ["xi", "r_cut", "grid", "s/eval", "real space", "reciprocal", "rel. error"])


def ewald_scaling(result):
    """`benchmarks/ewald_report.py scaling --mesh-level 3`: Spectral Ewald's seconds per
    evaluation and per stage against the number of sources, and the fitted slope of
    log(seconds) against log(sources)."""
    rows = result["runs"]
    table = pd.concat([pd.DataFrame(rows)[["capsules", "sources", "nodes", "seconds_per_eval"]],
                       stage_seconds(rows)], axis=1).assign(grid=[grid_text(r) for r in rows])
    text = markdown_table(table, {k: ".3f" for k in ["seconds_per_eval"] + EWALD_STAGES},
                          ["capsules", "sources", "nodes", "s/eval", "real space", "near",
                           "spreading", "FFT", "gathering", "grid"])
    return (f"Fitted slope d log(seconds) / d log(sources) = {result['slope']:.3f}\n\n"
            + text)


def _double_single(rows, field, stages):
    """Rows of `capsim bench` in double / single `field` at each tolerance: the error
    against the tight direct reference, the seconds per evaluation and of `stages`."""
    out = []
    for tol in sorted({r["tolerance"] for r in rows}, reverse=True):
        d, s = (next(r for r in rows if r["tolerance"] == tol and r[field] == p)
                for p in ("double", "single"))

        def pair(get, f):
            return f"{get(d):{f}} / {get(s):{f}}"

        out.append({"tolerance": f"{tol:.0e}",
                    "error": pair(lambda r: r["rel_error"], ".3e"),
                    "eval": pair(lambda r: r["seconds_per_eval"], ".3f"),
                    **{k: pair(lambda r, k=k: r["seconds"][k], ".3f") for k in stages}})
    return pd.DataFrame(out)


def precision_table(rows):
    """`benchmarks/ewald_report.py precision --capsules 27 --mesh-level 3`: Spectral Ewald
    with double / single grids at each tolerance: the error against the tight direct
    reference, the seconds per evaluation and of the grid stages."""
    return markdown_table(_double_single(rows, "precision", ("spreading", "fft", "gathering")),
                          headers=["tolerance", "velocity error", "s per evaluation",
                                   "spreading", "FFT", "gathering"])


def real_space_precision_table(rows):
    """`benchmarks/ewald_report.py real-space-precision --capsules 27 --mesh-level 3`: the
    real-space sum in double / single precision (double grids) at each tolerance: the
    error against the tight direct reference, the seconds per evaluation and of the
    real-space sum."""
    return markdown_table(_double_single(rows, "real_space_precision", ("real_space",)),
                          headers=["tolerance", "velocity error", "s per evaluation",
                                   "real-space sum"])


def kernel_rate(kernel, peak):
    """`build/bench_screened_kernel` and `build/peak_flops`: the real-space kernel's flop
    rate on its own against the FMA peak, per thread count."""
    rows = [{"threads": t, "kernel": kernel["gflops"][t], "peak": peak["gflops"][t],
             "share": 100 * kernel["gflops"][t] / peak["gflops"][t]}
            for t in sorted(kernel["gflops"], key=int)]
    return markdown_table(pd.DataFrame(rows), {"kernel": ".1f", "peak": ".1f", "share": ".0f"},
                          ["threads", "kernel GFLOP/s", "peak GFLOP/s", "share of peak %"])


RENDERERS = {"step_profile": step_profile, "step_rates": step_rates,
             "near_corrections": near_corrections, "setting_compare": setting_compare,
             "build_compare": build_compare, "near_settings": near_settings,
             "ewald_accuracy": ewald_accuracy, "ewald_speed": ewald_speed,
             "xi_table": xi_table, "ewald_scaling": ewald_scaling,
             "precision_table": precision_table, "kernel_rate": kernel_rate,
             "real_space_precision_table": real_space_precision_table}


def render(kind, records):
    if kind not in RENDERERS:
        raise SystemExit(f"doc_tables: unknown table kind '{kind}' "
                         f"(known: {', '.join(RENDERERS)})")
    data = [json.loads((ROOT / r).read_text()) for r in records]
    return RENDERERS[kind](*data) + "\n"


def regenerate(text):
    """The page with every generated table rendered anew from its records."""
    return BLOCK.sub(lambda m: m.group(1) + render(m.group(2), m.group(3).split())
                     + m.group(5), text)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    mode = ap.add_mutually_exclusive_group(required=True)
    mode.add_argument("--write", action="store_true", help="rewrite the tables in place")
    mode.add_argument("--check", action="store_true", help="exit 1 if a table is stale")
    ap.add_argument("pages", nargs="+", help="Markdown pages")
    args = ap.parse_args(argv)
    stale = []
    for page in map(Path, args.pages):
        text = page.read_text()
        new = regenerate(text)
        if new != text:
            stale.append(str(page))
            if args.write:
                page.write_text(new)
    if args.check and stale:
        print("doc_tables: generated tables differ from their records in "
              f"{', '.join(stale)}: run benchmarks/doc_tables.py --write on them",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
