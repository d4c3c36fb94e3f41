# The runs of every study, by one generic rule: a run (pipeline.run_spec.RunSpec, looked
# up by its folder's wildcards by run_of(); the job receives it whole, as JSON) is a chain
# of segments (config segments: about 25 minutes each by default), each a job that
# resumes the run from the previous one's checkpoint and pauses at its own end (`capsim
# run --pause-at`), so a killed invocation loses at most one segment and a cluster job
# fits its wall-time limit; the chain ends exactly where the unbroken run would. The last
# segment writes summary.json. With config archive, every segment is recorded in the
# results archive as soon as it is done (pipeline.archive), and the rules of archive.smk
# restore from there what was computed before: jobs, so that a dry run writes nothing
# and Snakemake's lock covers them.
#
# The solver is an input only to be built first: ancient() keeps a rebuilt binary from
# re-running finished runs (a physics change bumps solver/PHYSICS_VERSION, which makes
# archive records stale). pipeline.job starts the run, or resumes it from its checkpoint
# when the folder holds one (a killed job, a cluster time limit, a raised t_end; on resume
# only t_end, t_avg_start and threads are given, capsim refuses the rest). It says in the
# log which it does, locks the log while capsim runs (a second job for the same run is
# refused) and on failure names the run, how capsim ended and its message. Exit 3
# (contact, numerical failure) with summary.json is a success for all but the dilute
# study's runs (RunSpec.stop_is_result): summary.json says how the run "ended", its data
# up to the stop stay in the study and the figures name it; later segments of a stopped
# run run nothing.
import shlex


def run_job(wc, threads, pause=None, restore=False):
    """The command of one segment (pause: its end) or of the last (pause None); with
    `restore` the job that restores it from the archive instead. The job receives the
    run's spec and derives the rest from it (pipeline.job)."""
    spec = run_of(wc.study, wc.run)
    segment = "" if pause is None else f".segment{wc.k}"
    log = os.path.join("results", "logs", wc.study,
                       f"{wc.run}{'.restore' if restore else ''}{segment}.log")
    words = [PYTHON, "-m", "pipeline.job", "--capsim", CAPSIM, "--log", log,
             "--spec", spec.to_json(), "--threads", str(threads)]
    if pause is not None:
        words += ["--pause-at", str(pause), "--segment", str(wc.k)]
    if ARCHIVE:
        words += ["--archive", ARCHIVE] + (["--restore"] if restore else [])
    return shlex.join(words)


def run_resource(wc, what):
    """A run's cluster resource: config resources dilute_<what> or suspension_<what>."""
    kind = "dilute" if run_of(wc.study, wc.run).dilute else "suspension"
    return config["resources"][f"{kind}_{what}"]


def previous_segment(wc, last=False):
    """The marker of the segment before this one; for the first, that of the restore of a
    state before its pause where the archive continues the run from one (segment 0,
    archive.smk), else []."""
    spec = run_of(wc.study, wc.run)
    k = len(segment_ends(spec)) if last else int(wc.k)
    if k == 1 and archive_plan()["continue"].get(spec.folder, (None, None, None))[1] != 0:
        return []
    return [str(archive.marker(spec.folder, k - 1))]


rule run_segment:
    input:
        ancient(CAPSIM),
        previous=previous_segment,
    output:
        temp("results/{study}/{run}/segment{k}.done"),
    log:
        "results/logs/{study}/{run}.segment{k}.log",
    params:
        command=lambda wc, threads: run_job(
            wc, threads, segment_ends(run_of(wc.study, wc.run))[int(wc.k) - 1]),
    threads: config["resources"]["threads"]
    resources:
        runtime=lambda wc: run_resource(wc, "minutes"),
        mem_mb=lambda wc: run_resource(wc, "mem_mb"),
    shell:
        "{params.command}"


rule run:
    input:
        ancient(CAPSIM),
        previous=lambda wc: previous_segment(wc, last=True),
    output:
        "results/{study}/{run}/summary.json",
    log:
        "results/logs/{study}/{run}.log",
    params:
        command=lambda wc, threads: run_job(wc, threads),
    threads: config["resources"]["threads"]
    resources:
        runtime=lambda wc: run_resource(wc, "minutes"),
        mem_mb=lambda wc: run_resource(wc, "mem_mb"),
    shell:
        "{params.command}"


rule run_table:
    """Averages (from config averages.t_start) of a list of runs, one CSV row per run."""
    wildcard_constraints:
        study="|".join(SUSPENSION_STUDIES),
        table="table|runs",  # runs: the grid's runs where the grid table is eblimit's
    output:
        "results/{study}/{table}.csv",
    input:
        code=analysis_module("tables"),
        suspensions=lambda wc: study_runs(wc.study),
        configs=CONFIG_FILES,
        dilute=lambda wc: STUDY_DILUTE.get(wc.study, lambda: [])(),
    log:
        "results/logs/{study}/{table}.log",
    params:
        python=PYTHON,
        t_start=config["averages"]["t_start"],
    shell:
        "{params.python} -m analysis.tables --out {output} --t-start {params.t_start} "
        "{input.suspensions} --own-window {input.dilute} > {log} 2>&1"
