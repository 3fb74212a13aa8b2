"""`bushel calibrate SPEC --out DIR`: a calibration file (calibration_spec.py) run through
campaigns of scenario runs (bushel.doe.run: parallel jobs or MPI ranks, resumable), with its
results written to DIR (docs/calibration.md):

    DIR/points.csv          every point asked for, in order (written before it runs)
    DIR/<case>/batch_<b>/   the campaign of each batch and case (DIR/runs/batch_<b>/ without cases)
    DIR/observed.json       the targets' values of the finished batches
    DIR/calibration.json    the result: status, best point, posterior, the runs
    DIR/calibration.md      the same as tables
    DIR/runs.csv            every run: batch, parameters, targets' values, whether it counted
    DIR/convergence.png, DIR/region.png

Killed, it continues where it stopped when run again with the same file: the points asked for
are in points.csv, and the stopped batch's campaign skips the runs that finished.
"""
import argparse
import csv
import json
import os
import sys
import warnings

import numpy as np

from . import doe
from .doe import _write_atomically
from ._bushel import InputError, _build, _rows_kept
from .calibrate import Record, Settings, calibrate
from .calibration_report import write_report
from .calibration_spec import read_spec

_BOOKKEEPING = ("std_order", "run_order")  # (a design's columns that are not factors)


def _identity(spec):
    """What a folder's runs depend on: a later call with another file must not mix with them."""
    return {"scenario": spec.scenario, "command": spec.command, "set": spec.set, "cases": spec.cases,
            "seed_parameter": spec.seed_parameter, "seed": spec.settings.seed,
            "initial": spec.settings.initial, "where": spec.where,
            "parameters": [[p.name, p.low, p.high] for p in spec.parameters]}


class CampaignEvaluator:
    """Evaluates points by one campaign per batch and case (DIR/<case>/batch_<b>/; each point
    a design row with std_order its number from 1). The values of finished batches are kept in
    DIR/observed.json, so that a failed run is not run again by later batches."""

    def __init__(self, spec, out, jobs, threads, ranks, log):
        self.spec, self.out, self.jobs, self.threads, self.ranks, self.log = spec, out, jobs, threads, ranks, log
        self.points_csv = os.path.join(out, "points.csv")
        self.observed_json = os.path.join(out, "observed.json")
        self.names = [p.name for p in spec.parameters]
        self.factors = self.names + ([spec.seed_parameter] if spec.seed_parameter else [])
        self.rows, self.observed = [], []
        if os.path.exists(self.points_csv):
            with open(self.points_csv) as f:
                self.rows = [{"batch": int(r["batch"]), "values": {n: float(r[n]) for n in self.names}}
                             for r in csv.DictReader(f)]
        if os.path.exists(self.observed_json):
            self.observed = json.load(open(self.observed_json))

    def _table(self, rows, design, extra=None):
        """Points `rows` (0-based) as CSV: the point's number from 1 (as std_order and run_order
        in a design; with its batch in points.csv), its values, its seed, and the columns
        `extra` ({name: value}: a command's case, the same in every row)."""
        extra = extra or {}
        head = (list(_BOOKKEEPING) if design else ["point", "batch"]) + self.factors + list(extra)
        lines = [",".join(head)]
        for k in rows:
            r = self.rows[k]
            cells = [str(k + 1), str(k + 1) if design else str(r["batch"])]
            cells += [repr(r["values"][n]) for n in self.names]
            if self.spec.seed_parameter:
                cells.append(str(self.spec.settings.seed * 100000 + k + 1))  # each run its own packing
            lines.append(",".join(cells + [str(v) for v in extra.values()]))
        return "\n".join(lines) + "\n"

    def responses(self, case):
        wanted = [t.response for t in self.spec.targets if t.case == case]
        extra = [c for c in self.spec.where_columns() if c not in self.names and c not in ("status", "std_order")]
        return list(dict.fromkeys(wanted + extra))

    def evaluate(self, points, batch):
        """Runs the points (those asked for before are taken from points.csv: a resumed call
        asks for the same points again), returns their targets' values."""
        first = len(self.observed)
        for k, p in enumerate(points):
            if first + k >= len(self.rows):
                self.rows.append({"batch": batch, "values": dict(p)})
        _write_atomically(self.points_csv, self._table(range(len(self.rows)), False))
        self._run(first, first + len(points))
        return self.observed[first:first + len(points)]

    def resume(self):
        """The points evaluated before (the last batch finished if it was stopped): (values,
        observed, batch) each."""
        self._run(len(self.observed), len(self.rows))
        return [(r["values"], o, r["batch"]) for r, o in zip(self.rows, self.observed)]

    def _run(self, first, last):
        """Runs points [first, last) (one batch's, or the rest of a stopped one)."""
        if first >= last:
            return
        spec, batch = self.spec, self.rows[first]["batch"]
        observed = [dict() for _ in range(first, last)]
        for case, overrides in spec.cases.items():
            folder = os.path.join(self.out, case or "runs", f"batch_{batch}")
            os.makedirs(folder, exist_ok=True)
            design = os.path.join(folder, "design.csv")
            # (a command's case is columns of its design, for its {name} placeholders)
            _write_atomically(design, self._table(range(first, last), True, None if spec.scenario else overrides))
            self.log(f"calibrate: batch {batch}{' of case ' + case if case else ''}: points {first + 1} to {last}")
            common = dict(responses=self.responses(case), jobs=self.jobs, threads=self.threads, ranks=self.ranks)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)  # (failed runs are counted below)
                if spec.scenario:
                    c = doe.run(design, folder, scenario=spec.scenario, set={**spec.set, **overrides},
                                factors=self.factors, **common)
                else:
                    c = doe.run(design, folder, command=spec.command, **common)
            if len(c.failed):
                self.log(f"calibrate: runs {', '.join(str(first + k) for k in c.failed)} failed and do not count "
                         f"(their stderr.txt in {folder})")
            kept = _rows_kept(os.path.join(folder, "results.csv"), spec.where) if spec.where else None
            for k, order in enumerate(c.table["std_order"]):
                i = int(order) - 1 - first
                counts = c.status[k] == "done" and (kept is None or kept[k])
                for t in spec.targets:
                    if t.case == case:
                        v = c.responses[t.response][k]
                        observed[i][t.name] = float(v) if counts and np.isfinite(v) else None
        self.observed += observed
        _write_atomically(self.observed_json, json.dumps(self.observed))


