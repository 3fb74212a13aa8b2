"""Campaigns and the compromise of several responses from Python (bushel.doe.run, optimize)
against `bushel doe design`, `bushel doe run` and `bushel doe optimize` on the bin model, a
run that fails, and bad campaigns refused before anything runs.
usage: test_doe.py BUSHEL WORKDIR"""
import json
import os
import shutil
import subprocess
import sys
import warnings

import bushel

bushel_program, work = os.path.abspath(sys.argv[1]), sys.argv[2]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
os.chdir(work)


def check(cond, what):
    if not cond:
        print("FAILED:", what)
        sys.exit(1)


def cli(*args):
    return subprocess.run([bushel_program, *args], check=True, capture_output=True, text=True).stdout


# The design table is the one `bushel doe design` writes, byte for byte.
d = bushel.doe.design("factorial", {"mu": (0.2, 0.4), "k": (0.4, 0.6)}, centre=2, seed=3)
check(d.csv == cli("doe", "design", "factorial", "--factors", "mu=0.2:0.4,k=0.4:0.6", "--center", "2", "--seed", "3"),
      "design CSV as the CLI writes it:\n" + d.csv)
check(list(d.point_type).count(0) == 2, "two centre points")

# A campaign of bin-model runs, two at a time: each row's responses are what `bushel bin` gives.
bin_cmd = ["{bushel}", "bin", "--diameter", "9m", "--grain-height", "7m", "--test-weight", "60lb/bu", "--wpacking",
           "0.35,3,0.01", "--moisture", "12%", "--wall-friction", "{mu}", "--k", "{k}", "--json"]
responses = ["mass_kg", "bottom_pressure_Pa"]
c = bushel.doe.run(d, "camp", command=bin_cmd, responses=responses, jobs=2)
check(len(c.status) == 6 and all(c.status == "done") and len(c.failed) == 0, f"six runs done: {c.status}")
k = list(c.table["std_order"]).index(1)
one = json.loads(cli(*[str(a).replace("{bushel}", "").replace("{mu}", "%g" % c.values["mu"][k])
                       .replace("{k}", "%g" % c.values["k"][k]) for a in bin_cmd[1:]]))
check(abs(c.responses["mass_kg"][k] / one["mass_kg"] - 1) < 1e-9, f"run 1's mass {c.responses['mass_kg'][k]} vs {one['mass_kg']}")
again = bushel.doe.run(d, "camp", command=bin_cmd, responses=responses, jobs=2)
check(all((again.table[n] == c.table[n]).all() for n in responses), "run again: the finished runs are kept")
check(list(c.dataframe().columns) == list(c.table), "a pandas DataFrame of the table")

# The same campaign on MPI ranks (mpirun -n 2: rank 1 runs the rows): the same numbers.
os.environ.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")  # (CI containers run as root)
m = bushel.doe.run(d, "camp-mpi", command=bin_cmd, responses=responses, ranks=2)
check(all((m.table[n] == c.table[n]).all() for n in responses), "MPI and local campaigns agree")

# Several responses at once, as `bushel doe optimize --goal` finds it.
goals = {"mass_kg": "maximize:354000:355600", "bottom_pressure_Pa": "minimize:38000:49000"}
models = {r: bushel.doe.fit(c.values, c.responses[r], d.ranges, model="interactions") for r in responses}
best = bushel.doe.optimize(models, goals)
ref = json.loads(cli("doe", "optimize", "camp/results.csv", "--factors", "mu,k", "--response", ",".join(responses),
                     "--model", "interactions", "--goal", ",".join(goals[r] for r in responses), "--json"))
check(abs(best["composite"] - ref["composite_desirability"]) < 1e-9, f"D {best['composite']} vs {ref}")
check(all(abs(best["settings"][f] - ref["settings"][f]) < 1e-9 for f in ("mu", "k")), f"{best} vs {ref}")
held = bushel.doe.optimize(models, goals, fixed={"k": 0.5}, weights={"mass_kg": 3})
check(held["settings"]["k"] == 0.5, f"k held: {held}")

# A run that fails (negative wall friction) is recorded, the others finish.
bad = bushel.doe.design("factorial", {"mu": (-0.1, 0.3), "k": (0.4, 0.6)}, centre=1)
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    f = bushel.doe.run(bad, "camp-failing", command=bin_cmd, responses=responses)
check(sorted(f.failed) == [1, 3], f"the rows with mu = -0.1 failed: {f.failed}, {f.status}")
check(any("2 runs failed" in str(w.message) for w in caught), f"a warning: {[str(w.message) for w in caught]}")

# Bad campaigns: refused before anything runs, with the CLI's message.
scenario = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scenarios", "cup-pour.yaml")
for what, call in (
        ("expected a scenario or a command", lambda: bushel.doe.run(d, "x1", responses=responses)),
        ("expected a mass with a unit", lambda: bushel.doe.run(bushel.doe.design("lhs", {"mass": (0.01, 0.02)}, runs=2, seed=1),
                                                              "x2", scenario=scenario, responses=["bulk_density"])),
        ("placeholder {kk} names no column", lambda: bushel.doe.run(d, "x3", command=bin_cmd + ["{kk}"],
                                                                     responses=responses)),
        ("holds another design", lambda: bushel.doe.run(bad, "camp", command=bin_cmd, responses=responses)),
        ("expected a goal for each model", lambda: bushel.doe.optimize(models, {"mass_kg": goals["mass_kg"]})),
        ("weights: expected a weight > 0", lambda: bushel.doe.optimize(models, goals, weights={"mass_kg": 0}))):
    try:
        call()
        check(False, f"no error for: {what}")
    except bushel.InputError as e:
        check(what in str(e), f"expected '{what}' in: {e}")
print("doe check passed")
