"""Fuzzed input for `capsim run`, `capsim bench` and `capsim greens` (docs/reliability.md,
"Fuzzed run files").

The cases are generated deterministically: for every key that `capsim params` lists (the
solver's one table of keys, so this file holds no copy of it), values out of its range, of
the wrong type, empty, huge, NaN and infinite, unicode and with control characters, given
with --set and in run files; duplicated and unknown keys; malformed and truncated YAML;
--resume with bad or frozen keys; bad options of bench and greens. Each must end with exit
2 and one stderr line `capsim: error: ...` that names the key (or option, or file), with
no signal and no sanitizer report, must leave an existing run folder byte for byte as it
was, and must not create a fresh output folder.

Every case runs with build/capsim; when the sanitized build (build-sanitize/capsim, made
by scripts/test.sh) exists, a deterministic subset also runs with it (every case with
CAPSIM_FUZZ_SANITIZED=all).
"""

import hashlib
import json
import os
import random
import re
import shutil
import subprocess
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
CAPSIM = ROOT / "build" / "capsim"
SANITIZED = ROOT / "build-sanitize" / "capsim"
EXIT_CONFIG = 2
TIMEOUT_S = 60  # a case is cheap (rejected before any step); more means it hangs
SANITIZED_EVERY = 4  # the share of cases the sanitized binary runs (1 in N)
MAX_LINE = 2000  # the longest error line accepted (the unknown-key line lists every key)


@dataclass
class Case:
    name: str
    args: list  # after the binary; "{existing}", "{fresh}" and "{file}" are filled in
    names: tuple  # the error line must contain one of these
    run_file: str | None = None  # text of the run file, when the case has one
    expect_rc: int = EXIT_CONFIG


# ------------------------------------------------------------------ the keys and ranges

@dataclass
class Key:
    name: str
    kind: str  # "real", "integer" or "choice"
    lo: float = 0.0
    hi: float = 0.0
    lo_open: bool = False
    hi_open: bool = False
    choices: tuple = ()
    auto: bool = False  # 'auto' is allowed besides the range


RANGE = re.compile(r"(a number|an integer) in ([\[(])([^,]+), ([^\])]+)([\])])")


def parse_key(name, allowed):
    if allowed.startswith("one of {"):
        return Key(name, "choice", choices=tuple(allowed[8:-1].split(", ")))
    m = RANGE.search(allowed)
    assert m, f"{name}: cannot read its allowed values '{allowed}'"
    return Key(name, "integer" if m[1] == "an integer" else "real", float(m[3]),
               float(m[4]), m[2] == "(", m[5] == ")", auto="'auto'" in allowed)


def read_keys(binary):
    """Every key of `capsim params` with its allowed values."""
    out = subprocess.run([str(binary), "params"], capture_output=True, text=True,
                         check=True).stdout
    keys = []
    for line in out.splitlines()[2:]:
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        keys.append(parse_key(cells[0].strip("`"), cells[2]))
    assert len(keys) > 20
    return keys


# ------------------------------------------------------------------ values per key

# Wrong for every key: no number, no choice (but "true" of a boolean key), no 'auto'.
ALWAYS_BAD = ["", " ", "abc", "nan", "NaN", "-nan", ".nan", "inf", "-inf", ".inf",
              "Infinity", "1e400", "-1e400", "1e", "--1", "0,5", "1/2", "0.2.3",
              "0.2 apples", "\u0660\u066b\u0662", "\uff10\uff0e\uff12", "0.2\u00a0",
              "\U0001f642", "0.2\n0.3", "a\tb", "\x1b[31mred", "9" * 400,
              "1" + "0" * 330, "x" * 5000, "true", "null", "~", "[1, 2]", "{a: 1}"]


def bad_numbers(k):
    """Out of range for a number key: the open ends, just outside, far outside."""
    span = max(k.hi - k.lo, 1.0)
    values = [k.lo - span, k.hi + span, 1e308, 5e-324 if k.lo > 0 else k.lo - 1e-9]
    if k.lo_open:
        values.append(k.lo)
    if k.hi_open:
        values.append(k.hi)
    if k.lo > 0:
        values.append(-k.lo)
    if k.kind == "integer":
        values += [k.lo + 0.5, 2.0**31, 1e19]
    return [v for v in values if not in_range(k, v)]


