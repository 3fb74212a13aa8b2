#!/usr/bin/env python3
"""Bad input of every class bushel must refuse, run as a user runs it.

Each case runs `bushel` and expects, within a time limit, the exit code 1 (or the one given),
no signal, and one line on stderr, "bushel: error: ...", that matches a pattern (the file,
line or option and what was wrong). A crash, a hang, a second line or a silent success fails.

    bad_inputs_check.py BUSHEL REPO_ROOT
"""
import os
import re
import subprocess
import sys
import tempfile

BUSHEL, ROOT = sys.argv[1], sys.argv[2]
CUP = os.path.join(ROOT, "scenarios", "cup-pour.yaml")
BASE = open(CUP).read()
TIME_LIMIT = 20  # seconds: every case is refused before a step runs

work = tempfile.mkdtemp(prefix="bushel-bad-")


def write(name, text, mode="w"):
    path = os.path.join(work, name)
    with open(path, mode) as f:
        f.write(text)
    return path


def replaced(old, new, text=BASE):
    assert old in text, old
    return text.replace(old, new, 1)


def laughs(levels=9):
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x]"]
    for k in range(1, levels + 1):
        lines.append(f"a{k}: &a{k} [" + ", ".join([f"*a{k - 1}"] * 9) + "]")
    return "\n".join(lines) + "\n"


# name, arguments (a str is a scenario text for `validate`), pattern, exit code
CASES = [
    # --- YAML structure ---
    ("complex key", "? [a, b]\n: 1\n", r"complex\.yaml:1: a list as a key", 1),
    ("complex key, flow map", "{a: 1}: x\n", r"a map as a key", 1),
    ("self-referencing alias", "a: &x [1, *x]\n", r":1: an alias \(\*name\) to the list or map that contains it", 1),
    ("alias fan-out", laughs(), r"more than 100000 values once its aliases", 1),
    ("duplicate parameter", replaced("  rate: 0.5 kg/s\n", "  rate: 0.5 kg/s\n  mass: 20 g\n"),
     r":(\d+): the key 'mass' appears twice in one map \(lines \d+ and \1\)", 1),
    ("duplicate material", replaced("  steel: {", "  wheat: {shear_modulus: 1 GPa, poisson_ratio: 0.3, density: 1000 kg/m3}\n  steel: {"),
     r"the key 'wheat' appears twice", 1),
    ("second document", BASE + "---\nstages: []\n", r":\d+: a second YAML document", 1),
    ("YAML syntax", "a: [1, 2\nb: 3\n", r"not valid YAML", 1),
    ("not a map", "- 1\n- 2\n", r"a scenario is a map of sections", 1),
    # --- expressions ---
    ("20,000 parentheses", replaced("    mass: ${mass}\n", "    mass: ${" + "(" * 20000 + "90 g" + ")" * 20000 + "}\n"),
     r"key 'factories\.pour\.mass': in the expression '\(\(\(.*\.\.\. \(40004 characters\)': longer than 4096", 1),
    ("500,000 unary minuses", replaced("    mass: ${mass}\n", "    mass: ${" + "-" * 500000 + "90 g}\n"),
     r"longer than 4096 characters", 1),
    ("nested 100 deep", replaced("    mass: ${mass}\n", "    mass: ${" + "(" * 100 + "90 g" + ")" * 100 + "}\n"),
     r"nested more than 64 levels deep", 1),
    ("exponent overflow", replaced("    mass: ${mass}\n", "    mass: ${" + "*".join(["2 m"] * 40) + "}\n"),
     r"a unit to a power beyond 32", 1),
    # --- files ---
    ("scenario is /dev/zero", ["validate", "/dev/zero"], r"/dev/zero: expected a file, this is a device", 1),
    ("scenario is a folder", ["validate", ROOT], r"expected a file, this is a folder", 1),
    ("template is /dev/zero", ["validate", CUP, "--set", "particle_types.large.template=/dev/zero"],
     r"key 'particle_types\.large\.template': /dev/zero: expected a file, this is a device", 1),
    ("300-character template name", ["validate", CUP, "--set", "particle_types.large.template=" + "x" * 300],
     r"key 'particle_types\.large\.template': unknown particle template", 1),
    # --- numbers ---
    ("NaN template sphere", None, r"key 'particle_types\.large\.template': .*t3\.csv:2: key 'radius_mm': expected a finite number", 1),
    ("infinite template sphere", None, r"expected a finite number", 1),
    ("template sphere of 1e-300 mm", None, r"expected a sphere radius between 1e-06 and 10 m, got 1e-303 m", 1),
    ("shear modulus 1 Pa", ["validate", CUP, "--set", "materials.wheat.shear_modulus=1 Pa"],
     r"key 'materials\.wheat\.shear_modulus': expected a shear modulus between 1 kPa and 1000 GPa", 1),
    ("gravity 1e6", ["validate", CUP, "--set", "simulation.gravity=0 0 -1e6 m/s2"],
     r"key 'simulation\.gravity': expected at most 1000 m/s2", 1),
    ("factory at 1000 m/s", ["validate", CUP, "--set", "factories.pour.velocity=0 0 -1000 m/s"],
     r"key 'factories\.pour\.velocity': a speed of 1000 m/s, above the guard's 100 m/s", 1),
    ("a run of 1e12 steps", ["validate", CUP, "--set", "stages.1.until.max_time=1e9 s"],
     r"key 'stages': the stages' time limits need up to .* steps", 1),
    ("a guard out of range", replaced("  seed: 1\n", "  seed: 1\n  guards: {max_lost: 150%}\n"),
     r"key 'simulation\.guards\.max_lost': expected a fraction in \(0, 1\]", 1),
    # --- the command line ---
    ("--set of an undeclared parameter", ["validate", CUP, "--set", "parameters.mas=20g"],
     r"command line: --set parameters\.mas: the scenario declares no parameter 'mas' \(did you mean 'mass'\?\)", 1),
    ("--set value with a bad unit", ["validate", CUP, "--set", "parameters.mass=20x"],
     r"key 'factories\.pour\.mass': .*got '20x'.*\(the value comes from --set parameters\.mass=20x\)", 1),
    ("--restart of a folder without a checkpoint", ["run", "--restart", work], r"no checkpoint to continue from", 1),
    ("--restart of a damaged checkpoint", None, r"not a bushel checkpoint", 1),
    ("--out holds another run", None, r"key '--out': the folder holds another run \(summary\.json\)", 1),
    # --- doe ---
    ("doe duplicate factor", ["doe", "design", "ccd", "--factors", "mu=0.2:0.4,mu=0.4:0.6"],
     r"key '--factors': the factor 'mu' is given twice", 1),
    ("doe low above high", ["doe", "design", "ccd", "--factors", "mu=0.4:0.2,k=1:2"],
     r"key '--factors': the factor 'mu' has its low level 0\.4 above or at its high 0\.2", 1),
    ("doe zero runs", ["doe", "design", "lhs", "--factors", "mu=0.2:0.4", "--runs", "0"],
     r"--runs: Value 0 not in range", 105),
    ("doe analyze --out /dev/null", None, r"key '--out': expected a folder for the tables and plots", 1),
    ("doe command without a factor", None, r"key 'command': the command uses none of the design's factors \(mu, k\)", 1),
    ("doe scenario without the factor", None, r"--set parameters\.mu: the scenario declares no parameter 'mu'.*\(design row on line 2 of", 1),
]


