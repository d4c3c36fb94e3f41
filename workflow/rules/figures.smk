# One script per figure (figures/figNN.py) and one for Table 1 (figures/table1.py). Each
# writes results/figures/<name>.png, .pdf and the plotted data as .csv; table1 writes .md
# and .csv. The scripts read only the tables and run folders named here.
FIGURE_INPUTS = {
    "fig01": multipole_tables,
    "fig02": snapshot_runs,
    "fig03": lambda: ["results/grid/table.csv"],
    "fig04": lambda: ["results/grid/table.csv"],
    "fig05": lambda: ["results/grid/table.csv"],
    "fig06": lambda: ["results/grid/table.csv"],
    "fig07": lambda: ["results/grid/table.csv"],
    "fig08": lambda: ["results/grid/table.csv"],
    "fig09": lambda: ["results/grid/table.csv"],
    "fig10": lambda: ["results/grid/table.csv"],
    "fig11": initial_runs,
    "fig12": lambda: ["results/boxsize/table.csv"],
}
FIGURE_OUTPUTS = expand("results/figures/{name}.{ext}", name=FIGURE_INPUTS,
                        ext=["png", "pdf", "csv"]) + ["results/figures/table1.md",
                                                     "results/figures/table1.csv"]
FIGURE_OPTIONS = (f"--t-start {config['averages']['t_start']} "
                  f"--fit-phi-max {config['figures']['fit_phi_max']} "
                  f"--phi-m {config['figures']['phi_m']} "
                  f"--images {config['figures']['snapshot_images']}")


rule figure:
    input:
        lambda wc: FIGURE_INPUTS[wc.name](),
    output:
        png="results/figures/{name}.png",
        pdf="results/figures/{name}.pdf",
        csv="results/figures/{name}.csv",
    log:
        "results/logs/figures/{name}.log",
    wildcard_constraints:
        name=r"fig\d\d",
    params:
        options=FIGURE_OPTIONS,
    shell:
        "{PYTHON} {ROOT}/figures/{wildcards.name}.py --out results/figures/{wildcards.name} "
        "{params.options} {input} > {log} 2>&1"


rule table1:
    input:
        "results/mesh/table.csv",
    output:
        md="results/figures/table1.md",
        csv="results/figures/table1.csv",
    log:
        "results/logs/figures/table1.log",
    shell:
        "{PYTHON} {ROOT}/figures/table1.py --out results/figures/table1 {input} "
        "> {log} 2>&1"
