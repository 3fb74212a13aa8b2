"""`bushel calibrate` (docs/calibration.md) on an analytic model whose answer is known: it stops
with a run that confirms a point within the tolerance, its result files agree with each other,
it continues a stopped calibration to the same points, failed runs are excluded, and bad
calibration files are refused with file, line and key.
usage: test_calibrate.py BUSHEL WORKDIR"""
import csv
import json
import os
import shutil
import subprocess
import sys

import numpy as np

from bushel.calibrate import Parameter, Settings, Target, calibrate
from bushel.calibration_spec import read_spec

bushel_program, work = os.path.abspath(sys.argv[1]), sys.argv[2]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
os.chdir(work)


def check(cond, what):
    if not cond:
        print("FAILED:", what)
        sys.exit(1)


# The model: y = 100 + 20 a - 10 b + 5 a b with noise of sd 0.5 seeded by the run's seed; it
# fails (exit 1) where a > 0.85, and reports ok = 0 (a clogged cup, say) where b > 0.9.
with open("model.py", "w") as f:
    f.write("import json, sys, numpy as np\n"
            "a, b, seed = float(sys.argv[1]), float(sys.argv[2]), int(sys.argv[3])\n"
            "if a > 0.85: sys.exit('model: a out of its valid range')\n"
            "y = 100 + 20 * a - 10 * b + 5 * a * b + np.random.default_rng(seed).normal(0, 0.5)\n"
            "print(json.dumps({'y': y, 'ok': 0 if b > 0.9 else 1}))\n")


def truth(a, b):
    return 100 + 20 * a - 10 * b + 5 * a * b


SPEC = """command: [{python}, "{{spec_dir}}/model.py", "{{a}}", "{{b}}", "{{seed}}"]
seed_parameter: seed
parameters:
  a: {{low: 0, high: 1}}
  b: {{low: 0, high: 1}}
targets:
  y: {{value: 112, sd: 0.5, tolerance: 1, scatter: 0.5}}
where: ok>=1
batch: 2
budget: 20
seed: 3
"""
with open("model.yaml", "w") as f:
    f.write(SPEC.format(python=sys.executable))


def calibrate_cli(*args, ok=True):
    p = subprocess.run([bushel_program, "calibrate", *args], capture_output=True, text=True)
    check((p.returncode == 0) == ok, f"bushel calibrate {args}: exit {p.returncode}\n{p.stdout}\n{p.stderr}")
    return p


# A calibration stopped by a small budget, then continued to its end, asks for the same points
# and gives the same result as one that ran through.
calibrate_cli("model.yaml", "--out", "stopped", "--budget", "5")
first = json.load(open("stopped/calibration.json"))
check(first["status"] == "budget" and first["runs"] == 5, f"stopped at the budget: {first['status']} {first['runs']}")
p = calibrate_cli("model.yaml", "--out", "stopped")
check("5 runs from before" in p.stderr, "continued from the 5 runs before:\n" + p.stderr)
calibrate_cli("model.yaml", "--out", "through")
a, b = json.load(open("stopped/calibration.json")), json.load(open("through/calibration.json"))
check(open("stopped/points.csv").read() == open("through/points.csv").read(), "the same points stopped or not")
check(a["best"] == b["best"], f"the same best point: {a['best']} vs {b['best']}")

# On MPI ranks (rank 0 hands out the batch's runs) the same points and values.
if shutil.which("mpirun"):
    os.environ.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")  # (CI containers run as root)
    calibrate_cli("model.yaml", "--out", "ranks", "--budget", "7", "--ranks", "3")
    check(open("ranks/points.csv").read().splitlines() == open("through/points.csv").read().splitlines()[:8],
          "the same points on MPI ranks")

# The answer: validated, within the tolerance of the noise-free model, in fewer runs than a
# 3-level factorial with replicates would take.
check(b["status"] == "validated", f"validated: {b['status']}")
best = b["best"]["parameters"]
check(abs(truth(best["a"], best["b"]) - 112) <= 1.0, f"the model at the best point within 1 of 112: {best}")
check(abs(b["best"]["observed"]["y"] - 112) <= 1.0, "the confirming run within the tolerance")
check(b["best"]["meet_probability"] >= 0.9, "P(meet) at least the confidence")
check(b["runs"] <= 12, f"at most 12 runs: {b['runs']}")
# The region that meets the target lies along the line 20 a - 10 b + 5 a b = 12, within
# a few tolerances of it, and holds the best point.
region = b["region"]
check(region["samples"] > 0 and region["low"]["a"] <= best["a"] <= region["high"]["a"], f"region {region}")

