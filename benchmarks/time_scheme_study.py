"""Speed against error of the time schemes, each case run with a baseline (explicit Heun)
and a candidate (IMEX with an adaptive step) one after the other on this machine: wall
seconds per capsule per unit strain, the averages of D, mu_sp and N1 over the window
with block standard errors, and the candidate's relative difference from the baseline.

Usage: .venv/bin/python benchmarks/time_scheme_study.py [--cases dilute,table1,...]
           [--capsim PATH] [--threads 2] [--out benchmarks/records/FILE.json]
Cases (names, or a comma-separated list of them):
  dilute     one capsule, Ca 0.2, 0.4, 0.6 at mesh levels 2, 3, 4, t = 20, window
             [10, 20]: Heun at the default step against IMEX at time.tolerance 1e-3
  dilute2    the dilute table's level 2 (Ca 0.2, 0.4, 0.6) with IMEX also at the tighter
             time.tolerance 3e-4 and 1e-4 (the same folders as `dilute` for the rest)
  dilute05   one capsule, Ca 0.05, level 4: Heun at dt_safety 1 (the default step, the
             best explicit run) against IMEX at time.tolerance 1e-3, with the max and
             the rms error norm (time.error_norm)
  level4auto one capsule at level 4, Ca 0.05, 0.2, 0.6: Heun at dt_safety 1 against
             IMEX at time.tolerance auto (the workflow's setting: a time error a tenth
             of the level-4 mesh error), with the max and the rms error norm
  table1     the reduced Table 1 case (Ca 0.2, phi 0.3, level 3, M = 27, t = 20):
             Heun at dt_safety 1 with ewald.tolerance 1e-4 (the best explicit run)
             against IMEX at time.tolerance 1e-3 (max norm) and at 3e-3 and 1e-2 (rms
             norm), same Ewald tolerance
  bending    a bending point of the quantitative grid (Ca 0.3, phi 0.4, M = 27, level 3,
             eb 0.025, F0 5, the configuration's run options), from rest to t = 2,
             window [1, 2]: Heun at dt_safety 1 (the grid's run) against IMEX at
             time.tolerance auto and 1e-3, and Heun at dt_safety 0.5 as the reference
  developed  the same suspension developed: the grid's Ca 0.3 and 0.4, phi 0.4, eb 0.025
             points, each from its archived state near gammadot t = 30 (capsim run
             --branch) for 1.5 strain units, window the whole branch: Heun as the grid
             ran it (the record's own numerics) against IMEX at time.tolerance 1e-3, and
             IMEX at 1e-4 as the reference
  developed5 the same branches of IMEX at time.tolerance 1e-3 alone over 5 strain units,
             with its steps in each strain unit (how much the step count varies)
  viscosity_ratio
             the dense viscosity-ratio study's phi 0.1, lambda 5 run (Ca 0.2, M = 27,
             level 3) from its archived state (its last checkpoint, gammadot t = 24.6)
             for 0.5 strain units: the study's numerics (Heun, gmres.tolerance 1e-5)
             against GMRES at 1e-4 and 1e-3, rkc of 3 stages at time.tolerance 1e-3 (and
             with GMRES at 1e-4), and Heun with
             GMRES at 1e-8 as the reference; the lambda 0.2 run's likewise (1e-5, 1e-4
             and 1e-8); with the grid's lambda 1 run at phi 0.1 branched from its state
             for the same strain as the cost's baseline
  viscosity_step_dilute
             one capsule at level 3 to t = 20, window [10, 20]: at lambda 1 (Ca 0.2,
             0.6) Heun at 1, 1.5 and 2 times the automatic step; at lambda 5 (Ca 0.2,
             0.6) at 1, 2, 3 and 4.5 times lambda 1's, at lambda 10 (Ca 0.2) at 1, 2, 3
             and 5.5 times (dt_lambda_max, and dt_safety past (1 + lambda)/2); against
             half lambda 1's step as the reference: where Heun's stability limit lies
             and what the step costs in accuracy
  viscosity_step
             the dense study's lambda 5 runs at phi 0.1 and 0.2 (Ca 0.2, M = 27, level
             3) from their archived states for 0.5 strain units: Heun at the study's
             step (the automatic one, lambda 1's) and at 2 and 3 times it (the mesh-scale
             waves relax (1 + lambda)/2 = 3 times slower at lambda 5), against Heun at
             half the step with GMRES at 1e-8 as the reference; first the grid's
             lambda 1 run at phi 0.1 branched from its state, the cost's baseline
Every run samples every 0.25 strain units (the bending and developed cases every 0.05). Where a case has
a reference, each row also gives the largest difference of the suspension's mean D, mu_sp
and N1 from the reference's over the run (the reference interpolated to the row's sample
times by a cubic spline), relative to the reference's mean over the window, and the
relative difference of its window averages from the reference's (_rel_diff). Runs are
kept in results/benchmarks/schemes/ and reused when finished, so the study can be run in
pieces. Writes results/benchmarks/time_schemes.json and .md.
"""

