#!/usr/bin/env python3
"""The tables of the study's experiments at full size (validation/run-study.sh writes them to
validation/results/study.md): per experiment, each case's results beside the lab values the
project has (data/reference_values.csv), the checks the physics requires, and per case its
engine build, wall time and particle-steps/s, or how far an unfinished case has got.

usage: study_table.py RUNS KEPT REFERENCES [CASE...]
       study_table.py --expected REFERENCES   # the lab's expected test weights, as a reference CSV
  RUNS        the run folders (runs/validation/study): CASE/ with summary.json, or with
              checkpoint.bin and timeseries.csv while it runs
  KEPT        the kept results (validation/results/study-runs): CASE/summary.json of finished
              cases, CASE/checkpoint.bin.xz and timeseries.csv.xz of parked ones; a kept
              summary is read before the run folder's; tap-phases.csv beside it, where there is
              one, gives each tapped case's kinetic energy through a tap's period
  REFERENCES  data/reference_values.csv
  CASE        tw-SAMPLE-MODEL-DROP[-seedN] (test weight of the sample kanmark or garrison, or of
              one pure fraction, large, medium or small; with another seed), tw-dt-PERCENT-seedN
              (the single-sphere test weight's time step),
              comp-FRACTION-MODEL[-stiff] (compression), comp-dt-PERCENT (its time step),
              tap-FRACTION-MODEL[-HZhz] (tapped density; at another rate), tap-rate-HZhz-seedN (the
              tapping rate, reduced), tap-model-WHAT-seedN (the reduced taps with other kernels,
              beside tap-rate-8.66hz-seed1 and -seed2);
              default: every case with a folder in RUNS or KEPT, by name
"""
import csv
import json
import os
import re
import sys
from dataclasses import dataclass

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cup_table import engine, exponent, fmt, progress  # noqa: E402
from tap_series import quietest  # noqa: E402

FRACTIONS = ("large", "medium", "small")
SAMPLES = {"kanmark": (0.815, 0.155, 0.030), "garrison": (0.218, 0.606, 0.176)}  # by mass (docs/wheat.md)
LEVELS = (0, 7, 21, 34, 48, 69, 103, 138)  # kPa, compression.yaml's p1 .. p7
DROPS = ("1h", "2h", "4h", "8h", "16h", "32h")  # h = 5.1 cm
STUDY_DROPS = ("1h", "8h", "32h")  # those of every sample and model (run-study.sh)
MODELS = ("1s", "5s")  # single spheres, 5-sphere clumps
STIFF_OVERLAP = 10 ** (-2 / 3)  # Hertz overlap of kernels ten times stiffer (comp-large-MODEL-stiff), relative
KERNEL_DENSITY = 1373.0  # the kernels' solid density [kg/m3] (docs/wheat.md), that of the packing ratio
LB_BU = 12.8719  # kg/m3 in 1 lb/bu (docs/wheat.md)


@dataclass
class Refs:
    """The lab values the tables set the cases against (references)."""
    test_weight: dict  # pure fraction -> its test weight at h [lb/bu]
    tapped: dict  # (fraction, "packing_ratio" or "compressibility") -> value [-]
    excess: dict  # sample -> the lab's mixing excess over the ideal mixture at its shares [-]
    cup: dict  # pure fraction -> its bulk density in the calibration cup [kg/m3]


def references(path):
    """The lab's test weight at h of each pure fraction, its packing ratio and compressibility
    of each fraction (tapped density) and its calibration cup's bulk density of each; and per
    sample the lab's own mixing excess (mixing_excess, from the ternary mixtures in the same
    folder), as Refs."""
    with open(path) as f:
        rows = list(csv.DictReader(l for l in f if not l.startswith("#")))
    refs = Refs({}, {}, {}, {})
    for r in rows:
        if r["scenario"] == "test-weight" and r["result"] == "bulk_density":
            shares = [r["share_" + f] for f in FRACTIONS]
            refs.test_weight[FRACTIONS[shares.index("100%")]] = float(r["value"])
        elif r["scenario"] == "tapped-density":
            refs.tapped[(r["fraction"], r["result"])] = float(r["value"])
        elif r["scenario"] == "calibration-cup" and r["result"] == "bulk_density" and not r["model"]:
            refs.cup[r["fraction"]] = float(r["value"])
    ternary = os.path.join(os.path.dirname(path), "ternary_packing_compressibility.csv")
    refs.excess = {s: mixing_excess(ternary, shares) for s, shares in SAMPLES.items()}
    return refs


def mixing_excess(path, shares):
    """How much denser the lab's mixtures of the fractions pack than the ideal mixture, at
    `shares` (by mass) [-]: data/ternary_packing_compressibility.csv holds the tapped packing
    ratio of 21 mixtures of KanMark's sieve fractions (the three alone, 12 binary, 6 ternary);
    a special cubic (Scheffe) mixture model fitted to them by least squares, at the shares,
    over the ideal mixture of the model's three pure fractions (specific volumes added by
    mass)."""
    import numpy as np
    with open(path) as f:
        rows = list(csv.DictReader(l for l in f if not l.startswith("#")))
    x = np.array([[float(r[k]) / 100 for k in ("m7_pct", "m8_pct", "m10_pct")] for r in rows])
    y = np.array([float(r["packing_ratio_kanmark"]) for r in rows])

    def terms(m):  # (large, medium, small) -> the model's terms
        m = np.atleast_2d(m)
        l, md, s = m.T
        return np.column_stack([l, md, s, l * md, l * s, md * s, l * md * s])

    coef = np.linalg.lstsq(terms(x), y, rcond=None)[0]
    ideal = 1 / sum(s / p for s, p in zip(shares, coef[:3]))  # (the model's pure fractions)
    return float((terms(np.array(shares)) @ coef)[0]) / ideal - 1


