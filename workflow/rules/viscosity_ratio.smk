# The viscosity ratio lambda (interior over exterior viscosity; analysis/viscosity_ratio.py):
# one capsule in unbounded shear at every Ca and lambda of config["viscosity_ratio"], at
# its mesh level, to its t_end, with the dilute block's options. A run at lambda 1 with the
# dilute study's t_end is the dilute study's own run (pipeline.run_spec.viscosity_ratio),
# so it is computed once; the others are results/viscosity_ratio/ca<Ca>_level<l>_lambda<r>.
# A run that stops early (a fold: capsim's exit 3) is a result, marked in the table.
# Optional: a configuration without the block has no such runs. Run by its own target,
# `snakemake viscosity_ratio`, not by `all`; `on_page: true` (set it once its runs are in
# the archive) puts its table and figure on the results page, whose rule then needs them.
# No suspensions yet: at lambda 5 a dense run costs 33 times lambda 1's (docs/method.md).
# Output: results/viscosity_ratio/table.csv (and .md), results/figures/viscosity_ratio.png.
import json

VISCOSITY_RATIO = config.get("viscosity_ratio")
VISCOSITY_RATIO_PAGE = (["results/viscosity_ratio/table.csv",
                         "results/figures/viscosity_ratio.png"]
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


# Every run, the dilute study's at lambda 1 too: the dilute study need not list the
# block's Ca and mesh level, and run_of() finds a run only in the configuration's runs.
ON_DEMAND_RUNS["viscosity_ratio"] = lambda: [spec for _, spec in viscosity_ratio_runs()]


rule viscosity_ratio_table:
    input:
        code=analysis_module("viscosity_ratio"),
        runs=[os.path.join(spec.folder, "summary.json") for _, spec in viscosity_ratio_runs()],
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
