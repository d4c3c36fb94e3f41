# The accuracy study (`snakemake --cores 2 accuracy`, not part of the default target):
# settings around a base run of the reduced Table 1 case and of the dilute limit, the
# error of <D>, mu_sp and N1 split into discretisation, Ewald, time step and statistics,
# against the CPU seconds per unit strain of each run (analysis/accuracy.py says how).
# Runs: results/accuracy/<run>/ (the name says every setting), made by the generic run
# rule (runs.smk) from pipeline.run_spec.accuracy; their segments.json holds the CPU
# seconds of each segment.
import json

ACCURACY = config["accuracy"]
ACCURACY_RUNS = accuracy_study.run_names(ACCURACY)


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
        caption="results/figures/speed_error.txt",
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