def template_csv(radius):
    return write(f"t{len(radius)}.csv", f"template,sphere,x_mm,y_mm,z_mm,radius_mm\nk,0,0,0,0,{radius}\n")


def prepared(name):
    """The arguments of the cases that need files made first."""
    if name.startswith("NaN template"):
        return ["validate", CUP, "--set", "particle_types.large.template=" + template_csv("nan")]
    if name.startswith("infinite template"):
        return ["validate", CUP, "--set", "particle_types.large.template=" + template_csv("inf")]
    if name.startswith("template sphere of 1e-300"):
        return ["validate", CUP, "--set", "particle_types.large.template=" + template_csv("1e-300")]
    if name.startswith("--restart of a damaged"):
        os.makedirs(os.path.join(work, "damaged"), exist_ok=True)
        write("damaged/checkpoint.bin", b"\xff" * 8, "wb")
        return ["run", "--restart", os.path.join(work, "damaged")]
    if name.startswith("--out holds"):
        os.makedirs(os.path.join(work, "taken"), exist_ok=True)
        write("taken/summary.json", "{}\n")
        return ["run", CUP, "--out", os.path.join(work, "taken")]
    design = write("design.csv", "std_order,run_order,mu,k\n1,1,0.2,1\n2,2,0.4,2\n3,3,0.3,1.5\n")
    if name.startswith("doe analyze"):
        write("responses.csv", "mu,k,y\n0.2,1,1\n0.4,1,2\n0.2,2,2\n0.4,2,4\n0.3,1.5,2.2\n")
        return ["doe", "analyze", os.path.join(work, "responses.csv"), "--factors", "mu,k", "--response", "y",
                "--out", "/dev/null"]
    if name.startswith("doe command"):
        return ["doe", "run", design, "--out", os.path.join(work, "camp"), "--response", "y", "--", "echo", "hello"]
    if name.startswith("doe scenario"):
        return ["doe", "run", design, "--out", os.path.join(work, "camp2"), "--response", "bulk_density",
                "--scenario", CUP]
    raise KeyError(name)


failed = 0
for k, (name, args, pattern, code) in enumerate(CASES):
    if args is None:
        args = prepared(name)
    elif isinstance(args, str):
        args = ["validate", write(f"case{k}.yaml" if "complex" not in name else "complex.yaml", args)]
    try:
        p = subprocess.run([BUSHEL] + args, capture_output=True, text=True, timeout=TIME_LIMIT, cwd=work)
    except subprocess.TimeoutExpired:
        print(f"FAIL {name}: no answer in {TIME_LIMIT} s (a hang)")
        failed += 1
        continue
    err = p.stderr.strip()
    problems = []
    if p.returncode < 0:
        problems.append(f"killed by signal {-p.returncode}")
    elif p.returncode != code:
        problems.append(f"exit {p.returncode}, expected {code}")
    if "\n" in err:
        problems.append("more than one line on stderr")
    if not err.startswith("bushel: error: "):
        problems.append("stderr does not start with 'bushel: error: '")
    if not re.search(pattern, err):
        problems.append(f"stderr does not match {pattern!r}")
    if problems:
        failed += 1
        print(f"FAIL {name}: {'; '.join(problems)}\n  stderr: {err[:600]}")
    else:
        print(f"ok   {name}: {err[:160]}")

print(f"{len(CASES) - failed} passed, {failed} failed")
sys.exit(1 if failed else 0)
