# The dilute limit (phi = 0): one capsule in unbounded shear for every Ca and mesh level
# listed in config["dilute"], made by the generic run rule (runs.smk); a numerical failure
# (exit 3) fails the job here: the dilute table has no row for a stopped run. Adding a value
# to a list runs only the new runs. Other studies (grid: phi = 0 of figures 3-10;
# multipole: figure 1) ask for dilute runs at their own Ca and mesh level through
# dilute_summary() (common.smk) and register them in DILUTE_KEYS; they land in the same
# folders.
DILUTE = config["dilute"]


DILUTE_KEYS.append(lambda: [(ca, level) for ca in DILUTE["ca"] for level in DILUTE["mesh_levels"]])


rule dilute_table:
    input:
        script=figure_script("dilute_table"),
        code=imported_modules(figure_script("dilute_table")),
        summaries=[dilute_summary(ca, level) for ca in DILUTE["ca"]
                   for level in DILUTE["mesh_levels"]],
        configs=CONFIG_FILES,
    output:
        table="results/dilute/table.md",
        csv="results/dilute/table.csv",
    log:
        "results/logs/dilute/table.log",
    params:
        python=PYTHON,
    shell:
        "{params.python} {input.script} --out-md {output.table} "
        "--out-csv {output.csv} {input.summaries} > {log} 2>&1"
