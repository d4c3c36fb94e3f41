# The reproduction workflow: `snakemake --cores 2` (or `bash scripts/reproduce.sh`).
# Thin on purpose: the configuration is read here, each study lives in workflow/rules/.
import sys

configfile: "config/config.yaml"

CAPSIM = "build/capsim"


include: "workflow/rules/build.smk"
include: "workflow/rules/dilute.smk"


rule all:
    input:
        "results/dilute/table.md",