def run_calibration(spec, out, jobs=None, threads=0, ranks=None, budget=None, log=None):
    """Runs (or continues) the calibration of `spec` in the folder `out`; returns the Result."""
    log = log or (lambda s: print(s, file=sys.stderr, flush=True))
    os.makedirs(out, exist_ok=True)
    identity_path = os.path.join(out, "identity.json")
    identity = _identity(spec)
    if os.path.exists(identity_path):
        if json.load(open(identity_path)) != json.loads(json.dumps(identity)):
            raise InputError(f"{out}: the folder holds a calibration of another file (its scenario, cases, "
                             f"parameters, seed or where differ: {identity_path}); use a new folder")
    else:
        _write_atomically(identity_path, json.dumps(identity, indent=1))
    settings = spec.settings
    if budget:
        settings = Settings(**{**settings.__dict__, "budget": int(budget)})
    jobs = int(jobs or settings.batch)
    evaluator = CampaignEvaluator(spec, out, jobs, threads, ranks, log)
    records = [Record(np.array([p.unit(v[p.name]) for p in spec.parameters]), v, obs, b)
               for v, obs, b in evaluator.resume()]
    if records:
        log(f"calibrate: {len(records)} runs from before")
    result = calibrate(spec.parameters, spec.targets, evaluator.evaluate, settings, records, log)
    write_report(spec, result, out, _build())
    return result


class _Arguments(argparse.ArgumentParser):
    def error(self, message):  # (one line, as the program's own errors)
        print(f"bushel: error: {message} (bushel calibrate --help lists the options)", file=sys.stderr)
        sys.exit(2)


def main(argv=None):
    ap = _Arguments(prog="bushel calibrate",
                                 description="Calibrate parameters against measured targets (docs/calibration.md)")
    ap.add_argument("spec", help="the calibration file (YAML)")
    ap.add_argument("--out", required=True, help="folder of the calibration (continued if it exists)")
    ap.add_argument("--jobs", type=int, default=0, help="runs at a time (default: the batch size)")
    ap.add_argument("--threads", type=int, default=0, help="threads per run (0: cores / jobs)")
    ap.add_argument("--ranks", type=int, default=0, help="run the batches on MPI ranks (mpirun -n RANKS)")
    ap.add_argument("--budget", type=int, default=0, help="most runs (overrides the file's budget)")
    a = ap.parse_args(argv)
    try:
        for name in ("jobs", "threads", "ranks", "budget"):
            if getattr(a, name) < 0:
                raise InputError(f"--{name}: expected 0 or more, got {getattr(a, name)}")
        spec = read_spec(a.spec)
        result = run_calibration(spec, a.out, a.jobs, a.threads, a.ranks or None, a.budget or None)
    except (InputError, RuntimeError) as e:
        print(f"bushel: error: {e}", file=sys.stderr)
        return 1
    b = result.best
    print(f"{result.status}: {result.runs} runs; best " +
          ", ".join(f"{k} {v:.6g}" for k, v in b["parameters"].items()) +
          f"; P(meet) {b['meet_probability']:.3f}; {os.path.join(a.out, 'calibration.md')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
