#include <fmt/format.h>
#include <memory>
#include <nlohmann/json.hpp>

#include "bushel/core/input_error.hpp"
#include "bushel/experiments/verification.hpp"
#include "commands.hpp"

namespace bushel::cli {
namespace {

struct VerifyOptions {
  bool json = false;
  bool quick = false;
};

void run_verify(const VerifyOptions& o) {
  const auto results = verification::run_all({o.quick});
  std::size_t failed = 0;
  for (const auto& r : results) failed += r.pass ? 0 : 1;
  if (o.json) {
    auto a = nlohmann::ordered_json::array();
    for (const auto& r : results) {
      a.push_back({{"check", r.check},
                   {"quantity", r.quantity},
                   {"expected", r.expected},
                   {"measured", r.measured},
                   {"error", r.error()},
                   {"tolerance", r.tolerance},
                   {"pass", r.pass}});
    }
    fmt::print("{}\n", nlohmann::ordered_json{{"checks", a}, {"failed", failed}}.dump(
                           2, ' ', false, nlohmann::json::error_handler_t::replace));
  } else {
    fmt::print("{:<58} {:<22} {:>12} {:>12} {:>10} {:>9}  {}\n", "check", "quantity", "expected", "measured", "error",
               "tolerance", "result");
    for (const auto& r : results) {
      fmt::print("{:<58} {:<22} {:>12.5g} {:>12.5g} {:>10.2e} {:>9.1e}  {}\n", r.check, r.quantity, r.expected,
                 r.measured, r.error(), r.tolerance, r.pass ? "pass" : "FAIL");
    }
    fmt::print("{} checks, {} passed, {} failed\n", results.size(), results.size() - failed, failed);
  }
  if (failed > 0) throw InputError(fmt::format("{} verification check(s) failed", failed));
}

}  // namespace

void add_verify_command(CLI::App& app) {
  auto o = std::make_shared<VerifyOptions>();
  auto* cmd = app.add_subcommand("verify", "Run the analytic checks of the contact model and integrator");
  cmd->add_flag("--json", o->json, "Print JSON");
  cmd->add_flag("--quick", o->quick, "Fewer cases and steps");
  cmd->callback([o] { run_verify(*o); });
}

}  // namespace bushel::cli
