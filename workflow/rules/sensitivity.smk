# The sensitivity study (`snakemake --cores 2 sensitivity`, not part of the default
# target): the points where the paper's membrane folds (docs/suspensions.md, "Hard
# cases") under each membrane of config["sensitivity"], at two mesh levels, and the dilute
# limit under the same regularisers against the dilute study's runs of the paper's
# membrane; <D>, mu_sp and N1 of each against the paper's (analysis/sensitivity.py).
# Runs: results/sensitivity/<name>/ (the name says every setting, its membrane code
# last), made by the generic run rule (runs.smk) from pipeline.run_spec.sensitivity; a
# run that folds or touches (capsim's exit 3) is a success with summary.json, since how
# and when it stopped is a result of this study. The plan is checked when the workflow
# starts, so a bad membrane code is named before any run.
import json

SENSITIVITY = config["sensitivity"]
SENSITIVITY_RUNS = sensitivity_study.run_names(SENSITIVITY, config["dilute"])
# The dilute study's runs that the study's dilute runs are compared with, in the order of
# analysis.sensitivity.dilute_references (the folders go to it as they are: --references).
SENSITIVITY_REFERENCES = [
    dilute_spec(run.ca, run.level).folder
    for run in sensitivity_study.dilute_references(SENSITIVITY, config["dilute"])
]


rule sensitivity_table:
    input:
        code=analysis_module("sensitivity"),
        runs=expand("results/sensitivity/{name}/summary.json", name=SENSITIVITY_RUNS),
        references=[os.path.join(f, "summary.json") for f in SENSITIVITY_REFERENCES],
    output:
        csv="results/sensitivity/table.csv",
        md="results/sensitivity/table.md",
    log:
        "results/logs/sensitivity/table.log",
    params:
        python=PYTHON,
        plan=json.dumps(SENSITIVITY),
        dilute=json.dumps(config["dilute"]),
        references=json.dumps(SENSITIVITY_REFERENCES),
    shell:
        "{params.python} -m analysis.sensitivity --plan {params.plan:q} "
        "--dilute {params.dilute:q} --results results/sensitivity "
        "--references {params.references:q} --out-csv {output.csv} --out-md {output.md} "
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
        caption="results/figures/sensitivity.txt",
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