def in_range(k, v):
    return (v > k.lo if k.lo_open else v >= k.lo) and (v < k.hi if k.hi_open else v <= k.hi)


def number_text(v):
    return str(int(v)) if float(v).is_integer() and abs(v) < 1e30 else repr(v)


def bad_choices(k):
    """Near misses of a choice key's first value, and words that are values of other keys
    ("auto" is one of ewald.precision's own)."""
    first = k.choices[0]
    values = [first.upper(), first + " ", " " + first, first[:-1], first + "x",
              first.replace(first[0], "\u00e9", 1), ",".join(k.choices), "1", "auto"]
    return [v for v in values if v not in k.choices]


def bad_values(k, index, share):
    """Bad values of key number `index`: its own out-of-range ones and `share` of
    ALWAYS_BAD, in turn, so that the keys together try every one of them."""
    start = index * share % len(ALWAYS_BAD)
    values = (ALWAYS_BAD * 2)[start:start + share]
    if k.kind == "choice":
        # "true" is bad for every key but a boolean one (a choice of true and false).
        values = [v for v in values if v not in k.choices] + bad_choices(k)
    else:
        values += [number_text(v) for v in bad_numbers(k)]
        values += ["AUTO", "auto "] if k.auto else ["auto"]
    return values


def good_values(k):
    """Values inside the range: accepted, so they meet the existing-run refusal."""
    if k.kind == "choice":
        return [c for c in k.choices if c != "cuda"]
    values = [v for v in (k.lo, k.hi, 0.5 * (k.lo + k.hi)) if in_range(k, v)]
    if k.kind == "integer":
        values = [float(round(v)) for v in values]
    # Big meshes and many capsules are valid but slow to set up: keep the small end.
    if k.name in ("mesh_level", "capsules", "threads"):
        values = [min(values)]
    return [number_text(v) for v in values] + (["auto"] if k.auto else [])


# ------------------------------------------------------------------ run files

def yaml_scalar(text):
    """A YAML double-quoted scalar holding exactly `text` (JSON's escapes are YAML's)."""
    return json.dumps(text, ensure_ascii=False)


def yaml_entry(key, value_text):
    """`a.b: v` as nested YAML, `a:\\n  b: v`, as run.yaml writes it."""
    parts = key.split(".")
    return "".join("  " * i + p + ":\n" for i, p in enumerate(parts[:-1])) + \
        "  " * (len(parts) - 1) + parts[-1] + ": " + value_text + "\n"


# Set before the fuzzed key, so that a value accepted by mistake costs a short run only.
TINY = ["--set", "mesh_level=1", "--set", "t_end=0.01", "--set", "t_avg_start=0"]


def run_set_cases(keys):
    cases = []
    for n, k in enumerate(keys):
        for i, v in enumerate(bad_values(k, n, 3)):
            cases.append(Case(f"run --set {k.name} #{i}",
                              ["run", "-q", *TINY, "--set", f"{k.name}={v}", "-o",
                               "{fresh}"], (k.name,)))
    return cases


