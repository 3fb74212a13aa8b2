#!/usr/bin/env python3
"""The include graph follows the library layers of ARCHITECTURE.md ("Layers").

Every `#include "bushel/<module>/..."` in include/bushel/<m>/ and src/<m>/ must name a module
of the same library or of a library below it; engine internals (src/integrate/*.hpp) are
included only from src/integrate/. Prints each offending include and exits 1.
usage: layering_check.py [REPO_ROOT]
"""
import pathlib
import re
import sys

LIBRARY = {
    "core": "core", "units": "core", "io": "core",
    "particles": "engine", "contact": "engine", "geometry": "engine", "integrate": "engine",
    "insertion": "engine", "sensors": "engine", "experiments": "engine",
    "analysis": "analysis", "doe": "doe", "scenario": "scenario", "report": "report",
}
BELOW = {  # each library and the libraries it may include
    "core": {"core"},
    "engine": {"engine", "core"},
    "analysis": {"analysis", "core"},
    "doe": {"doe", "core"},
    "scenario": {"scenario", "engine", "core"},
    "report": {"report", "scenario", "engine", "core"},
}
INCLUDE = re.compile(r'^\s*#\s*include\s+"bushel/(\w+)/', re.M)


def main(root: pathlib.Path) -> int:
    bad = []
    for top in (root / "include" / "bushel", root / "src"):
        for path in sorted(top.rglob("*.[ch]pp")):
            module = path.relative_to(top).parts[0]
            if module not in LIBRARY:
                bad.append(f"{path}: module '{module}' is in no library of the layering")
                continue
            allowed = BELOW[LIBRARY[module]]
            text = path.read_text(encoding="utf-8")
            for m in INCLUDE.finditer(text):
                target = m.group(1)
                if LIBRARY.get(target) not in allowed:
                    line = text.count("\n", 0, m.start()) + 1
                    bad.append(f"{path}:{line}: {module} ({LIBRARY[module]}) includes {target} "
                               f"({LIBRARY.get(target, 'no library')})")
    internal = re.compile(r'^\s*#\s*include\s+"(world|stages)\.hpp"', re.M)
    for path in sorted((root / "src").rglob("*.[ch]pp")):
        if path.parent.name != "integrate" and internal.search(path.read_text(encoding="utf-8")):
            bad.append(f"{path}: includes an engine internal of src/integrate/")
    for b in bad:
        print(b)
    print(f"layering: {len(bad)} offending include(s)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parents[2])))
