# The dilute limit (phi = 0): one capsule in unbounded shear for every Ca and mesh level
# listed in config["dilute"]. Adding a value to a list runs only the new runs.
DILUTE = config["dilute"]


def dilute_dir(wildcards):
    return f"results/dilute/ca{wildcards.ca}_level{wildcards.level}"


# The solver is an input only to be built first: ancient() keeps a rebuilt binary from
# re-running finished runs (a physics change means a new results folder, not a rerun).
rule dilute_run:
    input:
        ancient(CAPSIM),
    output:
        "results/dilute/ca{ca}_level{level}/summary.json",
    log:
        "results/logs/dilute/ca{ca}_level{level}.log",
    params:
        dir=dilute_dir,
        t_end=DILUTE["t_end"],
        t_avg_start=DILUTE["t_avg_start"],
    threads: 2
    # A run that was stopped (killed job, cluster time limit) resumes from its checkpoint.
    shell:
        """
        if [ -f {params.dir}/checkpoint.h5 ]; then
          {input} run --resume {params.dir} --set threads={threads} 2> {log}
        else
          {input} run --set ca={wildcards.ca} --set mesh_level={wildcards.level} \
            --set t_end={params.t_end} --set t_avg_start={params.t_avg_start} \
            --set threads={threads} -o {params.dir} 2> {log}
        fi
        """


rule dilute_table:
    input:
        expand(
            "results/dilute/ca{ca}_level{level}/summary.json",
            ca=DILUTE["ca"],
            level=DILUTE["mesh_levels"],
        ),
    output:
        table="results/dilute/table.md",
        csv="results/dilute/table.csv",
    log:
        "results/logs/dilute/table.log",
    params:
        python=sys.executable,
    shell:
        "{params.python} figures/dilute_table.py --out-md {output.table} --out-csv {output.csv} "
        "{input} > {log} 2>&1"
