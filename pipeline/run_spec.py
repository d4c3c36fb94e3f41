"""One capsim run of the workflow, described once: its folder name, its capsim command
lines (fresh and resumed), its archive record and provenance key, its segments and its
estimated cost.

Every study asks for runs as RunSpec objects. The workflow hands the job the spec itself
(RunSpec.to_json(), pipeline.job --spec), and the job, the results archive
(pipeline.archive) and the workflow's rules derive everything else from it here: a folder
name, a command line or a record is spelled in this module only and never parsed back.

A suspension run folder names all that distinguishes the run within a configuration:
    ca<Ca>_phi<phi>_M<M>_level<level>_seed<seed>[_<membrane>]
(the membrane code of analysis.membrane where the run does not carry the paper's), a
dilute run (one capsule in unbounded shear) ca<Ca>_level<level>, or
dilute_ca<Ca>_level<level>_<membrane> where it does not carry the paper's membrane. A
number is spelt as number() writes it (0.05, 1e-05; 1.0 as 1). A study whose runs differ
in more than these (the accuracy study: Ewald tolerance, time scheme, length; the
sensitivity study: the membrane always named; the viscosity-ratio study: lambda) names
them itself (RunSpec.label).

The provenance key is a hash of the physics version (solver/PHYSICS_VERSION) and every
option of the run as capsim resolves it (`capsim params --json`, the values run.yaml
holds), so that a default changed in the solver's table changes the key of every run that
takes it. Left out: t_end and t_avg_start (a record that reached t_end = 20 is the first
part of the same run to t_end = 30, and t_avg_start changes only the averages of
summary.json), threads and backend (they change the last bits of the floating-point
reductions, not the physics; a record says which it used), and, for a dilute run, the
options it does not use (the periodic sums, the suspension's, the seed). The key of an
archived record is computed the same way from the options it stores (options_key()).
"""

import dataclasses
import functools
import hashlib
import json
import math
import subprocess
from pathlib import Path

from analysis import bending_limit
from analysis import membrane as membrane_codes
from analysis.accuracy import time_options
from pipeline.command_line import option_value, resume_command, run_command, set_arguments

ROOT = Path(__file__).resolve().parent.parent
PHYSICS_VERSION_FILE = ROOT / "solver" / "PHYSICS_VERSION"

# The options whose capsim default changed since physics version 1, with the default then:
# a run that pins none of them there takes the present ones, which cost less per step
# (docs/performance.md, "The defaults of precision and quadrature"; seconds_per_strain).
FORMER_DEFAULTS = {
    "ewald.precision": "double",
    "quadrature.near_ratio": 1.5,
    "quadrature.far_ratio": 2,
    "ewald.real_space_precision": "double",
}

# The options capsim gained after runs had been recorded, with the value that every run
# before them took: a record whose run.yaml lacks one is read with it (and capsim resumes
# such a run's checkpoint with it: kFormerValues in solver/config/run_options.cpp).
ADDED_OPTIONS = {
    "ewald.precision": "double",
    "ewald.real_space_precision": "double",
    "time.stages": "4",
    "lambda": "1",
    "membrane.law": "neo_hookean",
    "gmres.guess": "previous",
    "dt_lambda_max": "1",
}

# The options added after the archive's records were keyed (a subset of ADDED_OPTIONS):
# at the value every earlier run took they leave the key out, as the run is then the
# earlier one bit for bit, so the records keep their keys; any other value is in it.
UNKEYED_AT_FORMER_VALUE = ("lambda", "membrane.law", "gmres.guess", "dt_lambda_max")

# What does not fix the trajectory (see above), and what a dilute run does not use (a key
# or a prefix of keys).
NOT_IN_KEY = ("t_end", "t_avg_start", "threads", "backend")
UNUSED_BY_DILUTE = ("method", "seed", "ewald.", "suspension.")
UNUSED_AT_LAMBDA_1 = ("gmres.",)  # the second-kind solve's: no solve at lambda = 1
UNUSED_UP_TO_LAMBDA_1 = ("dt_lambda_max",)  # the automatic step's growth at lambda > 1