def shares_of(sample):
    """A sample's shares of the fractions, by mass: a variety's, or one pure fraction's."""
    return SAMPLES.get(sample) or tuple(float(f == sample) for f in FRACTIONS)


def ideal_mixture(test_weight, shares):
    """The test weight of a mixture whose fractions keep their own packing [lb/bu]: their
    specific volumes added by mass. Small kernels that fill the large ones' voids make a real
    mixture denser than this."""
    return 1 / sum(s / test_weight[f] for f, s in zip(FRACTIONS, shares))


class Case:
    """One case's summary, or its progress where it has none."""

    def __init__(self, runs, kept, name):
        self.name, self.j = name, None
        for folder in (kept, runs):
            path = os.path.join(folder, name, "summary.json")
            if os.path.exists(path):
                with open(path) as f:
                    self.j = json.load(f)
                break
        if self.j is None:
            self.status = progress(runs, kept, name, prefix="")
        elif self.j.get("failed"):
            self.status = "FAILED: " + self.j["failed"]
        elif self.j["interrupted"]:
            self.status = "interrupted at t = %.2f s" % self.j["simulated_time_s"]
        else:
            self.status = "done"

    @property
    def done(self):
        return self.status == "done"

    def result(self, key):
        """A result's value (SI), or None."""
        if self.j is None:
            return None
        return (self.j["results"].get(key) or {}).get("value")

    def cell(self, key, spec, scale=1):
        """A result formatted for the table, 'not full' beside a density over a sensor the grain
        did not fill (the run's warning says by how much)."""
        value = self.result(key)
        if value is None:
            return ""
        not_full = (self.j["results"][key] or {}).get("not_full")
        if not not_full:
            return format(value * scale, spec)
        by = re.search(r"lay ([0-9.]+) mm below", not_full)
        return format(value * scale, spec) + (f" (not full by {by.group(1)} mm)" if by else " (not full)")

    def strike(self):
        """What the strike cost [%]: the struck density against the kernels centred in the
        vessel before it, or None."""
        bd, before = self.result("bulk_density"), self.result("bulk_density_sensor")
        return over(bd, before)

    def parameter(self, key):
        """A scenario parameter as the run took it (its text), or ''."""
        return ((self.j or {}).get("parameters") or {}).get(key, "")

    def stage(self, name):
        """A stage's record in the summary (dt_s, values at its end, ...), or {}."""
        return next((s for s in (self.j or {}).get("stages", []) if s["name"] == name), {})

    def before_strike(self, which):
        """The kernels centred in the tapped-density cylinder before the loose or the tapped strike
        [kg/m3]: at the end of the stage before it (tapped-density.yaml's rest and unextended),
        when the grain still stood above the rim; or None."""
        before = self.stage({"loose": "rest", "tapped": "unextended"}[which]).get("values", {})
        return before.get("cylinder.bulk_density")

    def tap_strike(self, which):
        """What the loose or the tapped strike cost [%]: the struck density against
        before_strike, or None."""
        return over(self.result(which + "_bulk_density"), self.before_strike(which))

    def tap_compaction(self):
        """What the taps alone compacted the cylinder's grain [-]: the kernels centred in it before
        the tapped strike less those before the loose strike, over the former (compressibility's
        form without either strike's cost); None until done."""
        a, b = self.before_strike("loose"), self.before_strike("tapped")
        return (b - a) / b if self.done and a and b else None

    def tail(self):
        """The columns every table ends with: particles, time step, simulated and wall time,
        speed, engine, status."""
        if self.j is None:
            return f"| | | | | | | {self.status} |"
        j = self.j
        count = sum(f["count"] for f in j["factories"])
        return (f"| {count:,} | {j['dt_s'] * 1e6:.2f} ({j['time_step_rule']}) | {j['simulated_time_s']:.2f} "
                f"| {j['wall_time_s'] / 3600:.2f} | {exponent(j['particle_steps_per_s'])} | {engine(j)} "
                f"| {self.status} |")


TAIL = "| particles | dt [us] (rule) | simulated [s] | wall [h] | particle-steps/s | engine | status |"


def header(columns):
    cells = columns + " " + TAIL
    return [cells, "|" + "---|" * (cells.count("|") - 1)]


def verdict(values, holds, spec=".1f"):
    """'holds: a, b, c' / 'does NOT hold: ...' / 'not every case has finished'."""
    if None in values:
        return "not every case has finished"
    return ("holds" if holds(values) else "does NOT hold") + ": " + ", ".join(format(v, spec) for v in values)


def over(value, reference):
    """How far value lies over reference [%], or None where either is missing."""
    return value and reference and 100 * (value / reference - 1)


def expected(refs):
    """The test weight at h that the lab's data expect of each sample [lb/bu]: the ideal mixture
    of the lab's pure fractions, made denser by the lab's own mixing excess."""
    return {s: ideal_mixture(refs.test_weight, shares) * (1 + refs.excess[s]) for s, shares in SAMPLES.items()}


