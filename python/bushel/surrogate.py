"""Gaussian-process surrogates of a simulation's responses over its parameters, and what a
calibration asks of them (docs/calibration.md): the probability that a point meets every target,
batches of points chosen where that probability is highest, and the posterior over the
parameters. The Gaussian processes are scikit-learn's; the optimiser is scipy's.

Points live in the unit cube (each parameter's range mapped to 0 .. 1); responses in their
own units.
"""
import warnings

import numpy as np
from scipy.optimize import minimize
from scipy.special import ndtr
from scipy.stats import qmc
from sklearn.exceptions import ConvergenceWarning
from sklearn.gaussian_process import GaussianProcessClassifier, GaussianProcessRegressor
from sklearn.gaussian_process.kernels import ConstantKernel, DotProduct, Matern, WhiteKernel


class ResponseModel:
    """One response's Gaussian process: a constant times a Matern 5/2 kernel with a length
    scale per parameter, plus a linear kernel (a prior on a trend: far from the runs the
    surrogate follows the runs' slope instead of falling back to their mean, which sent batches
    to the box's far corners), plus white noise (the seed-to-seed scatter of the runs), fitted
    by maximum likelihood on the normalised response. The noise's standard deviation is
    `scatter` where that is known, else fitted, at least `floor` (a few runs cannot tell noise
    from signal: fitted freely, the noise came out near zero and a lucky run passed as
    confirmation)."""

    def __init__(self, points, values, seed, scatter=None, floor=0.0, scale=None, kernel=None):
        points, values = np.asarray(points, float), np.asarray(values, float)
        d = points.shape[1]
        # normalised here (not by sklearn) so that a known scatter fixes the noise level
        self.shift, self.scale = scale or (float(np.mean(values)), float(np.std(values)) or 1.0)
        if kernel is None:
            low = max((floor / self.scale) ** 2, 1e-8)
            fitted = (max(1e-2, 2 * low), (low, max(1.0, 4 * low)))
            noise = ((scatter / self.scale) ** 2, "fixed") if scatter else fitted
            kernel = (ConstantKernel(1.0, (1e-2, 1e2)) *
                      Matern(length_scale=np.full(d, 0.5), length_scale_bounds=(0.05, 20.0), nu=2.5) +
                      ConstantKernel(1.0, (1e-3, 1e2)) * DotProduct(1.0, "fixed") + WhiteKernel(*noise))
            optimizer, restarts = "fmin_l_bfgs_b", 4
        else:  # a fitted kernel kept (the fantasies of a batch)
            optimizer, restarts = None, 0
        self.gp = GaussianProcessRegressor(kernel, n_restarts_optimizer=restarts, optimizer=optimizer,
                                           random_state=seed)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            self.gp.fit(points, (values - self.shift) / self.scale)
        self.points, self.values = points, values

    @property
    def noise_sd(self):
        """The white noise's standard deviation, in the response's units: the runs' scatter
        about the smooth response (given, or fitted)."""
        return float(np.sqrt(self.gp.kernel_.k2.noise_level) * self.scale)

    def predict(self, points):
        """(mean, sd) of the smooth response (without the noise) at `points` (n x d)."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # (sklearn's "predicted variances smaller than 0")
            mean, sd = self.gp.predict(np.atleast_2d(points), return_std=True)
        var = np.maximum(sd * sd - self.gp.kernel_.k2.noise_level, 1e-12)
        return self.shift + self.scale * mean, self.scale * np.sqrt(var)

    def with_fantasy(self, point, value):
        """The same model (kernel and scaling kept) with one more observation: a batch's
        "kriging believer"."""
        return ResponseModel(np.vstack([self.points, point]), np.append(self.values, value), 0,
                             scale=(self.shift, self.scale), kernel=self.gp.kernel_)


class FailureModel:
    """The probability that a run at a point succeeds (its funnel did not clog, it did not stop
    with an error): scikit-learn's Gaussian-process classifier once both outcomes were seen,
    else 1 everywhere."""

    def __init__(self, points, succeeded, seed):
        succeeded = np.asarray(succeeded, bool)
        self.classifier = None
        if succeeded.any() and not succeeded.all():
            d = np.asarray(points).shape[1]
            kernel = ConstantKernel(1.0, (1e-2, 1e2)) * Matern(np.full(d, 0.5), (0.05, 20.0), nu=2.5)
            self.classifier = GaussianProcessClassifier(kernel, random_state=seed)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ConvergenceWarning)
                self.classifier.fit(np.asarray(points, float), succeeded.astype(int))

    def success(self, points):
        points = np.atleast_2d(points)
        if self.classifier is None:
            return np.ones(len(points))
        return self.classifier.predict_proba(points)[:, 1]


def meet_probability(models, targets, points):
    """The probability that the smooth responses at `points` lie within every target's
    tolerance (the responses' models taken as independent): prod_k P(|f_k - T_k| <= tol_k)."""
    p = np.ones(len(np.atleast_2d(points)))
    for model, t in zip(models, targets):
        mean, sd = model.predict(points)
        p *= ndtr((t.value + t.tolerance - mean) / sd) - ndtr((t.value - t.tolerance - mean) / sd)
    return p


def likelihood(models, targets, points):
    """The targets' likelihood at `points`: prod_k N(T_k; mean_k, sd_k^2 + s_k^2), with s_k the
    measurement's standard deviation and sd_k the surrogate's own."""
    log = np.zeros(len(np.atleast_2d(points)))
    for model, t in zip(models, targets):
        mean, sd = model.predict(points)
        var = sd * sd + t.sd * t.sd
        log += -0.5 * (mean - t.value) ** 2 / var - 0.5 * np.log(2 * np.pi * var)
    return np.exp(log - log.max()) if len(log) else log


def sobol(d, n, seed):
    """n points (a power of two) of a scrambled Sobol sequence in the unit cube."""
    return qmc.Sobol(d, scramble=True, seed=seed).random(n)


def next_batch(models, targets, prior, failure, size, seed, candidates=4096):
    """`size` points where every target is most likely met: the acquisition
    a(x) = P(meet | x) P(success | x) prior(x) / max prior, maximised over Sobol candidates and
    refined by L-BFGS-B from the best few; each further point of a batch is chosen after the
    ones before it were added with their predicted values (the kriging believer), which
    shrinks the uncertainty there and spreads the batch."""
    d = models[0].points.shape[1]
    chosen = []
    for k in range(size):
        def acquisition(u):
            return meet_probability(models, targets, u) * failure.success(u) * prior(u)
        start = sobol(d, candidates, seed * 1000 + k)
        a = acquisition(start)
        best_u, best_a = start[int(np.argmax(a))], float(np.max(a))
        for u0 in start[np.argsort(a)[-4:]]:
            r = minimize(lambda u: -float(acquisition(u[None, :])[0]), u0, method="L-BFGS-B",
                         bounds=[(0.0, 1.0)] * d)
            if -r.fun > best_a:
                best_u, best_a = np.clip(r.x, 0.0, 1.0), -float(r.fun)
        chosen.append(best_u)
        models = [m.with_fantasy(best_u, m.predict(best_u[None, :])[0][0]) for m in models]
    return np.array(chosen)
