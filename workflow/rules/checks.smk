# `snakemake check`: the figure data against the expected values of the files listed in
# config["check"]["expected"] (analytic limits and reference runs, each with its
# provenance and tolerance), and, where the configuration names a folder of committed
# figure data (config["check"]["committed"]), the regenerated figure CSVs, Table 1 and the
# paper comparison's datum table against those: every datum equal within round-off and
# every verdict the same (analysis/check.py). A failure fails the rule, with one line per
# failure on the terminal and in the log.
import glob

COMMITTED = config["check"].get("committed")


rule check:
    input:
        FIGURE_OUTPUTS,
        "results/dilute/table.csv",
        "results/grid/fits.csv",
        COMPARISON_OUTPUTS[2],
        code=analysis_module("check"),
        expected=[os.path.join(ROOT, f) for f in config["check"]["expected"]],
        committed=(glob.glob(os.path.join(ROOT, COMMITTED, "*.csv")) if COMMITTED else []),
    output:
        "results/check/report.md",
    log:
        "results/logs/check.log",
    params:
        python=PYTHON,
        committed=f"--committed {os.path.join(ROOT, COMMITTED)}" if COMMITTED else "",
    shell:
        "{params.python} -m analysis.check --results results "
        "--report {output} {params.committed} {input.expected} 2>&1 | tee {log}"