def test_weight(cases, refs):
    lab, excess = refs.test_weight, refs.excess
    expect = expected(refs)
    at_h = dict(expect, **lab)  # (a pure fraction against the lab's measurement)
    out = ["## Test weight per bushel (scenarios/test-weight.yaml)", "",
           "1.1 kg of each sample falls from the drop height into the one-quart kettle, which is struck "
           "level. The lab's test weight at h of the pure fractions: "
           + ", ".join(f"{f} {lab[f]} lb/bu" for f in FRACTIONS) + "; a mixture whose fractions kept "
           "their own packing would weigh "
           + ", ".join(f"{s} {ideal_mixture(lab, SAMPLES[s]):.2f} lb/bu" for s in SAMPLES)
           + " (their specific volumes added by mass). A real mixture packs denser: the lab's tapped mixtures "
           "of the same fractions (data/ternary_packing_compressibility.csv, a special cubic fit) pack "
           + ", ".join(f"{s} {100 * excess[s]:.2f} %" for s in SAMPLES) + " denser than their ideal mixture; "
           "with that excess the lab's data expect "
           + ", ".join(f"{s} {expect[s]:.2f} lb/bu" for s in SAMPLES) + " at h (an estimate: the excess "
           "was measured tapped, not poured). A pure fraction is set against the lab's measurement. "
           "Strike: the struck density against the kernels centred in the kettle before the strike, when the "
           "heap covered it.", ""]
    out += header("| case | sample | model | drop | unstruck [kg/m3] | struck [kg/m3] | test weight [lb/bu] "
                  "| against the lab at h [%] | strike [%] | kettle large / medium / small [%] "
                  "(sample) | filling time [s] | heap angle [deg]")
    struck = {}  # (sample, model, drop) -> the struck density of each seed [kg/m3], None until done
    for c in cases:
        _, sample, model, drop = c.name.split("-")[:4]
        shares = " / ".join(f"{100 * s:.1f}" for s in shares_of(sample))
        kettle = [c.result("fraction_" + f) for f in FRACTIONS]
        kettle = " / ".join(f"{100 * v:.1f}" for v in kettle) if None not in kettle else ""
        bd, lb = c.result("bulk_density"), c.result("test_weight_lb_bu")
        struck.setdefault((sample, model, drop), []).append(bd if c.done else None)
        # (unstruck: all the grain in and on the kettle over the kettle's volume, by a sensor that
        # reaches above the heap on purpose, so never full)
        out.append(f"| {c.name} | {sample} | {model} | {drop} | {fmt(c.result('bulk_density_unstruck'), '.1f')} "
                   f"| {c.cell('bulk_density', '.1f')} | {c.cell('test_weight_lb_bu', '.2f')} "
                   f"| {fmt(over(lb, at_h[sample]), '+.1f')} "
                   f"| {fmt(c.strike(), '+.1f')} | {kettle} ({shares}) "
                   f"| {fmt(c.result('filling_time'), '.2f')} | {fmt(c.result('heap_angle'), '.1f')} " + c.tail())
    out.append("")
    return out + test_weight_checks(struck, refs)


def pooled_sd(groups):
    """The standard deviation of one run from the groups of runs that differ only in their seed
    (pooled: the squares about each group's mean over the degrees of freedom), or None."""
    done = [g for g in groups if None not in g and len(g) > 1]
    dof = sum(len(g) - 1 for g in done)
    if not dof:
        return None
    return (sum(sum((v - mean(g)) ** 2 for v in g) for g in done) / dof) ** 0.5


def mean(values):
    return sum(values) / len(values)


def apart(a, b, sd):
    """Whether the means of the runs a and b differ by two standard deviations of their
    difference or more, one run's being sd; and that standard deviation."""
    sd_diff = sd * (1 / len(a) + 1 / len(b)) ** 0.5
    return abs(mean(b) - mean(a)) >= 2 * sd_diff, sd_diff


def ordered(groups, labels, sd, sign=1):
    """The check that each group's mean lies above (sign 1) or below (sign -1) the one before,
    as verdict words; with the seeds' scatter, the steps that are smaller than two standard
    deviations of their difference are named by their labels: they do not tell the order."""
    if any(None in g for g in groups):
        return "not every case has finished"
    words = verdict([mean(g) for g in groups], lambda v: all(sign * (b - a) > 0 for a, b in zip(v, v[1:])))
    if sd is None:
        return words
    close = [i for i in range(1, len(groups)) if not apart(groups[i - 1], groups[i], sd)[0]]
    steps = ", ".join(f"{labels[i - 1]} to {labels[i]}" for i in close)
    return words + (f" ({steps}: within two standard deviations of the seeds' scatter)" if close else "")


def test_weight_checks(struck, refs):
    """KanMark above Garrison at each drop that both have, the rise with the drop height, the
    pure fractions in the lab's order (large > medium > small), each against the lab's three
    loose densities of it, and the samples' mixing excess over them against the lab's, on the
    means of the seeds; and the seeds' scatter where a case ran with more than one."""
    sd = pooled_sd(list(struck.values()))
    out = []
    for model in sorted({k[1] for k in struck}):
        out += lab_loose(struck, refs, model) + pure_checks(struck, refs.excess, model, sd)
        drops = {s: [d for d in DROPS if (s, model, d) in struck] for s in SAMPLES}
        for drop in (d for d in DROPS if all(d in drops[s] for s in SAMPLES)):
            out.append(f"- KanMark > Garrison, {model}, {drop} (struck, kg/m3): "
                       + ordered([struck[(s, model, drop)] for s in SAMPLES], list(SAMPLES), sd, sign=-1))
        for sample in SAMPLES:  # (over the study's three heights, then over every height run)
            study = [d for d in drops[sample] if d in STUDY_DROPS]
            for ladder in (study, drops[sample]) if drops[sample] != study else (study,):
                if len(ladder) > 1:
                    out.append(f"- rises with the drop height, {sample} {model} ({', '.join(ladder)}; struck, "
                               "kg/m3): " + ordered([struck[(sample, model, d)] for d in ladder], ladder, sd))
    for (sample, model, drop), values in struck.items():
        if len(values) > 1 and None not in values:
            out.append(f"- seeds, {sample} {model} {drop} (struck, kg/m3): " + ", ".join(f"{v:.1f}" for v in values))
    if sd is not None:
        out.append(f"- the seeds' scatter: one run's struck density has a standard deviation of {sd:.2f} kg/m3 "
                   f"(pooled over the cases run with more than one seed)")
    return out


