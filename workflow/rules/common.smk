# The workflow's functions and shared names, apart from its rules (as Snakemake's linter
# wants). Every run is a pipeline.run_spec.RunSpec: its folder results/<study>/<name>/
# (named there only), its capsim command lines, its archive record, its provenance key
# and its segments all come from there, and a rule finds it by its folder in RUNS
# (run_of()), never by parsing the name. A run that two studies both need is made once,
# in the folder of the first of them in SUSPENSION_STUDIES.
import functools
from modulefinder import ModuleFinder

from analysis import accuracy as accuracy_study
from analysis import membrane as membrane_codes
from analysis import sensitivity as sensitivity_study
from pipeline import archive, results_page, run_spec

SUSPENSION_STUDIES = ["grid", "mesh", "initial", "boxsize", "snapshots", "reference"]
# Studies that only their own target runs, not `all` (their runs take hours and are
# archived first): study -> function returning the RunSpecs it makes. The archive restores
# and records them as any run; the estimate of the main studies leaves them out.
ON_DEMAND_RUNS = {}

# The configuration files of this invocation, an input of every rule that gathers a
# study's runs (its table): under the profile's modification-time rule a run added to a
# study's list (a seed, a point of t_end_at) is otherwise not seen where the table
# exists (Snakemake 9.27: "Nothing to be done"). An edited configuration remakes the
# tables (seconds) and what reads them; the runs themselves are not remade.
CONFIG_FILES = [os.path.abspath(f) for f in workflow.configfiles]
# Studies outside SUSPENSION_STUDIES whose runs `all` needs (eblimit with in_grid).
MAIN_STUDY_RUNS = {}


wildcard_constraints:
    study="|".join(SUSPENSION_STUDIES + ["dilute", "accuracy", "sensitivity", "eblimit",
                                         "viscosity_ratio"]),
    run=r"(dilute_)?ca[^/]+",  # dilute_: the sensitivity study's dilute runs
    k=r"\d+",
    ca=r"[0-9.eE+-]+",
    level=r"\d+",


def suspension_spec(study, keys):
    """The RunSpec of the suspension run of `study` with keys (ca, phi, M, level, seed[,
    membrane]), in its own study folder."""
    options = {**config["run_options"], **config[study].get("options", {})}
    return run_spec.suspension(study, keys, config[study], config["averages"]["t_start"],
                               options)


def run_name(**keys):
    """The folder name of a suspension run (keys: ca, phi, M, level, seed, and membrane,
    a code of analysis.membrane, the paper's where it is missing)."""
    return suspension_spec("grid", keys).name


# Filled in by each study: study -> function returning the keys (ca, phi, M, level, seed)
# of its runs, and for those that include the dilute limit a function returning the
# dilute summaries (averaged over their own window).
STUDY_KEYS = {}
STUDY_DILUTE = {}


def same_runs(study, other):
    """Whether a run of `other` with the same keys is the run `study` asks for: the run
    folder holds everything else of the study block that goes to capsim."""
    settings = ("t_end", "snapshot_interval")
    return all(config[study].get(k) == config[other].get(k) for k in settings)


@functools.cache
def study_run_names(study):
    return frozenset(run_name(**keys) for keys in STUDY_KEYS[study]())


def run_owner(study, **keys):
    """The RunSpec of one run of `study` (keys: ca, phi, M, level, seed[, membrane]).
    Where an earlier study of SUSPENSION_STUDIES makes the same run (the same keys, t_end
    and snapshot interval: the mesh study's Table 1 case is often a grid point, the
    initial positions' runs some of the box-size study's), that study's run: it is run
    once, and a changed study block never redoes the other's runs."""
    name = run_name(**keys)
    for owner in SUSPENSION_STUDIES[: SUSPENSION_STUDIES.index(study)]:
        if same_runs(study, owner) and name in study_run_names(owner):
            return suspension_spec(owner, keys)
    return suspension_spec(study, keys)