def run_file_cases(keys):
    cases = []
    for n, k in enumerate(keys):
        for i, v in enumerate(bad_values(k, n + 3, 2)[:4]):
            cases.append(Case(f"run file {k.name} #{i}", ["run", "-q", "{file}", "-o",
                                                          "{existing}"],
                              (k.name,), run_file=yaml_entry(k.name, yaml_scalar(v))))
        for i, v in enumerate(good_values(k)[:2]):
            # Accepted values: the existing run folder must still be refused.
            cases.append(Case(f"run file {k.name} valid #{i}",
                              ["run", "-q", "{file}", "-o", "{existing}"],
                              ("already holds a run", k.name),
                              run_file=yaml_entry(k.name, v)))
        # The same key twice: in one form, and nested against dotted.
        twice = yaml_entry(k.name, yaml_scalar(good_values(k)[0])) * 2
        cases.append(Case(f"run file {k.name} twice", ["run", "-q", "{file}", "-o",
                                                       "{existing}"], (k.name,),
                          run_file=twice))
        if "." in k.name:
            both = (yaml_entry(k.name, yaml_scalar(good_values(k)[0])) +
                    f"{k.name}: {yaml_scalar(good_values(k)[-1])}\n")
            cases.append(Case(f"run file {k.name} nested and dotted",
                              ["run", "-q", "{file}", "-o", "{existing}"], (k.name,),
                              run_file=both))
        # A key given a list or a map instead of one value.
        for i, shape in enumerate(["[1, 2]", "{x: 1}", "", "[]", "{}"][n % 5:n % 5 + 2]):
            cases.append(Case(f"run file {k.name} shape #{i}",
                              ["run", "-q", "{file}", "-o", "{existing}"], (k.name,),
                              run_file=yaml_entry(k.name, shape)))
    return cases


UNKNOWN_KEYS = ["viscosity_ratio", "Ca", "CA", "ca ", " ca", "quadrature", "quadrature.",
                ".ca", "ca.x", "quadrature.far", "output", "ewald.xi.x", "t-end",
                "m\u00e9thod", "\u043c\u0435\u0442\u043e\u0434", "key\nwith newline",
                "key\x07bell", "k" * 3000]


def unknown_key_cases():
    cases = []
    for i, key in enumerate(UNKNOWN_KEYS):
        shown = re.split(r"[\x00-\x1f]", key.strip(" ."))[0][:40] or "."
        # YAML allows keys of at most 1024 characters: a longer one is a YAML error.
        in_file = (shown,) if len(key) <= 1024 else ("{file}",)
        cases.append(Case(f"run --set unknown #{i}",
                          ["run", "-q", "--set", f"{key}=1", "-o", "{fresh}"],
                          ("unknown key",), ))
        cases.append(Case(f"run file unknown #{i}", ["run", "-q", "{file}", "-o",
                                                     "{existing}"],
                          in_file, run_file=f"{yaml_scalar(key)}: 1\n"))
    for i, arg in enumerate(["ca", "=0.3", "", "=", "ca0.3"]):
        cases.append(Case(f"run --set malformed #{i}",
                          ["run", "-q", "--set", arg, "-o", "{fresh}"], ("--set",)))
    return cases


# Whole files: not YAML, not a map, odd YAML features.
BROKEN_FILES = [
    "ca: [0.3", "{ca: 0.3", "ca: 'x", 'ca: "x', "ca: 0.3\n  phi: 0.1\n", "\tca: 0.3\n",
    "- ca: 0.3\n", "0.3\n", "just text\n", "ca: *alias\n", "ca: &a 0.3\nphi: *a\n",
    "? [ca, phi]\n: 0.3\n", "[ca]: 0.3\n", "ca: !!binary aGVsbG8=\n", "ca: !custom 0.3\n",
    "---\nca: 0.3\n---\nca: -1\n", "...\n", "%YAML 9.9\n---\nca: 0.3\n",
    "\ufeffca: -0.3\n", "ca: 0.3\x00phi: 0.1\n", "a:\n" + "  " * 200 + "b: 1\n",
    "x: " + "[" * 3000 + "]" * 3000 + "\n", "x: " + "{a: " * 3000 + "1" + "}" * 3000,
    "ca: 0.3\n" + "# comment\n" * 1000 + "ca: 0.4\n", "ca: |\n  0.3\n  0.4\n",
    "ca: >\n  0.3\n", "ca: 0x10\n", "ca: 1_000\n", "ca: 0o7\n",
]


def any_name(keys):
    """What the error line about a whole run file may name: the file, a key, the folder."""
    return ("{file}", "unknown key", "already holds a run", *(k.name for k in keys))


def broken_file_cases(keys):
    return [Case(f"run file broken #{i}", ["run", "-q", "{file}", "-o", "{existing}"],
                 any_name(keys), run_file=text) for i, text in enumerate(BROKEN_FILES)]


