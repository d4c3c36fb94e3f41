# The viscosity ratio lambda (interior over exterior viscosity; analysis/viscosity_ratio.py):
# one capsule in unbounded shear at every Ca and lambda of config["viscosity_ratio"], at
# its mesh level, to its t_end, with the dilute block's options. A run at lambda 1 with the
# dilute study's t_end is the dilute study's own run (pipeline.run_spec.viscosity_ratio),
# so it is computed once; the others are results/viscosity_ratio/ca<Ca>_level<l>_lambda<r>.
# A run that stops early (a fold: capsim's exit 3) is a result, marked in the table.
# Optional: a configuration without the block has no such runs. Run by its own target,
# `snakemake viscosity_ratio`, not by `all`; `on_page: true` (set it once its runs are in
# the archive) puts its table and figure on the results page, whose rule then needs them.
# Output: results/viscosity_ratio/table.csv (and .md), results/figures/viscosity_ratio.png.
#
# Its dense part (viscosity_ratio.dense: ca, phi, lambda, options), by its own target
# `snakemake viscosity_ratio_dense`: the grid's suspension (its M, mesh level, t_end, seed,
# membrane and run options; not a point's longer grid.t_end_at) at the block's Ca and phi
# with interior viscosity lambda and the block's further options,
# results/viscosity_ratio/ca<Ca>_phi<phi>_..._lambda<r>; lambda 1 is the grid's own run. A
# dense run at lambda 5 costs about 27 times lambda 1's (docs/method.md), so they are long:
# segments of about an hour (run_segment), each archived. With its own on_page
# (dense.on_page, set once its runs are archived), the results page shows its table and
# figure too.
# Output: results/viscosity_ratio/dense.csv (and .md), results/figures/viscosity_ratio_dense.png.
import json

VISCOSITY_RATIO = config.get("viscosity_ratio")
VISCOSITY_RATIO_DENSE = (VISCOSITY_RATIO or {}).get("dense")
VISCOSITY_RATIO_PAGE = (["results/viscosity_ratio/table.csv",
                         "results/figures/viscosity_ratio.png"]
                        + (["results/viscosity_ratio/dense.csv",
                            "results/figures/viscosity_ratio_dense.png"]
                           if VISCOSITY_RATIO_DENSE and VISCOSITY_RATIO_DENSE.get("on_page")
                           else [])
                        if VISCOSITY_RATIO and VISCOSITY_RATIO.get("on_page") else [])


def viscosity_ratio_runs():
    """(entry, RunSpec) of every run the study reads: entry {"ca", "lambda", "folder"}
    as analysis.viscosity_ratio takes it, by Ca then lambda."""
    if not VISCOSITY_RATIO:
        return []
    out = []
    for ca in VISCOSITY_RATIO["ca"]:
        for ratio in VISCOSITY_RATIO["lambda"]:
            spec = run_spec.viscosity_ratio(ca, ratio, VISCOSITY_RATIO, config["dilute"])
            out.append(({"ca": ca, "lambda": ratio, "folder": spec.folder}, spec))
    return out


def viscosity_ratio_dense_runs():
    """(entry, RunSpec) of every run of the dense part: entry {"ca", "phi", "lambda",
    "folder"}, by phi then lambda; at lambda 1 the grid's own run."""
    if not VISCOSITY_RATIO_DENSE:
        return []
    block, out = VISCOSITY_RATIO_DENSE, []
    ca = block["ca"]
    for phi in block["phi"]:
        keys = dict(ca=ca, phi=phi, M=GRID["capsules"], level=GRID["mesh_level"],
                    seed=GRID["seeds"][0],
                    membrane=GRID_MEMBRANES.get((float(ca), float(phi)), membrane_codes.PAPER))
        for ratio in block["lambda"]:
            spec = run_owner("grid", **keys) if float(ratio) == 1.0 else \
                run_spec.viscosity_ratio_dense(
                    keys, ratio, GRID, config["averages"]["t_start"],
                    config["run_options"], block.get("options"))
            out.append(({"ca": ca, "phi": phi, "lambda": ratio, "folder": spec.folder},
                        spec))
    return out


