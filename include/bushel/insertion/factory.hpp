#pragma once
// A particle factory: creates particles at random places and orientations in a region,
// never overlapping what is there, at a rate (kg/s or particles/s) up to a total (mass or
// count), with a mix of particle types given by mass or by count fractions. Each new
// particle is of the type furthest behind its share, so every type stays within one
// particle of its target at all times (the requested fractions are met over the run, not
// only on average).

#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "bushel/geometry/region.hpp"
#include "bushel/core/triangle_mesh.hpp"
#include "bushel/integrate/simulation.hpp"
#include "bushel/io/archive_fwd.hpp"

namespace bushel {

struct FactorySpec {
  std::string name;
  Region region;  ///< where particles are created (whole particles inside)
  /// A mesh-surface factory instead (when it has triangles): particles are created touching
  /// the surface on its front (at a random point of it, by area), e.g. a spout's mouth.
  TriangleMesh surface;
  bool rate_by_mass = true;                               ///< rate in kg/s (true) or particles/s
  double rate = 0.0;                                      ///< [kg/s] or [1/s]; 0 = everything at once
  bool total_by_mass = true;                              ///< total in kg (true) or a count
  double total = 0.0;                                     ///< [kg] or particles
  std::vector<std::uint32_t> types;                       ///< particle types (indices in the simulation)
  std::vector<double> fractions;                          ///< their shares, summing to 1 [-]
  bool fractions_by_mass = true;                          ///< shares of mass (true) or of count
  Vec3 velocity;                                          ///< initial velocity [m/s]
  double start = 0.0;                                     ///< [s]
  double stop = std::numeric_limits<double>::infinity();  ///< [s]
  std::uint64_t seed = 1;
  int attempts = 200;  ///< random places tried per particle before it waits for room
};

/// What a factory has created so far, per type (in the order of FactorySpec::types).
struct FactoryReport {
  std::vector<std::size_t> count;
  std::vector<double> mass;  ///< [kg]
  std::size_t total_count = 0;
  double total_mass = 0.0;  ///< [kg]
  std::size_t waiting = 0;  ///< particles due that found no room at the last call
};

class Factory {
 public:
  /// Checks the spec against the simulation's types; throws InputError keyed by the field.
  Factory(FactorySpec spec, const Simulation& sim);

  /// Creates the particles due after `active` more seconds of creating (time in which the
  /// factory was enabled and within [start, stop), measured by the caller). Returns how many
  /// were created.
  std::size_t run(Simulation& sim, double active);
  /// The total has been created.
  bool done() const;
  const FactorySpec& spec() const { return spec_; }
  const FactoryReport& report() const { return report_; }
  /// Achieved share of each type by the spec's measure (mass or count) [-].
  std::vector<double> achieved_fractions() const;
  /// What it has done and its random state, for a checkpoint.
  void save(io::BinaryWriter& out) const;
  void load(io::BinaryReader& in);

 private:
  std::size_t next_type() const;
  double created_measure() const;  // in the total's measure (kg or count)

  FactorySpec spec_;
  std::vector<double> type_mass_;                            // mass of one particle of each type [kg]
  std::vector<double> type_radius_;                          // bounding radius of each type [m]
  double active_ = 0.0;                                      // time spent creating [s]
  Vec3 place(std::size_t type, std::mt19937_64& rng) const;  // a random centre for a particle of a type

  std::vector<double> cumulative_area_;  // surface factories: running sum of the triangles' areas [m2]
  std::mt19937_64 rng_;
  FactoryReport report_;
};

}  // namespace bushel
