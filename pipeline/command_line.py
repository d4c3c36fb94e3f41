"""capsim's command line, spelt in one place: the `--set key=value` options of a run (a
RunSpec's capsim_options(), or a benchmark's or a test's own mapping) and the commands
that start a run with them or resume one (RunSpec.command() for the workflow's runs, the
archive's replay of a record).

It imports nothing, so that a script run by a bare python3 with numpy and h5py only
(benchmarks/backend_compare.py on a GPU machine) can use it.
"""


def option_value(value):
    """A configuration value as capsim's `--set key=value` spells it: YAML's booleans as
    true/false (capsim refuses Python's True), the rest as str() writes it."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def set_arguments(options):
    """`--set key=value` for each item of a mapping, in its order, as the words of a
    command line."""
    return [word for key, value in options.items()
            for word in ("--set", f"{key}={option_value(value)}")]


def run_command(capsim, options, folder, *flags):
    """`capsim run` of a new run in `folder` with the options of a mapping and further
    flags of capsim run (-q, --profile FILE)."""
    return [str(capsim), "run", *flags, *set_arguments(options), "-o", str(folder)]


def resume_command(capsim, folder, options, *flags):
    """`capsim run --resume` of the run in `folder` from its checkpoint, with the options
    of a mapping (those capsim lets change on resume: t_end, threads, ...) and further
    flags of capsim run (-q, --pause-at T)."""
    return [str(capsim), "run", *flags, "--resume", str(folder), *set_arguments(options)]
