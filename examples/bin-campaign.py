#!/usr/bin/python3
"""A designed-experiment campaign from Python: how wall friction and the lateral pressure
ratio K change the mass of wheat in a 9 m bin and the pressure on its floor (the bin model,
docs/bins.md: each run is `bushel bin`, a second). A central composite design, run two at a
time, a quadratic model of each response, and the settings that keep the floor pressure low
while holding the most grain.

  PYTHONPATH=build/release/python /usr/bin/python3 examples/bin-campaign.py [OUT]

OUT (default runs/bin-campaign) holds the campaign: run_N/ per row and results.csv. Run it
again and the finished runs are kept.
"""
import os
import sys

import bushel

out = sys.argv[1] if len(sys.argv) > 1 else os.path.join("runs", "bin-campaign")
design = bushel.doe.design("ccd", {"wall_friction": (0.3, 0.5), "k": (0.4, 0.6)}, centre=3, seed=1)
command = ["{bushel}", "bin", "--diameter", "9m", "--grain-height", "7m", "--test-weight", "60lb/bu",
           "--wpacking", "0.35,3,0.01", "--moisture", "12%", "--wall-friction", "{wall_friction}", "--k", "{k}",
           "--json"]
campaign = bushel.doe.run(design, out, command=command, responses=["mass_kg", "bottom_pressure_Pa"], jobs=2)

models = {r: bushel.doe.fit(campaign.values, campaign.responses[r], design.ranges, model="quadratic")
          for r in campaign.responses}
for name, m in models.items():
    print(f"{name}: R2 {m.r2:.4f}; " + ", ".join(f"{c['term']} {c['coef']:.4g}" for c in m.coefficients))

p, mass = campaign.responses["bottom_pressure_Pa"], campaign.responses["mass_kg"]
best = bushel.doe.optimize(models, {"bottom_pressure_Pa": f"minimize:{p.min():.0f}:{p.max():.0f}",
                                    "mass_kg": f"maximize:{mass.min():.0f}:{mass.max():.0f}"})
print("compromise (desirability {:.3f}): wall friction {wall_friction:.3f}, K {k:.3f}".format(
    best["composite"], **best["settings"]))
for name, y in best["predicted"].items():
    print(f"  {name} {y:.6g} (desirability {best['desirability'][name]:.3f})")
