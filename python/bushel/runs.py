"""A run's outputs (summary.json, timeseries.csv with its units, frames) as Python objects.

    run = bushel.open_run("runs/cup-pour")
    run.results["bulk_density"]          # Quantity(value=805.7, unit='kg/m3')
    run.timeseries["cup.bulk_density"]   # numpy array, unit in run.units
    run.dataframe()                      # the time series as a pandas DataFrame (if pandas is installed)
    run.particles(-1)                    # the last frame's elements as numpy arrays
"""
import csv
import json
import os
from collections import namedtuple

import numpy as np

from .frames import read_pvd, read_vtu

Quantity = namedtuple("Quantity", "value unit")
Quantity.__doc__ = "A value in SI (angles in degrees) and its unit; value None: not computed."


class Run:
    """The outputs of a bushel run in `folder` (finished, interrupted or failed)."""

    def __init__(self, folder):
        self.folder = os.fspath(folder)
        path = os.path.join(self.folder, "summary.json")
        if not os.path.exists(path):
            raise FileNotFoundError(f"{path}: no summary.json (not a bushel run folder)")
        with open(path) as f:
            self.summary = json.load(f)
        self._series = None

    def __repr__(self):
        return f"Run({self.folder!r}, t = {self.simulated_time} s, {len(self.stages)} stages)"

    @property
    def results(self):
        """The scenario's results: name -> Quantity."""
        return {k: Quantity(v["value"], v["unit"]) if v else Quantity(None, "")
                for k, v in self.summary.get("results", {}).items()}

    @property
    def stages(self):
        """Each finished stage: name, what ended it, start and end [s], steps and its end values."""
        return self.summary.get("stages", [])

    def stage(self, name):
        """The end values of stage `name` (a dict), from summary.json."""
        for s in self.stages:
            if s["name"] == name:
                return s
        raise KeyError(f"no stage '{name}'; the run has {[s['name'] for s in self.stages]}")

    @property
    def simulated_time(self):
        return self.summary.get("simulated_time_s")

    @property
    def interrupted(self):
        return bool(self.summary.get("interrupted", False))

    @property
    def failed(self):
        """Why a guard stopped the run, or None."""
        return self.summary.get("failed")

    def _read_series(self):
        if self._series is None:
            with open(os.path.join(self.folder, "timeseries.csv")) as f:
                rows = list(csv.reader(f))
            header, body = rows[0], rows[1:]
            series = {"stage": np.array([r[0] for r in body])}
            for k, name in enumerate(header[1:], start=1):
                series[name] = np.array([float(r[k]) for r in body])
            self._series = series
        return self._series

    @property
    def timeseries(self):
        """Column name -> numpy array (the `stage` column as strings); units in `units`."""
        return self._read_series()

    @property
    def units(self):
        """Column name -> unit of timeseries.csv ('-': none)."""
        path = os.path.join(self.folder, "timeseries.units.csv")
        with open(path) as f:
            return {r["column"]: r["unit"] for r in csv.DictReader(f)}

    def dataframe(self):
        """The time series as a pandas DataFrame (columns as in the file; units in `units`)."""
        import pandas  # optional: Debian's python3-pandas
        return pandas.DataFrame(self._read_series())

    @property
    def frames(self):
        """The particle frames: a list of (time [s], file)."""
        path = os.path.join(self.folder, "frames", "particles.pvd")
        return read_pvd(path) if os.path.exists(path) else []

    def _frame(self, collection, k):
        listed = read_pvd(os.path.join(self.folder, "frames", collection))
        return read_vtu(listed[k][1])

    def particles(self, k=-1):
        """Frame k's sphere elements (frames.Frame): points, point_data (radius_m, velocity_m_s,
        body_id, type, orientation_wxyz and the fields asked for) and field_data['type_names']."""
        return self._frame("particles.pvd", k)

    def geometry(self, k=-1):
        """Frame k's parts as triangles (frames.Frame, cell_data['part'])."""
        return self._frame("geometry.pvd", k)

    def contacts(self, k=-1):
        """Frame k's contact lines (frames.Frame, cell_data: overlap_m, normal_force_elastic_N),
        if the frames have the field `contacts`."""
        return self._frame("contacts.pvd", k)


def open_run(folder):
    """The run in `folder`."""
    return Run(folder)
