# The sensitivity study (`snakemake --cores 2 sensitivity`, not part of the default
# target): the points where the paper's membrane folds (docs/suspensions.md, "Hard
# cases") under each membrane of config["sensitivity"], at two mesh levels, and the dilute
# limit under the same regularisers against the dilute study's runs of the paper's
# membrane; <D>, mu_sp and N1 of each against the paper's (analysis/sensitivity.py).
# Runs: results/sensitivity/<name>/ (the name says every setting, its membrane code
# last); the plan is checked when the workflow starts, so a bad membrane code is named
# before any run.
import json
import re

from analysis import sensitivity as sensitivity_study

SENSITIVITY = config["sensitivity"]
SENSITIVITY_RUNS = sensitivity_study.run_names(SENSITIVITY, config["dilute"])
SENSITIVITY_REFERENCES = [
    dilute_summary(f"{run.ca:g}", run.level)
    for run in sensitivity_study.dilute_references(SENSITIVITY, config["dilute"])
]


# As every suspension run (runs.smk): started, or resumed from its checkpoint with the
# configuration's t_end and threads, by pipeline.job. A run that folds or touches
# (capsim's exit 3) is a success with summary.json: how and when it stopped is a result
# of this study, and its data up to the stop stay. The dilute runs stop the same way
# here (the dilute study's own runs fail instead: its table has no row for a stopped run).
rule sensitivity_run:
    input:
        ancient(CAPSIM),
    output:
        "results/sensitivity/{name}/summary.json",
    log:
        "results/logs/sensitivity/{name}.log",
    wildcard_constraints:
        name="|".join(re.escape(name) for name in SENSITIVITY_RUNS),
    params:
        python=PYTHON,
        dir="results/sensitivity/{name}",
        t_end=lambda wc: f"{SENSITIVITY_RUNS[wc.name].t_end:g}",
        options=lambda wc, threads: sensitivity_study.capsim_options(
            SENSITIVITY_RUNS[wc.name], config["run_options"], threads),
    threads: config["resources"]["threads"]
    resources:
        runtime=lambda wc: config["resources"][
            "suspension_minutes" if SENSITIVITY_RUNS[wc.name].phi > 0 else "dilute_minutes"],
        mem_mb=lambda wc: config["resources"][
            "suspension_mem_mb" if SENSITIVITY_RUNS[wc.name].phi > 0 else "dilute_mem_mb"],
    shell:
        "{params.python} -m pipeline.job --capsim {input} --dir {params.dir} "
        "--log {log} --stopped-ok --resume-set threads={threads} "
        "--resume-set t_end={params.t_end} -- {params.options}"


rule sensitivity_table:
    input:
        code=analysis_module("sensitivity"),
        runs=expand("results/sensitivity/{name}/summary.json", name=SENSITIVITY_RUNS),
        references=SENSITIVITY_REFERENCES,
    output:
        csv="results/sensitivity/table.csv",
        md="results/sensitivity/table.md",
    log:
        "results/logs/sensitivity/table.log",
    params:
        python=PYTHON,
        plan=json.dumps(SENSITIVITY),
        dilute=json.dumps(config["dilute"]),
    shell:
        "{params.python} -m analysis.sensitivity --plan {params.plan:q} "
        "--dilute {params.dilute:q} --results results/sensitivity "
        "--dilute-results results/dilute --out-csv {output.csv} --out-md {output.md} "
        "> {log} 2>&1"


rule sensitivity_figure:
    input:
        script=figure_script("sensitivity"),
        code=imported_modules(figure_script("sensitivity")),
        style=os.path.join(ROOT, "figures", "matplotlibrc"),
        table="results/sensitivity/table.csv",
    output:
        png="results/figures/sensitivity.png",
        pdf="results/figures/sensitivity.pdf",
        csv="results/figures/sensitivity.csv",
    log:
        "results/logs/figures/sensitivity.log",
    params:
        python=PYTHON,
        stem=lambda wc, output: os.path.splitext(output.png)[0],
    shell:
        "{params.python} {input.script} --out {params.stem} {input.table} > {log} 2>&1"


rule sensitivity:
    input:
        "results/sensitivity/table.md",
        "results/figures/sensitivity.png",
