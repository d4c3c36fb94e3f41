# The dilute limit (phi = 0): one capsule in unbounded shear for every Ca and mesh level
# listed in config["dilute"]. Adding a value to a list runs only the new runs. Other studies
# (grid: phi = 0 of figures 3-10; multipole: figure 1) ask for dilute runs at their own Ca
# and mesh level through dilute_summary() (common.smk); they land in the same folders.
DILUTE = config["dilute"]


rule dilute_run:
    input:
        ancient(CAPSIM),
    output:
        "results/dilute/ca{ca}_level{level}/summary.json",
    log:
        "results/logs/dilute/ca{ca}_level{level}.log",
    params:
        python=PYTHON,
        dir="results/dilute/ca{ca}_level{level}",
        t_end=DILUTE["t_end"],
        t_avg_start=DILUTE["t_avg_start"],
    threads: config["resources"]["threads"]
    resources:
        runtime=config["resources"]["dilute_minutes"],
        mem_mb=config["resources"]["dilute_mem_mb"],
    # Started, or resumed from its checkpoint (a killed job, a raised t_end), by
    # analysis.capsim_job as a suspension run is (runs.smk); a numerical failure (exit 3)
    # fails the job here: the dilute table has no row for a stopped run.
    shell:
        "{params.python} -m analysis.capsim_job --capsim {input} --dir {params.dir} "
        "--log {log} --resume-set threads={threads} --resume-set t_end={params.t_end} -- "
        "--set ca={wildcards.ca} --set mesh_level={wildcards.level} "
        "--set t_end={params.t_end} --set t_avg_start={params.t_avg_start} "
        "--set threads={threads}"


rule dilute_table:
    input:
        script=figure_script("dilute_table"),
        code=imported_modules(figure_script("dilute_table")),
        summaries=expand(dilute_summary("{ca}", "{level}"), ca=DILUTE["ca"],
                         level=DILUTE["mesh_levels"]),
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
