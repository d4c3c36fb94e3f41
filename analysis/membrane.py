"""Membrane codes: which regularisation of the paper's membrane a run carries, in one word.

The paper's membrane (neo-Hookean, eq. 2.11, no bending) folds at the element scale in
strongly stretched capsules (docs/suspensions.md, "Hard cases"); capsim has two
regularisers, both off by default (docs/usage.md): the relaxed (tension-field) membrane
`membrane.wrinkling` and a hinge bending modulus `membrane.bending` eb = kb / (Gs a^2).
A code names a run's membrane and, where a point needs them, a stronger repulsion
between capsules or another time scheme:

    paper                 nothing added (alone only)
    wrinkling             --set membrane.wrinkling=true
    eb<value>             --set membrane.bending=<value>, 0 < value <= 1 (capsim's range)
    rep<value>            --set suspension.repulsion_force=<value>, 0 < value <= 100
    consistent            --set membrane.load=consistent --set dt_safety=0.2
    imex                  --set time.scheme=imex --set time.tolerance=auto
    imex<value>           --set time.scheme=imex --set time.tolerance=<value>,
                          0 < value <= 0.1

joined by "+", e.g. wrinkling+eb0.01, eb0.025+rep5, rep5+consistent, eb0.01+imex or
eb0.025+rep5+imex0.001 (imex at 1e-3 runs a dense bending point from rest in 2.35 times
less wall time than Heun at no larger time error, and the developed suspension at
eb 0.025, phi 0.4 in 1.2-2.3 times less: docs/time_stepping.md).
consistent is the load mapping that carries the paper's membrane where the lumped one
folds (docs/suspensions.md, "The paper's membrane by the consistent load"), at the step it
needs; like the repulsion and the time scheme it is not part of the membrane. rep is for the dense
points whose capsules come into contact at the configuration's repulsion
(docs/suspensions.md, "Hard cases"); it overrides run_options' suspension.repulsion_force
for that run only. The canonical spelling (canonical()) orders the tokens as above and
writes the values with %g; it is what run folders, tables and figure footers show.
code_from_parameters() reads the membrane part back from a run's summary.json
parameters, so a table says which membrane each run carried even where it was not
planned by code (every study's table, analysis.tables).
"""

import math
import re

# The configuration key whose codes these are: named in every error, so that a bad code
# in the configuration is found at once.
CONFIG_KEY = "sensitivity.membranes"
ALLOWED = ("paper (alone), or wrinkling, eb<kb/(Gs a^2), 0 < eb <= 1>, rep<F0 in "
           "mu gammadot a^2, 0 < F0 <= 100>, consistent and imex[<time.tolerance, "
           "0 < tol <= 0.1>] joined by + (e.g. wrinkling, eb0.05, wrinkling+eb0.01, "
           "eb0.025+rep5, consistent, eb0.01+imex, eb0.025+rep5+imex0.001)")
PAPER = "paper"
# The tokens with a value: the value's name in errors, the upper end of its range
# (0, high] (capsim's; for imex the auto tolerance's, run_options.cpp checks them again)
# and what to write instead of a zero. imex alone takes time.tolerance auto.
VALUED = {"eb": ("bending modulus", 1.0, "eb0 is the paper's membrane: write paper"),
          "rep": ("repulsion force", 100.0, "leave rep out for run_options' repulsion"),
          "imex": ("time tolerance", 0.1, "imex alone takes time.tolerance auto")}
VALUE = re.compile(r"^(eb|rep|imex)([0-9.eE+-]+)$")
ORDER = ("wrinkling", "eb", "rep", "consistent", "imex")  # the canonical order of the tokens


def parse(code, key=CONFIG_KEY):
    """The tokens of a code as a dict {"wrinkling": True, "eb": value, "rep": value,
    "consistent": True, "imex": True or its tolerance} (only those present; {} for
    paper). Raises ValueError naming the configuration key `key`
    (sensitivity.membranes) and the allowed forms for anything else."""
    def _error(code, why):
        return ValueError(f"{key}: membrane '{code}' {why}; allowed: {ALLOWED}")

    if not isinstance(code, str) or not code:
        raise _error(code, "is not a code")
    if code == PAPER:
        return {}
    tokens = {}
    for token in code.split("+"):
        match = VALUE.match(token)
        if token == PAPER:
            raise _error(code, "uses paper with other tokens (paper is alone only)")
        if match:
            name, text = match.groups()
            what, high, instead = VALUED[name]
            try:
                value = float(text)
            except ValueError:
                raise _error(code, f"has a {what} '{text}' that is not a number") from None
            if not math.isfinite(value) or value <= 0 or value > high:
                raise _error(code, f"has a {what} {text} outside 0 < {name} <= {high:g} "
                                   f"({instead})")
        elif token in ("wrinkling", "consistent", "imex"):
            name, value = token, True
        else:
            raise _error(code, f"has an unknown token '{token}'")
        if name in tokens:
            raise _error(code, f"repeats {name}")
        tokens[name] = value
    return tokens