import argparse
import dataclasses
import json
import math
import pathlib
import platform
import subprocess
from datetime import date

import h5py
import numpy as np
import pandas as pd
from scipy.interpolate import CubicSpline

from analysis.read_run import read_timeseries
from analysis.rheology import particle_stress
from analysis.tables import markdown_table
from pipeline import archive
from pipeline.archive import read_record
from pipeline.run_spec import RunSpec

ROOT = pathlib.Path(__file__).resolve().parent.parent
OUT = ROOT / "results" / "benchmarks"
STUDY = "benchmarks/schemes"  # run folders: results/benchmarks/schemes/<case>_<variant>
SAMPLES = {"output.sample_interval": 0.25, "output.snapshot_interval": 0}
HEUN = {"time.scheme": "heun"}
HEUN_1 = {"time.scheme": "heun", "dt_safety": 1.0}
IMEX = {"time.scheme": "imex", "time.tolerance": 1e-3}
REFERENCE = "reference"  # the variant the others' series are held against, where given
ARCHIVE = ROOT / "archive" / "quantitative"
BRANCH_STRAIN = {"developed": 1.5, "developed5": 5.0,  # strain units of the branches
                 "viscosity_ratio": 0.5, "viscosity_step": 0.5}
# An adaptive step never passes a sample time: samples every 0.25 leave rkc's step free.
RKC3 = {"time.scheme": "rkc", "time.stages": 3, "time.tolerance": 1e-3,
        "output.sample_interval": 0.25}
BRANCHES = {}  # case label: the archive record whose state its runs branch from


def lambda_step(factor):
    """The automatic step at lambda > 1 grown to at most `factor` times lambda 1's."""
    return {"dt_lambda_max": factor}


def imex_rms(tolerance):
    return {"time.scheme": "imex", "time.tolerance": tolerance, "time.error_norm": "rms"}


def dilute(level, ca):
    """One capsule to t = 20, averaged over [10, 20]."""
    return RunSpec(study=STUDY, ca=ca, level=level, t_end=20, t_avg_start=10)


