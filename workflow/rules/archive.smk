# The results archive's rules (pipeline.archive, docs/workflow.md "Runs, segments and the
# results archive"), with an archive only. Included once the configuration's runs are
# known (RUNS) and archive_plan() has read, and only read, what the archive holds:
# restoring is a job, so that a dry run writes nothing and Snakemake's lock covers it.
# One job restores every finished run the archive holds (a job per run cost a process
# start each, a minute of the main command); a run to continue is restored by the job of
# the last segment its state covers. Rule order puts both before run and run_segment.
import json
import shlex

from pipeline.job import record_run


def restore_segment_input(wc):
    """The record that rule restore_segment restores for segment k of a run, where
    archive_plan() says it does; else a path that is never there, so that the rule is
    not a candidate and the segment is computed."""
    spec = run_of(wc.study, wc.run)
    record, last, _ = archive_plan()["continue"].get(spec.folder, (None, None, None))
    if record is None or last != int(wc.k):
        return [f"(no record to restore {spec.folder} from)"]
    return [ancient(CAPSIM), ancient(os.path.join(record, "record.json"))]


def restore_command():
    """The command of rule restore: pipeline.job restoring, each from its record, every
    run that archive_plan() restores whole."""
    specs = [json.loads(RUNS[folder].to_json()) for folder in archive_plan()["restore"]]
    return shlex.join([PYTHON, "-m", "pipeline.job", "--capsim", CAPSIM, "--log",
                       os.path.join("results", "logs", "restore.log"), "--archive", ARCHIVE,
                       "--restore", "--specs", json.dumps(specs)])


if ARCHIVE and archive_plan()["restore"]:

    ruleorder: restore > run

    rule restore:
        input:
            ancient(CAPSIM),
            [ancient(os.path.join(record, "record.json"))
             for record in archive_plan()["restore"].values()],
        output:
            [os.path.join(folder, "summary.json") for folder in archive_plan()["restore"]],
        log:
            "results/logs/restore.log",
        params:
            command=restore_command(),
        localrule: True
        shell:
            "{params.command}"


if ARCHIVE:

    ruleorder: restore_segment > run_segment

    rule restore_segment:
        input:
            restore_segment_input,
        output:
            temp("results/{study}/{run}/segment{k}.done"),
        log:
            "results/logs/{study}/{run}.restore.segment{k}.log",
        params:
            # segment 0: the state before the first pause, whatever its time
            command=lambda wc: run_job(
                wc, 1, segment_ends(run_of(wc.study, wc.run))[int(wc.k) - 1]
                if int(wc.k) > 0 else 0.0, restore=True),
        localrule: True
        shell:
            "{params.command}"

    rule record_archive:
        """Records every run folder that reaches further than its record (the segment in
        progress, before a machine goes: docs/workflow.md)."""
        localrule: True
        run:
            for folder in archive_plan()["ahead"]:
                try:
                    record_run(RUNS[folder], CAPSIM, ARCHIVE)
                    print(f"archive: recorded {folder}", file=sys.stderr)
                except (archive.ArchiveError, OSError) as e:
                    print(f"archive: {folder} NOT RECORDED: {e}", file=sys.stderr)