def spell(tokens):
    """A code from parsed tokens (parse()'s inverse, in the canonical spelling)."""
    words = [f"{key}{tokens[key]:g}" if tokens[key] is not True else key
             for key in ORDER if key in tokens]
    return "+".join(words) if words else PAPER


def canonical(code, key=CONFIG_KEY):
    """The code in its canonical spelling: tokens in the order wrinkling, eb, rep,
    consistent, imex; values with %g (eb0.050+wrinkling -> wrinkling+eb0.05). A bad code
    raises ValueError naming `key`."""
    return spell(parse(code, key))


def options(code):
    """The capsim `--set` options (key=value strings) of a code, in the canonical order."""
    tokens = parse(code)
    out = []
    if "wrinkling" in tokens:
        out.append("membrane.wrinkling=true")
    if "eb" in tokens:
        out.append(f"membrane.bending={tokens['eb']:g}")
    if "rep" in tokens:
        out.append(f"suspension.repulsion_force={tokens['rep']:g}")
    if "consistent" in tokens:
        # The consistent mass-matrix solve is stable only at a fifth of Heun's step
        # (capsim refuses more: docs/usage.md).
        out += ["membrane.load=consistent", "dt_safety=0.2"]
    if "imex" in tokens:
        # imex at the code's tolerance, or at the one whose time error is a tenth of the
        # mesh error (time.tolerance auto, docs/method.md).
        tolerance = tokens["imex"]
        out += ["time.scheme=imex",
                "time.tolerance=" + ("auto" if tolerance is True else f"{tolerance:g}")]
    return out


def membrane_part(code):
    """The membrane of a code without its repulsion, load mapping and time scheme
    (eb0.01+rep5+consistent+imex -> eb0.01): what code_from_parameters reads back from the
    run."""
    return spell({k: v for k, v in parse(code).items()
                  if k not in ("rep", "consistent", "imex")})


def bending(code):
    """The bending modulus eb of a code (0 without one)."""
    return float(parse(code).get("eb", 0.0))


def is_pure_bending(code):
    """Whether a code is eb<value> alone: only bending, the paper's time scheme."""
    return set(parse(code)) == {"eb"}


def _flag(value):
    if isinstance(value, str):
        return value.strip().lower() in ("true", "1", "yes", "on")
    return bool(value)


def code_from_parameters(parameters):
    """The membrane code of a run from its summary.json "parameters": membrane.wrinkling
    and membrane.bending ("paper", "wrinkling", "eb0.05", "wrinkling+eb0.01"). A summary
    of a version without these keys ran the paper's membrane. The time scheme is not part
    of it, nor the repulsion: neither changes the membrane."""
    tokens = {}
    if _flag(parameters.get("membrane.wrinkling", False)):
        tokens["wrinkling"] = True
    eb = float(parameters.get("membrane.bending", 0.0) or 0.0)
    if eb > 0:
        tokens["eb"] = eb
    return spell(tokens)


def study_points(entries, cas, phis, key, value):
    """{(Ca, phi): value(entry)} of a list of a study's points ([{ca, phi, ...}, ...]).
    Each point must be one of the study's (Ca in cas, phi in phis) and listed once; a bad
    point raises ValueError naming `key`, as `value` does for a bad entry."""
    def match(v, values):  # the study's own value, as its keys hold it
        return next((float(u) for u in values if math.isclose(v, float(u))), None)

    out = {}
    for entry in entries:
        ca, phi = float(entry["ca"]), float(entry["phi"])
        point = (match(ca, cas), match(phi, phis))
        if None in point:
            raise ValueError(f"{key}: Ca {ca:g}, phi {phi:g} is not a point of the study "
                             f"(Ca in {list(cas)}, phi in {list(phis)})")
        if point in out:
            raise ValueError(f"{key}: Ca {point[0]:g}, phi {point[1]:g} is listed twice")
        out[point] = value(entry)
    return out


def point_membranes(entries, cas, phis, key):
    """{(Ca, phi): canonical code} of a study's list of points that carry another membrane
    (config grid.membranes: [{ca, phi, membrane}, ...]), checked as study_points() does;
    a bad code raises ValueError naming `key`."""
    return study_points(entries, cas, phis, key, lambda e: canonical(e["membrane"], key))