def cases(name):
    """(case label, the runs' common RunSpec, [(variant label, settings)])."""
    if name == "dilute":
        for level in (2, 3, 4):
            for ca in (0.2, 0.4, 0.6):
                yield (f"dilute_L{level}_Ca{ca}", dilute(level, ca),
                       [("heun", HEUN), ("imex", IMEX)])
    elif name == "dilute2":
        for ca in (0.2, 0.4, 0.6):
            yield (f"dilute_L2_Ca{ca}", dilute(2, ca),
                   [("heun", HEUN), ("imex", IMEX),
                    ("imex_3e-4", {**IMEX, "time.tolerance": 3e-4}),
                    ("imex_1e-4", {**IMEX, "time.tolerance": 1e-4})])
    elif name == "dilute05":
        yield ("dilute_L4_Ca0.05", dilute(4, 0.05),
               [("heun_1", HEUN_1), ("imex", IMEX), ("imex_rms", imex_rms(1e-3))])
    elif name == "level4auto":
        for ca in (0.05, 0.2, 0.6):
            yield (f"dilute_L4_Ca{ca}", dilute(4, ca),
                   [("heun_1", HEUN_1), ("imex_auto", {**IMEX, "time.tolerance": "auto"}),
                    ("imex_rms_auto", imex_rms("auto"))])
    elif name == "bending":
        grid = {"ewald.tolerance": "auto", "ewald.precision": "double",
                "ewald.real_space_precision": "double", "quadrature.near_ratio": 1.5,
                "quadrature.far_ratio": 2, "output.sample_interval": 0.05}
        common = RunSpec(study=STUDY, ca=0.3, level=3, t_end=2, t_avg_start=1, phi=0.4,
                         M=27, seed=1, membrane="eb0.025+rep5",
                         options=tuple(sorted(grid.items())))
        yield ("bending", common, [("heun_1", HEUN_1),
                                   ("imex_auto", {**IMEX, "time.tolerance": "auto"}),
                                   ("imex", IMEX),
                                   (REFERENCE, {**HEUN, "dt_safety": 0.5})])
    elif name == "viscosity_ratio":
        run = "ca0.2_phi0.1_M27_level3_seed1"
        yield branch_case(name, "lambda1", ARCHIVE / "grid" / run, 0.2, 0.1,
                          [("heun_1", {})])
        yield branch_case(name, "lambda5", ARCHIVE / "viscosity_ratio" / f"{run}_lambda5",
                          0.2, 0.1,
                          [("heun_1", {}), ("gmres_1e-4", {"gmres.tolerance": 1e-4}),
                           ("gmres_1e-3", {"gmres.tolerance": 1e-3}),
                           ("rkc3", RKC3), ("rkc3_gmres_1e-4", {**RKC3,
                                                              "gmres.tolerance": 1e-4}),
                           (REFERENCE, {"gmres.tolerance": 1e-8})])
        yield branch_case(name, "lambda0.2",
                          ARCHIVE / "viscosity_ratio" / f"{run}_lambda0.2", 0.2, 0.1,
                          [("heun_1", {}), ("gmres_1e-4", {"gmres.tolerance": 1e-4}),
                           (REFERENCE, {"gmres.tolerance": 1e-8})])
    elif name == "viscosity_step_dilute":
        # Heun's stability limit and time error against the step at lambda 1, 5 and 10;
        # the step as a multiple of lambda 1's automatic one through dt_lambda_max (and
        # dt_safety beyond (1 + lambda)/2).
        steps = {"1": [("step_1", {}), ("step_1.5", {"dt_safety": 1.5}),
                       ("step_2", {"dt_safety": 2})],
                 "5": [("step_1", lambda_step(1)), ("step_2", lambda_step(2)),
                       ("step_3", lambda_step(3)),
                       ("step_4.5", {**lambda_step(3), "dt_safety": 1.5})],
                 "10": [("step_1", lambda_step(1)), ("step_2", lambda_step(2)),
                        ("step_3", lambda_step(3)), ("step_5.5", lambda_step(5.5))]}
        for ratio, ca in (("1", 0.2), ("1", 0.6), ("5", 0.2), ("5", 0.6), ("10", 0.2)):
            common = dataclasses.replace(dilute(3, ca), options=(("lambda", ratio),))
            yield (f"dilute_lambda{ratio}_Ca{ca}", common,
                   steps[ratio] + [(REFERENCE, {**lambda_step(1), "dt_safety": 0.5})])
    elif name == "viscosity_step":
        # The cost's baseline: the grid's lambda 1 run at phi 0.1 (the one that keeps a
        # state) branched from it.
        yield branch_case(name, "phi0.1_lambda1", ARCHIVE / "grid" /
                          "ca0.2_phi0.1_M27_level3_seed1", 0.2, 0.1, [("heun_1", {})])
        for phi in (0.1, 0.2):
            run = f"ca0.2_phi{phi}_M27_level3_seed1"
            record = ARCHIVE / "viscosity_ratio" / f"{run}_lambda5"
            # The record's step: the automatic one, lambda 1's at lambda >= 1.
            dt = json.loads((record / "summary.json").read_text())["dt"]
            yield branch_case(name, f"phi{phi}", record, 0.2, phi,
                              [("heun_1", {}), ("dt_2", {"dt": 2 * dt}),
                               ("dt_3", {"dt": 3 * dt}),
                               (REFERENCE, {"dt": dt / 2, "gmres.tolerance": 1e-8})])
    elif name in BRANCH_STRAIN:
        for ca in (0.3, 0.4):
            record = ARCHIVE / "grid" / f"ca{ca}_phi0.4_M27_level3_seed1_eb0.025+rep5"
            yield branch_case(name, f"Ca{ca}", record, ca, 0.4,
                              [("imex", IMEX)] if name == "developed5" else
                              [("heun_1", {}), ("imex", IMEX),
                               (REFERENCE, {**IMEX, "time.tolerance": 1e-4})],
                              membrane="eb0.025+rep5")
    elif name == "table1":
        common = RunSpec(study=STUDY, ca=0.2, level=3, t_end=20, t_avg_start=10, phi=0.3,
                         M=27, seed=1, options=(("ewald.tolerance", 1e-4),))
        yield ("table1", common, [("heun_1", HEUN_1), ("imex", IMEX),
                                  ("imex_rms_3e-3", imex_rms(3e-3)),
                                  ("imex_rms_1e-2", imex_rms(1e-2))])
    else:
        raise SystemExit(f"unknown case '{name}'")