def truncated_file_cases(keys, existing_run_yaml, rng):
    """run.yaml of a real run cut at many points, and with bytes flipped: whatever is
    left, the existing folder is refused (or the file is) and stays as it was."""
    text = existing_run_yaml
    cuts = sorted(set(rng.randrange(1, len(text)) for _ in range(40)))
    cases = [Case(f"run file truncated at {c}", ["run", "-q", "{file}", "-o", "{existing}"],
                  any_name(keys), run_file=text[:c]) for c in cuts]
    for i in range(20):
        chars = list(text)
        for _ in range(3):
            chars[rng.randrange(len(chars))] = chr(rng.choice([0x20, 0x3a, 0x7b, 0x5b,
                                                               0x22, 0x27, 0x26, 0x2a,
                                                               0x09, 0x0a, 0xe9]))
        cases.append(Case(f"run file flipped #{i}", ["run", "-q", "{file}", "-o",
                                                     "{existing}"],
                          any_name(keys), run_file="".join(chars)))
    return cases


# Suspensions (phi > 0) whose keys are each in range but together cannot be set up, or
# only at a cost out of proportion: refused in one line, or set up quickly and then
# refused for the existing folder.
SUSPENSION = "phi: 0.3\ncapsules: 2\nmesh_level: 1\n"
COMBINATIONS = [
    "ewald:\n  xi: 1e-9\n", "ewald:\n  xi: 100\n", "ewald:\n  xi: 0.01\n",
    "ewald:\n  tolerance: 1e-12\n  xi: 100\n", "method: direct\newald:\n  xi: 100\n",
    "method: direct\newald:\n  xi: 1e-6\n", "method: patches\newald:\n  patch_level: 3\n",
    "phi: 0.45\nsuspension:\n  min_gap: 2\n", "capsules: 10000\nphi: 0.0001\n",
    "phi: 0\ncapsules: 2\n", "t_end: 1\nt_avg_start: 1\n", "t_end: 1e-300\n",
    "dt: 1e-300\n", "t_end: 100000\ndt: 1e-12\n", "output:\n  sample_interval: 1e-300\n",
    "output:\n  checkpoint_interval: 1e-300\n", "dt_safety: 1e-300\nca: 1e-300\n",
]


def combination_cases(keys):
    return [Case(f"run file combination #{i}", ["run", "-q", "{file}", "-o", "{existing}"],
                 any_name(keys), run_file=SUSPENSION + extra)
            for i, extra in enumerate(COMBINATIONS)]


def resume_cases(keys):
    cases = []
    for n, k in enumerate(keys):
        frozen = not (k.name in ("t_end", "t_avg_start", "threads", "backend")
                      or k.name.startswith("output."))
        values = good_values(k)[:1] if frozen else bad_values(k, n + 5, 2)[:5]
        for i, v in enumerate(values):
            cases.append(Case(f"run --resume --set {k.name} #{i}",
                              ["run", "-q", "--resume", "{existing}", "--set",
                               f"{k.name}={v}"], (k.name,)))
    cases += [
        Case("run --resume with -o", ["run", "-q", "--resume", "{existing}", "-o",
                                      "{fresh}"], ("--resume",)),
        Case("run --resume with a run file", ["run", "-q", "{file}", "--resume",
                                              "{existing}"], ("--resume",),
             run_file="ca: 0.3\n"),
        Case("run --resume unknown key", ["run", "-q", "--resume", "{existing}", "--set",
                                          "nonsense=1"], ("nonsense",)),
    ]
    return cases


def command_line_cases():
    """The command line itself: missing -o, missing run file, unknown options."""
    return [
        Case("run without -o", ["run", "-q", "--set", "ca=0.3"], ("-o",)),
        Case("run missing file", ["run", "-q", "no/such/file.yaml", "-o", "{fresh}"],
             ("no/such/file.yaml",)),
        Case("run folder as file", ["run", "-q", "{existing}", "-o", "{fresh}"],
             ("{existing}",)),
        Case("run unknown option", ["run", "--frobnicate", "-o", "{fresh}"],
             ("--frobnicate",)),
        Case("run -o empty", ["run", "-q", "-o", ""], ("-o",)),
        Case("run -o is a file", ["run", "-q", "-o", "{existing}/run.yaml"],
             ("run.yaml",)),
        Case("no subcommand", [], ("command is required",)),
        Case("unknown subcommand", ["frobnicate"], ("frobnicate",)),
    ]


