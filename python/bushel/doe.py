"""Designed experiments from Python, as `bushel doe` does them (docs/doe.md): designs in the
factors' own units, campaigns of runs (parallel jobs or MPI ranks, resumable), least-squares
response models with Minitab's statistics, the factor settings that hit a target, and the
compromise over several responses (desirability).

    d = bushel.doe.design("ccd", {"fs_ww": (0.2, 0.4), "fr_ww": (0.005, 0.02)}, centre=3, seed=1)
    c = bushel.doe.run(d, "runs/camp", scenario="scenarios/calibration-cup.yaml",
                       responses=["bulk_density"], jobs=2)
    m = bushel.doe.fit(c.values, c.responses["bulk_density"], d.ranges, model="quadratic")
    m.r2, m.coefficients, m.predict({"fs_ww": 0.3, "fr_ww": 0.01}), m.solve(826.1)
    bushel.doe.optimize({"bulk_density": m, "heap_angle": m2}, {"bulk_density": "target:826.1:820:832", ...})
"""
import csv
import json
import os
import shutil
import subprocess
import sys
from dataclasses import dataclass

import numpy as np

from ._bushel import InputError, _Factor, _build, _design, _fit, _maximize_desirability


def _ranges(ranges):
    names = list(ranges)
    low = np.array([float(ranges[n][0]) for n in names])
    high = np.array([float(ranges[n][1]) for n in names])
    if np.any(high <= low):
        raise ValueError(f"each factor's range must be (low, high) with high > low: {ranges}")
    return names, low, high


def _coded(x, low, high):
    """Factors' values (last axis in the order of the ranges) -> coded levels (-1 .. 1)."""
    return (np.asarray(x, dtype=float) - (low + high) / 2) / ((high - low) / 2)


def _uncoded(coded, low, high):
    """Coded levels -> the factors' values."""
    return (low + high) / 2 + np.asarray(coded, dtype=float) * (high - low) / 2


@dataclass
class Design:
    """Runs in standard order: coded levels (-1 .. 1) and the factors' values."""
    kind: str
    ranges: dict           # name -> (low, high), the levels at -1 and +1
    coded: np.ndarray      # runs x factors
    values: dict           # name -> array of the runs' values
    block: np.ndarray      # per run, from 1
    centre: np.ndarray     # per run: a centre point
    run_order: np.ndarray  # per run: its position when run (random with a seed), from 1
    point_type: np.ndarray  # per run, Minitab's: 1 corner, 0 centre, -1 axial, 2 edge
    csv: str               # the table `bushel doe design` writes (run order, 6 digits)

    def to_csv(self, path):
        """Writes the design table (as `bushel doe design --out` does) to `path`."""
        _write_atomically(path, self.csv)

    def rows(self, in_run_order=True):
        """The runs as {name: value} dicts, in run order (or standard order)."""
        order = np.argsort(self.run_order) if in_run_order else np.arange(len(self.run_order))
        return [{n: float(self.values[n][i]) for n in self.values} for i in order]


def design(kind, ranges, runs=None, centre=0, ccd="circumscribed", blocks=1, seed=None):
    """A design: kind "plackett-burman" (runs 12, 20 or 24), "factorial" (full, with `centre`
    centre points), "ccd" (type `ccd`: circumscribed, face, inscribed; `blocks` 1 or 2),
    "box-behnken" or "lhs" (a latin hypercube of `runs`; needs `seed`). `ranges`: {name:
    (low, high)}. With `seed` the run order is random (reproducible)."""
    names, low, high = _ranges(ranges)
    d = _design(kind, [_Factor(n, lo, hi) for n, lo, hi in zip(names, low, high)], int(runs or 0), int(centre), ccd,
                int(blocks), seed)
    coded = np.asarray(d["coded"])
    x = _uncoded(coded, low, high)
    values = {n: x[:, i] for i, n in enumerate(names)}
    return Design(d["kind"], dict(ranges), coded, values, np.asarray(d["block"]), np.asarray(d["centre"]),
                  np.asarray(d["run_order"]), np.asarray(d["point_type"]), d["csv"])