EDGE_LEVEL3 = 0.151  # mean edge length of the level-3 icosphere of radius 1
# imex at a given time.tolerance T (max norm) in a developed dense suspension: its mean
# step about 0.50 sqrt(T), each step 1.15 times Heun's wall time (the grid's Ca 0.3 and
# 0.4, phi 0.4, eb 0.025 points branched from their archived states near gammadot t 30
# for 1.5 strain units: steps 0.0143 and 0.0174 at 1e-3, 1.06 and 1.24 times Heun's
# cost a step; benchmarks/records/time_schemes_developed.json). From rest its step is
# longer (0.0233 at 1e-3 to t = 2, time_schemes_bending.json): a run's first strain
# units cost less than the model says.
IMEX_STEP_PER_ROOT_TOLERANCE = 0.50
IMEX_STEP_COST = 1.15


def number(value):
    """A number as a folder name spells it: the shortest text that reads back as the same
    float, without a trailing ".0" (Ca 1 and 1.0 are one run, ca1). Every name the
    archives hold reads the same as before (0.05, 0.0125: what both str() and :g gave)."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


def physics_version():
    """The solver's physics version: the first word of solver/PHYSICS_VERSION."""
    return PHYSICS_VERSION_FILE.read_text().split()[0]


def _same_value(given, default):
    """Whether a spelt option value is the default (1.5 and "1.50" are)."""
    try:
        return float(given) == float(default)
    except ValueError:
        return given == option_value(default)


def _canonical(value):
    """An option value in one spelling: a number as Python writes the float (27, "27"
    and 27.0 alike), the rest as capsim's --set spells it."""
    text = option_value(value)
    try:
        return repr(float(text))
    except ValueError:
        return text


def flat_options(options, prefix=""):
    """Nested options (run.yaml as YAML reads it) as one level of dotted keys."""
    out = {}
    for key, value in options.items():
        if isinstance(value, dict):
            out.update(flat_options(value, f"{prefix}{key}."))
        else:
            out[prefix + key] = value
    return out


DENSE_COST_RECORDS = ("viscosity_ratio_cost_dense.json",       # M 8, level 2
                      "viscosity_ratio_cost_dense_M27.json")   # M 27, level 3


@functools.cache
def _lambda_cost_ratios(dense, tolerance=None):
    """(level, lambda): the measured cost ratio of the benchmark's records at capsim's
    defaults, or where the records measured it at gmres.tolerance `tolerance` (the
    guess and the time scheme the defaults), that case."""
    names = DENSE_COST_RECORDS if dense else ("viscosity_ratio_cost.json",)
    cases = [c for name in names for c in
             json.loads((ROOT / "benchmarks" / "records" / name).read_text())["cases"]]

    def defaults(c, but=()):
        return all(v for k, v in c.items() if k.startswith("default_") and k not in but)

    table = {(c["mesh_level"], c["lambda"]): c["cost_ratio"] for c in cases if defaults(c)}
    if tolerance is not None:
        table |= {(c["mesh_level"], c["lambda"]): c["cost_ratio"] for c in cases
                  if defaults(c, but=("default_tolerance",))
                  and math.isclose(c["gmres_tolerance"], tolerance)}
    return table


def lambda_cost_ratio(level, ratio, dense, tolerance=None):
    """A capsule-strain's cost at viscosity ratio `ratio` over lambda 1's, from the
    benchmark's records (benchmarks/records/viscosity_ratio_cost.json, one capsule;
    _dense.json, M 8 at phi 0.3, level 2; _dense_M27.json, M 27 at phi 0.3, level 3,
    gmres.tolerance 1e-5, the dense study's): the measured case at the nearest level and
    the nearest ratio on the same side of 1, at gmres.tolerance `tolerance` where
    measured; one capsule's doubled a level up and halved a level down (measured: 1.75
    times from level 2 to 3), a suspension's as measured."""
    if ratio == 1.0:
        return 1.0
    table = _lambda_cost_ratios(dense, tolerance)
    side = [(lev, lam) for lev, lam in table
            if lam != 1.0 and (lam < 1.0) == (ratio < 1.0)]
    near = min({lev for lev, _ in side}, key=lambda lev: abs(lev - level))
    lam = min((v for lev, v in side if lev == near), key=lambda v: abs(math.log(v / ratio)))
    return table[(near, lam)] * (1.0 if dense else 2.0 ** (level - near))


