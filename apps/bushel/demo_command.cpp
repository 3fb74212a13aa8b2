#include <fmt/format.h>
#include <unistd.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>

#include "bushel/core/input_error.hpp"
#include "bushel/experiments/pour_scene.hpp"
#include "commands.hpp"

#ifdef BUSHEL_HAVE_OPENMP
#include <omp.h>
#endif

namespace bushel::cli {
namespace {

struct DemoOptions {
  std::size_t count = 2000;
  std::string particle = "large_5s";
  std::string max_time = "3s", settled = "1e-9";
  std::uint64_t seed = 12345;
  int threads = 0;
  bool json = false;
};

// Mass of particles whose centre lies in the lower `fraction` of the bed, over that
// cylinder's volume: the bulk density of the poured bed away from its surface.
struct BedMeasure {
  double bed_height, region_height, bulk_density, packing_fraction;
};

BedMeasure measure_bed(const PourScene& scene, double fraction) {
  const auto& p = scene.simulation.particles();
  double top = 0.0;
  for (const auto& x : p.position) top = std::max(top, x.z);
  const double h = fraction * top;
  double mass = 0.0;
  for (std::size_t b = 0; b < p.bodies(); ++b) mass += p.position[b].z <= h ? p.mass(b) : 0.0;
  const double volume = std::numbers::pi * scene.container_radius * scene.container_radius * h;
  const double rho = p.types().front().material.density;
  return {top, h, mass / volume, mass / volume / rho};
}

void run_demo(const DemoOptions& o) {
  set_threads(o.threads);
  const double max_time = option_quantity("--max-time", o.max_time, units::dim::time);
  // Kinetic energy per particle in J: a plain number, since the units layer has no energies.
  double settled = 0.0;
  try {
    settled = units::parse_number(o.settled);
  } catch (const InputError& e) {
    throw e.with_key("--settled");
  }
  if (!(settled > 0.0)) throw InputError("expected a positive energy in J, e.g. 1e-9").with_key("--settled");
  PourSpec spec;
  spec.count = o.count;
  spec.particle = o.particle;
  spec.seed = o.seed;
  PourScene scene = make_pour_scene(spec);
  Simulation& sim = scene.simulation;
  const double dt = sim.settings().dt;
  fmt::print(stderr, "pour: {} x {} in a {:.1f} mm cylinder, dt = {:.3f} us ({:g} of the Rayleigh step {:.3f} us)\n",
             o.count, o.particle, 2e3 * scene.container_radius, dt * 1e6, spec.dt_fraction, scene.rayleigh_step * 1e6);
  const bool tty = isatty(fileno(stderr)) != 0;
  const auto chunk = static_cast<std::uint64_t>(0.01 / dt);
  const auto start = std::chrono::steady_clock::now();
  double ke_per_particle = 0.0;
  while (sim.time() < max_time) {
    sim.step(chunk);
    ke_per_particle = sim.particles().kinetic_energy() / static_cast<double>(sim.particles().bodies());
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    fmt::print(stderr, "{}t = {:.2f} s  steps {}  KE/particle {:.2e} J  contacts {}  {:.2f} M sphere-steps/s{}",
               tty ? "\r" : "", sim.time(), sim.steps(), ke_per_particle, sim.contacts(),
               static_cast<double>(sim.steps()) * static_cast<double>(sim.particles().spheres()) / wall * 1e-6,
               tty ? "   " : "\n");
    if (sim.time() > 0.2 && ke_per_particle < settled) break;
  }
  if (tty) fmt::print(stderr, "\n");
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const BedMeasure m = measure_bed(scene, 0.6);
  const bool is_settled = ke_per_particle < settled;
  if (o.json) {
    const nlohmann::ordered_json j = {{"particles", o.count},
                                      {"particle", o.particle},
                                      {"simulated_time_s", sim.time()},
                                      {"steps", sim.steps()},
                                      {"settled", is_settled},
                                      {"kinetic_energy_per_particle_j", ke_per_particle},
                                      {"bed_height_m", m.bed_height},
                                      {"region_height_m", m.region_height},
                                      {"bulk_density_kg_m3", m.bulk_density},
                                      {"packing_fraction", m.packing_fraction},
                                      {"wall_time_s", wall}};
    fmt::print("{}\n", j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace));
    return;
  }
  fmt::print("{} after {:.2f} s simulated ({} steps, {:.1f} s wall)\n", is_settled ? "settled" : "NOT settled",
             sim.time(), sim.steps(), wall);
  fmt::print("bed height (highest centre)  {:.1f} mm\n", m.bed_height * 1e3);
  fmt::print("measured region              lower {:.1f} mm of the bed, full cylinder\n", m.region_height * 1e3);
  fmt::print("bulk density                 {:.1f} kg/m3\n", m.bulk_density);
  fmt::print("packing fraction             {:.4f}\n", m.packing_fraction);
}

}  // namespace

void set_threads(int threads) {
#ifdef BUSHEL_HAVE_OPENMP
  if (threads > 0) omp_set_num_threads(threads);
#else
  (void)threads;
#endif
}

void add_demo_command(CLI::App& app) {
  auto o = std::make_shared<DemoOptions>();
  auto* demo = app.add_subcommand("demo", "Scenario-free demonstrations of the engine");
  demo->require_subcommand(1);
  auto* pour = demo->add_subcommand("pour", "Pour particles into a cylinder and measure the bed");
  pour->add_option("--count", o->count, "Number of particles")->capture_default_str()->check(CLI::Range(1, 10'000'000));
  pour->add_option("--particle", o->particle, "sphere (d 3.64 mm) or a template name")->capture_default_str();
  pour->add_option("--max-time", o->max_time, "Simulated time limit")->capture_default_str();
  pour->add_option("--settled", o->settled, "Kinetic energy per particle [J] below which the bed counts as settled")
      ->capture_default_str();
  pour->add_option("--seed", o->seed, "Random seed")->capture_default_str();
  pour->add_option("--threads", o->threads, "OpenMP threads (0 = default)")->capture_default_str();
  pour->add_flag("--json", o->json, "Print the result as JSON");
  pour->callback([o] { run_demo(*o); });
  add_demo_funnel_command(*demo);
}

}  // namespace bushel::cli
