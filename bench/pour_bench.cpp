// The pour benchmark (shared/reference/liggghts-pour): times the phases pour (from rest),
// settle and dense (the settled bed) of the pour scene and prints particle-steps per second
// per phase, one CSV line each:
//   bench_pour N PARTICLE THREADS NPOUR NSETTLE NDENSE [DATAFILE]
// With DATAFILE, the initial state is also written for LIGGGHTS (same positions).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fmt/format.h>
#include <string>

#include "bushel/experiments/pour_scene.hpp"

#ifdef BUSHEL_HAVE_OPENMP
#include <omp.h>
#endif

int main(int argc, char** argv) {
  if (argc < 7) {
    fmt::print(stderr, "usage: bench_pour N PARTICLE THREADS NPOUR NSETTLE NDENSE [DATAFILE]\n");
    return 2;
  }
  bushel::PourSpec spec;
  spec.count = std::stoul(argv[1]);
  spec.particle = argv[2];
  if (const char* skin = std::getenv("BUSHEL_SKIN")) spec.skin = std::stod(skin);  // for tuning runs
  const int threads = std::stoi(argv[3]);
#ifdef BUSHEL_HAVE_OPENMP
  omp_set_num_threads(threads);
#endif
  bushel::PourScene scene = bushel::make_pour_scene(spec);
  if (argc > 7) bushel::write_liggghts_data(argv[7], scene.simulation.particles(), scene.container_radius);
  auto& sim = scene.simulation;
  const char* phases[] = {"pour", "settle", "dense"};
  fmt::print("code,particle,n,threads,phase,steps,seconds,particle_steps_per_s,contacts\n");
  for (int k = 0; k < 3; ++k) {
    const auto steps = std::stoull(argv[4 + k]);
    const auto t0 = std::chrono::steady_clock::now();
    sim.step(steps);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    fmt::print("bushel,{},{},{},{},{},{:.3f},{:.4e},{}\n", spec.particle, spec.count, threads, phases[k], steps, s,
               static_cast<double>(steps) * static_cast<double>(spec.count) / s, sim.contacts());
    std::fflush(stdout);
  }
  return 0;
}
