#pragma once
// The "pour" scene (as LIGGGHTS's pour inputs in bench/liggghts/): N particles placed at
// random without overlap in a vertical cylinder at a loose solid fraction, at rest, then
// poured onto the flat bottom under gravity. Built once here and used by `bushel demo pour`, the
// determinism test and the benchmark against LIGGGHTS.

#include <cstdint>
#include <string>
#include <vector>

#include "bushel/integrate/simulation.hpp"

namespace bushel {

/// A wheat kernel: "sphere" (d = 3.64 mm) or a template name (e.g. large_5s), wheat material.
ParticleType wheat_particle(const std::string& particle);
/// Rayleigh time step of a type's smallest element [s].
double rayleigh_step(const ParticleType& type);
/// Settings of the wheat scenes: time step dt [s], the rolling model, the Verlet skin [m]
/// (0 = default), and the pour benchmark's contact table (wheat-wheat e 0.5, fs 0.27, fr 0.01;
/// wheat-steel 0.33, 0.17, 0.01).
SimulationSettings wheat_settings(double dt, const std::string& rolling = "cdt", double skin = 0.0);

struct PourSpec {
  std::size_t count = 10'000;       ///< number of particles
  std::string particle = "sphere";  ///< "sphere" (d = 3.64 mm) or a template name (e.g. large_5s)
  double container_diameter = 0.0;  ///< [m]; 0 = 90 mm (count/10000)^(1/3)
  double solid_fraction = 0.30;     ///< of the initial cloud, counted with exclusion spheres [-]
  std::uint64_t seed = 12345;       ///< random placement and orientation
  double dt_fraction = 0.2;         ///< time step as a fraction of the Rayleigh step [-]
  std::string rolling = "cdt";      ///< rolling model
  double skin = 0.0;                ///< Verlet skin [m]; 0 = the engine's default
  double initial_speed = 0.0;       ///< each particle starts at this speed [m/s] in a random direction
  int bottom_mesh_cells = 0;        ///< 0: the bottom is a plane; n: a square mesh of 2 n^2 triangles
  ThreadPolicy threads;             ///< the steps' threads (default: OpenMP's setting as it is)
};

struct PourScene {
  Simulation simulation;
  double container_radius = 0.0;  ///< [m]
  double rayleigh_step = 0.0;     ///< of the smallest element [s]
};

/// Random sequential addition of non-overlapping spheres of diameter `exclusion` [m] in a
/// cylinder of radius `radius` [m] above z = 0, centres at least 0.6 `exclusion` from the
/// wall and the bottom, filled to `solid_fraction` (as the reference generator does).
std::vector<Vec3> random_cloud(std::size_t count, double radius, double exclusion, double solid_fraction,
                               std::uint64_t seed);

/// The scene with the study's materials (docs/wheat.md; wheat in a steel cylinder; e 0.5/0.33, mu_s 0.27/0.17,
/// mu_r 0.01/0.01), ready to step. Throws InputError for a bad spec.
PourScene make_pour_scene(const PourSpec& spec);

/// Writes the particles' positions as a LIGGGHTS data file (atom_style granular), so the
/// reference solver starts from the same state.
void write_liggghts_data(const std::string& path, const ParticleSystem& particles, double container_radius);

}  // namespace bushel
