# `snakemake check`: the figure data against the expected values of the files listed in
# config["check"]["expected"] (each value with its provenance and tolerance). A failed
# expectation fails the rule, with one line per expectation on the terminal and in the log.
rule check:
    input:
        FIGURE_OUTPUTS,
        "results/dilute/table.csv",
        "results/grid/fits.csv",
        code=analysis_module("check"),
        expected=[os.path.join(ROOT, f) for f in config["check"]["expected"]],
    output:
        "results/check/report.md",
    log:
        "results/logs/check.log",
    params:
        python=PYTHON,
    shell:
        "{params.python} -m analysis.check --results results --report {output} "
        "{input.expected} 2>&1 | tee {log}"
