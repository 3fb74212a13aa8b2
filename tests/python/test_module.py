"""The Python module agrees with the C++ library and raises ValueError on bad input."""
import math
import sys

import bushel


def check(cond, what):
    if not cond:
        print("FAILED:", what)
        sys.exit(1)


t = bushel.template("large_5s")
check(abs(t["mass_kg"] / 0.0346e-3 - 1) < 0.01, "large_5s mass 0.0346 g")
check(len(t["spheres"]) == 5, "five spheres")
check("large_asg" in bushel.template_names(), "template names")
check(math.isclose(bushel.parse("60lb/bu", "density"), 772.31, rel_tol=1e-4), "lb/bu")
g = bushel.pseudo_ellipsoid(6.12e-3, 3.05e-3, 5, mass=0.0346e-3)
check(abs(g["mass_kg"] / 0.0346e-3 - 1) < 1e-4, "ellipsoid hits its mass")
check(abs(bushel.shape_factors(5.42, 2.96, 2.65)["elongation"] - 2.045) < 1e-3, "elongation")
check(bushel.shape_factors("5.42mm", "2.96 mm", "2.65mm") == bushel.shape_factors(5.42e-3, 2.96e-3, 2.65e-3),
      "lengths with units")
check(bushel.template("large_5s", density="1373 kg/m3") == bushel.template("large_5s", density=1373.0), "density text")
check(math.isclose(bushel.mass_in_bin("60 lb/bu", 1.0, "1 bu"), 27.2155, rel_tol=1e-4), "bushel of 60 lb/bu wheat")
for bad in (lambda: bushel.parse("6.12", "length"), lambda: bushel.template("no_such_kernel"),
            lambda: bushel.shape_factors("5.42 kg", 1, 1), lambda: bushel.packing_ratio([1], 2)):
    try:
        bad()
        check(False, "bad input raises")
    except ValueError as e:
        check("expected" in str(e) or "unknown" in str(e), str(e))
# Designed experiments: a design in the factors' units; the study's response surface
# (data/rsm_5sphere_large_table3_10.csv) refitted from Python, and the settings it solves for
# predict the target.
import csv, os  # noqa: E401,E402
d = bushel.doe.design("ccd", {"a": (0.2, 0.4), "b": (10, 30)}, centre=3, seed=7)
check(d.coded.shape == (11, 2) and sorted(d.run_order) == list(range(1, 12)), "ccd of 2 factors, 3 centre points")
check(abs(d.values["b"].max() - (20 + 10 * 2 ** 0.5)) < 1e-9, "axial points at alpha in the factor's units")
root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
rows = list(csv.DictReader(l for l in open(os.path.join(root, "data", "rsm_5sphere_large_table3_10.csv"))
                           if not l.startswith("#")))
factors = ["fs_ww", "fr_ww", "e_ww", "fs_ws"]
values = {f: [float(r[f]) for r in rows] for f in factors}
ranges = {f: (min(v), max(v)) for f, v in values.items()}
m = bushel.doe.fit(values, [float(r["bulk_density"]) for r in rows], ranges, model="quadratic")
check(m.runs == 30 and abs(m.r2 - 0.99920) < 5e-5, f"R2 {m.r2}, as `bushel doe analyze` reports it (99.92 %)")
at = m.solve(826.1, fixed={"fr_ww": ranges["fr_ww"][0]})
check(abs(m.predict(at) - 826.1) < 0.05, f"solved settings predict the target: {m.predict(at)}")
lo, hi = m.prediction_interval(at)
check(lo < 826.1 < hi, "the target inside its prediction interval")
for bad in (lambda: bushel.doe.design("ccc", {"a": (0, 1)}), lambda: bushel.doe.design("lhs", {"a": (0, 1)}, runs=5)):
    try:
        bad()
        check(False, "bad design raises")
    except ValueError as e:
        check("did you mean" in str(e) or "seed" in str(e), str(e))
print("1 passed, 0 failed")
