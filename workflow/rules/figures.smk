# One script per figure (figures/figNN.py) and one for Table 1 (figures/table1.py, the
# entry of analysis/table1.py). Each writes results/figures/<name>.png, .pdf, the plotted
# data as .csv and its caption as .txt; table1 writes .md and .csv. The scripts read only
# the tables and run folders named here.
GRID_WITH_FITS = ["results/grid/table.csv", "results/grid/fits.csv"]
FIGURE_INPUTS = {
    "fig01": multipole_tables,
    "fig02": lambda: study_runs("snapshots"),
    "fig03": lambda: ["results/grid/table.csv"],
    "fig04": lambda: ["results/grid/table.csv"],
    "fig05": lambda: GRID_WITH_FITS,
    "fig06": lambda: GRID_WITH_FITS,
    "fig07": lambda: GRID_WITH_FITS,
    "fig08": lambda: GRID_WITH_FITS,
    "fig09": lambda: ["results/grid/table.csv"],
    "fig10": lambda: GRID_WITH_FITS,
    "fig11": lambda: study_runs("initial"),
    "fig12": lambda: ["results/boxsize/table.csv"],
}
FIGURE_OUTPUTS = expand("results/figures/{name}.{ext}", name=FIGURE_INPUTS,
                        ext=["png", "pdf", "csv", "txt"]) + ["results/figures/table1.md",
                                                     "results/figures/table1.csv"]
FIGURE_OPTIONS = (f"--t-start {config['averages']['t_start']} "
                  f"--phi-m {config['figures']['phi_m']} "
                  f"--images {config['figures']['snapshot_images']}")


# The coefficients of section 4.2 per Ca (a1, a2, b1, b2 with their standard errors): one
# table that figures 5-8 and 10 and the paper comparison read (analysis/coefficients.py).
rule coefficients:
    input:
        table="results/grid/table.csv",
        code=analysis_module("coefficients"),
    output:
        "results/grid/fits.csv",
    log:
        "results/logs/figures/coefficients.log",
    params:
        python=PYTHON,
        phi_max=config["figures"]["fit_phi_max"],
    shell:
        "{params.python} -m analysis.coefficients --phi-max {params.phi_max} "
        "--out {output} {input.table} > {log} 2>&1"


# A script, the modules it imports, the style and the configuration files are inputs:
# editing one redraws the figures that use it.
rule figure:
    input:
        script=lambda wc: figure_script(wc.name),
        code=lambda wc: imported_modules(figure_script(wc.name)),
        style=os.path.join(ROOT, "figures", "matplotlibrc"),
        data=lambda wc: FIGURE_INPUTS[wc.name](),
        configs=CONFIG_FILES,  # the runs a figure reads directly, and its options
    output:
        png="results/figures/{name}.png",
        pdf="results/figures/{name}.pdf",
        csv="results/figures/{name}.csv",
        caption="results/figures/{name}.txt",
    log:
        "results/logs/figures/{name}.log",
    wildcard_constraints:
        name=r"fig\d\d",
    params:
        python=PYTHON,
        stem=lambda wc, output: os.path.splitext(output.csv)[0],
        options=FIGURE_OPTIONS,
    shell:
        "{params.python} {input.script} --out {params.stem} {params.options} {input.data} "
        "> {log} 2>&1"


rule table1:
    input:
        script=figure_script("table1"),
        code=imported_modules(figure_script("table1")),
        table="results/mesh/table.csv",
    output:
        md="results/figures/table1.md",
        csv="results/figures/table1.csv",
    log:
        "results/logs/figures/table1.log",
    params:
        python=PYTHON,
        stem=lambda wc, output: os.path.splitext(output.csv)[0],
    shell:
        "{params.python} {input.script} --out {params.stem} {input.table} > {log} 2>&1"


# Every checkable statement of the paper (config/paper_numbers.yaml: its numbers, its
# trends over Ca and phi, other papers' dilute values, its arithmetic) against this run's,
# with their standard errors and a verdict (analysis/paper_comparison.py): one row per
# claim (.md, .csv) and one per datum tested (_points.csv, which the check holds against
# the committed one). The column is labelled with the configuration files of this run. A
# second column from another results folder: `python -m analysis.paper_comparison ...
# --other DIR`.
COMPARISON_INPUTS = ["results/dilute/table.csv", "results/grid/table.csv",
                     "results/grid/fits.csv", "results/mesh/table.csv"] + [
    f"results/figures/{name}.csv"
    for name in ("table1", "fig01", "fig03", "fig05", "fig06", "fig08", "fig09", "fig10",
                 "fig11", "fig12")] + REFERENCE_PAGE
COMPARISON_OUTPUTS = ["results/figures/paper_comparison.md",
                      "results/figures/paper_comparison.csv",
                      "results/figures/paper_comparison_points.csv"]
# The --configfile files of this invocation (merged over config/config.yaml).
COMPARISON_LABEL = ", ".join(os.path.relpath(f, ROOT) for f in
                             (workflow.overwrite_configfiles or workflow.configfiles))


rule paper_comparison:
    input:
        COMPARISON_INPUTS,
        code=analysis_module("paper_comparison"),
        numbers=os.path.join(ROOT, "config", "paper_numbers.yaml"),
    output:
        md=COMPARISON_OUTPUTS[0],
        csv=COMPARISON_OUTPUTS[1],
        points=COMPARISON_OUTPUTS[2],
    log:
        "results/logs/figures/paper_comparison.log",
    params:
        python=PYTHON,
        stem=lambda wc, output: os.path.splitext(output.csv)[0],
        label=COMPARISON_LABEL,
    shell:
        "{params.python} -m analysis.paper_comparison --results results "
        "--numbers {input.numbers} --out {params.stem} --label '{params.label}' > {log} 2>&1"


# The results page of this configuration (docs/results.md, its figures reduced in
# docs/results/): a target of its own, outside `all`, since it writes into the
# repository's docs (pipeline/results_page.py). `snakemake results_page --configfile
# config/quantitative.yaml` publishes the quantitative reproduction.
rule results_page:
    input:
        COMPARISON_OUTPUTS,
        "results/figures/table1.md",
        expand("results/figures/{name}.{ext}", name=results_page.FIGURES,
               ext=["png", "txt"]),
        [f"results/{study}/table.csv" for study in ("grid", "mesh", "boxsize")],
        VISCOSITY_RATIO_PAGE,
        code=os.path.join(ROOT, "pipeline", "results_page.py"),
        numbers=os.path.join(ROOT, "config", "paper_numbers.yaml"),
    output:
        os.path.join(ROOT, "docs", "results.md"),
    params:
        python=PYTHON,
        label=COMPARISON_LABEL,
        archive=f"--archive {ARCHIVE}" if ARCHIVE else "",
        viscosity_ratio="--viscosity-ratio" if VISCOSITY_RATIO_PAGE else "",
    shell:
        "{params.python} -m pipeline.results_page --results results --out {output} "
        "--label '{params.label}' --numbers {input.numbers} {params.archive} "
        "{params.viscosity_ratio}"