# Every run, the dilute study's at lambda 1 too: the dilute study need not list the
# block's Ca and mesh level, and run_of() finds a run only in the configuration's runs.
ON_DEMAND_RUNS["viscosity_ratio"] = lambda: [spec for _, spec in viscosity_ratio_runs()]
ON_DEMAND_RUNS["viscosity_ratio_dense"] = lambda: [
    spec for _, spec in viscosity_ratio_dense_runs() if spec.study == "viscosity_ratio"]


rule viscosity_ratio_dense_table:
    input:
        code=analysis_module("viscosity_ratio"),
        runs=[os.path.join(spec.folder, "summary.json")
              for _, spec in viscosity_ratio_dense_runs()],
        configs=CONFIG_FILES,
    output:
        csv="results/viscosity_ratio/dense.csv",
        md="results/viscosity_ratio/dense.md",
    log:
        "results/logs/viscosity_ratio/dense.log",
    params:
        python=PYTHON,
        runs=json.dumps([entry for entry, _ in viscosity_ratio_dense_runs()]),
        t_start=config["averages"]["t_start"],
    shell:
        "{params.python} -m analysis.viscosity_ratio --dense --runs {params.runs:q} "
        "--t-start {params.t_start} --out-csv {output.csv} --out-md {output.md} "
        "> {log} 2>&1"


rule viscosity_ratio_dense_figure:
    input:
        script=figure_script("viscosity_ratio_dense"),
        code=imported_modules(figure_script("viscosity_ratio_dense")),
        style=os.path.join(ROOT, "figures", "matplotlibrc"),
        table="results/viscosity_ratio/dense.csv",
    output:
        png="results/figures/viscosity_ratio_dense.png",
        pdf="results/figures/viscosity_ratio_dense.pdf",
        csv="results/figures/viscosity_ratio_dense.csv",
        caption="results/figures/viscosity_ratio_dense.txt",
    log:
        "results/logs/figures/viscosity_ratio_dense.log",
    params:
        python=PYTHON,
        stem=lambda wc, output: os.path.splitext(output.png)[0],
    shell:
        "{params.python} {input.script} --out {params.stem} {input.table} > {log} 2>&1"


rule viscosity_ratio_dense:
    input:
        ["results/viscosity_ratio/dense.md", "results/figures/viscosity_ratio_dense.png"]
        if VISCOSITY_RATIO_DENSE else [],


rule viscosity_ratio_table:
    input:
        code=analysis_module("viscosity_ratio"),
        runs=[os.path.join(spec.folder, "summary.json") for _, spec in viscosity_ratio_runs()],
        configs=CONFIG_FILES,
    output:
        csv="results/viscosity_ratio/table.csv",
        md="results/viscosity_ratio/table.md",
    log:
        "results/logs/viscosity_ratio/table.log",
    params:
        python=PYTHON,
        runs=json.dumps([entry for entry, _ in viscosity_ratio_runs()]),
        t_start=VISCOSITY_RATIO["t_avg_start"] if VISCOSITY_RATIO else 0,
    shell:
        "{params.python} -m analysis.viscosity_ratio --runs {params.runs:q} "
        "--t-start {params.t_start} --out-csv {output.csv} --out-md {output.md} "
        "> {log} 2>&1"


rule viscosity_ratio_figure:
    input:
        script=figure_script("viscosity_ratio"),
        code=imported_modules(figure_script("viscosity_ratio")),
        style=os.path.join(ROOT, "figures", "matplotlibrc"),
        table="results/viscosity_ratio/table.csv",
    output:
        png="results/figures/viscosity_ratio.png",
        pdf="results/figures/viscosity_ratio.pdf",
        csv="results/figures/viscosity_ratio.csv",
        caption="results/figures/viscosity_ratio.txt",
    log:
        "results/logs/figures/viscosity_ratio.log",
    params:
        python=PYTHON,
        stem=lambda wc, output: os.path.splitext(output.png)[0],
    shell:
        "{params.python} {input.script} --out {params.stem} {input.table} > {log} 2>&1"


rule viscosity_ratio:
    input:
        ["results/viscosity_ratio/table.md", "results/figures/viscosity_ratio.png"]
        if VISCOSITY_RATIO else [],