def branch_case(name, tag, record, ca, phi, variants, **spec):
    """A case of branches from an archive record's state of the dense suspension (M = 27,
    level 3) for BRANCH_STRAIN[name], window the whole branch."""
    t0 = read_record(record)["state_time"]
    common = RunSpec(study=STUDY, ca=ca, level=3, t_end=round(t0 + BRANCH_STRAIN[name], 6),
                     t_avg_start=t0, phi=phi, M=27, seed=1, **spec)
    BRANCHES[f"{name}_{tag}"] = record
    return f"{name}_{tag}", common, variants


def variant_spec(common, label, variant, settings):
    """The RunSpec of one variant of a case, in the folder <case label>_<variant>."""
    options = {**SAMPLES, **dict(common.options), **settings}
    return dataclasses.replace(common, options=tuple(sorted(options.items())),
                               label=f"{label}_{variant}")


def source_folder(record):
    """The run folder of an archive record's state (restored once, then only read)."""
    folder = ROOT / "results" / STUDY / f"source_{record.name}"
    if not (folder / "checkpoint.h5").exists():
        archive.restore(record, folder, read_record(record), full=False)
    return folder


def branch_command(spec, settings, source, a):
    """`capsim run --branch`: the source's state, model and numerics, with `settings`."""
    sets = {**SAMPLES, "output.sample_interval": 0.05, **settings, "t_end": spec.t_end,
            "t_avg_start": spec.t_avg_start, "threads": a.threads}
    return [str(a.capsim), "run", "-q", "--branch", str(source), "-o",
            str(ROOT / spec.folder)] + [f"--set={k}={v}" for k, v in sets.items()]


def run(spec, a, settings=None, record=None):
    """Runs capsim once into the spec's folder unless a finished run is there (a branch
    from the archive record's state where one is given); returns the folder."""
    folder = ROOT / spec.folder
    if (folder / "summary.json").exists():
        return folder
    if record is None:
        cmd, _ = spec.command(a.capsim, a.threads, root=ROOT)
    else:
        cmd = branch_command(spec, settings, source_folder(record), a)
    print(" ".join(cmd[1:]), flush=True)
    subprocess.run(cmd, check=False)  # an early stop still leaves a summary
    return folder


def block_mean(values, blocks=5):
    """Mean and the standard error of `blocks` block means (None with fewer samples)."""
    if len(values) < blocks:
        return float(values.mean()), None
    parts = np.array_split(values, blocks)
    means = np.array([p.mean() for p in parts])
    return float(values.mean()), float(means.std(ddof=1) / math.sqrt(blocks))


def mean_series(ts, spec):
    """The suspension's mean D, mu_sp and N1 at each sample."""
    stress = particle_stress(ts["stresslet"].mean(axis=1), spec.phi, spec.ca)
    return {"D": ts["D"].mean(axis=1), "mu_sp": stress[:, 0, 1],
            "N1": stress[:, 0, 0] - stress[:, 1, 1]}


def series_error(folder, reference, spec):
    """The largest difference of the mean D, mu_sp and N1 from the reference's over the
    samples both runs cover, relative to the reference's window mean."""
    ts, ref = read_timeseries(folder), read_timeseries(reference)
    got, want = mean_series(ts, spec), mean_series(ref, spec)
    inside = ts["time"] <= ref["time"][-1]
    window = (ref["time"] >= spec.t_avg_start) & (ref["time"] <= spec.t_end)
    out = {}
    for key in got:
        at = CubicSpline(ref["time"], want[key])(ts["time"][inside])
        scale = abs(want[key][window].mean())
        out[f"{key}_error"] = float(np.abs(got[key][inside] - at).max() / scale)
    return out


