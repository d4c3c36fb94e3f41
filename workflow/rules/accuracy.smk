# The accuracy study (`snakemake --cores 2 accuracy`, not part of the default target):
# settings around a base run of the reduced Table 1 case and of the dilute limit, the
# error of <D>, mu_sp and N1 split into discretisation, Ewald, time step and statistics,
# against the CPU seconds per unit strain of each run (analysis/accuracy.py says how).
# Runs: results/accuracy/<run>/ (the name says every setting); their summary.json holds
# the wall and CPU seconds.
import json
import re

from analysis import accuracy as accuracy_study

ACCURACY = config["accuracy"]
ACCURACY_RUNS = accuracy_study.run_names(ACCURACY)


rule accuracy_run:
    input:
        ancient(CAPSIM),
    output:
        "results/accuracy/{name}/summary.json",
    log:
        "results/logs/accuracy/{name}.log",
    wildcard_constraints:
        name="|".join(re.escape(name) for name in ACCURACY_RUNS),
    params:
        python=PYTHON,
        dir="results/accuracy/{name}",
        options=lambda wc, threads: accuracy_study.capsim_options(
            ACCURACY_RUNS[wc.name], threads, ACCURACY["sample_interval"]),
    threads: config["resources"]["threads"]
    resources:
        runtime=lambda wc: config["resources"]["suspension_minutes"],
        mem_mb=lambda wc: config["resources"]["suspension_mem_mb"],
    # As every run (runs.smk): started, or resumed from its checkpoint; a run stopped by
    # contact is kept (its averages, if it stopped before its window, are left out). A
    # resumed run's summary.json times only its last invocation: its cost is left out.
    shell:
        "{params.python} -m pipeline.job --capsim {input} --dir {params.dir} "
        "--log {log} --stopped-ok --resume-set threads={threads} -- {params.options}"


rule accuracy_errors:
    input:
        code=analysis_module("accuracy"),
        runs=expand("results/accuracy/{name}/summary.json", name=ACCURACY_RUNS),
    output:
        "results/accuracy/errors.csv",
    log:
        "results/logs/accuracy/errors.log",
    params:
        python=PYTHON,
        plan=json.dumps(ACCURACY),
    shell:
        "{params.python} -m analysis.accuracy --plan {params.plan:q} "
        "--results results/accuracy --out {output} > {log} 2>&1"


rule speed_error_figure:
    input:
        script=figure_script("speed_error"),
        code=imported_modules(figure_script("speed_error")),
        style=os.path.join(ROOT, "figures", "matplotlibrc"),
        table="results/accuracy/errors.csv",
    output:
        png="results/figures/speed_error.png",
        pdf="results/figures/speed_error.pdf",
        csv="results/figures/speed_error.csv",
    log:
        "results/logs/figures/speed_error.log",
    params:
        python=PYTHON,
        stem="results/figures/speed_error",
    shell:
        "{params.python} {input.script} --out {params.stem} {input.table} > {log} 2>&1"


rule accuracy:
    input:
        "results/figures/speed_error.png",
