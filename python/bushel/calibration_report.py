"""A calibration's results as files (docs/calibration.md): calibration.json, calibration.md,
runs.csv, and the plots convergence.png (each run's values against the targets' bands) and
region.png (the parameters that meet every target, pair by pair, with the runs)."""
import json
import os

import numpy as np

from .doe import _write_atomically


def _save(fig, path):
    """The figure as a PNG, written under another name and renamed (never half written)."""
    fig.savefig(path + ".tmp.png", dpi=100)
    os.replace(path + ".tmp.png", path)


def result_json(spec, result, build):
    targets = {t.name: {"response": t.response, "case": t.case or None, "value": t.value, "sd": t.sd,
                        "tolerance": t.tolerance, "scatter": t.scatter, "noise_sd_fitted": result.noise_sd[t.name]}
               for t in spec.targets}
    runs = [{"run": k + 1, "batch": r.batch, "parameters": r.values, "observed": r.observed, "counted": r.ok}
            for k, r in enumerate(result.records)]
    return {"status": result.status, "runs": result.runs, "build": build,
            "parameters": {p.name: {"low": p.low, "high": p.high, "prior_mean": p.prior_mean, "prior_sd": p.prior_sd}
                           for p in spec.parameters},
            "targets": targets, "best": result.best, "posterior": result.posterior,
            "region": {"samples": int(len(result.region)), "of": int(len(result.samples)),
                       "low": dict(zip([p.name for p in spec.parameters], np.min(result.region, 0).tolist()))
                       if len(result.region) else None,
                       "high": dict(zip([p.name for p in spec.parameters], np.max(result.region, 0).tolist()))
                       if len(result.region) else None},
            "settings": dict(spec.settings.__dict__), "where": spec.where or None, "run_list": runs}


def _markdown(spec, result, j):
    b = result.best
    status = {"validated": "validated: a run at the best point met every target, and the posterior puts it within "
                           f"tolerance with probability {b['meet_probability']:.3f} (at least "
                           f"{spec.settings.confidence})",
              "budget": f"budget of {result.runs} runs spent before a point was validated"}[result.status]
    lines = [f"# Calibration: {os.path.basename(spec.source)}", "", f"Status: {status}.", "",
             f"Runs: {result.runs} ({sum(not r.ok for r in result.records)} failed or excluded"
             f"{' by where: ' + spec.where if spec.where else ''}); build {j['build']}.", "",
             "## Best point", "", "| parameter | value | posterior mean | sd | 5 % | 95 % |",
             "|---|---|---|---|---|---|"]
    for p in spec.parameters:
        q = result.posterior[p.name]
        lines.append(f"| {p.name} | {b['parameters'][p.name]:.6g} | {q['mean']:.4g} | {q['sd']:.3g} | {q['q05']:.4g} | "
                     f"{q['q95']:.4g} |")
    lines += ["", "| target | measured | tolerance | observed at the best point | predicted there | runs' scatter |",
              "|---|---|---|---|---|---|"]
    for t in spec.targets:
        o = b["observed"][t.name]
        pr = b["predicted"][t.name]
        lines.append(f"| {t.name} | {t.value:.6g} +- {t.sd:.3g} | {t.tolerance:.3g} | "
                     f"{'failed' if o is None else f'{o:.6g}'} | {pr['mean']:.6g} +- {pr['sd']:.3g} | "
                     f"{result.noise_sd[t.name]:.3g}{' (given)' if t.scatter else ' (fitted)'} |")
    r = j["region"]
    lines += ["", "## The region that meets every target", "",
              "The posterior mean and quantiles above weigh the parameter box by the targets' likelihood. "
              f"The region where the surrogate gives P(meet) >= 0.5 holds {r['samples']} of {r['of']} Sobol points"]
    if r["low"]:
        lines[-1] += " and spans: " + "; ".join(f"{n} {r['low'][n]:.4g} to {r['high'][n]:.4g}" for n in r["low"])
    lines[-1] += " (region.png shows it pair by pair: a calibrated set is one point of it)."
    lines += ["", "## Runs", "", "| run | batch | " + " | ".join(p.name for p in spec.parameters) + " | " +
              " | ".join(t.name for t in spec.targets) + " |", "|---" * (2 + len(spec.parameters) + len(spec.targets)) +
              "|"]
    for k, rec in enumerate(result.records):
        cells = [str(k + 1), str(rec.batch)] + [f"{rec.values[p.name]:.4g}" for p in spec.parameters]
        cells += ["failed" if rec.observed[t.name] is None else f"{rec.observed[t.name]:.5g}" for t in spec.targets]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _runs_csv(spec, result):
    header = ["run", "batch"] + [p.name for p in spec.parameters] + [t.name for t in spec.targets] + ["counted"]
    rows = [",".join(header)]
    for k, r in enumerate(result.records):
        cells = [str(k + 1), str(r.batch)] + [repr(r.values[p.name]) for p in spec.parameters]
        cells += ["" if r.observed[t.name] is None else repr(r.observed[t.name]) for t in spec.targets]
        rows.append(",".join(cells + [str(int(r.ok))]))
    return "\n".join(rows) + "\n"


