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
print("1 passed, 0 failed")
