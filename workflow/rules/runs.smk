# One capsim suspension run, shared by every study that needs one (grid, mesh, initial,
# boxsize, snapshots), and the table of averages of a study's runs. The study's block of
# the configuration gives t_end and the snapshot interval. Keys in config["run_options"]
# (e.g. method, ewald.tolerance) go to every suspension run.


# The solver is an input only to be built first: ancient() keeps a rebuilt binary from
# re-running finished runs (a physics change means a new results folder, not a rerun).
# analysis.capsim_job starts the run, or resumes it from its checkpoint when the folder
# holds one (a killed job, a cluster time limit, a raised t_end; on resume only t_end,
# t_avg_start, threads and output.* may change, capsim refuses the rest). It says in the
# log which it does, locks the log while capsim runs (a second job for the same run is
# refused) and on failure names the run, how capsim ended and its message.
# Exit 3 (contact, numerical failure) with summary.json is a success: summary.json says
# how the run "ended", its data up to the stop stay in the study and the figures name it.
rule suspension_run:
    input:
        ancient(CAPSIM),
    output:
        os.path.join("results", "{study}", RUN_NAME, "summary.json"),
    log:
        os.path.join("results", "logs", "{study}", f"{RUN_NAME}.log"),
    params:
        python=PYTHON,
        # From the wildcards as before: a changed parameter would redo every finished run.
        dir=lambda wc: os.path.join("results", wc.study, RUN_NAME.format(**wc)),
        t_end=lambda wc: config[wc.study]["t_end"],
        t_avg_start=lambda wc: min(config["averages"]["t_start"], 0.5 * config[wc.study]["t_end"]),
        snapshots=lambda wc: config[wc.study]["snapshot_interval"],
        options=run_option_sets(),
        membrane=lambda wc: membrane_options(wc.membrane),
    threads: config["resources"]["threads"]
    resources:
        runtime=lambda wc: config["resources"]["suspension_minutes"],
        mem_mb=lambda wc: config["resources"]["suspension_mem_mb"],
    shell:
        "{params.python} -m analysis.capsim_job --capsim {input} --dir {params.dir} "
        "--log {log} --stopped-ok --resume-set threads={threads} "
        "--resume-set t_end={params.t_end} -- "
        "--set ca={wildcards.ca} --set phi={wildcards.phi} --set capsules={wildcards.M} "
        "--set mesh_level={wildcards.level} --set seed={wildcards.seed} "
        "--set t_end={params.t_end} --set t_avg_start={params.t_avg_start} "
        "--set output.snapshot_interval={params.snapshots} {params.options} "
        "{params.membrane} "
        "--set threads={threads}"


rule run_table:
    """Averages (from config averages.t_start) of a list of runs, one CSV row per run."""
    output:
        "results/{study}/table.csv",
    input:
        code=analysis_module("tables"),
        suspensions=lambda wc: study_runs(wc.study),
        dilute=lambda wc: STUDY_DILUTE.get(wc.study, lambda: [])(),
    log:
        "results/logs/{study}/table.log",
    params:
        python=PYTHON,
        t_start=config["averages"]["t_start"],
    shell:
        "{params.python} -m analysis.tables --out {output} --t-start {params.t_start} "
        "{input.suspensions} --own-window {input.dilute} > {log} 2>&1"
