"""Sequential Bayesian calibration of a simulation's parameters against measured targets
(docs/calibration.md): a Latin hypercube to start, then batches of runs where Gaussian-process
surrogates of the responses say the targets are most likely met, until a run confirms a point
that the posterior puts within every target's tolerance, or the run budget is spent.

    p = [bushel.calibrate.Parameter("fs_ww", 0.1, 0.4), bushel.calibrate.Parameter("fr_ww", 0.0, 0.1)]
    t = [bushel.calibrate.Target("bulk_density", value=826.1, sd=1.2, tolerance=2.0)]
    result = bushel.calibrate.calibrate(p, t, evaluate, bushel.calibrate.Settings(batch=2, budget=20))
    result.best, result.status, result.posterior

`evaluate(points, batch)` runs the simulation at each point ({name: value}) and returns per
point {target name: value, or None where the run failed}. `bushel calibrate` (calibration_run.py)
evaluates through campaigns of scenario runs, resumably.
"""
from dataclasses import dataclass, field

import numpy as np
from scipy.stats import qmc

from . import surrogate


@dataclass
class Parameter:
    """A calibrated parameter: its range, and optionally a normal prior (truncated to it)."""
    name: str
    low: float
    high: float
    prior_mean: float = None
    prior_sd: float = None

    def value(self, u):
        return self.low + np.asarray(u) * (self.high - self.low)

    def unit(self, x):
        return (np.asarray(x, float) - self.low) / (self.high - self.low)


@dataclass
class Target:
    """A measured value of one response [the response's SI unit] with its standard deviation
    `sd` and the `tolerance` within which a calibrated model must put it; `case` names the
    scenario overrides of the runs that give it (targets of one case share runs)."""
    name: str
    value: float
    sd: float
    tolerance: float
    response: str = None
    case: str = ""
    scatter: float = None  # the runs' seed-to-seed standard deviation, if known (else fitted, at least sd)

    def __post_init__(self):
        self.response = self.response or self.name


@dataclass
class Settings:
    batch: int = 1            # runs per batch (run at once)
    initial: int = 0          # runs of the starting Latin hypercube (0: parameters + 1)
    budget: int = 30          # most runs (points; each runs every case)
    confidence: float = 0.9   # the posterior probability of meeting every target that stops it
    seed: int = 1
    candidates: int = 4096    # Sobol points over which each batch's acquisition is maximised
    posterior_samples: int = 16384


@dataclass
class Record:
    """One evaluated point: its unit-cube coordinates, parameter values, the targets' values
    (None where the run failed) and its batch (0: the starting design)."""
    u: np.ndarray
    values: dict
    observed: dict
    batch: int

    @property
    def ok(self):
        return all(v is not None and np.isfinite(v) for v in self.observed.values())


@dataclass
class Result:
    status: str                  # "validated" or "budget"
    records: list
    best: dict                   # the best point: parameters, predicted and observed targets, P(meet)
    noise_sd: dict               # per target: the runs' scatter the surrogate found
    posterior: dict              # per parameter: mean, sd, 5/50/95 % quantiles
    region: np.ndarray           # posterior samples' parameter values where P(meet) >= 0.5 (n x d)
    region_probability: np.ndarray
    samples: np.ndarray = field(repr=False, default=None)   # all posterior samples (n x d, values)
    weights: np.ndarray = field(repr=False, default=None)

    @property
    def runs(self):
        return len(self.records)


def _prior(parameters):
    """prior(u) for n x d unit points, scaled to 1 at its largest in the box (uniform: 1)."""
    def prior(u):
        u = np.atleast_2d(u)
        p = np.ones(len(u))
        for k, par in enumerate(parameters):
            if par.prior_mean is None:
                continue
            x = par.value(u[:, k])
            peak = np.clip(par.prior_mean, par.low, par.high)
            z, z_peak = (x - par.prior_mean) / par.prior_sd, (peak - par.prior_mean) / par.prior_sd
            p *= np.exp(-0.5 * (z * z - z_peak * z_peak))
        return p
    return prior


def _fit(records, targets, seed):
    ok = [r for r in records if r.ok]
    u = np.array([r.u for r in ok])
    models = [surrogate.ResponseModel(u, [r.observed[t.name] for r in ok], seed, t.scatter, t.sd) for t in targets]
    failure = surrogate.FailureModel(np.array([r.u for r in records]), [r.ok for r in records], seed)
    return models, failure


