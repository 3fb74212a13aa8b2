"""The calibration file that `bushel calibrate` reads (docs/calibration.md): what to run, the
parameters with their ranges, the targets with their units, and the settings. Every error
names the file, the line and the key, as the scenario reader's do.
"""
import difflib
import os
import re
from dataclasses import dataclass, field

import yaml

from ._bushel import InputError, parse
from .calibrate import Parameter, Settings, Target

_DIMENSIONS = ("dimensionless", "length", "area", "volume", "mass", "time", "frequency", "velocity", "acceleration",
               "density", "mass_flow", "force", "pressure", "angle", "angular_velocity")
_TOP = ("scenario", "command", "set", "seed_parameter", "parameters", "targets", "cases", "where", "batch", "initial",
        "budget", "confidence", "seed")
_WHERE_COLUMN = re.compile(r"^\s*([A-Za-z_][\w.]*)\s*(<=|>=|==|!=|<|>|=)")


@dataclass
class CalibrationSpec:
    source: str                    # the file
    scenario: str = None           # a scenario file (absolute), or
    command: list = None           # a command per run ("{column}", "{run_dir}", "{bushel}")
    set: dict = field(default_factory=dict)     # overrides for every run
    cases: dict = field(default_factory=dict)   # case name -> overrides ("" : none)
    seed_parameter: str = None     # the scenario parameter that takes each run's own seed
    parameters: list = field(default_factory=list)
    targets: list = field(default_factory=list)
    where: str = ""                # conditions a run must meet to count (else it failed)
    settings: Settings = field(default_factory=Settings)

    def where_columns(self):
        """The columns the `where` conditions name."""
        return [m.group(1) for m in (_WHERE_COLUMN.match(c) for c in self.where.split(",") if c.strip()) if m]


class _Reader:
    def __init__(self, path):
        self.path = path

    def fail(self, node, key, message):
        line = node.start_mark.line + 1 if node is not None else 1
        raise InputError(f"{self.path}:{line}: key '{key}': {message}")

    def mapping(self, node, key, allowed=None):
        if not isinstance(node, yaml.MappingNode):
            self.fail(node, key, f"expected a mapping, got {_kind(node)}")
        out = {}
        for k, v in node.value:
            name = k.value
            if allowed is not None and name not in allowed:
                near = difflib.get_close_matches(name, allowed, 1)
                hint = f" (did you mean '{near[0]}'?)" if near else ""
                self.fail(k, f"{key}.{name}" if key else name,
                          f"unknown key '{name}'{hint}; expected one of {', '.join(allowed)}")
            if name in out:
                self.fail(k, f"{key}.{name}" if key else name, "the key appears twice")
            out[name] = v
        return out

    def scalar(self, node, key):
        if not isinstance(node, yaml.ScalarNode) or node.value == "":
            self.fail(node, key, f"expected a value, got {_kind(node)}")
        return node.value

    def number(self, node, key, low=None, integer=False):
        text = self.scalar(node, key)
        try:
            value = int(text) if integer else float(text)
        except ValueError:
            self.fail(node, key, f"expected {'an integer' if integer else 'a number'}, got '{text}'")
        if not value == value or value in (float("inf"), float("-inf")):
            self.fail(node, key, f"expected a finite number, got '{text}'")
        if low is not None and value < low:
            self.fail(node, key, f"expected at least {low}, got {value}")
        return value

    def quantity(self, node, key, dimension=None, like=None):
        """A number (SI) or a value with its unit: (SI value, dimension or None). With `like`
        (the key it must agree with), of `dimension`, or a bare number if that is None."""
        text = self.scalar(node, key)
        try:
            return float(text), dimension
        except ValueError:
            pass
        if like and not dimension:
            self.fail(node, key, f"expected a number in the SI unit of {like} (which has no unit), got '{text}'")
        for dim in ([dimension] if dimension else _DIMENSIONS):
            try:
                return parse(text, dim), dim
            except InputError:
                continue
        expected = f"a {dimension} (e.g. a number in SI units or a value with a unit)" if dimension else \
            "a number (SI) or a value with its unit, e.g. '826.1 kg/m3'"
        self.fail(node, key, f"expected {expected}, got '{text}'")

    def overrides(self, node, key):
        return {k: self.scalar(v, f"{key}.{k}") for k, v in self.mapping(node, key).items()}


def _kind(node):
    if node is None:
        return "nothing"
    if isinstance(node, yaml.ScalarNode):
        return f"'{node.value}'" if node.value else "an empty value"
    return "a list" if isinstance(node, yaml.SequenceNode) else "a mapping"