# The files agree: every run in runs.csv, runs.csv's counted runs are those with a value.
with open("through/runs.csv") as f:
    rows = list(csv.DictReader(f))
check(len(rows) == b["runs"], "a row per run")
for r, j in zip(rows, b["run_list"]):
    check((r["y"] != "") == (r["counted"] == "1") == j["counted"], f"counted where it has a value: {r}")
for name in ("calibration.md", "convergence.png", "region.png", "points.csv", "observed.json"):
    check(os.path.getsize(os.path.join("through", name)) > 0, name)

# Failed runs (a > 0.85 exits with an error) and excluded runs (ok = 0 where b > 0.9) are
# recorded as not counted; the calibration goes on without them. The starting design of seed
# 7 has such points.
with open("failing.yaml", "w") as f:
    f.write(SPEC.format(python=sys.executable).replace("seed: 3", "seed: 7").replace("value: 112", "value: 117"))
calibrate_cli("failing.yaml", "--out", "failing")
c = json.load(open("failing/calibration.json"))
failed = [r for r in c["run_list"] if not r["counted"]]
check(failed, f"some run failed or was excluded: {c['run_list']}")
for r in failed:
    check(r["parameters"]["a"] > 0.85 or r["parameters"]["b"] > 0.9, f"only the failing region fails: {r}")
check(c["status"] == "validated", f"validated despite the failures: {c['status']}")

# Two cases at once: the same model shifted by k (a command's case fills its {k}); the targets
# 112 at k = 0 and 117 at k = 5 agree, so one point meets both.
with open("shifted.py", "w") as f:
    f.write("import json, sys, subprocess\n"
            "y = json.loads(subprocess.run([sys.executable] + sys.argv[1:5], capture_output=True, text=True,"
            " check=True).stdout)['y']\n"
            "print(json.dumps({'y': y + float(sys.argv[5])}))\n")
with open("cases.yaml", "w") as f:
    f.write(f"""command: [{sys.executable}, "{{spec_dir}}/shifted.py", "{{spec_dir}}/model.py", "{{a}}", "{{b}}", "{{seed}}", "{{k}}"]
seed_parameter: seed
cases:
  plain: {{k: 0}}
  shifted: {{k: 5}}
parameters:
  a: {{low: 0, high: 1}}
  b: {{low: 0, high: 1}}
targets:
  y0: {{response: y, case: plain, value: 112, sd: 0.5, tolerance: 1, scatter: 0.5}}
  y5: {{response: y, case: shifted, value: 117, sd: 0.5, tolerance: 1, scatter: 0.5}}
batch: 2
budget: 16
""")
calibrate_cli("cases.yaml", "--out", "cases")
d = json.load(open("cases/calibration.json"))
best = d["best"]["parameters"]
check(d["status"] == "validated" and abs(truth(best["a"], best["b"]) - 112) <= 1, f"two cases: {d['status']} {best}")
check(os.path.exists("cases/plain/batch_0/results.csv") and os.path.exists("cases/shifted/batch_0/results.csv"),
      "a campaign per case")
obs = d["best"]["observed"]
check(abs(obs["y5"] - obs["y0"] - 5) < 1e-9, f"the same run's seed in both cases: {obs}")

# The Python API with a function as the simulation gives the same kind of answer.
rng = np.random.default_rng(5)
r = calibrate([Parameter("a", 0, 1), Parameter("b", 0, 1)], [Target("y", 112, 0.5, 1.0, scatter=0.5)],
              lambda pts, batch: [{"y": truth(p["a"], p["b"]) + rng.normal(0, 0.5)} for p in pts],
              Settings(batch=1, budget=20, seed=1), log=lambda s: None)
check(r.status == "validated" and abs(truth(**r.best["parameters"]) - 112) <= 1, f"API: {r.status} {r.best}")

# A prior moves the posterior along the solution set (the line 20 a - 10 b + 5 a b = 12):
# with b ~ N(0.2, 0.05) the posterior of b centres near 0.2, and a near (12 + 2) / 21 = 0.67.
rng = np.random.default_rng(6)
r = calibrate([Parameter("a", 0, 1), Parameter("b", 0, 1, prior_mean=0.2, prior_sd=0.05)],
              [Target("y", 112, 0.5, 1.0, scatter=0.5)],
              lambda pts, batch: [{"y": truth(p["a"], p["b"]) + rng.normal(0, 0.5)} for p in pts],
              Settings(batch=1, budget=20, seed=1), log=lambda s: None)
