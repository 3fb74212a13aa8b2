#include "bushel/io/python_plot.hpp"

#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>

#include "bushel/core/input_error.hpp"

extern char** environ;

namespace bushel::io {

std::string python_interpreter() {
  if (const char* chosen = std::getenv("BUSHEL_PYTHON"); chosen != nullptr && *chosen != '\0') return chosen;
  if (std::filesystem::exists("/usr/bin/python3")) return "/usr/bin/python3";
  return "python3";
}

void run_python(const std::string& script, const std::vector<std::string>& args) {
  const std::string python = python_interpreter();
  std::vector<std::string> argv_text{python, "-c", script};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
    throw InputError(
        fmt::format("cannot run {} to draw the plot; install python3 and python3-matplotlib "
                    "(scripts/setup.sh) or set BUSHEL_PYTHON",
                    python));
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw InputError(
        fmt::format("{} could not draw the plot (exit status {}); it needs matplotlib (Debian: "
                    "python3-matplotlib, installed by scripts/setup.sh)",
                    python, WIFEXITED(status) ? WEXITSTATUS(status) : -1));
  }
}

}  // namespace bushel::io
