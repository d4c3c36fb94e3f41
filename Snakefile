# The reproduction workflow: `snakemake --cores 2` (or `bash scripts/reproduce.sh`).
# Thin on purpose: the configuration is read and validated here, each study lives in
# workflow/rules/<study>.smk, the shared functions in common.smk (apart from the rules, as
# `snakemake --lint` wants), the suspension run and study tables in runs.smk. Other
# configurations: --configfile config/ci.yaml (tiny, a few minutes) or config/paper.yaml
# (the paper's values). `snakemake check` compares the figure data with
# config/expected/*.yaml.
import os
import sys

from snakemake.utils import min_version, validate

min_version("8.0")

ROOT = workflow.basedir  # the repository; results go to the working directory


configfile: os.path.join(ROOT, "config", "config.yaml")


validate(config, os.path.join(ROOT, "workflow", "schemas", "config.schema.yaml"))

CAPSIM = config["capsim"] if os.path.isabs(config["capsim"]) else os.path.join(ROOT, config["capsim"])
# The venv's Python, where the analysis package is installed (pip install -e .).
PYTHON = sys.executable


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
include: "workflow/rules/figures.smk"
include: "workflow/rules/checks.smk"
include: "workflow/rules/accuracy.smk"
include: "workflow/rules/sensitivity.smk"


rule all:
    default_target: True
    input:
        "results/dilute/table.md",
        FIGURE_OUTPUTS,
        COMPARISON_OUTPUTS,


# A failed invocation ends with the list of its failed jobs, each with its log and capsim's
# message (docs/workflow.md, "When a run fails").
onerror:
    from analysis.capsim_job import failure_report

    report = failure_report(log)
    if report:
        print(report, file=sys.stderr)
