#pragma once
// Plots as PNG files through Python's matplotlib (Debian package python3-matplotlib,
// installed by scripts/setup.sh): the program writes the data, then runs a short script that
// it carries in its own text, so nothing has to be found on disk at run time.

#include <string>
#include <vector>

namespace bushel::io {

/// The interpreter: $BUSHEL_PYTHON if set, else /usr/bin/python3 if present (the one Debian's
/// python3-matplotlib serves), else python3 from the PATH.
std::string python_interpreter();

/// The folder holding this build's `bushel` Python package (the one to put on sys.path), found
/// beside the running program: BIN/../python (the build tree) or
/// PREFIX/lib/python3.X/dist-packages (installed); "" when this build has none.
std::string python_package_path();

/// Runs `script` (Python source) with `args` as sys.argv[1:]; throws InputError naming the
/// interpreter and, when matplotlib is missing, the package to install, if it fails.
void run_python(const std::string& script, const std::vector<std::string>& args);

}  // namespace bushel::io