def pure_checks(struck, excess, model, sd):
    """At each drop where the three pure fractions have a case: their order, and how much denser
    than the ideal mixture of them each sample run at that drop packs (the lab's tapped mixtures:
    excess)."""
    out = []
    for drop in (d for d in DROPS if all((f, model, d) in struck for f in FRACTIONS)):
        pure = [struck[(f, model, drop)] for f in FRACTIONS]
        out.append(f"- large > medium > small, {model}, {drop} (struck, kg/m3): "
                   + ordered(pure, list(FRACTIONS), sd, sign=-1))
        for sample in (s for s in SAMPLES if (s, model, drop) in struck):
            runs = struck[(sample, model, drop)]
            if any(None in g for g in pure + [runs]):
                continue
            ideal = ideal_mixture({f: mean(g) for f, g in zip(FRACTIONS, pure)}, SAMPLES[sample])
            out.append(f"- mixing excess, {sample} {model}, {drop}: {100 * (mean(runs) / ideal - 1):+.2f} % over the "
                       f"ideal mixture of the model's pure fractions ({ideal:.1f} kg/m3); the lab's tapped "
                       f"mixtures {100 * excess[sample]:+.2f} %")
    return out


def lab_loose(struck, refs, model):
    """Each pure fraction's struck density at h against the lab's three loose densities of it:
    its kettle (the test weight at h), the loose fill of the tapped-density cylinder (packing
    ratio x kernel density x (1 - compressibility)) and the calibration cup, on which the
    model's parameters were calibrated."""
    out = []
    for f in FRACTIONS:
        runs = struck.get((f, model, "1h"))
        if not runs or None in runs:
            continue
        lab = (("its kettle", refs.test_weight[f] * LB_BU),
               ("the tapped cylinder's loose fill", lab_loose_fill(refs.tapped, f)),
               ("the calibration cup", refs.cup[f]))
        m = mean(runs)
        out.append(f"- the {f} fraction, {model}, 1h: {m:.1f} kg/m3 struck; the lab's loose density of it "
                   + ", ".join(f"in {where} {v:.1f} ({100 * (m / v - 1):+.1f} %)" for where, v in lab))
    return out


def densities(c):
    """The bulk density at each pressure level [kg/m3] (None where not reached)."""
    return [c.result("bulk_density_0")] + [c.result(f"bulk_density_{i}") for i in range(1, len(LEVELS))]


def worst(c, key):
    """The value of key_1 .. key_7 largest in size and its level, as 'VALUE at P kPa'."""
    values = [(v, LEVELS[i]) for i in range(1, len(LEVELS)) if (v := c.result(f"{key}_{i}")) is not None]
    if not values:
        return ""
    v, level = max(values, key=lambda x: abs(x[0]))
    return (f"{v / 1e3:+.2f} kPa" if key == "drift" else exponent(v, 2)) + f" at {level} kPa"


def compression(cases):
    out = ["## Confined compression (scenarios/compression.yaml)", "",
           "The 58.74 mm cylinder filled, struck and pressed by a lid to each level, held there by a servo "
           "until quasi-static, then held still for 0.2 s (drift: the lid's pressure at the end of that "
           "hold against the level; unbalanced: the force ratio there, quasi-static below 1e-4).", ""]
    out += header("| case | model | " + " | ".join(f"{p} kPa" for p in LEVELS)
                  + " | compaction 0 to 138 kPa [%] | largest drift | largest unbalanced")
    compaction = {}
    for c in cases:
        rho = densities(c)
        if c.done and rho[0] and rho[-1]:
            compaction[c.name] = 100 * (rho[-1] - rho[0]) / rho[0]
        model = c.name.split("-")[2]
        cells = [c.cell("bulk_density_0", ".1f")] + [c.cell(f"bulk_density_{i}", ".1f") for i in range(1, len(LEVELS))]
        out.append(f"| {c.name} | {model} | " + " | ".join(cells)
                   + f" | {fmt(compaction.get(c.name), '.1f')} | {worst(c, 'drift')} | {worst(c, 'unbalanced')} "
                   + c.tail())
    out += ["", "The lid's pressure at the end of each still hold, against the level [kPa]:", "",
            "| case | " + " | ".join(f"{p} kPa" for p in LEVELS[1:]) + " |", "|---|" + "---|" * (len(LEVELS) - 1)]
    for c in cases:
        out.append(f"| {c.name} | " + " | ".join(c.cell(f"drift_{i}", "+.2f", 1e-3) for i in range(1, len(LEVELS))) + " |")
    out.append("")
    for c in cases:
        rho = densities(c)
        if None not in rho:
            out.append(f"- the bulk density rises with every level, {c.name}: "
                       + verdict(rho, lambda v: all(a < b for a, b in zip(v, v[1:]))))
            out.append(wpacking(c.name, rho))
    for model in MODELS:
        soft, stiff = compaction.get(f"comp-large-{model}"), compaction.get(f"comp-large-{model}-stiff")
        if not soft or stiff is None:
            continue
        # Hertz: under one load the overlap goes as G^(-2/3), so the stiff kernels still overlap
        # STIFF_OVERLAP as deep. Soft = R + O, stiff = R + STIFF_OVERLAP O, if both rearrange
        # alike (R): O / soft = (1 - stiff / soft) / (1 - STIFF_OVERLAP); 1 - stiff / soft alone
        # is the least it can be.
        least = 1 - stiff / soft
        out.append(f"- overlap, {model}: the kernels ten times stiffer compact {stiff:.1f} % where the study's "
                   f"compact {soft:.1f} %; of the study's material's compaction at least {100 * least:.0f} % is "
                   f"the kernels' overlap, about {100 * least / (1 - STIFF_OVERLAP):.0f} % if both rearrange "
                   f"alike (the stiff kernels overlap {STIFF_OVERLAP:.2f} times as deep), the rest their "
                   f"rearranging")
    return out


