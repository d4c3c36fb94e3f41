# One capsim suspension run, shared by every study that needs one (grid, mesh, initial,
# boxsize, snapshots), and the table of averages of a study's runs. The study's block of
# the configuration gives t_end and the snapshot interval. Keys in config["run_options"]
# (e.g. method, ewald.tolerance) go to every suspension run.


# The solver is an input only to be built first: ancient() keeps a rebuilt binary from
# re-running finished runs (a physics change means a new results folder, not a rerun).
# A stopped run (killed job, cluster time limit) resumes from its checkpoint; on resume
# only t_end, t_avg_start, threads and output.* may change (capsim refuses the rest).
rule suspension_run:
    input:
        ancient(CAPSIM),
    output:
        os.path.join("results", "{study}", RUN_NAME, "summary.json"),
    log:
        os.path.join("results", "logs", "{study}", f"{RUN_NAME}.log"),
    params:
        # From the wildcards as before: a changed parameter would redo every finished run.
        dir=lambda wc: os.path.join("results", wc.study, RUN_NAME.format(**wc)),
        t_end=lambda wc: config[wc.study]["t_end"],
        t_avg_start=lambda wc: min(config["averages"]["t_start"], 0.5 * config[wc.study]["t_end"]),
        snapshots=lambda wc: config[wc.study]["snapshot_interval"],
        options=run_option_sets(),
    threads: config["resources"]["threads"]
    resources:
        runtime=lambda wc: config["resources"]["suspension_minutes"],
        mem_mb=lambda wc: config["resources"]["suspension_mem_mb"],
    shell:
        """
        rc=0
        if [ -f {params.dir}/checkpoint.h5 ]; then
          {input} run -q --resume {params.dir} --set threads={threads} \
            --set t_end={params.t_end} > {log} 2>&1 || rc=$?
        else
          {input} run -q --set ca={wildcards.ca} --set phi={wildcards.phi} \
            --set capsules={wildcards.M} --set mesh_level={wildcards.level} \
            --set seed={wildcards.seed} --set t_end={params.t_end} \
            --set t_avg_start={params.t_avg_start} \
            --set output.snapshot_interval={params.snapshots} {params.options} \
            --set threads={threads} -o {params.dir} > {log} 2>&1 || rc=$?
        fi
        # Exit 3: the run stopped early (contact, numerical failure) and summary.json says
        # how ("ended"); its data up to the stop stay in the study and the figures name it.
        if [ "$rc" -eq 3 ] && [ -f {output} ]; then echo "stopped early: see {log}" >&2
        elif [ "$rc" -ne 0 ]; then exit "$rc"; fi
        """


rule run_table:
    """Averages (from config averages.t_start) of a list of runs, one CSV row per run."""
    output:
        "results/{study}/table.csv",
    input:
        code=analysis_module("tables"),
        suspensions=lambda wc: STUDY_RUNS[wc.study](),
        dilute=lambda wc: STUDY_DILUTE.get(wc.study, lambda: [])(),
    log:
        "results/logs/{study}/table.log",
    params:
        python=PYTHON,
        t_start=config["averages"]["t_start"],
    shell:
        "{params.python} -m analysis.tables --out {output} --t-start {params.t_start} "
        "{input.suspensions} --own-window {input.dilute} > {log} 2>&1"
