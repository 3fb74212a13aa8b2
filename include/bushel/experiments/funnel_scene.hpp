#pragma once
// The funnel discharge scene (docs/wheat.md, virtual experiment 1, without the cup): grain falls
// into a conical funnel closed by a hinged gate, settles, and the gate turns 180 degrees to
// open the outlet. The funnel is the cone primitive or, for comparison, any mesh (e.g. the
// same cone read from STL). Used by `bushel demo funnel`, the tests and the validation of
// cone against mesh.

#include <cstdint>
#include <optional>
#include <string>

#include "bushel/integrate/simulation.hpp"

namespace bushel {

struct FunnelSpec {
  std::size_t count = 1000;                ///< number of particles
  std::string particle = "sphere";         ///< "sphere" (d = 3.64 mm) or a template name
  double top_diameter = 0.100;             ///< funnel's top inner diameter [m]
  double outlet_diameter = 0.0165;         ///< [m]
  double wall_angle = 1.0471975511965976;  ///< from the horizontal [rad] (60 degrees)
  double gate_open_time = 0.6;             ///< the gate starts turning [s]
  double gate_speed = 7.85;                ///< [rad/s]; 180 degrees take pi / speed
  std::optional<TriangleMesh> mesh;        ///< the funnel as a mesh (outlet at z = 0) instead of the cone
  std::uint64_t seed = 12345;
  double dt_fraction = 0.2;  ///< of the Rayleigh step [-]
};

struct FunnelScene {
  Simulation simulation;
  double outlet_z = 0.0;   ///< height of the outlet [m]
  double gate_z = 0.0;     ///< height of the closed gate [m]
  std::size_t funnel = 0;  ///< part indices
  std::size_t gate = 0;
};

/// Builds the scene; throws InputError for a bad spec (key = the field).
FunnelScene make_funnel_scene(const FunnelSpec& spec);
/// Mass of the particles whose centre is below the gate [kg]: what has left the funnel.
double discharged_mass(const FunnelScene& scene);
/// The cone of a spec as faces turned to triangles (for an STL of the same funnel).
TriangleMesh funnel_mesh(const FunnelSpec& spec, int segments = 96);

}  // namespace bushel
