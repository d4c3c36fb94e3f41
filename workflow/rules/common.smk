# The workflow's functions and shared names, apart from its rules (as Snakemake's linter
# wants). A suspension run folder names all that distinguishes the run:
#   results/<study>/ca<Ca>_phi<phi>_M<M>_level<level>_seed<seed>[_<membrane>]/
# (the membrane code of analysis.membrane where a run does not carry the paper's, as the
# grid's regularised points) and a dilute run folder results/dilute/ca<Ca>_level<level>/.
# A run that two studies both need is made once, in the folder of the first of them in
# SUSPENSION_STUDIES.
import functools
from modulefinder import ModuleFinder

from analysis import membrane as membrane_codes
from analysis.capsim_job import set_options

SUSPENSION_STUDIES = ["grid", "mesh", "initial", "boxsize", "snapshots"]
# {membrane}: "" for the paper's membrane, else "_" and the code (run_name()).
RUN_NAME = "ca{ca}_phi{phi}_M{M}_level{level}_seed{seed}{membrane}"


wildcard_constraints:
    study="|".join(SUSPENSION_STUDIES),
    ca=r"[0-9.eE+-]+",
    phi=r"[0-9.eE+-]+",
    M=r"\d+",
    level=r"\d+",
    seed=r"\d+",
    membrane=r"(_[a-z][a-z0-9.+-]*)?",


def run_name(**keys):
    """The folder name of a suspension run (keys: ca, phi, M, level, seed, and membrane,
    a code of analysis.membrane, the paper's where it is missing)."""
    code = keys.get("membrane", membrane_codes.PAPER)
    suffix = "" if code == membrane_codes.PAPER else "_" + code
    return RUN_NAME.format(**{**keys, "membrane": suffix})


def membrane_options(suffix):
    """The capsim options of a run folder's membrane suffix ("" or "_<code>")."""
    if not suffix:
        return ""
    return " ".join(f"--set {o}" for o in membrane_codes.options(suffix[1:]))


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


def run_summary(study, **keys):
    """The summary.json of one run of `study` (keys: ca, phi, M, level, seed[, membrane]). Where an
    earlier study of SUSPENSION_STUDIES makes the same run (the same keys, t_end and
    snapshot interval: the mesh study's Table 1 case is often a grid point, the initial
    positions' runs some of the box-size study's), the summary of that study's run: it is
    run once, and a changed study block never redoes the other's runs."""
    name = run_name(**keys)
    for owner in SUSPENSION_STUDIES[: SUSPENSION_STUDIES.index(study)]:
        if same_runs(study, owner) and name in study_run_names(owner):
            return os.path.join("results", owner, name, "summary.json")
    return os.path.join("results", study, name, "summary.json")


def study_runs(study):
    """The summaries of every run of `study`, in its order."""
    return [run_summary(study, **keys) for keys in STUDY_KEYS[study]()]


def dilute_summary(ca, level):
    """The summary.json of the dilute run (one capsule, phi = 0) at Ca and mesh level."""
    return os.path.join("results", "dilute", f"ca{ca}_level{level}", "summary.json")


def multipole_tables():
    """The multipole-error tables of figure 1: one per Ca of config["multipole"]."""
    return expand(os.path.join("results", "multipole", "ca{ca}_level{level}.csv"),
                  ca=config["multipole"]["ca"], level=config["multipole"]["mesh_level"])


def run_option_sets():
    return set_options(dict(sorted(config["run_options"].items())))


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