def wpacking(name, rho):
    """The WPACKING form D - D_o = a P + b sqrt(P) (docs/bins.md, at the run's one moisture, so
    without its c term) fitted to a compression curve by least squares, as a check line: the
    coefficients `bushel bin --wpacking a,b,0` takes."""
    import numpy as np
    p = np.array(LEVELS[1:], dtype=float)
    rise = np.array(rho[1:]) - rho[0]
    terms = np.column_stack([p, np.sqrt(p)])
    a, b = np.linalg.lstsq(terms, rise, rcond=None)[0]
    worst_residual = float(np.abs(terms @ (a, b) - rise).max())
    return (f"- WPACKING form, {name}: D - D_o = a P + b sqrt(P) with a = {a:.3f} kg/m3 per kPa, "
            f"b = {b:.2f} kg/m3 per sqrt(kPa) (least squares over the levels; largest residual "
            f"{worst_residual:.1f} kg/m3)")


def time_step(cases):
    out = ["## Time step of the compression (reduced sample)", "",
           "120 g of large 5-sphere kernels in the cylinder cut to 30 mm, filled at 0.5 of the critical step "
           "(the same loose sample in every case), the lid's stages at PERCENT of the critical step.", ""]
    out += header("| case | lid's step [% critical] | lid's dt [us] | 0 kPa [kg/m3] | 138 kPa [kg/m3] "
                  "| against the smallest step at 138 kPa [%] | unbalanced at 138 kPa")
    finest = None
    rows = sorted(cases, key=lambda c: int(c.name.split("-")[2]))
    if rows[0].done:
        finest = rows[0].result("bulk_density_7")
    top = []
    for c in rows:
        rho = c.result("bulk_density_7")
        if c.done:
            top.append(rho)
        diff = f"{100 * (rho - finest) / finest:+.2f}" if rho and finest else ""
        dt = c.stage("hold_7").get("dt_s")
        out.append(f"| {c.name} | {c.name.split('-')[2]} | {fmt(dt and dt * 1e6, '.3f')} "
                   f"| {c.cell('bulk_density_0', '.1f')} | {c.cell('bulk_density_7', '.1f')} | {diff} "
                   f"| {fmt(c.result('unbalanced_7') and exponent(c.result('unbalanced_7'), 2), '')} " + c.tail())
    out.append("")
    if len(top) == len(rows) and None not in top:
        out.append(f"- the bulk density at 138 kPa spans {max(top) - min(top):.1f} kg/m3 "
                   f"({100 * (max(top) - min(top)) / min(top):.2f} %) over the steps")
    return out


LAB_TAP_RATE = 4.33  # [Hz] the lab's tapping rate (docs/wheat.md)


def lab_loose_fill(lab, fraction):
    """The lab's loose density of a fraction in the tapped-density cylinder [kg/m3]: packing
    ratio x kernel density x (1 - compressibility); None where the references lack either."""
    ratio, c = lab.get((fraction, "packing_ratio")), lab.get((fraction, "compressibility"))
    return None if ratio is None or c is None else ratio * KERNEL_DENSITY * (1 - c)


