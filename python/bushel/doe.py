"""Designed experiments from Python, as `bushel doe` does them (docs/doe.md): designs in the
factors' own units, least-squares response models with Minitab's statistics, and the factor
settings that hit a target.

    d = bushel.doe.design("ccd", {"fs_ww": (0.2, 0.4), "fr_ww": (0.005, 0.02)}, centre=3, seed=1)
    y = [run(row) for row in d.rows()]          # e.g. bushel.run(..., set=row)
    m = bushel.doe.fit(d.values, y, d.ranges, model="quadratic")
    m.r2, m.coefficients, m.predict({"fs_ww": 0.3, "fr_ww": 0.01}), m.solve(826.1)
"""
from dataclasses import dataclass

import numpy as np

from ._bushel import _design, _fit


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
    d = _design(kind, len(names), int(runs or 0), int(centre), ccd, int(blocks), seed)
    coded = np.asarray(d["coded"])
    x = _uncoded(coded, low, high)
    values = {n: x[:, i] for i, n in enumerate(names)}
    return Design(d["kind"], dict(ranges), coded, values, np.asarray(d["block"]), np.asarray(d["centre"]),
                  np.asarray(d["run_order"]))


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
