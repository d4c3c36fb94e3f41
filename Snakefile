# The reproduction workflow: `snakemake --cores 2` (or `bash scripts/reproduce.sh`).
# Thin on purpose: the configuration is read and validated here, each study lives in
# workflow/rules/<study>.smk, the shared functions in common.smk (apart from the rules, as
# `snakemake --lint` wants), the suspension run and study tables in runs.smk. Other
# configurations: --configfile config/ci.yaml (tiny, a few minutes) or config/paper.yaml
# (the paper's values). `snakemake check` compares the figure data with
# config/expected/*.yaml.
import os
import sys

from snakemake.exceptions import WorkflowError
from snakemake.utils import min_version, validate

min_version("8.0")

ROOT = workflow.basedir  # the repository; results go to the working directory


configfile: os.path.join(ROOT, "config", "config.yaml")


validate(config, os.path.join(ROOT, "workflow", "schemas", "config.schema.yaml"))

CAPSIM = config["capsim"] if os.path.isabs(config["capsim"]) else os.path.join(ROOT, config["capsim"])
# The venv's Python, where the analysis package is installed (pip install -e .).
PYTHON = sys.executable
# The results archive of this configuration (pipeline.archive), or None.
ARCHIVE = config.get("archive") and os.path.join(ROOT, config["archive"])


include: "workflow/rules/common.smk"
include: "workflow/rules/build.smk"
include: "workflow/rules/runs.smk"
include: "workflow/rules/dilute.smk"
include: "workflow/rules/grid.smk"
include: "workflow/rules/mesh.smk"
include: "workflow/rules/initial.smk"
include: "workflow/rules/boxsize.smk"
include: "workflow/rules/multipole.smk"
include: "workflow/rules/snapshots.smk"
include: "workflow/rules/reference.smk"
include: "workflow/rules/eblimit.smk"
include: "workflow/rules/viscosity_ratio.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/checks.smk"
include: "workflow/rules/accuracy.smk"
include: "workflow/rules/sensitivity.smk"

# Read only (a dry run writes nothing): what the archive restores, what it keeps and does
# not use, and how many runs are left to compute; the restores are jobs (archive.smk).
RUNS = configuration_runs()
report_before_scheduling()


include: "workflow/rules/archive.smk"


# On a cluster (profiles/slurm) only the rules that run or build capsim (and restore runs
# from the archive) are jobs: those that read finished runs into tables, figures, the
# comparison with the paper, the check and the page take seconds each and run where
# snakemake runs, instead of waiting in the queue one by one.
localrules:
    all,
    accuracy_errors,
    check,
    coefficients,
    dilute_table,
    eblimit_table,
    figure,
    grid_paper_membrane,
    paper_comparison,
    results_page,
    run_table,
    sensitivity_figure,
    sensitivity_table,
    speed_error_figure,
    table1,
    viscosity_ratio_dense_figure,
    viscosity_ratio_dense_table,
    viscosity_ratio_figure,
    viscosity_ratio_table,


rule all:
    default_target: True
    input:
        "results/dilute/table.md",
        FIGURE_OUTPUTS,
        COMPARISON_OUTPUTS,


# A failed invocation ends with the list of its failed jobs, each with its log and capsim's
# message (docs/workflow.md, "When a run fails").
onerror:
    from pipeline.job import failure_report

    report = failure_report(log)
    if report:
        print(report, file=sys.stderr)