# ------------------------------------------------------------------ bench and greens

BAD_REALS = ["nan", "inf", "-inf", "abc", "", "1e400", "\uff11"]
BAD_INTS = ["nan", "abc", "", "2.5", "1e400", "99999999999", "-99999999999"]

# (option, extra bad values): the valid rest of the command keeps each case cheap.
BENCH_OPTIONS = [
    ("--capsules", BAD_INTS + ["0", "-1", "100001"]),
    ("--mesh-level", BAD_INTS + ["-1", "6", "40"]),
    ("--phi", BAD_REALS + ["0", "-0.1", "0.46", "1e300"]),
    ("--method", ["", "SPECTRAL", "ewald", "\u00e9"]),
    ("--patch-level", BAD_INTS + ["-1", "2"]),
    ("--tolerance", BAD_REALS + ["0", "1", "1e-13", "-1e-4"]),
    ("--strain", BAD_REALS),
    ("--seed", BAD_INTS + ["-1"]),
    ("--xi", BAD_REALS + ["-1", "1e-300", "1e300", "101"]),
    ("--repeats", BAD_INTS + ["0", "101", "-5"]),
    ("--threads", BAD_INTS + ["-1", "1000000"]),
]
BENCH_BASE = {"--capsules": "2", "--mesh-level": "1", "--phi": "0.1",
              "--tolerance": "1e-3", "--repeats": "1", "--patch-level": "1"}

GREENS_OPTIONS = [
    ("--box", BAD_REALS + ["0", "-1", "1e7", "1e-300"]),
    ("--strain", BAD_REALS),
    ("--xi", BAD_REALS + ["-1", "1e-6", "1e6", "1e300"]),
    ("--tolerance", BAD_REALS + ["0", "1", "1e-17", "-1e-6"]),
]


def bench_cases():
    cases = []
    for option, values in BENCH_OPTIONS:
        for i, v in enumerate(values):
            args = dict(BENCH_BASE, **{option: v})
            flat = [x for kv in args.items() for x in kv]
            cases.append(Case(f"bench {option} #{i}", ["bench", "--no-reference", *flat],
                              (option,)))
    cases.append(Case("bench unknown option", ["bench", "--frobnicate", "1"],
                      ("--frobnicate",)))
    return cases


def greens_cases():
    base = ["--box", "2", "--point", "0.3", "0.2", "0.1"]
    cases = []
    for option, values in GREENS_OPTIONS:
        for i, v in enumerate(values):
            args = list(base)
            if option == "--box":
                args[1] = v
            else:
                args += [option, v]
            cases.append(Case(f"greens {option} #{i}", ["greens", *args], (option,)))
    points = [["nan", "0", "0"], ["inf", "0", "0"], ["0", "0"], ["0", "0", "0", "0"],
              ["abc", "0", "0"], ["1e400", "0", "0"], ["0", "0", "0"], ["2", "2", "2"],
              ["1e300", "0", "0"]]
    for i, p in enumerate(points):
        cases.append(Case(f"greens --point #{i}", ["greens", "--box", "2", "--point", *p],
                          ("--point",)))
    cases.append(Case("greens without --box", ["greens", "--point", "1", "0", "0"],
                      ("--box",)))
    return cases


# ------------------------------------------------------------------ running the cases

def tree_digest(folder):
    """Every file under `folder` with its SHA-256 (and nothing else is there)."""
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def memory_limit(binary):
    """A case that is accepted by mistake may allocate without bound (an earlier capsim
    asked for 23 GB): the plain binary runs under a 4 GB address-space limit. The
    sanitized one reserves terabytes of address space for its shadow memory, so it runs
    without."""
    prlimit = shutil.which("prlimit")
    if binary == SANITIZED or not prlimit:
        return []
    return [prlimit, f"--as={4 << 30}"]


