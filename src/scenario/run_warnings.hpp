#pragma once
// The warnings a run gives in its summary: at the end of each stage (a condition not met, a
// packing not at rest) and at the end of the run (overlaps, factories not done, particles
// lost, builds mixed by a restart). Internal to src/scenario.

#include <cstdint>
#include <string>
#include <vector>

#include "run_state.hpp"

namespace bushel::scenario_running {

/// docs/physics.md section 3: warn when the largest overlap exceeds a few percent of the radius.
/// Deeper than this the contacts are too soft for the impacts or loads of the stage, and what
/// it measures (a density under load above all) includes kernels interpenetrating.
constexpr double overlap_warning_ratio = 0.05;

/// The warnings of a stage that has just ended by `end` after `steps` steps of `dt`; appended
/// to `warnings`.
void add_stage_end_warnings(const StageSpec& stage, StageEnd end, std::uint64_t steps, double dt, const RunState& st,
                            std::vector<std::string>& warnings);

/// The warnings of a run at its end, after those of its stages (report.warnings).
void add_run_end_warnings(RunReport& report, const Position& pos, const RunState& st);

}  // namespace bushel::scenario_running
