// The pour benchmark (the scene of LIGGGHTS's pour inputs, bench/liggghts/): times the phases
// pour (from rest), settle and dense (the settled bed) of the pour scene and prints
// particle-steps per second per phase, one CSV line each:
//   bench_pour N PARTICLE THREADS NPOUR NSETTLE NDENSE [DATAFILE]
// Each phase length is a step count or simulated seconds ("0.245s").
// With DATAFILE, the initial state is also written for LIGGGHTS (same positions).
// BUSHEL_STATE=<file> (for A/B runs of the settled bed): if the file exists, the bodies start
// from the state in it and the pour and settle phases are skipped; otherwise the state after
// the settle phase is written to it. Contact history is not kept; a loaded bed takes one
// untimed step first (the set-up).
#include <fmt/format.h>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "bushel/experiments/pour_scene.hpp"

int main(int argc, char** argv) {
  if (argc < 7) {
    fmt::print(stderr, "usage: bench_pour N PARTICLE THREADS|auto NPOUR NSETTLE NDENSE [DATAFILE]\n");
    return 2;
  }
  bushel::PourSpec spec;
  spec.count = std::stoul(argv[1]);
  spec.particle = argv[2];
  if (const char* skin = std::getenv("BUSHEL_SKIN")) spec.skin = std::stod(skin);  // for tuning runs
  // "auto": the engine's thread governor picks the team size (thread_governor.hpp).
  const std::string threads = argv[3];
  spec.threads = threads == "auto" ? bushel::ThreadPolicy{.max = 0, .adaptive = true}
                                   : bushel::ThreadPolicy{.max = std::stoi(threads), .adaptive = false};
  bushel::PourScene scene = bushel::make_pour_scene(spec);
  if (argc > 7) bushel::write_liggghts_data(argv[7], scene.simulation.particles(), scene.container_radius);
  auto& sim = scene.simulation;
  auto& ps = sim.particles();
  const char* state = std::getenv("BUSHEL_STATE");
  // Per body, by stable id: position, orientation, velocity, angular velocity, angular momentum
  // (where the system keeps no orientation and momentum, their derived values; read and dropped).
  auto transfer = [&](std::fstream& stream, bool write) {
    std::vector<std::size_t> index(ps.bodies());
    for (std::size_t b = 0; b < ps.bodies(); ++b) index[ps.body_id[b]] = b;
    for (const std::size_t b : index) {
      bushel::Quat q = ps.orientation_of(b);
      bushel::Vec3 l = ps.angular_momentum_of(b);
      bushel::Quat& orientation = ps.keeps_rotation() ? ps.orientation[b] : q;
      bushel::Vec3& momentum = ps.keeps_rotation() ? ps.angular_momentum[b] : l;
      double* fields[] = {&ps.position[b].x, &orientation.w, &ps.velocity[b].x, &ps.angular_velocity[b].x, &momentum.x};
      const int sizes[] = {3, 4, 3, 3, 3};
      for (int f = 0; f < 5; ++f) {
        for (int k = 0; k < sizes[f]; ++k) {
          if (write) {
            stream.write(reinterpret_cast<const char*>(fields[f] + k), sizeof(double));
          } else {
            stream.read(reinterpret_cast<char*>(fields[f] + k), sizeof(double));
          }
        }
      }
    }
  };
  bool loaded = false;
  if (state) {
    if (std::fstream in(state, std::ios::in | std::ios::binary); in) {
      // 16 doubles per body: a bed of another size or particle is refused.
      const auto expected = static_cast<std::uintmax_t>(ps.bodies() * 16 * sizeof(double));
      if (std::filesystem::file_size(state) != expected) {
        fmt::print(stderr, "bench_pour: {} does not hold {} bodies of this scene\n", state, ps.bodies());
        return 2;
      }
      transfer(in, false);
      loaded = true;
      // One untimed step for the set-up (pair coefficients, first neighbour list), which
      // LIGGGHTS's loop time leaves out as well.
      sim.step(1);
    }
  }
  const char* phases[] = {"pour", "settle", "dense"};
  fmt::print("code,particle,n,threads,phase,steps,seconds,particle_steps_per_s,contacts\n");
  for (int k = 0; k < 3; ++k) {
    if (loaded && k < 2) continue;
    if (state && !loaded && k == 2) {
      std::fstream out(state, std::ios::out | std::ios::binary);
      transfer(out, true);
    }
    // A phase length is a step count, or simulated seconds with an "s" suffix ("0.245s"), so
    // that beds with different time steps (clumps) reach the same physical stage.
    const std::string arg = argv[4 + k];
    const auto steps = arg.ends_with('s') ? static_cast<std::uint64_t>(std::ceil(std::stod(arg) / sim.settings().dt))
                                          : std::stoull(arg);
    const auto t0 = std::chrono::steady_clock::now();
    sim.step(steps);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    fmt::print("bushel,{},{},{},{},{},{:.3f},{:.4e},{}\n", spec.particle, spec.count, threads, phases[k], steps, s,
               static_cast<double>(steps) * static_cast<double>(spec.count) / s, sim.contacts());
    std::fflush(stdout);
    fmt::print(stderr, "{}: {} neighbour-list builds so far, {}\n", phases[k], sim.neighbors().builds(),
               sim.threads().describe());
  }
  // The final bed, for checking that two builds give the same bits (cmp the files).
  if (const char* final_state = std::getenv("BUSHEL_FINAL")) {
    std::fstream out(final_state, std::ios::out | std::ios::binary);
    transfer(out, true);
  }
  return 0;
}
