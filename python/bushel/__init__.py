"""bushel from Python: validate and run scenarios, read their outputs, and the grain formulas.

    import bushel
    run = bushel.run("scenarios/cup-pour.yaml", out="runs/cup", set={"parameters.mass": "20 g"})
    run.results["bulk_density"]   # Quantity(value=..., unit='kg/m3')

Quantities are SI numbers or strings with units ("5.42 mm") everywhere. docs/python.md shows
every call.
"""
import json
import os
import signal

from ._bushel import (InputError, compressibility, mass_in_bin, pack_factor, packing_ratio, parse,
                      pseudo_ellipsoid, rayleigh_time_step, shape_factors, template, template_names)
from ._bushel import _run, _validate
from . import doe, pictures
from .frames import Frame, read_pvd, read_vtu
from .runs import Quantity, Run, open_run

__all__ = ["InputError", "Frame", "doe", "Quantity", "Run", "compressibility", "mass_in_bin", "open_run",
           "pack_factor", "packing_ratio", "parse", "pictures", "pseudo_ellipsoid", "rayleigh_time_step", "read_pvd",
           "read_vtu", "resume", "run", "shape_factors", "template", "template_names", "validate"]


def _source(scenario):
    """(text or path, is_text): a dict is sent as JSON, which the YAML reader takes."""
    if isinstance(scenario, dict):
        return json.dumps(scenario, indent=1), True  # (a line per key: errors name it)
    if isinstance(scenario, (str, os.PathLike)):
        return os.fspath(scenario), False
    raise TypeError(f"scenario: expected a file path or a dict, got {type(scenario).__name__}")


def _sets(values):
    """Overrides as 'path=value' texts, from a dict {path: value} or a list of such texts."""
    if values is None:
        return []
    if isinstance(values, dict):
        return [f"{k}={v}" for k, v in values.items()]
    return [str(v) for v in values]


def validate(scenario, set=None):  # noqa: A002 (the CLI's name for it)
    """Reads and checks a scenario (a file path or a dict) with overrides `set` ({path: value},
    values with units as text); returns its stages, values, time step and the steps it derives
    from. Raises InputError (a ValueError) naming the file, line and key of a mistake."""
    text, is_text = _source(scenario)
    return _validate(text, is_text, _sets(set))


def run(scenario, out, set=None, threads=0, overwrite=False, stop_at=None, checkpoint_every=5.0,  # noqa: A002
        progress=None):
    """Runs a scenario (a file path or a dict) into the folder `out` as `bushel run` does, with
    the same results to the bit; returns the Run.

    set: overrides {path: value} (values may carry units: {"parameters.mass": "60 g"}).
    threads: a fixed thread count (0: the scenario's, by default chosen while running).
    overwrite: replace another run's outputs in `out`.
    stop_at: stop at this simulated time (seconds, or "0.5 s") with a checkpoint; continue with resume().
    checkpoint_every: minutes of wall time between checkpoints (0: only when stopped).
    progress: called at every check with a dict (stage, stage_index, stages, time_s,
      particles, steps, wall_time_s); returning True stops the run there with a checkpoint, as
      Ctrl-C does. An exception in it stops the run the same way, then is raised.
    Ctrl-C stops the run with a checkpoint and raises KeyboardInterrupt."""
    text, is_text = _source(scenario)
    return _finish(_run(text, is_text, _sets(set), os.fspath(out), False, threads, overwrite, stop_at,
                        checkpoint_every, progress))


def resume(out, threads=0, stop_at=None, checkpoint_every=5.0, progress=None):
    """Continues the run in `out` from its checkpoint (as `bushel run --restart`); returns the Run."""
    return _finish(_run("", False, [], os.fspath(out), True, threads, False, stop_at, checkpoint_every,
                        progress))


def _finish(report):
    if report["interrupted"] and report["signal"] == signal.SIGINT:
        raise KeyboardInterrupt(f"the run stopped with a checkpoint in {report['out']}; continue it with resume()")
    return Run(report["out"])