def key_options(options):
    """The options a key hashes, from a run's resolved options (flat or nested, as
    run.yaml, summary.json's parameters or `capsim params --json` hold them): every one
    but NOT_IN_KEY (and UNUSED_BY_DILUTE for phi = 0), ADDED_OPTIONS filled in, those of
    UNKEYED_AT_FORMER_VALUE left out at their former value, UNUSED_AT_LAMBDA_1 at
    lambda = 1 and UNUSED_UP_TO_LAMBDA_1 at lambda <= 1, in one spelling."""
    flat = {**ADDED_OPTIONS, **flat_options(options)}
    dilute = float(flat.get("phi", 0)) == 0
    ratio = float(flat["lambda"])
    unused = (UNUSED_BY_DILUTE if dilute else ()) + (
        UNUSED_AT_LAMBDA_1 if ratio == 1 else ()) + (
        UNUSED_UP_TO_LAMBDA_1 if ratio <= 1 else ())
    former = {key for key in UNKEYED_AT_FORMER_VALUE
              if _canonical(flat[key]) == _canonical(ADDED_OPTIONS[key])}
    return {key: _canonical(value) for key, value in sorted(flat.items())
            if key not in NOT_IN_KEY and key not in former
            and not key.startswith(unused)}


def options_key(options, version):
    """The provenance key of a run with these resolved options under a physics version:
    sha256 (hex) of both."""
    content = {"physics_version": str(version), "options": key_options(options)}
    text = json.dumps(content, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def options_differ(got, want):
    """The options (key_options) where `got` differs from `want`, for a message:
    "mesh_level 1 (not 3), ..."; "" where none does."""
    a, b = key_options(got), key_options(want)
    return ", ".join(f"{k} {a.get(k, '-')} (not {b.get(k, '-')})"
                     for k in sorted(set(a) | set(b)) if a.get(k) != b.get(k))


@functools.cache
def _resolved(capsim, words):
    done = subprocess.run([str(capsim), "params", "--json", *words], capture_output=True,
                          text=True)
    if done.returncode != 0:
        raise ValueError(f"{capsim} params --json {' '.join(words)}: "
                         f"{done.stderr.strip() or f'exit {done.returncode}'}")
    return json.loads(done.stdout)


def resolved_options(capsim, set_words):
    """The options, flat, that a run started with the `--set KEY=VALUE` words takes, as
    capsim resolves them (`capsim params --json`, what its run.yaml would hold): the
    solver's own defaults, never a copy of them."""
    return dict(_resolved(str(capsim), tuple(set_words)))


@dataclasses.dataclass(frozen=True)
class RunSpec:
    """One run. study: the results folder that holds it ("dilute" for phi = 0);
    options: further capsim options (for a suspension of the main studies, the
    configuration's run_options)."""

    study: str  # "dilute" for the dilute runs of the main studies
    ca: float
    level: int
    t_end: float
    t_avg_start: float
    phi: float = 0.0
    M: int = 1
    seed: int = 1
    membrane: str = membrane_codes.PAPER
    snapshot_interval: float = 0.0
    options: tuple = ()  # (key, value) pairs of further capsim options, sorted
    label: str = ""  # the folder name, where the study names its runs itself

    @property
    def dilute(self):
        """One capsule in unbounded shear (phi = 0)."""
        return self.phi == 0

    @property
    def name(self):
        """The run's folder name (the module's docstring)."""
        if self.label:
            return self.label
        paper = self.membrane == membrane_codes.PAPER
        if self.dilute:
            return (f"ca{number(self.ca)}_level{self.level}" if paper else
                    f"dilute_ca{number(self.ca)}_level{self.level}_{self.membrane}")
        return (f"ca{number(self.ca)}_phi{number(self.phi)}_M{self.M}_level{self.level}"
                f"_seed{self.seed}{'' if paper else '_' + self.membrane}")

    @property
    def folder(self):
        """The run folder, relative to the workflow's working directory."""
        return f"results/{self.study}/{self.name}"

    @property
    def stop_is_result(self):
        """Whether capsim stopping the run early (exit 3: contact, numerical failure, with
        summary.json) is a result: for every run but the dilute study's, whose table has
        no row for a stopped run."""
        return self.study != "dilute"

    def record(self, archive_root):
        """The run's record in a results archive: <archive>/<study>/<name>, the run
        folder's own path under results/."""
        return Path(archive_root) / self.study / self.name

    def to_json(self):
        """The spec as the job receives it (pipeline.job --spec): every field, so that
        the job derives what the workflow would (from_json() reads it back equal)."""
        return json.dumps(dataclasses.asdict(self), sort_keys=True)

    @classmethod
    def from_json(cls, text):
        """The RunSpec that to_json() wrote (a JSON string, or the dict it holds)."""
        fields = json.loads(text) if isinstance(text, str) else dict(text)
        fields["options"] = tuple(tuple(pair) for pair in fields["options"])
        return cls(**fields)

    def trajectory_options(self):
        """The capsim options that fix the trajectory, as a dict in command-line order
        (membrane options last: a rep<F0> overrides run_options' repulsion)."""
        if self.dilute:
            out = {"ca": self.ca, "mesh_level": self.level}
        else:
            out = {"ca": self.ca, "phi": self.phi, "capsules": self.M,
                   "mesh_level": self.level, "seed": self.seed,
                   "output.snapshot_interval": self.snapshot_interval}
        out.update(dict(self.options))
        for option in membrane_codes.options(self.membrane):
            key, value = option.split("=", 1)
            out[key] = value
        return out

    def capsim_options(self, threads):
        """Every `--set` of a fresh start, as a dict."""
        return {**self.trajectory_options(), **self.resume_options(threads)}

    def resume_options(self, threads):
        """Every `--set` of a resume: the keys capsim lets change on resume (it refuses
        the rest), so that a raised t_end, another thread count or the configuration's
        backend (a run continued on a GPU, whichever backend began it) carries on the
        run."""
        out = {"t_end": self.t_end, "t_avg_start": self.t_avg_start, "threads": threads}
        backend = dict(self.options).get("backend")
        return out if backend is None else {**out, "backend": backend}

    def command(self, capsim, threads, pause_at=None, root="."):
        """The `capsim run` command of the run's next stretch, and whether it resumes:
        from the checkpoint of its folder (under `root`, the working directory by
        default) where there is one (a killed job, a paused segment, a state restored
        from the archive), else afresh; with pause_at, to the first checkpoint at or
        after that strain (one segment)."""
        folder = Path(root) / self.folder
        flags = ["-q"] + ([] if pause_at is None else ["--pause-at", str(pause_at)])
        if (folder / "checkpoint.h5").exists():
            cmd = resume_command(capsim, folder, self.resume_options(threads), *flags)
            return cmd, True
        return run_command(capsim, self.capsim_options(threads), folder, *flags), False

    def resolved_options(self, capsim):
        """The run's options as capsim resolves them (resolved_options())."""
        return resolved_options(capsim, set_arguments(self.capsim_options(threads=1)))

    def key(self, capsim, version=None):
        """The provenance key (options_key()) of the run's resolved options."""
        return options_key(self.resolved_options(capsim), version or physics_version())

    def seconds_per_strain(self):
        """Estimated wall seconds per unit strain on 2 cores (measured on the Table 1
        point with the quantitative settings, benchmarks/records/step_profile.json:
        level 3, M 27, Ca 0.2 17.5 s, level 4 10.8 times that (docs/performance.md),
        dt proportional to Ca; the dilute capsule about 0.5 s at level 3; all measured
        with the defaults of physics version 1). Bending eb shortens the step by
        1 + 4 eb / h^2 (its stability limit, h the mean edge: 0.151 at level 3, halved a
        level; the archived runs at Ca 0.5 phi 0.1 with eb 0.0125 and 0.025 took 18.9
        and 37.6 CPU s per strain and thread against 22.4 and 37.7 estimated);
        three-stage rkc takes 0.57 of the time (its stability interval over its stages;
        the reference run: 22 against 20.7). A suspension that pins none of FORMER_DEFAULTS:
        0.56 of that, with the present build: 0.44-0.47 of the cost of 4952f1d's build,
        benchmarks/records/build_compare_defaults.json, whose step was 1.22-1.26 times
        the profile's, build_compare.json). A capsule of another viscosity (lambda != 1)
        solves for its velocity each evaluation: lambda_cost_ratio times lambda 1's
        cost at lambda 1's step, the default; a dt_lambda_max given to a run at
        lambda > 1 grows the step by g = min((1 + lambda)/2, dt_lambda_max) and divides
        the cost by g^0.65, not g, as a longer step's solves take more GMRES iterations
        (measured at lambda 5, Ca 0.2, phi 0.1: 1.55 and 2.15 times less at g = 2 and
        3, docs/time_stepping.md). imex at a given
        time.tolerance T takes steps of about 0.50 sqrt(T) that bending does not
        shorten, each 1.15 times Heun's (measured at two dense bending points developed,
        where the model gives 1.64 and 1.23 times less than Heun against 1.62 and 1.27
        measured); at time.tolerance auto it is estimated as Heun (within 15 % at one of
        them from rest)."""
        per_level = 10.8 ** (self.level - 3)
        base = 0.5 if self.dilute else 17.5 * self.M / 27
        eb = membrane_codes.parse(self.membrane, "membrane").get("eb", 0.0)
        stiff = 1.0 + 4.0 * eb / (EDGE_LEVEL3 * 2.0 ** (3 - self.level)) ** 2
        given = self.trajectory_options()
        present = not self.dilute and not any(
            name in given and _same_value(option_value(given[name]), then)
            for name, then in FORMER_DEFAULTS.items())
        rkc3 = option_value(given.get("time.scheme", "")) == "rkc" and \
            str(option_value(given.get("time.stages", ""))) == "3"
        tolerance = given.get("gmres.tolerance")
        ratio = float(option_value(given.get("lambda", 1)))
        solved = lambda_cost_ratio(self.level, ratio, dense=not self.dilute,
                                   tolerance=None if tolerance is None
                                   else float(option_value(tolerance)))
        # The ratios were measured at lambda 1's step, the default; dt_lambda_max grows it.
        most = given.get("dt_lambda_max")
        if ratio > 1 and most is not None:
            solved /= min(0.5 * (1 + ratio), float(option_value(most))) ** 0.65
        # The time loop's cost against Heun's at the Table 1 point (dt = 0.2 h): Heun's
        # steps per strain, or imex's times the cost of its step.
        stepping = stiff * 0.2 / self.ca
        time_tolerance = option_value(given.get("time.tolerance", "auto"))
        if option_value(given.get("time.scheme", "")) == "imex" and \
                time_tolerance != "auto" and float(time_tolerance) > 0:
            edge = EDGE_LEVEL3 * 2.0 ** (3 - self.level)
            step = IMEX_STEP_PER_ROOT_TOLERANCE * math.sqrt(float(time_tolerance))
            stepping = 0.2 * edge / step * IMEX_STEP_COST
        return (base * per_level * stepping * (0.56 if present else 1.0)
                * (0.57 if rkc3 else 1.0) * solved)

    def segment_ends(self, minutes=None, strain=None):
        """The pause times of the run's segments and its t_end last: segments of
        `strain` units, or of about `minutes` of wall time by seconds_per_strain()
        (whole strain units, at least one); one segment when neither is given."""
        if strain is None and minutes is None:
            return [self.t_end]
        if strain is None:
            strain = max(1.0, math.floor(60.0 * minutes / self.seconds_per_strain()))
        count = max(1, math.ceil(self.t_end / strain - 1e-9))
        return [round(k * strain, 9) for k in range(1, count)] + [self.t_end]


def point_t_ends(block, key):
    """{(Ca, phi): t_end} of the points of a study block (the grid's) that run longer
    than its t_end (`t_end_at`: [{ca, phi, t_end}, ...], for the precision a point's
    averages need: t_end is not in a run's key, so such a run continues its record).
    A point not of the study, listed twice or shorter than t_end raises ValueError
    naming `key`."""
    def longer(entry):
        t_end = float(entry["t_end"])
        if t_end < float(block["t_end"]):
            raise ValueError(f"{key}: Ca {float(entry['ca']):g}, phi {float(entry['phi']):g}"
                             f": t_end {t_end:g} is below the study's {block['t_end']:g} "
                             "(a point runs longer, never shorter)")
        return t_end

    if not block.get("t_end_at"):
        return {}
    return membrane_codes.study_points(block["t_end_at"], block["ca"], block["phi"], key,
                                       longer)


def eblimit_grid_block(grid_block, eblimit_block):
    """The grid block as the runs of the limit eb -> 0 (config eblimit) take it: at a
    point that `eblimit.t_end_at` lists ({ca, phi, t_end}) their own t_end, elsewhere the
    grid's (grid.t_end_at). The run at half the modulus weighs twice the grid's run in
    the extrapolation 2 f(eb/2) - f(eb) (analysis/bending_limit.py) and costs less a
    strain unit, so for one standard error it pays to run it longer
    (docs/suspensions.md). A point without bending, or one listed twice or below the
    grid's t_end, raises ValueError naming eblimit.t_end_at."""
    own = eblimit_block.get("t_end_at") or []
    if not own:
        return grid_block
    ends = point_t_ends({**grid_block, "t_end_at": own}, "eblimit.t_end_at")
    bending = [(p.ca, p.phi) for p in bending_limit.points(grid_block)]
    for ca, phi in ends:
        if not any(math.isclose(ca, c) and math.isclose(phi, f) for c, f in bending):
            raise ValueError(f"eblimit.t_end_at: Ca {ca:g}, phi {phi:g} carries no bending "
                             "(grid.membranes), so the limit eb -> 0 has no runs there")
    kept = [entry for entry in grid_block.get("t_end_at", [])
            if (float(entry["ca"]), float(entry["phi"])) not in ends]
    return {**grid_block, "t_end_at": kept + list(own)}


def suspension(study, keys, block, averages_start, run_options):
    """The RunSpec of a suspension run of `study` with keys (ca, phi, M, level, seed[,
    membrane]) from its configuration block (t_end, or the point's own of t_end_at;
    snapshot_interval)."""
    t_end = point_t_ends(block, f"{study}.t_end_at").get(
        (float(keys["ca"]), float(keys["phi"])), block["t_end"])
    return RunSpec(study=study, ca=keys["ca"], phi=keys["phi"], M=keys["M"],
                   level=keys["level"], seed=keys["seed"],
                   membrane=keys.get("membrane", membrane_codes.PAPER), t_end=t_end,
                   t_avg_start=min(averages_start, 0.5 * t_end),
                   snapshot_interval=block.get("snapshot_interval", 0),
                   options=tuple(sorted(run_options.items())))


def dilute(ca, level, block):
    """The RunSpec of a dilute run from the configuration's dilute block (its options:
    further capsim options of every dilute run)."""
    return RunSpec(study="dilute", ca=ca, level=level, t_end=block["t_end"],
                   t_avg_start=block["t_avg_start"],
                   options=tuple(sorted(block.get("options", {}).items())))


def viscosity_ratio(ca, ratio, block, dilute_block):
    """The RunSpec of a run of the viscosity-ratio study (config viscosity_ratio): one
    capsule in unbounded shear at Ca, the block's mesh level and the viscosity ratio
    `ratio` (capsim's lambda), with the dilute block's options, as the dilute study's
    runs it is compared with. At ratio 1 with the dilute study's t_end it is the dilute
    study's own run (dilute()), computed once for both; otherwise a run of its own,
    ca<Ca>_level<level>_lambda<ratio> (at ratio 1 lambda is not set: the run is the
    dilute one to another t_end)."""
    level = int(block["mesh_level"])
    reference = dilute(ca, level, dilute_block)
    if float(ratio) == 1.0 and float(block["t_end"]) == float(dilute_block["t_end"]):
        return reference
    options = dict(reference.options) | ({} if float(ratio) == 1.0 else {"lambda": ratio})
    return dataclasses.replace(
        reference, study="viscosity_ratio", t_end=block["t_end"],
        t_avg_start=block["t_avg_start"], options=tuple(sorted(options.items())),
        label=f"ca{number(ca)}_level{level}_lambda{number(ratio)}")


def viscosity_ratio_dense(keys, ratio, grid_block, averages_start, run_options,
                          options=None):
    """The RunSpec of a dense run of the viscosity-ratio study (viscosity_ratio.dense): the
    grid's suspension at keys (ca, phi, M, level, seed) with interior viscosity `ratio`
    (capsim's lambda, != 1: at 1 the run is the grid's own) and the block's further
    options (gmres.tolerance), ca<Ca>_phi<phi>_M<M>_level<l>_seed<s>_lambda<ratio>. It runs
    to the grid's t_end: a point's longer t_end (grid.t_end_at) buys the lambda = 1 run's
    precision for the O(phi^3) shares, not this study's, where it would cost 10-20 times
    as much a strain."""
    if float(ratio) == 1.0:
        raise ValueError("viscosity_ratio.dense: lambda 1 is the grid's own run")
    block = {key: value for key, value in grid_block.items() if key != "t_end_at"}
    spec = suspension("viscosity_ratio", keys, block, averages_start,
                      dict(run_options) | dict(options or {}) | {"lambda": ratio})
    return dataclasses.replace(spec, label=f"{spec.name}_lambda{number(ratio)}")


def accuracy(setting, sample_interval):
    """The RunSpec of a setting of the accuracy study (analysis.accuracy.Setting), in the
    folder the study names: every setting is in the name. An adaptive step ends on every
    sample time, so the sample interval bounds it: it must not be what limits the step of
    the settings compared."""
    options = {"output.sample_interval": setting.sample_interval or sample_interval,
               "output.snapshot_interval": 0}
    options |= dict(o.split("=", 1) for o in time_options(setting.time))
    if setting.phi > 0:
        options["ewald.tolerance"] = setting.ewald
    return RunSpec(study="accuracy", ca=setting.ca, level=setting.level,
                   t_end=setting.t_end, t_avg_start=setting.window[0], phi=setting.phi,
                   M=setting.capsules, seed=setting.seed,
                   options=tuple(sorted(options.items())), label=setting.run)


def sensitivity(run, run_options, dilute_options):
    """The RunSpec of a run of the sensitivity study (analysis.sensitivity.Run), in the
    folder the study names. A suspension run gets `run_options` (config["run_options"],
    as every suspension run of the workflow), a dilute run `dilute_options` (the dilute
    block's options), as the dilute study's runs it is compared with. The membrane keys
    are always set, so that the code alone says which membrane a run carries whatever
    run_options hold; the code's own options come last (trajectory_options)."""
    options = dict(run_options if run.phi > 0 else dilute_options)
    options |= {"membrane.wrinkling": False, "membrane.bending": 0,
                "output.snapshot_interval": 0}
    return RunSpec(study="sensitivity", ca=run.ca, level=run.level, t_end=run.t_end,
                   t_avg_start=run.window[0], phi=run.phi, M=run.capsules, seed=run.seed,
                   membrane=run.membrane, options=tuple(sorted(options.items())),
                   label=run.name)
