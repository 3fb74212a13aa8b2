#pragma once
// The readers of read_scenario's sections (scenario.hpp), one per section, and what they
// share: the names each section declares for the later ones to refer to, and the checks of
// a name, a direction, a region against the domain. Internal to src/scenario.

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "bushel/scenario/scenario.hpp"
#include "bushel/scenario/scenario_node.hpp"

namespace bushel::scenario_reading {

/// What the sections read so far declared, for the sections after them.
struct ReadContext {
  std::string dir;         ///< the scenario's folder: relative files (meshes, templates) are found there
  std::uint64_t seed = 1;  ///< simulation.seed
  std::map<std::string, Material> materials;
  std::vector<std::string> material_names, type_names, part_names, factory_names, sink_names;
  std::vector<std::string> values;  ///< every value of the run (Scenario::value_names), once the sensors are read
};

// --- shared checks (read_common.cpp) ----------------------------------------------------------

/// A name from a list of known names, with a did-you-mean; errors point at `node`.
std::size_t index_named(const ScenarioNode& node, const std::string& name, const std::vector<std::string>& names,
                        const std::string& what);
/// The node's text as a name from `names`.
std::size_t index_in(const ScenarioNode& node, const std::vector<std::string>& names, const std::string& what);
/// A non-zero direction, normalised.
Vec3 unit_vector(const ScenarioNode& node);
/// A cylinder or box region.
Region read_region(const ScenarioNode& n);
/// Throws unless the box from `lo` to `hi` lies within the domain (a box).
void require_inside(const ScenarioNode& n, const Vec3& lo, const Vec3& hi, const Region& domain,
                    const std::string& what);

// --- the sections, in the order read_scenario reads them ---------------------------------------

/// simulation: everything but its time step (which needs the particle types).
void read_simulation(const ScenarioNode& sim, Scenario& sc, ReadContext& cx);
/// materials: and particle_types:.
void read_materials(const ScenarioNode& root, ReadContext& cx);
void read_particle_types(const ScenarioNode& root, Scenario& sc, ReadContext& cx);
/// simulation.time_step, from the particle types' Rayleigh step or the critical step of the
/// types' and parts' contacts (read after contacts: and parts:).
void read_simulation_time_step(const ScenarioNode& sim, Scenario& sc);
/// contacts: (optional).
void read_contacts(const ScenarioNode& contacts, Scenario& sc, const ReadContext& cx);
/// parts: (optional).
void read_parts(const ScenarioNode& parts, Scenario& sc, ReadContext& cx);
/// factories: and sinks: (optional).
void read_factories(const ScenarioNode& factories, Scenario& sc, ReadContext& cx);
void read_sinks(const ScenarioNode& sinks, Scenario& sc, ReadContext& cx);
/// sensors: (optional).
void read_sensors(const ScenarioNode& sensors, Scenario& sc, const ReadContext& cx);
/// stages: (required).
void read_stages(const ScenarioNode& stages, Scenario& sc, const ReadContext& cx);
/// results: (optional).
void read_results(const ScenarioNode& results, Scenario& sc, const ReadContext& cx);
/// outputs: (optional).
void read_outputs(const ScenarioNode& outputs, Scenario& sc, const ReadContext& cx);

// --- pieces shared by sections -------------------------------------------------------------------

/// Motion segments, times from the start of the run (of the stage, for a stage's motions).
Motion read_motion(const ScenarioNode& list);
/// `parent`'s time_step, "20 us" or "0.2 rayleigh" (of the smallest element's Rayleigh step):
/// [s]. `fraction` is set to the Rayleigh fraction if given so, else 0.
double read_time_step(const ScenarioNode& parent, const Scenario& sc, TimeStepRule& rule);
/// A part's shape; mesh files are found relative to `scenario_dir`.
ShapeSpec read_shape(const ScenarioNode& n, const std::string& shape, const std::string& scenario_dir);

}  // namespace bushel::scenario_reading
