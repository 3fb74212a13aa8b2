#include "bushel/doe/campaign.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "bushel/core/input_error.hpp"
#include "bushel/io/atomic_file.hpp"
#include "bushel/io/csv.hpp"
#include "campaign_run.hpp"

extern char** environ;

namespace bushel::doe {

namespace fs = std::filesystem;

namespace detail {
namespace {

// The command of one row: placeholders replaced; InputError for an unknown one.
std::vector<std::string> expand(const std::vector<std::string>& command, const std::vector<std::string>& header,
                                const Row& row, const std::string& run_dir) {
  std::vector<std::string> out;
  for (const std::string& arg : command) {
    std::string text;
    for (std::size_t i = 0; i < arg.size();) {
      const std::size_t open = arg.find('{', i);
      if (open == std::string::npos) {
        text += arg.substr(i);
        break;
      }
      const std::size_t close = arg.find('}', open);
      if (close == std::string::npos) throw InputError(fmt::format("unclosed placeholder in '{}'", arg));
      text += arg.substr(i, open - i);
      const std::string name = arg.substr(open + 1, close - open - 1);
      if (name == "run_dir") {
        text += run_dir;
      } else if (name == "bushel") {
        // This program, also after it was rebuilt mid-campaign: the link then reads "PATH
        // (deleted)", and this process's link (not "self": a shell between would be self)
        // still starts the image that is running.
        const std::string self = fs::read_symlink("/proc/self/exe").string();
        text += self.ends_with(" (deleted)") ? fmt::format("/proc/{}/exe", ::getpid()) : self;
      } else {
        const auto it = std::find(header.begin(), header.end(), name);
        if (it == header.end()) {
          throw InputError(fmt::format("placeholder {{{}}} names no column of the design (columns: {})", name,
                                       fmt::join(header, ", ")))
              .with_key("command");
        }
        text += row.values[static_cast<std::size_t>(it - header.begin())];
      }
      i = close + 1;
    }
    out.push_back(text);
  }
  return out;
}

double response_value(const nlohmann::json& j, const std::string& key) {
  const nlohmann::json* node = &j;
  std::stringstream path(key);
  for (std::string part; std::getline(path, part, '.');) {
    if (!node->is_object() || !node->contains(part)) throw InputError(fmt::format("no key '{}' in the output", key));
    node = &(*node)[part];
  }
  if (!node->is_number()) throw InputError(fmt::format("'{}' in the output is not a number", key));
  return node->get<double>();
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

void write_results(const Campaign& c) {
  const auto& responses = c.spec.responses;
  std::string csv = fmt::format("{},{},status\n", fmt::join(c.header, ","), fmt::join(responses, ","));
  for (const Row& r : c.rows) {
    std::vector<std::string> cells = r.values;
    for (std::size_t k = 0; k < responses.size(); ++k) {
      cells.push_back(r.status == "done" ? fmt::format("{:.10g}", r.responses[k]) : "");
    }
    csv += fmt::format("{},{}\n", fmt::join(cells, ","), r.status);
  }
  io::write_file_atomically(c.results, csv);
}

int threads_per_run(const CampaignSpec& spec, int runs_at_a_time) {
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  return spec.threads > 0 ? spec.threads : std::max(1, static_cast<int>(cores) / std::max(1, runs_at_a_time));
}

Campaign prepare(const CampaignSpec& spec, int threads, bool write) {
  if (spec.command.empty()) throw InputError("expected a command to run per row, after --").with_key("command");
  if (spec.responses.empty()) throw InputError("expected response keys, e.g. mass_kg").with_key("responses");
  if (spec.jobs < 1) throw InputError("expected at least 1 job").with_key("jobs");
  Campaign c;
  c.spec = spec;
  const io::CsvTable table = io::CsvTable::read(spec.design);
  c.header = table.header();
  const std::size_t order_column = table.column("std_order");
  for (const io::CsvRow& r : table.rows()) {
    Row row;
    row.std_order = static_cast<int>(table.number(r, order_column));
    row.values = r.fields;
    c.rows.push_back(row);
  }
  std::sort(c.rows.begin(), c.rows.end(), [](const Row& a, const Row& b) { return a.std_order < b.std_order; });
  for (std::size_t i = 1; i < c.rows.size(); ++i) {
    if (c.rows[i].std_order == c.rows[i - 1].std_order) {
      throw InputError(fmt::format("std_order {} appears twice", c.rows[i].std_order)).at(spec.design);
    }
  }
  for (const Row& r : c.rows) (void)expand(spec.command, c.header, r, "");  // placeholders
  if (write) fs::create_directories(spec.out);
  c.results = (fs::path(spec.out) / "results.csv").string();
  // Finished runs: their done.json holds the responses.
  for (std::size_t i = 0; i < c.rows.size(); ++i) {
    const fs::path done = fs::path(spec.out) / fmt::format("run_{}", c.rows[i].std_order) / "done.json";
    bool finished = false;
    if (fs::exists(done)) {
      try {
        const nlohmann::json j = nlohmann::json::parse(read_file(done));
        for (const std::string& key : spec.responses) c.rows[i].responses.push_back(response_value(j, key));
        c.rows[i].status = "done";
        finished = true;
      } catch (const std::exception&) {
        c.rows[i].responses.clear();  // unreadable: run again
      }
    }
    if (finished) {
      ++c.skipped;
    } else {
      c.todo.push_back(i);
    }
  }
  // In the design's run order where it has one (a randomised order guards a lab experiment
  // against drift; for simulations it costs nothing to keep).
  if (table.has_column("run_order")) {
    const std::size_t col = table.column("run_order");
    std::map<int, double> run_order;
    for (const io::CsvRow& r : table.rows())
      run_order[static_cast<int>(table.number(r, order_column))] = table.number(r, col);
    std::stable_sort(c.todo.begin(), c.todo.end(), [&](std::size_t a, std::size_t b) {
      return run_order[c.rows[a].std_order] < run_order[c.rows[b].std_order];
    });
  }
  for (char** e = environ; *e != nullptr; ++e) {
    if (std::string(*e).rfind("OMP_NUM_THREADS=", 0) != 0) c.env.emplace_back(*e);
  }
  c.env.push_back(fmt::format("OMP_NUM_THREADS={}", threads));
  if (write) write_results(c);
  return c;
}

pid_t start_run(const Campaign& c, std::size_t i) {
  const Row& row = c.rows[i];
  const fs::path dir = fs::path(c.spec.out) / fmt::format("run_{}", row.std_order);
  fs::remove_all(dir);  // a run cut short starts afresh
  fs::create_directories(dir);
  std::vector<std::string> args = expand(c.spec.command, c.header, row, dir.string());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> env = c.env;
  std::vector<char*> envp;
  for (std::string& e : env) envp.push_back(e.data());
  envp.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  const std::string out = (dir / "stdout.txt").string(), err = (dir / "stderr.txt").string();
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, argv[0], &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw InputError(fmt::format("cannot run '{}'", args[0])).with_key("command");
  return pid;
}

void finish_run(Campaign& c, std::size_t i, int status) {
  Row& row = c.rows[i];
  const fs::path dir = fs::path(c.spec.out) / fmt::format("run_{}", row.std_order);
  row.status = "failed";
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return;
  try {
    const nlohmann::json j = nlohmann::json::parse(read_file(dir / "stdout.txt"));
    nlohmann::json done = nlohmann::json::object();
    row.responses.clear();
    for (const std::string& key : c.spec.responses) {
      row.responses.push_back(response_value(j, c.spec.response_root.empty() ? key : c.spec.response_root + "." + key));
      done[key] = row.responses.back();
    }
    io::write_file_atomically((dir / "done.json").string(),
                              done.dump(2, ' ', false, nlohmann::json::error_handler_t::replace));
    row.status = "done";
  } catch (const std::exception& e) {
    std::ofstream(dir / "stderr.txt", std::ios::app) << "bushel doe run: " << e.what() << "\n";
  }
}

}  // namespace detail

CampaignReport run_campaign(const CampaignSpec& spec, bool progress) {
  using namespace detail;
#ifdef BUSHEL_HAVE_MPI
  if (launched_by_mpi()) return run_campaign_mpi(spec, progress);
#endif
  Campaign c = prepare(spec, threads_per_run(spec, spec.jobs));
  CampaignReport report;
  report.runs = static_cast<int>(c.rows.size());
  report.skipped = c.skipped;
  report.results = c.results;
  std::map<pid_t, std::size_t> running;
  std::size_t next = 0;
  while (next < c.todo.size() || !running.empty()) {
    while (next < c.todo.size() && static_cast<int>(running.size()) < spec.jobs) {
      const std::size_t i = c.todo[next++];
      running[start_run(c, i)] = i;
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      break;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const std::size_t i = it->second;
    running.erase(it);
    finish_run(c, i, status);
    (c.rows[i].status == "done" ? report.ran : report.failed) += 1;
    write_results(c);
    if (progress) {
      fmt::print(stderr, "run {} {} ({} of {} done)\n", c.rows[i].std_order, c.rows[i].status,
                 report.skipped + report.ran, report.runs);
    }
  }
  return report;
}

}  // namespace bushel::doe
