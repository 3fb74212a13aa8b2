#pragma once
// checkpoint.bin: its magic line, then sections with checksums (binary_archive.hpp): the
// build that wrote it, the scenario as resolved, where the run stands, the engine's state.
// Internal to src/scenario.

#include <string>

#include "bushel/io/binary_archive.hpp"
#include "bushel/scenario/frame_writer.hpp"
#include "run_state.hpp"

namespace bushel::scenario_running {

/// Writes `out_dir`/checkpoint.bin (atomically); `wall` is the run's wall time so far [s].
void save_checkpoint(const std::string& out_dir, const RunState& st, const Position& pos, const io::FrameWriter* frames,
                     double wall);

/// Reads the magic line, the build and the scenario of the checkpoint in `in` (from `path`):
/// the scenario as it was resolved, read again as if from its file. Throws InputError if it is
/// not a checkpoint this build reads.
ScenarioDocument read_checkpoint_head(io::BinaryReader& in, const std::string& path);

/// Reads the rest, the run and engine sections, into `st` and `pos` (and the frames' count).
void load_checkpoint(io::BinaryReader& file, RunState& st, Position& pos, io::FrameWriter* frames);

}  // namespace bushel::scenario_running