class Model:
    """A fitted response model (coded units inside; factors' values outside)."""

    def __init__(self, fit, ranges):
        self._fit = fit
        self.ranges = dict(ranges)
        self._names, self._low, self._high = _ranges(ranges)
        for k in ("s", "r2", "r2_adjusted", "r2_predicted", "runs", "error_df", "coefficients", "anova"):
            setattr(self, k, getattr(fit, k))

    def coded(self, point):
        """{name: value} -> coded levels."""
        return _coded([float(point[n]) for n in self._names], self._low, self._high)

    def value(self, coded):
        """Coded levels -> {name: value}."""
        return {n: float(v) for n, v in zip(self._names, _uncoded(coded, self._low, self._high))}

    def predict(self, point):
        """The fitted response at {name: value}."""
        return self._fit.predict(self.coded(point))

    def prediction_interval(self, point, alpha=0.05):
        """(low, high) of the 1 - alpha prediction interval for a new run at {name: value}."""
        c = self.coded(point)
        y, h = self._fit.predict(c), self._fit.prediction_half_width(c, alpha)
        return y - h, y + h

    def solve(self, target, fixed=None, limit=1.0):
        """Factor values at which the model gives `target`, within the design's ranges
        (`limit` in coded units), with the factors in `fixed` ({name: value}) held; the point
        of the solution set nearest the centre's descent. Raises InputError if out of reach."""
        fixed = fixed or {}
        start = self.coded({n: fixed.get(n, (lo + hi) / 2) for n, lo, hi in zip(self._names, self._low, self._high)})
        held = [n in fixed for n in self._names]
        return self.value(self._fit.solve_for_target(float(target), float(limit), start, held))


def fit(values, y, ranges, model="quadratic", alpha=0.1):
    """Fits `model` ("main", "interactions", "quadratic") to responses `y` at the runs'
    `values` ({name: array}, in the units of `ranges`, {name: (low, high)}: the coding)."""
    names, low, high = _ranges(ranges)
    coded = _coded(np.column_stack([np.asarray(values[n], dtype=float) for n in names]), low, high)
    return Model(_fit(coded, np.asarray(y, dtype=float), names, model, float(alpha)), ranges)


def optimize(models, goals, fixed=None, weights=None, limit=1.0):
    """The factor settings that best meet several goals at once (Derringer and Suich's composite
    desirability D, as `bushel doe optimize --goal`). `models`: {response: Model}, fitted over
    the same factors and ranges; `goals`: {response: "target:T:L:U" | "minimize:T:U" |
    "maximize:L:T"} in the response's units; `weights`: {response: w > 0} (default 1);
    `fixed`: {factor: value} held. Returns {"settings": {factor: value}, "composite": D,
    "predicted": {response: y}, "desirability": {response: d}}."""
    names = list(models)
    if not names or set(goals) != set(names):
        raise InputError(f"expected a goal for each model and a model for each goal: models {names}, goals "
                         f"{list(goals)}")
    first = models[names[0]]
    for n in names[1:]:
        if models[n].ranges != first.ranges:
            raise InputError(f"the models of '{names[0]}' and '{n}' were fitted over different factors or ranges: "
                             f"{first.ranges} and {models[n].ranges}")
    weights = weights or {}
    for n, w in weights.items():
        if n not in models or not float(w) > 0:
            raise InputError(f"weights: expected a weight > 0 for a response of the models, got {n}={w}")
    fixed = fixed or {}
    unknown = [f for f in fixed if f not in first.ranges]
    if unknown:
        raise InputError(f"fixed: no factor {unknown}; the factors are {list(first.ranges)}")
    start = first.coded({f: fixed.get(f, (lo + hi) / 2) for f, (lo, hi) in first.ranges.items()})
    c = _maximize_desirability([models[n]._fit for n in names], [str(goals[n]) for n in names],
                               [float(weights.get(n, 1.0)) for n in names], float(limit), start,
                               [f in fixed for f in first.ranges])
    return {"settings": first.value(c["coded"]), "composite": c["composite"],
            "predicted": dict(zip(names, c["predicted"])), "desirability": dict(zip(names, c["individual"]))}


@dataclass
class Campaign:
    """A campaign's results table (results.csv): a row per run in standard order."""
    folder: str
    table: dict      # column -> numpy array (strings for `status`)
    values: dict     # factor -> array, in the design's units
    responses: dict  # response -> array (NaN where a run failed)
    status: np.ndarray

    @property
    def failed(self):
        """std_order of the runs that failed (their run_N/stderr.txt says why)."""
        return self.table["std_order"][self.status != "done"].astype(int)

    def dataframe(self):
        """The table as a pandas DataFrame (Debian's python3-pandas)."""
        import pandas
        return pandas.DataFrame(self.table)


_bookkeeping = ("std_order", "run_order", "center_pt", "pt_type", "block", "status")


