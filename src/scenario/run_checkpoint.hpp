#pragma once
// checkpoint.bin: its magic line, then named, versioned sections with checksums
// (binary_archive.hpp), each written and read by its component: the build that wrote it, the
// scenario as resolved, where the run stands (run), factories, sinks, flows, frames, guards,
// and the engine's (engine.*, Simulation::save_state).
// Internal to src/scenario.

#include <optional>
#include <string>

#include "bushel/io/binary_archive.hpp"
#include "bushel/scenario/frame_writer.hpp"
#include "run_state.hpp"

namespace bushel::scenario_running {

/// Writes `out_dir`/checkpoint.bin (atomically); `wall` is the run's wall time so far [s].
void save_checkpoint(const std::string& out_dir, const RunState& st, const Position& pos, const io::FrameWriter* frames,
                     double wall);

/// Reads the magic line and the sections of the checkpoint in `in` (from `path`) into
/// `sections`, and returns its scenario as it was resolved, read again as if from its file.
/// Throws InputError if it is not a checkpoint this build reads.
ScenarioDocument read_checkpoint_head(io::BinaryReader& in, const std::string& path,
                                      std::optional<io::SectionTable>& sections);

/// Reads the run's and the engine's sections into `st` and `pos` (and the frames' count).
void load_checkpoint(const io::SectionTable& sections, RunState& st, Position& pos, io::FrameWriter* frames);

}  // namespace bushel::scenario_running