def measure(folder, spec, record=None):
    """A run's steps, time and window averages; a branch's steps, rejections and strain
    are its own (counted from the source's checkpoint at t_avg_start)."""
    s = json.loads((folder / "summary.json").read_text())
    ts = read_timeseries(folder)
    inside = (ts["time"] >= spec.t_avg_start) & (ts["time"] <= spec.t_end)
    steps, rejected, t0 = s["steps"], s.get("rejected_steps"), 0.0
    if record is not None:
        with h5py.File(source_folder(record) / "checkpoint.h5", "r") as c:
            steps -= int(c["step"][()])
            rejected -= int(c["rejected_steps"][()])
            t0 = float(c["time"][()])
    row = {"ended": s["ended"], "steps": steps, "rejected": rejected,
           "mean_dt": (ts["time"][-1] - t0) / steps, "wall_s": s["wall_seconds"],
           "s_per_capsule_strain": s["wall_seconds"]
           / (s["parameters"]["capsules"] * (spec.t_end - t0))}
    if "gmres_iterations_mean" in s:  # lambda != 1: the second-kind solves' iterations
        row["gmres_iterations"] = s["gmres_iterations_mean"]
    if record is not None:  # the steps of each whole strain unit of the branch
        units = np.arange(t0, ts["time"][-1] + 1e-5, 1.0)  # t_end is rounded to 1e-6
        at = np.interp(units, ts["time"], ts["step"])
        row["steps_per_strain_unit"] = [int(round(b - a)) for a, b in zip(at, at[1:])]
    for name, series in mean_series(ts, spec).items():
        row[name], row[name + "_se"] = block_mean(series[inside])
    return row


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cases", default="dilute,dilute05,table1")
    p.add_argument("--capsim", type=pathlib.Path, default=ROOT / "build" / "capsim")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--out", type=pathlib.Path,
                   help="also write the rows as a record (date, machine, command) here")
    a = p.parse_args()
    (ROOT / "results" / STUDY).mkdir(parents=True, exist_ok=True)
    rows = []
    for name in a.cases.split(","):
        for label, common, variants in cases(name):
            baseline, case_rows = None, []
            for variant, settings in variants:
                spec = variant_spec(common, label, variant, settings)
                folder = run(spec, a, settings, BRANCHES.get(label))
                row = {"case": label, "variant": variant,
                       **measure(folder, spec, BRANCHES.get(label))}
                if baseline is None:
                    baseline = row
                else:
                    row["speedup"] = baseline["wall_s"] / row["wall_s"]
                case_rows.append((row, folder, spec))
            reference = [(row, f) for row, f, _ in case_rows
                         if row["variant"] == REFERENCE]
            for row, folder, spec in case_rows:
                if reference and row["variant"] != REFERENCE:
                    ref_row, ref_folder = reference[0]
                    row.update(series_error(folder, ref_folder, spec))
                    for key in ("D", "mu_sp", "N1"):  # the window averages' difference
                        row[f"{key}_rel_diff"] = row[key] / ref_row[key] - 1
                elif not reference and row is not baseline:
                    # Without a reference, the window averages against the baseline's
                    # (runs sampled at other times differ by more than their error
                    # where the averages still drift: the bending case from rest).
                    for key in ("D", "mu_sp", "N1"):
                        row[f"{key}_rel_diff"] = row[key] / baseline[key] - 1
                rows.append(row)
                print(json.dumps(row), flush=True)
    (OUT / "time_schemes.json").write_text(json.dumps(rows, indent=1))
    table = pd.DataFrame(rows)
    if "steps_per_strain_unit" in table:  # a list a branch's row: its counts in one cell
        table["steps_per_strain_unit"] = table["steps_per_strain_unit"].map(
            lambda counts: " ".join(map(str, counts)) if isinstance(counts, list) else "")
    (OUT / "time_schemes.md").write_text(markdown_table(table, na_rep=""))
    print(f"wrote {OUT / 'time_schemes.json'}")
    if a.out:
        record = {"benchmark": "time_scheme_study", "date": date.today().isoformat(),
                  "machine": f"{platform.machine()}, {a.threads} threads",
                  "command": "python3 benchmarks/time_scheme_study.py --cases "
                             f"{a.cases} --threads {a.threads}",
                  "rows": rows}
        a.out.write_text(json.dumps(record, indent=1) + "\n")
        print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