def tapped(cases, refs, phases):
    lab = refs.tapped
    out = ["## Loose and tapped density (scenarios/tapped-density.yaml)", "",
           "The 400 cm3 cylinder filled through a funnel and struck (loose), topped up in an extension, "
           "tapped (taps of 3 mm at the rate in the row; the lab's 500 at 4.33 Hz) and struck again (tapped). "
           f"Packing ratio: tapped bulk density over the kernels' density ({KERNEL_DENSITY:.0f} kg/m3); "
           "compressibility: (tapped - loose) / tapped. The lab's values are those of KanMark's sieve "
           "fractions (data/reference_values.csv); its loose density is packing ratio x kernels' density x "
           "(1 - compressibility). A case tapped at another rate (its name ends in the rate) is set against "
           "its twin at the lab's rate, below, not against the lab's packing ratio; a case of the study tapped at "
           "another rate is set against the lab's values, and a line below names the twins that measured that rate.", ""]
    out += header("| case | fraction | model | taps | loose [kg/m3] | lab | against the lab [%] | tapped [kg/m3] "
                  "| packing ratio | lab | against the lab [%] | compressibility | lab | strike loose / tapped [%]")
    ratios, compress = {}, {}  # (model, fraction) at the lab's rate -> the case's value [-], None until done
    cases = sorted(cases, key=lambda c: other_rate_case(c.name) is not None)  # (those at another rate last)
    for c in cases:
        _, fraction, model = c.name.split("-")[:3]
        taps, hz = c.parameter("taps"), c.parameter("tap_frequency")
        taps = f"{taps} at " + re.sub(r"\s*Hz$", " Hz", hz) if taps and hz else ""
        loose, ratio = c.result("loose_bulk_density"), c.result("packing_ratio")
        lab_loose, lab_ratio = lab_loose_fill(lab, fraction), lab.get((fraction, "packing_ratio"))
        other = other_rate_case(c.name) is not None
        if not other:
            ratios[(model, fraction)] = ratio if c.done else None
            compress[(model, fraction)] = c.result("compressibility") if c.done else None
        out.append(f"| {c.name} | {fraction} | {model} | {taps} | {c.cell('loose_bulk_density', '.1f')} "
                   f"| {fmt(lab_loose, '.1f')} | {fmt(over(loose, lab_loose), '+.1f')} "
                   f"| {c.cell('tapped_bulk_density', '.1f')} | {c.cell('packing_ratio', '.3f')} "
                   f"| {fmt(lab_ratio, '')} | {'' if other else fmt(over(ratio, lab_ratio), '+.1f')} "
                   f"| {c.cell('compressibility', '.4f')} | {fmt(lab.get((fraction, 'compressibility')), '')} "
                   f"| {strikes(c)} " + c.tail())
    out.append("")
    for model in sorted({m for m, _ in ratios}):
        if all((model, f) in ratios for f in FRACTIONS):
            out += [tapped_order("packing ratio, large > medium > small", model, ratios, lab, "packing_ratio", -1),
                    tapped_order("compressibility, large < medium < small", model, compress, lab, "compressibility", 1)]
    named = {c.name: c for c in cases}
    twins = [(c, named[c.name.rsplit("-", 1)[0]]) for c in cases
             if other_rate_case(c.name) is not None and c.name.rsplit("-", 1)[0] in named]
    out += [other_rate(c, twin) for c, twin in twins]
    out += [line for line in (study_case_rate(c, twins) for c in cases) if line]
    return out + at_rest(cases, phases)


def other_rate_case(name):
    """The rate [Hz] a twin case names: tap-FRACTION-MODEL-HZhz, the twin of tap-FRACTION-MODEL
    tapped at another rate than the lab's; None for any other name."""
    m = re.fullmatch(r"tap-[a-z]+-[0-9]+s-([0-9.]+)hz", name)
    return float(m.group(1)) if m else None


def study_case_rate(c, twins):
    """For a case of the study (not a twin) tapped at another rate than the lab's, a line that
    says so and names the twins (other-rate case, twin) that measured that rate; else ''."""
    hz = c.parameter("tap_frequency")
    hz = float(re.sub(r"\s*Hz$", "", hz)) if hz else LAB_TAP_RATE
    if other_rate_case(c.name) is not None or hz == LAB_TAP_RATE:
        return ""
    pairs = [f"{o.name} against {t.name}" for o, t in twins if other_rate_case(o.name) == hz]
    return (f"- {c.name} taps at {hz:g} Hz, not the lab's {LAB_TAP_RATE:g} Hz, and is set against the lab all the "
            "same; what that rate moves: " + ("; ".join(pairs) + " (above)" if pairs else "no twin tapped at both rates"))


def other_rate(c, twin):
    """A case tapped at another rate against its twin at the lab's rate (the same loose fill), as
    a check line."""
    what = f"- {c.name} against {twin.name}: "
    if not (c.done and twin.done):
        return what + "not every case has finished"
    a, b = twin.result("tapped_bulk_density"), c.result("tapped_bulk_density")
    return (what + f"loose {twin.result('loose_bulk_density'):.1f} and {c.result('loose_bulk_density'):.1f} kg/m3, "
            f"tapped {a:.1f} and {b:.1f} ({b - a:+.1f} kg/m3, {over(b, a):+.2f} %), compressibility "
            f"{twin.result('compressibility'):.4f} and {c.result('compressibility'):.4f}")


def strikes(c):
    """What the loose and the tapped strike cost [%], as 'LOOSE / TAPPED', or ''."""
    loose, tapped = c.tap_strike("loose"), c.tap_strike("tapped")
    return f"{loose:+.1f} / {tapped:+.1f}" if loose is not None and tapped is not None else ""


def tapped_order(what, model, values, lab, key, sign):
    """The check that the three fractions' values run in the lab's order (falling with sign -1,
    rising with 1), as a line with the lab's values beside."""
    v = [values[(model, f)] for f in FRACTIONS]
    words = verdict(v, lambda v: all(sign * (b - a) > 0 for a, b in zip(v, v[1:])), ".3f")
    return f"- {what}, {model}: {words}; the lab: " + ", ".join(f"{lab[(f, key)]:.3f}" for f in FRACTIONS)


