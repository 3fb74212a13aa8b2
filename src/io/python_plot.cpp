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

std::string python_package_path() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path bin = fs::read_symlink("/proc/self/exe", ec).parent_path();
  if (ec) return "";
  const auto holds = [](const fs::path& dir) {
    std::error_code missing;
    return fs::exists(dir / "bushel" / "__init__.py", missing) && fs::exists(dir / "bushel" / "pictures.py", missing);
  };
  if (holds(bin / ".." / "python")) return fs::weakly_canonical(bin / ".." / "python", ec).string();
  const fs::path lib = bin / ".." / "lib";
  for (const auto& e : fs::directory_iterator(lib, ec)) {
    const std::string name = e.path().filename().string();
    if (name.starts_with("python3") && holds(e.path() / "dist-packages")) {
      return fs::weakly_canonical(e.path() / "dist-packages", ec).string();
    }
  }
  return "";
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
