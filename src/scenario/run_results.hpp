#pragma once
// What summary.json holds, built from a run at its end: the scenario's results from its
// stages' end values, what the factories created and the sinks removed, the final values.
// Internal to src/scenario.

#include "bushel/scenario/run_summary.hpp"
#include "run_state.hpp"

namespace bushel::scenario_running {

/// The run's summary; the results are printed on stderr as they are computed (a finished run,
/// RunOptions::progress), and those that mean little or cannot be computed add warnings
/// after report.warnings.
RunSummary build_run_summary(const RunReport& report, const RunState& st, const RunOptions& o);

}  // namespace bushel::scenario_running