def tap_rate(cases, phases):
    out = ["## Loose and tapped density: the tapping rate (reduced sample)", "",
           "110 g of large single-sphere kernels into the cylinder cut to 30 mm, 40 g more into a 30 mm "
           "extension, 500 taps of 3 mm at the lab's 4.33 Hz and at 8.66 Hz, two seeds each. Each tap's "
           "impact (a 3 mm free fall) is the same at both rates; only the slow lift between taps is "
           "shorter. Before the strike: the kernels centred in the cylinder once the extension is off, "
           "the tapped grain still above the rim; the strike: the tapped density against it.", ""]
    out += header("| case | rate [Hz] | seed | loose [kg/m3] | before the strike [kg/m3] | tapped [kg/m3] "
                  "| strike [%] | compressibility")
    tapped, before = {}, {}  # rate -> the density of each seed [kg/m3], None until done
    for c in cases:
        _, _, rate, seed = c.name.split("-")
        rate, seed = rate.removesuffix("hz"), seed.removeprefix("seed")
        pre = c.before_strike("tapped")
        tapped.setdefault(rate, []).append(c.result("tapped_bulk_density") if c.done else None)
        before.setdefault(rate, []).append(pre if c.done else None)
        out.append(f"| {c.name} | {rate} | {seed} | {c.cell('loose_bulk_density', '.1f')} | {fmt(pre, '.1f')} "
                   f"| {c.cell('tapped_bulk_density', '.1f')} | {fmt(c.tap_strike('tapped'), '+.1f')} "
                   f"| {c.cell('compressibility', '.4f')} " + c.tail())
    out.append("")
    rates = sorted(tapped, key=float)
    if len(rates) == 2:
        for what, d in (("tapped density", tapped), ("density before the strike", before)):
            a, b = d[rates[0]], d[rates[1]]
            out += told_apart(f"{what} at {rates[1]} Hz against {rates[0]} Hz", a, b, pooled_sd([a, b]), "the rates")
    return out + at_rest(cases, phases)


MODEL_TWINS = ("tap-rate-8.66hz-seed1", "tap-rate-8.66hz-seed2")  # the calibrated single spheres beside tap-model


def tap_model(cases, twins, phases):
    """The reduced tapped sample at 8.66 Hz with other kernels (tap-model-*) beside the calibrated
    single spheres' runs of it (TWINS: tap-rate-8.66hz-seedN)."""
    out = ["## Loose and tapped density: what the taps' compaction depends on (reduced sample)", "",
           "The tapping rate's reduced sample (large kernels, the cylinder cut to 30 mm, 500 taps of 3 mm at "
           "8.66 Hz) with other kernels: the 5-sphere set, and single spheres without rolling friction between "
           "kernels; beside them the calibrated single spheres' runs of it. Before the strikes: the taps' own "
           "compaction, (tapped - loose) / tapped of the kernels centred in the cylinder before each strike, "
           "the grain still above the rim: free of what either strike cost.", ""]
    out += header("| case | model | rolling friction, kernels | loose [kg/m3] | tapped [kg/m3] | compressibility "
                  "| before the loose strike [kg/m3] | before the tapped strike [kg/m3] "
                  "| compaction before the strikes [%]")
    base = []  # the calibrated single spheres' compaction before the strikes [-], None until done
    for c in twins + cases:
        compaction = c.tap_compaction()
        if c in twins:
            base.append(compaction)
        out.append(f"| {c.name} | {c.parameter('model')} | {c.parameter('fr_ww')} "
                   f"| {c.cell('loose_bulk_density', '.1f')} | {c.cell('tapped_bulk_density', '.1f')} "
                   f"| {c.cell('compressibility', '.4f')} | {fmt(c.before_strike('loose'), '.1f')} "
                   f"| {fmt(c.before_strike('tapped'), '.1f')} | {fmt(compaction and 100 * compaction, '.2f')} "
                   + c.tail())
    out.append("")
    for c in cases:
        line = f"- compaction before the strikes, {c.name} against the calibrated single spheres: "
        if c.tap_compaction() is None or None in base or not base:
            out.append(line + "not every case has finished")
            continue
        spread = ", ".join(f"{100 * b:.2f}" for b in base)
        line += (f"{100 * c.tap_compaction():.2f} % against {100 * mean(base):.2f} % "
                 f"({100 * (c.tap_compaction() - mean(base)):+.2f} points; the single spheres' seeds {spread} %")
        sd = pooled_sd([base])  # (one run's scatter from the single spheres' seeds alone)
        if sd is not None:
            told, sd_diff = apart(base, [c.tap_compaction()], sd)
            line += (f"; one run's standard deviation {100 * sd:.2f} points from them, the difference's "
                     f"{100 * sd_diff:.2f}: " + ("told apart" if told else "not told apart (under two standard deviations)"))
        out.append(line + ")")
    return out + at_rest(cases, phases)


def tap_phases(kept):
    """The tapped cases' kinetic energy by the time into a tap's period, from tap-phases.csv beside
    KEPT (validation/tap_series.py --phases, which run-study.sh refreshes): {case: [(bin's start
    [s], kinetic energy per particle [J])]}; empty where there is no such file."""
    path = os.path.join(os.path.dirname(os.path.abspath(kept)), "tap-phases.csv")
    phases = {}
    if os.path.exists(path):
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                phases.setdefault(r["case"], []).append((float(r["phase_start"]),
                                                         float(r["kinetic_energy_per_particle"])))
    return phases


