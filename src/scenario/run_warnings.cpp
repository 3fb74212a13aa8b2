#include "run_warnings.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace bushel::scenario_running {
namespace {

// A stage that waits for the particles to come to rest (a kinetic_energy condition) should end
// near equilibrium: about 1e-4 (docs/wheat.md), and 0.001 to 0.02 in the calibration cups. Explicit
// integration of strong tangential damping without its bound (simulation.tangential_damping_limit
// off; restitution 0.05 at 0.2 of the Rayleigh step: 0.36) leaves the packing jittering, and it
// compacts (docs/scenarios.md): 0.26 to 0.51 in the cases measured. A stage that ends the
// moment the kinetic energy falls catches a small packing that has just come to rest at up to
// 0.14 (the unit tests' 300-sphere cup, 16 runs; 2e-4 0.2 s later), so the threshold lies
// between the two.
constexpr double jitter_unbalanced_force = 0.2;

// A run continued from a checkpoint by another build than the one that wrote it: its results
// mix the two (a changed contact law, say), which the summary must say.
std::string mixed_engines_warning(const std::vector<std::string>& engines) {
  std::string list;
  for (std::size_t k = 0; k < engines.size(); ++k) list += (k == 0 ? "" : ", then ") + engines[k];
  return "the run was continued from a checkpoint by another engine build, so its results mix builds: " + list;
}

// The value `value` at the end of the stage `r`, or 0 if it is not among its values.
double end_value(const StageReport& r, const std::string& value) {
  for (const auto& [name, v] : r.values)
    if (name == value) return v;
  return 0.0;
}

// The largest overlap over the smaller radius at the end of the finished stage `name`, or 0.
double end_overlap(const std::vector<StageReport>& done, const std::string& name) {
  for (const StageReport& r : done)
    if (r.name == name) return end_value(r, "max_overlap_ratio");
  return 0.0;
}

// The warning for `count` particles of `mass` [kg] that left the domain, with the stages they
// left in (from the rise of lost_count over each finished stage), so that a reader can tell
// kernels lost before a measurement from those lost after it.
std::string lost_warning(std::size_t count, double mass, const std::vector<StageReport>& done) {
  std::vector<std::pair<std::string, std::size_t>> in;  // stage, particles lost in it
  std::size_t before = 0;
  for (const StageReport& r : done) {
    const auto after = static_cast<std::size_t>(end_value(r, "lost_count"));
    if (after > before) in.emplace_back(r.name, after - before);
    before = std::max(before, after);
  }
  std::string where;  // none when the stages' counts do not add up to it (not all recorded)
  if (before == count && in.size() == 1) {
    where = fmt::format(", {}in stage '{}'", count == 1 ? "" : "all ", in.front().first);
  } else if (before == count) {
    where = ":";
    for (std::size_t k = 0; k < in.size(); ++k)
      where += fmt::format("{} {} in '{}'", k == 0 ? "" : ",", in[k].second, in[k].first);
  }
  return fmt::format("{} particle{} ({:.3g} g) left the domain{}", count, count == 1 ? "" : "s", 1e3 * mass, where);
}

// One warning for the stages whose deepest overlap passed overlap_warning_ratio. It says
// whether the overlap was still that deep at their ends: a stream's impacts pass it for a
// moment (the README's cup: 8.3 % in the fill, 0.5 % at the end of the settling), while a
// packing whose kernels sink into each other under load ends on it, and what it measures
// includes them interpenetrating.
std::string overlap_warning(const std::vector<std::pair<std::string, double>>& stages,
                            const std::vector<StageReport>& done) {
  const auto deepest =
      std::max_element(stages.begin(), stages.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  auto named = [](const std::string& stage, double ratio) {
    return fmt::format("'{}' ({:.1f} %)", stage, 100.0 * ratio);
  };
  const bool one = stages.size() == 1;
  const std::string where =
      one ? "stage " + named(stages.front().first, stages.front().second)
          : fmt::format("{} stages, from {} to {}, at most {:.1f} % in '{}'", stages.size(),
                        named(stages.front().first, stages.front().second),
                        named(stages.back().first, stages.back().second), 100.0 * deepest->second, deepest->first);
  std::vector<std::string> still;  // the stages that ended that deep
  double end_max = -1.0;
  std::string end_max_stage;
  for (const auto& [stage, peak] : stages) {
    const double end = end_overlap(done, stage);
    if (end > overlap_warning_ratio) still.push_back(named(stage, end));
    if (end > end_max) end_max = end, end_max_stage = stage;
  }
  const std::string head = fmt::format(
      "the largest overlap passed {:.0f} % of the smaller radius in {}: the contacts "
      "are soft for these impacts or loads",
      100.0 * overlap_warning_ratio, where);
  const std::string shallower = "(a stiffer material, or a gentler drop, makes the impacts shallower)";
  if (still.empty() && one) {
    return fmt::format(
        "{}, but at the stage's end it was {:.1f} %, so the packing it ends on is not interpenetrating {}", head,
        100.0 * end_max, shallower);
  }
  if (still.empty()) {
    return fmt::format(
        "{}, but at the end of each it was under {:.0f} % (at most {:.1f} %, at the end of '{}'), so the packings "
        "they end on are not interpenetrating {}",
        head, 100.0 * overlap_warning_ratio, 100.0 * end_max, end_max_stage, shallower);
  }
  return fmt::format(
      "{}, and at the end of {} it still was: what {} includes kernels interpenetrating (a stiffer "
      "material, or a gentler load or drop)",
      head, fmt::join(still, ", "), still.size() == 1 ? "that stage measures" : "those stages measure");
}

}  // namespace

void add_stage_end_warnings(const StageSpec& stage, StageEnd end, std::uint64_t steps, double dt, const RunState& st,
                            std::vector<std::string>& warnings) {
  if (end == StageEnd::max_time &&
      (stage.kinetic_energy || stage.factories_done || stage.servo_part || stage.reached || stage.stable)) {
    warnings.push_back(fmt::format("stage '{}' ended at its time limit before its condition was met", stage.name));
  }
  const double unbalanced = st.sim.unbalanced_force_ratio();
  // (ended at its first check, far from rest: particles made at rest, all at once, before)
  const bool at_first_check =
      end == StageEnd::kinetic_energy && steps <= static_cast<std::uint64_t>(std::round(st.sc.check_interval / dt));
  if (at_first_check && unbalanced > jitter_unbalanced_force) {
    warnings.push_back(fmt::format(
        "stage '{}' ended at its first check with the kinetic energy already below its limit, though the "
        "particles are not at rest (unbalanced force ratio {:.2g}): they had not started to move (made at rest, "
        "all at once?), so they have not settled; give the stage a min_time",
        stage.name, unbalanced));
  } else if (stage.kinetic_energy && unbalanced > jitter_unbalanced_force) {
    warnings.push_back(fmt::format(
        "stage '{}' ended with the packing not at rest (unbalanced force ratio {:.2g}, above {:g}): either it "
        "ended before the packing settled (a longer min_time), or the particles jitter, which compacts a "
        "packing: a smaller time step, and simulation.tangential_damping_limit on (docs/scenarios.md)",
        stage.name, unbalanced, jitter_unbalanced_force));
  }
}

void add_run_end_warnings(RunReport& report, const Position& pos, const RunState& st) {
  if (report.engines.size() > 1) report.warnings.push_back(mixed_engines_warning(report.engines));
  if (!pos.deep_overlaps.empty()) report.warnings.push_back(overlap_warning(pos.deep_overlaps, pos.done));
  if (report.interrupted || !pos.failed.empty()) return;
  for (const auto& f : st.factories) {
    if (f.done()) continue;
    const double made = f.spec().total_by_mass ? f.report().total_mass : static_cast<double>(f.report().total_count);
    report.warnings.push_back(fmt::format("factory '{}' created {:.4g} of its total {:.4g}{}", f.spec().name, made,
                                          f.spec().total, f.spec().total_by_mass ? " kg" : " particles"));
  }
  if (st.lost.total_count() > 0)
    report.warnings.push_back(lost_warning(st.lost.total_count(), st.lost.total_mass(), report.stages));
}

}  // namespace bushel::scenario_running