def run_summary(study, **keys):
    """The summary.json of one run of `study` (run_owner())."""
    return os.path.join(run_owner(study, **keys).folder, "summary.json")


def study_runs(study):
    """The summaries of every run of `study`, in its order."""
    return [run_summary(study, **keys) for keys in STUDY_KEYS[study]()]


def dilute_spec(ca, level):
    """The RunSpec of the dilute run (one capsule, phi = 0) at Ca and mesh level."""
    return run_spec.dilute(ca, level, config["dilute"])


def dilute_summary(ca, level):
    """The summary.json of the dilute run at Ca and mesh level."""
    return os.path.join(dilute_spec(ca, level).folder, "summary.json")


# Filled in by the studies that use dilute runs: functions returning their (Ca, level).
DILUTE_KEYS = []


def main_runs():
    """The runs of the main studies (the suspension studies and the dilute runs they
    use: what the target all needs), by folder."""
    runs = {}
    for study in SUSPENSION_STUDIES:
        if study in ON_DEMAND_RUNS:
            continue
        for keys in STUDY_KEYS.get(study, lambda: [])():
            spec = run_owner(study, **keys)
            runs[spec.folder] = spec
    for keys in DILUTE_KEYS:
        for ca, level in keys():
            spec = dilute_spec(ca, level)
            runs[spec.folder] = spec
    for specs in MAIN_STUDY_RUNS.values():
        runs.update((spec.folder, spec) for spec in specs())
    return runs


def configuration_runs():
    """Every run of the configuration's studies, by folder: what the archive restores
    and records and what run_of() finds (the main runs, the on-demand studies', then the
    accuracy and sensitivity studies', and the dilute study's runs that the sensitivity
    study compares with)."""
    runs = main_runs()
    for specs in ON_DEMAND_RUNS.values():
        runs.update((spec.folder, spec) for spec in specs())
    block = config["accuracy"]
    for setting in accuracy_study.run_names(block).values():
        spec = run_spec.accuracy(setting, block["sample_interval"])
        runs[spec.folder] = spec
    for run in sensitivity_study.plan(config["sensitivity"], config["dilute"]):
        spec = run_spec.sensitivity(run, config["run_options"],
                                    config["dilute"].get("options", {}))
        runs[spec.folder] = spec
    for run in sensitivity_study.dilute_references(config["sensitivity"], config["dilute"]):
        spec = dilute_spec(run.ca, run.level)
        runs.setdefault(spec.folder, spec)
    return runs


@functools.cache
def runs_by_name():
    """RUNS by (study, name): a run folder's wildcards."""
    return {(spec.study, spec.name): spec for spec in RUNS.values()}


def run_of(study, run):
    """The RunSpec of a run folder's wildcards, looked up (RUNS): a name is never parsed
    back into a run."""
    spec = runs_by_name().get((study, run))
    if spec is None:
        raise ValueError(f"{study}/{run}: no run of this name in the configuration")
    return spec


def segment_ends(spec):
    """The pause times of a run's segments, its t_end last (config segments)."""
    return spec.segment_ends(config["segments"].get("minutes"),
                             config["segments"].get("strain"))


def multipole_runs():
    """{name: RunSpec} of the dilute runs whose capsules figure 1 reads: one per Ca of
    config["multipole"]; each one's table is results/multipole/<name>.csv."""
    specs = (dilute_spec(ca, config["multipole"]["mesh_level"])
             for ca in config["multipole"]["ca"])
    return {spec.name: spec for spec in specs}


def multipole_tables():
    """The multipole-error tables of figure 1 (multipole_runs())."""
    return [os.path.join("results", "multipole", f"{name}.csv") for name in multipole_runs()]