def plot(spec, result, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n_t = len(spec.targets)
    fig, axes = plt.subplots(n_t, 1, figsize=(7, 2.6 * n_t), squeeze=False)
    for ax, t in zip(axes[:, 0], spec.targets):
        runs = np.arange(1, result.runs + 1)
        y = np.array([np.nan if r.observed[t.name] is None else r.observed[t.name] for r in result.records])
        ax.axhspan(t.value - t.tolerance, t.value + t.tolerance, color="#c8e6c9", label="target +- tolerance")
        ax.axhline(t.value, color="#2e7d32", lw=1)
        ax.plot(runs, y, "o", color="#8c5a2b", label="runs")
        failed = np.isnan(y)
        if failed.any():
            ax.plot(runs[failed], np.full(failed.sum(), t.value), "x", color="red", label="failed or excluded")
        ax.set_xlabel("run")
        ax.set_ylabel(t.name)
        ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    _save(fig, os.path.join(out, "convergence.png"))
    plt.close(fig)

    d = len(spec.parameters)
    names = [p.name for p in spec.parameters]
    n = max(1, d - 1)
    fig, axes = plt.subplots(n, n, figsize=(max(6.0, 3.2 * n), max(4.5, 3.0 * n)), squeeze=False)
    x = np.array([[r.values[n] for n in names] for r in result.records])
    ok = np.array([r.ok for r in result.records])
    for i in range(n):
        for k in range(n):
            ax = axes[i, k]
            if d == 1:
                order = np.argsort(result.samples[:, 0])
                ax.plot(result.samples[order, 0], result.weights[order] / result.weights.max(), color="#4f6d8f")
                ax.plot(x[:, 0], np.zeros(len(x)), "|", color="#8c5a2b", ms=12)
                ax.set_xlabel(names[0])
                ax.set_ylabel("posterior (scaled)")
                continue
            a, c = k, i + 1  # x: parameter a, y: parameter c (lower triangle)
            if a >= c:
                ax.axis("off")
                continue
            if len(result.region):
                sc = ax.scatter(result.region[:, a], result.region[:, c], c=result.region_probability, s=3,
                                cmap="viridis", vmin=0.5, vmax=1.0)
            ax.plot(x[ok, a], x[ok, c], "o", mfc="none", color="#8c5a2b", ms=5)
            ax.plot(x[~ok, a], x[~ok, c], "x", color="red", ms=5)
            best = result.best["parameters"]
            ax.plot(best[names[a]], best[names[c]], "*", color="red", ms=12)
            ax.set_xlim(spec.parameters[a].low, spec.parameters[a].high)
            ax.set_ylim(spec.parameters[c].low, spec.parameters[c].high)
            ax.set_xlabel(names[a])
            ax.set_ylabel(names[c])
    fig.subplots_adjust(hspace=0.4, wspace=0.4)  # (before the colour bar, which takes its room from the axes)
    if d > 1 and len(result.region):
        fig.colorbar(sc, ax=axes.ravel().tolist(), label="P(meet every target)", shrink=0.8)
    fig.suptitle("where every target is met (dots, P >= 0.5), the runs (circles; x: failed) and the best point (star)",
                 fontsize=9)
    _save(fig, os.path.join(out, "region.png"))
    plt.close(fig)


def write_report(spec, result, out, build):
    j = result_json(spec, result, build)
    _write_atomically(os.path.join(out, "calibration.json"), json.dumps(j, indent=1))
    _write_atomically(os.path.join(out, "calibration.md"), _markdown(spec, result, j))
    _write_atomically(os.path.join(out, "runs.csv"), _runs_csv(spec, result))
    plot(spec, result, out)