def _validated(records, models, targets, confidence):
    """The evaluated point that meets every target with the largest posterior probability, and
    whether its own run confirms it (observed within tolerance, probability >= confidence)."""
    ok = [r for r in records if r.ok]
    p = surrogate.meet_probability(models, targets, np.array([r.u for r in ok]))
    within = np.array([all(abs(r.observed[t.name] - t.value) <= t.tolerance for t in targets) for r in ok])
    score = np.where(within, p, -1.0 + p)  # confirmed points first
    k = int(np.argmax(score))
    return ok[k], float(p[k]), bool(within[k] and p[k] >= confidence)


def _starting_design(parameters, settings):
    n = settings.initial or len(parameters) + 1
    return qmc.LatinHypercube(len(parameters), seed=settings.seed).random(n)


def calibrate(parameters, targets, evaluate, settings=None, records=None, log=print):
    """Calibrates `parameters` against `targets`; `records` are points evaluated before (a
    resumed calibration), `evaluate` as the module says. Returns a Result."""
    settings = settings or Settings()
    records = list(records or [])
    prior = _prior(parameters)

    def run(units, batch):
        points = [{p.name: float(p.value(u[k])) for k, p in enumerate(parameters)} for u in units]
        for u, x, obs in zip(units, points, evaluate(points, batch)):
            records.append(Record(np.asarray(u, float), x, {t.name: obs.get(t.name) for t in targets}, batch))

    start = _starting_design(parameters, settings)
    if len(records) < len(start):
        run(start[len(records):min(len(start), settings.budget)], 0)
    batch = max([r.batch for r in records], default=0)
    while sum(r.ok for r in records) < 2 and len(records) < settings.budget:
        # too few runs succeeded to fit anything: more of a Latin hypercube, apart from the first
        batch += 1
        size = min(max(settings.batch, 2), settings.budget - len(records))
        run(qmc.LatinHypercube(len(parameters), seed=settings.seed + 7919 * batch).random(size), batch)
    if sum(r.ok for r in records) < 2:
        raise RuntimeError(f"only {sum(r.ok for r in records)} of {len(records)} runs succeeded within the budget: "
                           "nothing to fit; see the failed runs' stderr.txt (docs/calibration.md)")
    while True:
        models, failure = _fit(records, targets, settings.seed)
        best, p_best, done = _validated(records, models, targets, settings.confidence)
        log(f"calibrate: {len(records)} runs; best so far P(meet) {p_best:.3f} at " +
            ", ".join(f"{k} {v:.4g}" for k, v in best.values.items()))
        if done or len(records) >= settings.budget:
            status = "validated" if done else "budget"
            break
        batch += 1
        size = min(settings.batch, settings.budget - len(records))
        run(surrogate.next_batch(models, targets, prior, failure, size, settings.seed + batch, settings.candidates),
            batch)
    return _result(parameters, targets, records, models, failure, prior, best, p_best, status, settings)


def _result(parameters, targets, records, models, failure, prior, best, p_best, status, settings):
    u = surrogate.sobol(len(parameters), settings.posterior_samples, settings.seed)
    w = surrogate.likelihood(models, targets, u) * prior(u) * failure.success(u)
    w = w / w.sum()
    x = np.column_stack([p.value(u[:, k]) for k, p in enumerate(parameters)])
    posterior = {}
    for k, p in enumerate(parameters):
        order = np.argsort(x[:, k])
        cdf = np.cumsum(w[order])
        q = [float(x[order[min(np.searchsorted(cdf, f), len(cdf) - 1)], k]) for f in (0.05, 0.5, 0.95)]
        mean = float(np.sum(w * x[:, k]))
        posterior[p.name] = {"mean": mean, "sd": float(np.sqrt(np.sum(w * (x[:, k] - mean) ** 2))),
                             "q05": q[0], "median": q[1], "q95": q[2]}
    meet = surrogate.meet_probability(models, targets, u) * failure.success(u)
    region = meet >= 0.5
    predicted = {}
    for m, t in zip(models, targets):
        mean, sd = m.predict(best.u[None, :])
        predicted[t.name] = {"mean": float(mean[0]), "sd": float(sd[0])}
    best_out = {"parameters": dict(best.values), "observed": dict(best.observed), "predicted": predicted,
                "meet_probability": p_best, "batch": best.batch}
    return Result(status, records, best_out, {t.name: m.noise_sd for m, t in zip(models, targets)}, posterior,
                  x[region], meet[region], x, w)
