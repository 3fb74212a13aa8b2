// What a large triangle mesh costs (issue "Geometry": a mesh of 100,000 triangles must cost
// little when the particles are far from most of it). Three beds of the pour scene, poured
// and settled alike, then timed in alternating rounds on the settled bed:
//   plane      the bottom is the analytic plane (the reference)
//   far-mesh   the same, plus a mesh of 2 CELLS^2 triangles beside the container
//   mesh-floor the bottom is a mesh of 2 CELLS^2 triangles under the whole bed
// Prints one CSV row per variant and round, then the median cost of each variant over the
// plane (time per step, same round).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "bushel/experiments/pour_scene.hpp"

#ifdef BUSHEL_HAVE_OPENMP
#include <omp.h>
#endif

int main(int argc, char** argv) {
  if (argc < 7) {
    fmt::print(stderr, "usage: bench_mesh N CELLS THREADS SETTLE_S NDENSE ROUNDS\n");
    return 2;
  }
  const std::size_t n = std::stoul(argv[1]);
  const int cells = std::stoi(argv[2]), threads = std::stoi(argv[3]), rounds = std::stoi(argv[6]);
  const double settle = std::stod(argv[4]);
  const std::uint64_t dense = std::stoull(argv[5]);
#ifdef BUSHEL_HAVE_OPENMP
  omp_set_num_threads(threads);
#endif
  const char* names[] = {"plane", "far-mesh", "mesh-floor"};
  std::vector<bushel::PourScene> scenes;
  for (int v = 0; v < 3; ++v) {
    bushel::PourSpec spec;
    spec.count = n;
    spec.bottom_mesh_cells = v == 2 ? cells : 0;
    scenes.push_back(bushel::make_pour_scene(spec));
    auto& sim = scenes.back().simulation;
    if (v == 1) {
      const double size = 0.2;
      sim.add_part(bushel::make_part("far", bushel::MeshSpec{bushel::square_mesh(size, cells), "square mesh"},
                                     bushel::materials::steel(),
                                     {{scenes.back().container_radius + 0.01 + 0.5 * size, 0.0, 0.0}, {}}));
    }
    sim.step(static_cast<std::uint64_t>(std::ceil(settle / sim.settings().dt)));
    fmt::print(stderr, "{}: settled, {} triangles in the scene\n", names[v], v == 0 ? 0 : 2 * cells * cells);
  }
  fmt::print("variant,triangles,round,steps,seconds,particle_steps_per_s\n");
  std::vector<double> cost[3];
  for (int r = 0; r < rounds; ++r) {
    double seconds[3];
    for (int v = 0; v < 3; ++v) {
      const auto t0 = std::chrono::steady_clock::now();
      scenes[static_cast<std::size_t>(v)].simulation.step(dense);
      seconds[v] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      fmt::print("{},{},{},{},{:.3f},{:.4e}\n", names[v], v == 0 ? 0 : 2 * cells * cells, r, dense, seconds[v],
                 static_cast<double>(dense) * static_cast<double>(n) / seconds[v]);
    }
    for (int v = 0; v < 3; ++v) cost[v].push_back(seconds[v] / seconds[0]);
  }
  for (int v = 1; v < 3; ++v) {
    std::sort(cost[v].begin(), cost[v].end());
    fmt::print(stderr, "{}: median time per step over the plane's {:.3f}\n", names[v], cost[v][cost[v].size() / 2]);
  }
  return 0;
}
