# One capsim suspension run, shared by every study that needs one (grid, mesh, initial,
# boxsize, snapshots). A run folder names all that distinguishes it:
#   results/<study>/ca<Ca>_phi<phi>_M<M>_level<level>_seed<seed>/
# and the study's block of the configuration gives t_end and the snapshot interval. Keys in
# config["run_options"] (e.g. method, ewald.tolerance) go to every suspension run.
SUSPENSION_STUDIES = ["grid", "mesh", "initial", "boxsize", "snapshots"]
RUN_NAME = "ca{ca}_phi{phi}_M{M}_level{level}_seed{seed}"


wildcard_constraints:
    study="|".join(SUSPENSION_STUDIES),
    ca=r"[0-9.eE+-]+",
    phi=r"[0-9.eE+-]+",
    M=r"\d+",
    level=r"\d+",
    seed=r"\d+",


def run_summary(study, **keys):
    """The summary.json of one run of `study` (keys: ca, phi, M, level, seed)."""
    return f"results/{study}/" + RUN_NAME.format(**keys) + "/summary.json"


def run_option_sets():
    return " ".join(f"--set {k}={v}" for k, v in sorted(config["run_options"].items()))


# The solver is an input only to be built first: ancient() keeps a rebuilt binary from
# re-running finished runs (a physics change means a new results folder, not a rerun).
# A stopped run (killed job, cluster time limit) resumes from its checkpoint; on resume
# only t_end, t_avg_start, threads and output.* may change (capsim refuses the rest).
rule suspension_run:
    input:
        ancient(CAPSIM),
    output:
        "results/{study}/" + RUN_NAME + "/summary.json",
    log:
        "results/logs/{study}/" + RUN_NAME + ".log",
    params:
        dir=lambda wc: f"results/{wc.study}/" + RUN_NAME.format(**wc),
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
        suspensions=lambda wc: STUDY_RUNS[wc.study](),
        dilute=lambda wc: STUDY_DILUTE.get(wc.study, lambda: [])(),
    log:
        "results/logs/{study}/table.log",
    params:
        t_start=config["averages"]["t_start"],
    shell:
        "{PYTHON} -m analysis.tables --out {output} --t-start {params.t_start} "
        "{input.suspensions} --own-window {input.dilute} > {log} 2>&1"


# Filled in by each study: study -> function returning its run summaries (and, for those
# that include the dilute limit, the dilute summaries averaged over their own window).
STUDY_RUNS = {}
STUDY_DILUTE = {}
