#pragma once
// Guards that stop a run that has gone wrong, instead of letting it run on to its end and
// report a number that means nothing (docs/scenarios.md, "Guards"). They are checked at
// every check interval; the first one that fails ends the run with a checkpoint, a summary
// marked failed and a non-zero exit. Each limit can be changed in the scenario under
// `simulation: guards:`.

#include <cstddef>
#include <string>

#include "bushel/io/archive_fwd.hpp"

namespace bushel {

class Simulation;

struct RunGuards {
  /// An overlap deeper than this, over the smaller radius, that lasts `overlap_time` stops the
  /// run [-]. A striker riding over kernels reaches about 0.4 for a moment; a packing under
  /// 138 kPa about 0.17.
  double max_overlap = 0.5;
  /// How long an overlap beyond `max_overlap` may last [s].
  double overlap_time = 0.01;
  /// A body faster than this stops the run [m/s]: a fall of 10 m reaches 14 m/s; energy that
  /// grows without a source (a time step too long for the contacts, an absurd gravity)
  /// passes it soon.
  double max_speed = 100.0;
  /// A body that moves more than this fraction of its smallest sphere's radius in one step
  /// stops the run [-]: it passes through walls and neighbours without touching them.
  double max_travel = 0.5;
  /// The fraction of all particles created that may have left the domain [-].
  double max_lost = 0.5;
  /// The most steps the stages' time limits may need together [-]: more is a time step far
  /// too short for the run (a sphere of 1e-300 mm), checked before the run starts.
  double max_steps = 1e9;
};

/// What the guards remember between checks: the time an overlap beyond the limit began [s],
/// or a negative value. A checkpoint holds it, so that a restart continues the same run.
struct GuardClock {
  double deep_since = -1.0;
  void save(io::BinaryWriter& out) const;
  void load(io::BinaryReader& in);
};

/// The particles of a run, for the lost guard.
struct ParticleTally {
  std::size_t lost = 0;     ///< left the domain
  std::size_t created = 0;  ///< ever made, those removed included
};

/// Checks the state after the steps from `since` [s] to now, whose deepest overlap over the
/// smaller radius was `peak_overlap`. Returns why the run must stop, or "" if it may go on.
std::string check_guards(const RunGuards& guards, GuardClock& clock, const Simulation& sim, double since,
                         double peak_overlap, const ParticleTally& tally);

}  // namespace bushel