def run_case(binary, case, index, workdir, existing, existing_digest):
    work = workdir / f"case{index:04d}"
    work.mkdir()
    fresh = work / "fresh"
    run_file = work / "run.yaml"
    if case.run_file is not None:
        run_file.write_bytes(case.run_file.encode("utf-8", "surrogatepass"))
    fill = {"{existing}": str(existing), "{fresh}": str(fresh), "{file}": str(run_file)}

    def filled(text):
        for k, v in fill.items():
            text = text.replace(k, v)
        return text

    args = [filled(a) for a in case.args]
    names = [filled(n) for n in case.names]
    try:
        proc = subprocess.run([*memory_limit(binary), str(binary), *args],
                              capture_output=True, timeout=TIMEOUT_S,
                              env=dict(os.environ, OMP_NUM_THREADS="1"))
    except subprocess.TimeoutExpired:
        return f"{case.name}: still running after {TIMEOUT_S} s"
    if "{existing}" in case.args and tree_digest(existing) != existing_digest:
        return f"{case.name}: changed the existing run folder"
    return judge(case, proc, names, fresh)


def judge(case, proc, names, fresh):
    err = proc.stderr.decode("utf-8", "replace")
    lines = [line for line in err.splitlines() if line.strip()]
    where = f"{case.name}: exit {proc.returncode}, stderr {err[-600:]!r}"
    if proc.returncode < 0:
        return f"{where} (killed by signal {-proc.returncode})"
    if "Sanitizer" in err or "runtime error" in err:
        return f"{where} (sanitizer report)"
    if proc.returncode != case.expect_rc:
        return f"{where} (expected exit {case.expect_rc})"
    if len(lines) != 1 or not lines[0].startswith("capsim: error: "):
        return f"{where} (expected one line 'capsim: error: ...')"
    if len(lines[0]) > MAX_LINE:
        return f"{case.name}: an error line of {len(lines[0])} characters"
    if not any(n in lines[0] for n in names):
        return f"{where} (the line names none of {names})"
    if fresh.exists():
        return f"{where} (left the fresh output folder: {sorted(os.listdir(fresh))})"
    return None


def all_cases(keys, run_yaml):
    rng = random.Random(20261201)
    return (run_set_cases(keys) + run_file_cases(keys) + unknown_key_cases() +
            broken_file_cases(keys) + truncated_file_cases(keys, run_yaml, rng) +
            combination_cases(keys) +
            resume_cases(keys) + command_line_cases() + bench_cases() + greens_cases())


@pytest.fixture(scope="module")
def existing_run(capsim_run):
    """A finished tiny run: the folder that no case may change."""
    return capsim_run("existing", "mesh_level=1", "t_end=0.1", "t_avg_start=0",
                      "output.snapshot_interval=0.1")


def binaries():
    every = 1 if os.environ.get("CAPSIM_FUZZ_SANITIZED") == "all" else SANITIZED_EVERY
    return [pytest.param(CAPSIM, 1, id="plain"),
            pytest.param(SANITIZED, every, id="sanitized", marks=pytest.mark.skipif(
                not SANITIZED.exists(),
                reason="build-sanitize/capsim is missing (scripts/test.sh builds it)"))]


@pytest.mark.parametrize("binary, every", binaries())
def test_bad_input_is_refused_in_one_line(binary, every, existing_run, tmp_path):
    keys = read_keys(CAPSIM)
    cases = all_cases(keys, (existing_run / "run.yaml").read_text())[::every]
    before = tree_digest(existing_run)
    with ThreadPoolExecutor(max_workers=2) as pool:
        failures = [f for f in pool.map(
            lambda ic: run_case(binary, ic[1], ic[0], tmp_path, existing_run, before),
            enumerate(cases)) if f]
    print(f"{len(cases)} fuzz cases with {binary.relative_to(ROOT)}")
    assert tree_digest(existing_run) == before, "a case changed the existing run"
    report = os.environ.get("CAPSIM_FUZZ_REPORT")  # every failure, for fixing them
    if report:
        Path(report).write_text("\n".join(failures) + "\n")
    assert not failures, f"{len(failures)} of {len(cases)} cases failed:\n" + \
        "\n".join(failures[:60])