def read_spec(path):
    """Reads and checks a calibration file; raises InputError at the first problem."""
    path = os.path.abspath(path)
    try:
        text = open(path).read()
    except OSError as e:
        raise InputError(f"{path}: cannot read the calibration file: {e.strerror}") from None
    try:
        root = yaml.compose(text)
    except yaml.YAMLError as e:
        line = e.problem_mark.line + 1 if getattr(e, "problem_mark", None) else 1
        raise InputError(f"{path}:{line}: not valid YAML: {getattr(e, 'problem', e)}") from None
    r = _Reader(path)
    top = r.mapping(root, "", _TOP)
    spec = CalibrationSpec(path)
    here = os.path.dirname(path)
    if ("scenario" in top) == ("command" in top):
        r.fail(root, "scenario", "expected a scenario (a file) or a command (a list), not both and not neither")
    if "scenario" in top:
        spec.scenario = os.path.join(here, r.scalar(top["scenario"], "scenario"))
        if not os.path.isfile(spec.scenario):
            r.fail(top["scenario"], "scenario", f"no such file: {spec.scenario}")
    else:
        node = top["command"]
        if not isinstance(node, yaml.SequenceNode) or not node.value:
            r.fail(node, "command", f"expected a list (the program and its arguments), got {_kind(node)}")
        spec.command = [r.scalar(a, f"command[{i}]").replace("{spec_dir}", here) for i, a in enumerate(node.value)]
    spec.set = r.overrides(top["set"], "set") if "set" in top else {}
    if spec.command and spec.set:
        r.fail(top["set"], "set", "set goes with a scenario; a command takes its fixed values in its arguments")
    if "seed_parameter" in top:
        spec.seed_parameter = r.scalar(top["seed_parameter"], "seed_parameter")
    _read_parameters(r, top, spec)
    _read_cases_and_targets(r, top, spec)
    if "where" in top:
        spec.where = r.scalar(top["where"], "where")
    s = spec.settings
    for name, low, integer in (("batch", 1, True), ("initial", 2, True), ("budget", 2, True), ("seed", 0, True),
                               ("confidence", 0.5, False)):
        if name in top:
            setattr(s, name, r.number(top[name], name, low, integer))
    if s.confidence >= 1.0:
        r.fail(top["confidence"], "confidence", f"expected a probability below 1, got {s.confidence}")
    if s.initial and s.initial > s.budget:
        r.fail(top["initial"], "initial", f"expected at most the budget ({s.budget}) runs, got {s.initial}")
    return spec


def _read_parameters(r, top, spec):
    if "parameters" not in top:
        r.fail(None, "parameters", "the key 'parameters' is missing: name each calibrated parameter with its range")
    names = set()
    for name, node in r.mapping(top["parameters"], "parameters").items():
        key = f"parameters.{name}"
        p = r.mapping(node, key, ("low", "high", "prior_mean", "prior_sd"))
        for k in ("low", "high"):
            if k not in p:
                r.fail(node, f"{key}.{k}", f"the key '{k}' is missing: the range is low .. high")
        low, dim = r.quantity(p["low"], f"{key}.low")
        high, _ = r.quantity(p["high"], f"{key}.high", dim, f"{key}.low")
        if not high > low:
            r.fail(p["high"], f"{key}.high", f"expected more than low ({low}), got {high}")
        par = Parameter(name, low, high)
        if ("prior_mean" in p) != ("prior_sd" in p):
            r.fail(node, key, "a prior needs both prior_mean and prior_sd (a normal, cut to the range)")
        if "prior_mean" in p:
            par.prior_mean, _ = r.quantity(p["prior_mean"], f"{key}.prior_mean", dim, f"{key}.low")
            par.prior_sd, _ = r.quantity(p["prior_sd"], f"{key}.prior_sd", dim, f"{key}.low")
            if not par.prior_sd > 0:
                r.fail(p["prior_sd"], f"{key}.prior_sd", f"expected more than 0, got {par.prior_sd}")
        spec.parameters.append(par)
        names.add(name)
    if not spec.parameters:
        r.fail(top["parameters"], "parameters", "expected at least one parameter")
    if spec.seed_parameter in names:
        r.fail(top["seed_parameter"], "seed_parameter", f"'{spec.seed_parameter}' is also a calibrated parameter")


def _read_cases_and_targets(r, top, spec):
    spec.cases = {"": {}}
    if "cases" in top:
        for name, node in r.mapping(top["cases"], "cases").items():
            if not re.fullmatch(r"[A-Za-z0-9_-]+", name):
                r.fail(node, f"cases.{name}", "expected a name of letters, digits, '_' and '-' (it names a folder)")
            spec.cases[name] = r.overrides(node, f"cases.{name}")
            for k, v in spec.cases[name].items():
                if spec.command and (not re.fullmatch(r"[A-Za-z_]\w*", k) or re.search(r"[,\n\"]", v)):
                    r.fail(node, f"cases.{name}.{k}", "a command's case gives values to its {name} placeholders: "
                                                      "expected a name of letters, digits and '_' with a value "
                                                      "without commas or quotes")
    if "targets" not in top:
        r.fail(None, "targets", "the key 'targets' is missing: give each measured response with value, sd and "
                                "tolerance")
    for name, node in r.mapping(top["targets"], "targets").items():
        key = f"targets.{name}"
        t = r.mapping(node, key, ("value", "sd", "tolerance", "scatter", "response", "case"))
        for k in ("value", "sd", "tolerance"):
            if k not in t:
                r.fail(node, f"{key}.{k}", f"the key '{k}' is missing")
        value, dim = r.quantity(t["value"], f"{key}.value")
        numbers = {}
        for k in ("sd", "tolerance", "scatter"):
            if k in t:
                numbers[k], _ = r.quantity(t[k], f"{key}.{k}", dim, f"{key}.value")
                if not numbers[k] > 0:
                    r.fail(t[k], f"{key}.{k}", f"expected more than 0, got {numbers[k]}")
        case = r.scalar(t["case"], f"{key}.case") if "case" in t else ""
        if case not in spec.cases:
            r.fail(t["case"], f"{key}.case", f"no case '{case}'; the cases are {', '.join(c for c in spec.cases if c)}")
        spec.targets.append(Target(name, value, numbers["sd"], numbers["tolerance"],
                                   r.scalar(t["response"], f"{key}.response") if "response" in t else None, case,
                                   numbers.get("scatter")))
    if not spec.targets:
        r.fail(top["targets"], "targets", "expected at least one target")
    used = {t.case for t in spec.targets}
    for name in spec.cases:
        if name and name not in used:
            r.fail(top["cases"], f"cases.{name}", "no target uses this case")
    if "" not in used:
        del spec.cases[""]
