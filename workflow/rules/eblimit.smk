# The paper's membrane where it folds, as the limit eb -> 0 (analysis/bending_limit.py):
# every grid point that carries bending (grid.membranes) is run again at the moduli of
# config["eblimit"] (its other tokens kept), and one capsule in unbounded shear at each of
# their Ca and moduli measures the extrapolation's error against the dilute study's run
# without bending. Optional: a configuration without the block has no such runs. Run by
# its own target, `snakemake eblimit`, not by `all`, until its runs are in the archive.
# Output: results/eblimit/table.csv (and .md), each point's averages at eb -> 0.
import dataclasses
import json

from analysis import bending_limit

EBLIMIT = config.get("eblimit")
# The grid block with the limit's own longer runs (eblimit.t_end_at) in its t_end_at.
EBLIMIT_GRID = run_spec.eblimit_grid_block(GRID, EBLIMIT) if EBLIMIT else GRID


def eblimit_runs():
    """(entry, RunSpec) of every run the study reads: entry {"case", "ca", "phi", "eb",
    "folder"} as analysis.bending_limit.table() takes it. The grid's own runs and the
    dilute study's are theirs."""
    if not EBLIMIT:
        return []
    level, out = GRID["mesh_level"], []
    for point in bending_limit.points(GRID):
        for eb in bending_limit.point_moduli(EBLIMIT, point, GRID) + [point.eb]:
            keys = dict(ca=point.ca, phi=point.phi, M=GRID["capsules"], level=level,
                        seed=GRID["seeds"][0], membrane=point.at(eb))
            spec = run_owner("grid", **keys) if eb == point.eb else run_spec.suspension(
                "eblimit", keys, EBLIMIT_GRID, config["averages"]["t_start"],
                config["run_options"])
            out.append(({"case": "suspension", "ca": point.ca, "phi": point.phi, "eb": eb,
                         "folder": spec.folder}, spec))
    for ca, eb in bending_limit.dilute_cases(EBLIMIT, GRID):
        spec = dataclasses.replace(dilute_spec(ca, level), study="eblimit",
                                   membrane=f"eb{eb:g}")
        out.append(({"case": "dilute", "ca": ca, "phi": 0.0, "eb": eb,
                     "folder": spec.folder}, spec))
    for ca in sorted({point.ca for point in bending_limit.points(GRID)} if EBLIMIT else []):
        spec = dilute_spec(ca, level)
        out.append(({"case": "reference", "ca": ca, "phi": 0.0, "eb": 0.0,
                     "folder": spec.folder}, spec))
    return out


IN_GRID = bool(EBLIMIT and EBLIMIT.get("in_grid"))
(MAIN_STUDY_RUNS if IN_GRID else ON_DEMAND_RUNS)["eblimit"] = lambda: [
    spec for _, spec in eblimit_runs() if spec.study == "eblimit"]


rule eblimit_table:
    input:
        code=analysis_module("bending_limit"),
        runs=[os.path.join(spec.folder, "summary.json") for _, spec in eblimit_runs()],
        configs=CONFIG_FILES,
    output:
        csv="results/eblimit/table.csv",
        md="results/eblimit/table.md",
    log:
        "results/logs/eblimit/table.log",
    params:
        python=PYTHON,
        grid=json.dumps(GRID),
        runs=json.dumps([entry for entry, _ in eblimit_runs()]),
        t_start=config["averages"]["t_start"],
        dilute_t_start=config["dilute"]["t_avg_start"],
    shell:
        "{params.python} -m analysis.bending_limit table --grid {params.grid:q} "
        "--runs {params.runs:q} --t-start {params.t_start} "
        "--dilute-t-start {params.dilute_t_start} --out-csv {output.csv} "
        "--out-md {output.md} > {log} 2>&1"


# eblimit.in_grid: the grid table (results/grid/table.csv) carries each point's limit in
# place of its run with bending (analysis.bending_limit.paper_membrane), the runs' own
# table is results/grid/runs.csv; set it once every run of the study is in the archive.
if IN_GRID:

    rule grid_paper_membrane:
        input:
            code=analysis_module("bending_limit"),
            runs="results/grid/runs.csv",
            limits="results/eblimit/table.csv",
        output:
            "results/grid/table.csv",
        log:
            "results/logs/grid/paper_membrane.log",
        params:
            python=PYTHON,
        shell:
            "{params.python} -m analysis.bending_limit grid --runs-table {input.runs} "
            "--limits {input.limits} --out {output} > {log} 2>&1"

    ruleorder: grid_paper_membrane > run_table


rule eblimit:
    input:
        "results/eblimit/table.md" if EBLIMIT else [],