post = r.posterior
check(abs(post["b"]["mean"] - 0.2) < 0.06 and post["b"]["sd"] < 0.08, f"the prior on b: {post['b']}")
check(abs(post["a"]["mean"] - 14 / 21) < 0.08, f"a on the line at b = 0.2: {post['a']}")

# The file's priors and units reach the parameters in SI.
with open("prior.yaml", "w") as f:
    f.write(SPEC.format(python=sys.executable).replace("a: {low: 0, high: 1}",
                                                       "a: {low: 1 mm, high: 5 mm, prior_mean: 2 mm, prior_sd: 0.5 mm}"))
pa = read_spec("prior.yaml").parameters[0]
check((pa.low, pa.high, pa.prior_mean, pa.prior_sd) == (0.001, 0.005, 0.002, 0.0005), f"prior in SI: {pa}")

# A folder holding another calibration is refused.
with open("other.yaml", "w") as f:
    f.write(SPEC.format(python=sys.executable).replace("a: {low: 0, high: 1}", "a: {low: 0, high: 2}"))
p = calibrate_cli("other.yaml", "--out", "through", ok=False)
check("holds a calibration of another file" in p.stderr, p.stderr)

# Bad files: the error names the file, the line and the key.
good = SPEC.format(python=sys.executable)
bad = [
    (good.replace("budget: 20", "budgit: 20"), ":10: key 'budgit': unknown key 'budgit' (did you mean 'budget'?)"),
    (good.replace("a: {low: 0, high: 1}", "a: {low: 1, high: 0}"), ":4: key 'parameters.a.high': expected more than"),
    (good.replace("sd: 0.5,", "sd: 0.5 mm,"), ":7: key 'targets.y.sd': expected a number in the SI unit of targets.y.value"),
    (good.replace("value: 112, sd: 0.5", "value: 112 kg/m3, sd: 0.5 mm"), ":7: key 'targets.y.sd': expected a density"),
    (good.replace("tolerance: 1,", ""), ":7: key 'targets.y.tolerance': the key 'tolerance' is missing"),
    (good.replace("batch: 2", "batch: 0"), ":9: key 'batch': expected at least 1"),
    (good.replace("batch: 2", "batch: two"), ":9: key 'batch': expected an integer, got 'two'"),
    (good + "confidence: 1.5\n", ":12: key 'confidence': expected a probability below 1"),
    (good.replace("y: {value", "y: {case: large, value"), ":7: key 'targets.y.case': no case 'large'"),
    (good + "scenario: x.yaml\n", ":1: key 'scenario': expected a scenario (a file) or a command"),
    (good.replace("seed_parameter: seed", "seed_parameter: [seed]"), ":2: key 'seed_parameter': expected a value, got a list"),
    (good.replace("  y: {value", "  y: 3\n  z: {value"), ":7: key 'targets.y': expected a mapping, got '3'"),
    (good.replace("  y: {value: 112", "  y: {value: [112]"), ":7: key 'targets.y.value': expected a value, got a list"),
    ("a: [1, 2\n", ":2: not valid YAML"),
    (good + "set: {x: 1}\n", ":12: key 'set': set goes with a scenario"),
    (good.replace("a: {low: 0, high: 1}", "a: {low: 0, high: 1, prior_mean: 0.5}"),
     ":4: key 'parameters.a': a prior needs both prior_mean and prior_sd"),
]
for k, (text, expected) in enumerate(bad):
    path = f"bad{k}.yaml"
    with open(path, "w") as f:
        f.write(text)
    p = calibrate_cli(path, "--out", f"bad{k}", ok=False)
    check(p.stderr.startswith("bushel: error: " + os.path.abspath(path) + expected.split(":", 2)[0] + ":") and
          expected in p.stderr, f"case {k}: expected {expected!r} in:\n{p.stderr}")
    check(not os.path.exists(f"bad{k}/points.csv"), f"case {k}: nothing ran")
p = calibrate_cli("missing.yaml", "--out", "x", ok=False)
check("cannot read the calibration file" in p.stderr, p.stderr)
p = calibrate_cli("model.yaml", "--out", "x", "--jobs", "-1", ok=False)
check("--jobs: expected 0 or more" in p.stderr, p.stderr)
p = calibrate_cli("model.yaml", ok=False)
check(p.stderr.startswith("bushel: error: the following arguments are required: --out"), p.stderr)
p = calibrate_cli("--help")
check("--budget" in p.stdout, "help lists the options:\n" + p.stdout)
print("calibrate: all checks passed")