@functools.cache
def imported_modules(script):
    """The repository's Python files that `script` imports, directly or through each other
    (a figure script: figures/common.py and the analysis modules). They are inputs of the
    rule that runs it, so that editing one redoes what it made. Only the script's folder
    and the repository are searched: numpy and the like are not followed."""
    finder = ModuleFinder(path=[os.path.dirname(script), ROOT])
    finder.run_script(script)
    files = {m.__file__ for m in finder.modules.values() if m.__file__}
    return sorted(f for f in files
                  if f != script and os.path.commonpath([f, ROOT]) == ROOT)


def analysis_module(name):
    """The file of `python -m analysis.<name>` and the modules it imports."""
    path = os.path.join(ROOT, "analysis", f"{name}.py")
    return [path] + imported_modules(path)


def figure_script(name):
    return os.path.join(ROOT, "figures", f"{name}.py")


@functools.cache
def archive_plan():
    """What the archive does for the configuration's runs (pipeline.archive.plan), read
    only; empty without an archive. Each run's options as capsim resolves them, so the
    solver must be built."""
    if not ARCHIVE:
        return {"restore": {}, "continue": {}, "stale": [], "changed": [], "ahead": []}
    if not os.path.exists(CAPSIM):
        raise WorkflowError(f"{CAPSIM} is missing: the archive {config['archive']} checks "
                            "its records against the solver's options; build it first "
                            "(bash scripts/setup.sh)")
    return archive.plan(RUNS.values(), ARCHIVE, lambda spec: spec.resolved_options(CAPSIM),
                        segment_ends)


def report_before_scheduling():
    """The archive's and the main studies' lines on stderr; a damaged or foreign record, a
    folder of the archive that is no record or a run folder that holds another run (or
    cannot be read) or a finished run of another t_end stops the workflow here, named,
    with what to do."""
    try:
        for spec in RUNS.values():
            archive.check_length(spec.folder, spec.t_end)
        report_archive(archive_plan())
        report_remaining(main_runs().values(), archive_plan())
    except (archive.ArchiveError, ValueError) as e:
        raise WorkflowError(str(e))


def report_archive(plan):
    """One line per kind of what the archive does, on stderr."""
    words = {"restore": "run(s) to restore whole",
             "continue": "run(s) to restore and continue",
             "stale": "record(s) of another physics version",
             "changed": "record(s) with other options than this configuration's",
             "ahead": "run(s) in results/ that reach further than their record, recorded "
                      "by their next job (or now by the target record_archive)"}
    for kind, folders in plan.items():
        if folders:
            folders = list(folders)
            shown = ", ".join(map(str, folders[:4])) + (", ..." if len(folders) > 4 else "")
            print(f"archive {config['archive']}: {len(folders)} {words[kind]}: {shown}",
                  file=sys.stderr)
    if plan["stale"] or plan["changed"]:
        print(f"archive {config['archive']}: those records are kept as they are and not "
              "used: their runs are computed anew into results/ and not recorded; to "
              "record them, remove the old records (git rm -r <record>)", file=sys.stderr)


def report_remaining(runs, plan):
    """One line on stderr: how many of the main runs neither results/ holds finished nor
    the archive restores whole, and their estimated wall time on 2 cores from where each
    stands (RunSpec.seconds_per_strain, within 0.9-1.45 of the CPU time that the
    quantitative archive's runs took: docs/workflow.md)."""
    left, restored, seconds = 0, 0, 0.0
    for spec in runs:
        state = archive.reached(spec.folder)
        if spec.folder in plan["restore"]:
            restored += 1
        elif state is None or not state[0]:
            left += 1
            start = state[1] if state else 0.0
            if spec.folder in plan["continue"]:
                _, k, t = plan["continue"][spec.folder]
                start = max(start, segment_ends(spec)[k - 1] if k else t)
            seconds += spec.seconds_per_strain() * (spec.t_end - start)
    from_archive = f" ({restored} restored from the archive)" if restored else ""
    print(f"main studies: {left} of {len(runs)} runs to compute{from_archive}, about "
          f"{seconds / 3600:.1f} h of 2-core wall time (estimated)", file=sys.stderr)
