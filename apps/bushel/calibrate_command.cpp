// `bushel calibrate SPEC --out DIR`: sequential Bayesian calibration (docs/calibration.md). The
// method lives in the Python package (bushel.calibration_run: scikit-learn's Gaussian
// processes and scipy's optimisers), so the command hands its arguments to that package's
// driver, run by Debian's python3 with this build's package and this program.
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "bushel/core/input_error.hpp"
#include "bushel/io/python_plot.hpp"
#include "commands.hpp"

namespace bushel::cli {

namespace {

[[noreturn]] void run_driver(const std::vector<std::string>& args) {
  const std::string package = io::python_package_path();
  if (package.empty()) {
    throw InputError(
        "this build has no Python package beside the program (pybind11-dev and python3-dev, installed by "
        "scripts/setup.sh, build it); `bushel calibrate` needs it");
  }
  const char* old = std::getenv("PYTHONPATH");
  const std::string path = package + (old != nullptr && *old != '\0' ? ":" + std::string(old) : "");
  std::error_code ec;
  const std::string self = std::filesystem::read_symlink("/proc/self/exe", ec).string();
  if (setenv("PYTHONPATH", path.c_str(), 1) != 0 || (!ec && setenv("BUSHEL_PROGRAM", self.c_str(), 1) != 0)) {
    throw InputError("cannot set the environment of the calibration driver");
  }
  std::vector<std::string> text{io::python_interpreter(), "-m", "bushel.calibration_run"};
  text.insert(text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : text) argv.push_back(a.data());
  argv.push_back(nullptr);
  execvp(argv[0], argv.data());  // (returns only on failure)
  throw InputError("cannot run " + text[0] + " (" + std::strerror(errno) +
                   "): install python3 with python3-sklearn and python3-scipy (scripts/setup.sh) or set "
                   "BUSHEL_PYTHON");
}

}  // namespace

void add_calibrate_command(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand(
      "calibrate",
      "Calibrate parameters against measured targets with Gaussian-process surrogates (docs/calibration.md); "
      "`bushel calibrate --help` lists its options");
  // Every argument, --help included, goes to the driver, which parses them.
  cmd->prefix_command();
  cmd->set_help_flag();
  cmd->callback([cmd] { run_driver(cmd->remaining()); });
}

}  // namespace bushel::cli