def read_campaign(folder, responses):
    """The results of the campaign in `folder` (its results.csv), with the response columns
    `responses`; the other columns but the bookkeeping are the factors."""
    path = os.path.join(os.fspath(folder), "results.csv")
    if not os.path.exists(path):
        raise FileNotFoundError(f"{path}: no results.csv (not a `bushel doe run` campaign folder)")
    with open(path) as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    table = {}
    for k, name in enumerate(header):
        cells = [r[k] for r in body]
        table[name] = np.array(cells) if name == "status" else np.array([float(c) if c else np.nan for c in cells])
    missing = [r for r in responses if r not in table]
    if missing:
        raise InputError(f"{path}: no column {missing}; its columns are {header}")
    values = {n: table[n] for n in header if n not in _bookkeeping and n not in responses}
    return Campaign(os.fspath(folder), table, values, {n: table[n] for n in responses}, table["status"])


def program():
    """The `bushel` program of this package's build: $BUSHEL_PROGRAM, else the one beside the
    package (build/release/bin/bushel for the build tree's package, PREFIX/bin/bushel for an
    installed one), else `bushel` on the PATH. It must be the same build as the package."""
    here = os.path.dirname(os.path.abspath(__file__))
    candidates = [os.environ.get("BUSHEL_PROGRAM", ""), os.path.join(here, "..", "..", "bin", "bushel"),
                  os.path.join(here, "..", "..", "..", "..", "bin", "bushel"), shutil.which("bushel") or ""]
    for c in candidates:
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            c = os.path.normpath(c)
            line = subprocess.run([c, "--version"], capture_output=True, text=True).stdout.strip()
            if line != "bushel " + _build():
                raise InputError(f"{c} is another build ({line!r}) than this package (bushel {_build()}): set "
                                 f"BUSHEL_PROGRAM to the program of the package's build")
            return c
    raise InputError("the bushel program was not found beside the package nor on the PATH: set BUSHEL_PROGRAM")


def run(design, out, scenario=None, command=None, responses=(), jobs=1, threads=0, set=None,  # noqa: A002
        factors=None, ranks=None):
    """Runs a campaign as `bushel doe run` does (docs/doe.md) and returns its Campaign: one run
    per row of `design` (a Design, or the path of a design table), each in OUT/run_<std_order>/,
    `jobs` at a time (or on `ranks` MPI ranks: `mpirun -n ranks`, rank 0 handing out rows),
    resumable: called again, it skips the finished runs.

    scenario: a scenario file or dict; the design's factor columns are its parameters
      (`factors` names them when the design has others) and `responses` its results;
      `set` ({path: value}) fixed overrides for every row.
    command: instead of a scenario, a command per row (a list; "{column}" is the row's value,
      "{run_dir}" its folder, "{bushel}" the program), printing JSON with the `responses` keys.
    threads: threads per run (0: cores / jobs).
    Runs that fail are in Campaign.failed (with a warning); a bad campaign raises InputError
    before anything runs."""
    out = os.fspath(out)
    if (scenario is None) == (command is None):
        raise InputError("expected a scenario or a command, not both and not neither")
    if not responses:
        raise InputError("responses: expected the results (or JSON keys) to collect, e.g. ['bulk_density']")
    os.makedirs(out, exist_ok=True)
    if isinstance(design, Design):
        path = os.path.join(out, "design.csv")
        if os.path.exists(path) and open(path).read() != design.csv:
            raise InputError(f"{path}: the campaign folder holds another design; use a new folder")
        design.to_csv(path)
        design = path
    argv = [program(), "doe", "run", os.fspath(design), "--out", out, "--response", ",".join(responses),
            "--jobs", str(int(jobs)), "--threads", str(int(threads))]
    if scenario is not None:
        if isinstance(scenario, dict):
            path = os.path.join(out, "scenario.json")
            _write_atomically(path, json.dumps(scenario, indent=1))
            scenario = path
        argv += ["--scenario", os.fspath(scenario)]
        for k, v in (set or {}).items():
            argv += ["--set", f"{k}={v}"]
        if factors:
            argv += ["--factors", ",".join(factors)]
    else:
        argv += ["--"] + [str(a) for a in command]
    if ranks:
        # (rank 0 only hands out rows, so one rank more than the cores is the usual count)
        argv = [shutil.which("mpirun") or "mpirun", "--oversubscribe", "-n", str(int(ranks))] + argv
    errors = []
    with subprocess.Popen(argv, stderr=subprocess.PIPE, text=True) as p:  # (progress passed on as it comes)
        for line in p.stderr:
            sys.stderr.write(line)
            if line.startswith("bushel: error: "):
                errors.append(line[len("bushel: error: "):].strip())
    if p.returncode != 0:
        message = errors[-1] if errors else f"{argv[0]} ended with exit status {p.returncode}"
        if "runs failed" not in message:
            raise InputError(message)
        import warnings
        warnings.warn(message, RuntimeWarning, stacklevel=2)
    return read_campaign(out, responses)


def _write_atomically(path, text):
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)