def at_rest(cases, phases):
    """Per finished case with phases: the quietest bin of a tap's period against the bin just
    after the impact, as a line: how still the bed is before the next fall (the reduced and
    full-size single spheres: 0.07 to 1.1 %, validation/results/tap-series.md)."""
    out = []
    for c in cases:
        bins = phases.get(c.name)
        if not (c.done and bins and len(bins) > 1):
            continue
        (t, _), ratio = quietest(bins)
        out.append(f"- before each fall, {c.name}: the quietest {1e3 * (bins[1][0] - bins[0][0]):.0f} ms of "
                   f"a tap's period ({1e3 * t:.0f} ms into it) holds {100 * ratio:#.2g} % of the grain's "
                   "kinetic energy just after the impact")
    return out


def told_apart(what, a, b, sd, things):
    """The difference of the means of the runs b and a [kg/m3] and whether two standard deviations
    of it (one run's: sd, None where unknown) tell them apart, as a check line; none until every
    run has finished."""
    if None in a + b:
        return []
    line = f"- {what}: {mean(b) - mean(a):+.1f} kg/m3 ({100 * (mean(b) / mean(a) - 1):+.2f} %) on the seeds' means"
    if sd is not None:
        told, sd_diff = apart(a, b, sd)
        line += (f"; one run's standard deviation {sd:.1f} kg/m3, the difference's {sd_diff:.1f}: {things} are "
                 + ("told apart" if told else "not told apart (under two standard deviations)"))
    return [line]


def tw_time_step(cases):
    out = ["## Test weight: the time step of single spheres (reduced sample)", "",
           "0.25 kg of Garrison's sample, single spheres, from h into a kettle of 250 cm3 and 60 mm, struck "
           "level, at PERCENT of the Rayleigh step, three seeds each. The single-sphere cases run at 20 %, "
           "where their parameters were calibrated: above the critical step of the pairs with restitution "
           "0.1 (their tangential mode, docs/physics.md section 3).", ""]
    out += header("| case | step [% Rayleigh] | step [critical] | seed | unstruck [kg/m3] | struck [kg/m3] "
                  "| strike [%] | filling time [s]")
    struck = {}  # percent -> the struck density of each seed [kg/m3], None until done
    for c in sorted(cases, key=lambda c: (-int(c.name.split("-")[2]), c.name)):
        _, _, percent, seed = c.name.split("-")
        struck.setdefault(int(percent), []).append(c.result("bulk_density") if c.done else None)
        critical = c.j and c.j["dt_s"] / c.j["critical_step_s"]
        out.append(f"| {c.name} | {percent} | {fmt(critical, '.2f')} | {seed.removeprefix('seed')} "
                   f"| {fmt(c.result('bulk_density_unstruck'), '.1f')} | {c.cell('bulk_density', '.1f')} "
                   f"| {fmt(c.strike(), '+.1f')} "
                   f"| {fmt(c.result('filling_time'), '.2f')} " + c.tail())
    out.append("")
    finest = min(struck)
    sd = pooled_sd(list(struck.values()))
    for percent in sorted(struck, reverse=True):
        if percent != finest:
            out += told_apart(f"struck density at {percent} % against {finest} % of the Rayleigh step",
                              struck[finest], struck[percent], sd, "the steps")
    return out


def tables(runs, kept, reference_csv, names):
    refs, phases = references(reference_csv), tap_phases(kept)
    cases = [Case(runs, kept, n) for n in names]
    groups = [
        (lambda n: n.startswith("tw-") and not n.startswith("tw-dt-"), lambda cs: test_weight(cs, refs)),
        (lambda n: n.startswith("tw-dt-"), tw_time_step),
        (lambda n: n.startswith("comp-") and not n.startswith("comp-dt-"), compression),
        (lambda n: n.startswith("comp-dt-"), time_step),
        (lambda n: n.startswith("tap-") and not n.startswith(("tap-rate-", "tap-model-")),
         lambda cs: tapped(cs, refs, phases)),
        (lambda n: n.startswith("tap-rate-"), lambda cs: tap_rate(cs, phases)),
        (lambda n: n.startswith("tap-model-"),
         lambda cs: tap_model(cs, [Case(runs, kept, n) for n in MODEL_TWINS], phases)),
    ]
    out = ["# The study's experiments at full size", "",
           "Written by `validation/run-study.sh` (validation/study_table.py); the command and how to "
           "read it: validation/README.md.", ""]
    for member, make in groups:
        chosen = [c for c in cases if member(c.name)]
        if chosen:
            out += make(chosen) + [""]
    return "\n".join(out)


def expected_csv(reference_csv):
    """The test weight at h that the lab's data expect of each sample (test_weight), as a
    reference table for `bushel report --reference` (docs/report.md)."""
    out = ["scenario,result,share_large,share_medium,share_small,drop,value,unit,sd,source"]
    for sample, value in expected(references(reference_csv)).items():
        shares = SAMPLES[sample]
        out.append("test-weight,bulk_density," + ",".join(f"{100 * s:g}%" for s in shares)
                   + f",5.1 cm,{value:.2f},lb/bu,,lab fractions mixed (estimate: ideal + tapped mixing excess)")
    return "\n".join(out) + "\n"


def found(runs, kept):
    """The cases with a folder in RUNS or KEPT."""
    names = set()
    for folder in (runs, kept):
        if os.path.isdir(folder):
            names |= {n for n in os.listdir(folder) if os.path.isdir(os.path.join(folder, n))
                      and n.split("-")[0] in ("tw", "comp", "tap")}
    return sorted(names)


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--expected":
        print(expected_csv(sys.argv[2]), end="")
    elif len(sys.argv) < 4:
        sys.exit(__doc__.strip())
    else:
        print(tables(*sys.argv[1:4], sys.argv[4:] or found(*sys.argv[1:3])), end="")
