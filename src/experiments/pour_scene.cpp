#include "bushel/experiments/pour_scene.hpp"

#include <fmt/format.h>
#include <cmath>
#include <utility>
#include <fstream>
#include <numbers>
#include <random>
#include <unordered_map>

#include "bushel/contact/time_scales.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/particles/template_library.hpp"

namespace bushel {

std::vector<Vec3> random_cloud(std::size_t count, double radius, double exclusion, double solid_fraction,
                               std::uint64_t seed) {
  const double r_in = radius - 0.6 * exclusion, z0 = 0.6 * exclusion;
  if (!(r_in > 0.0)) throw InputError("the container is narrower than one particle").with_key("container_diameter");
  const double v_p = std::numbers::pi / 6.0 * exclusion * exclusion * exclusion;
  const double height = static_cast<double>(count) * v_p / (solid_fraction * std::numbers::pi * r_in * r_in);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(-r_in, r_in), uz(z0, z0 + height);
  // Hash grid of cell size `exclusion`: a candidate checks the 27 cells around it.
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
  auto cell_key = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    return (static_cast<std::uint64_t>(i + (1 << 20)) << 42) | (static_cast<std::uint64_t>(j + (1 << 20)) << 21) |
           static_cast<std::uint64_t>(k + (1 << 20));
  };
  std::vector<Vec3> points;
  points.reserve(count);
  const double d2 = exclusion * exclusion;
  for (std::size_t attempts = 0; points.size() < count; ++attempts) {
    if (attempts > 200 * count) {
      throw InputError(fmt::format("could not place {} particles at solid fraction {:g}", count, solid_fraction))
          .with_key("solid_fraction");
    }
    const Vec3 p{ux(rng), ux(rng), uz(rng)};
    if (p.x * p.x + p.y * p.y > r_in * r_in) continue;
    const auto ci = static_cast<std::int64_t>(std::floor(p.x / exclusion)),
               cj = static_cast<std::int64_t>(std::floor(p.y / exclusion)),
               ck = static_cast<std::int64_t>(std::floor(p.z / exclusion));
    bool free = true;
    for (std::int64_t a = ci - 1; a <= ci + 1 && free; ++a) {
      for (std::int64_t b = cj - 1; b <= cj + 1 && free; ++b) {
        for (std::int64_t c = ck - 1; c <= ck + 1 && free; ++c) {
          const auto it = grid.find(cell_key(a, b, c));
          if (it == grid.end()) continue;
          for (const std::uint32_t q : it->second) {
            if (norm2(points[q] - p) < d2) {
              free = false;
              break;
            }
          }
        }
      }
    }
    if (!free) continue;
    grid[cell_key(ci, cj, ck)].push_back(static_cast<std::uint32_t>(points.size()));
    points.push_back(p);
  }
  return points;
}

ParticleType wheat_particle(const std::string& particle) {
  return {
      particle,
      particle == "sphere" ? make_template("sphere", {{{0, 0, 0}, 1.82e-3}}) : TemplateLibrary::builtin().get(particle),
      materials::wheat()};
}

double rayleigh_step(const ParticleType& type) {
  const Material& m = type.material;
  return rayleigh_time_step(type.shape.min_sphere_radius(), m.density, m.shear_modulus, m.poisson_ratio);
}

SimulationSettings wheat_settings(double dt, const std::string& rolling, double skin) {
  SimulationSettings s;
  s.dt = dt;
  s.rolling = rolling;
  s.skin = skin;
  s.contacts = ContactTable({0.5, 0.27, 0.01});
  s.contacts.set("wheat", "steel", {0.33, 0.17, 0.01});
  return s;
}

PourScene make_pour_scene(const PourSpec& spec) {
  if (spec.count == 0) throw InputError("expected at least one particle").with_key("count");
  if (!(spec.dt_fraction > 0.0 && spec.dt_fraction <= 1.0)) {
    throw InputError("expected a fraction of the Rayleigh step in (0, 1]").with_key("dt_fraction");
  }
  const Material steel = materials::steel();
  ParticleType type = wheat_particle(spec.particle);
  const double t_r = rayleigh_step(type);
  const double diameter = spec.container_diameter > 0.0 ? spec.container_diameter
                                                        : 0.090 * std::cbrt(static_cast<double>(spec.count) / 1e4);
  const double radius = 0.5 * diameter;

  SimulationSettings settings = wheat_settings(spec.dt_fraction * t_r, spec.rolling, spec.skin);
  settings.threads = spec.threads;
  PourScene scene{Simulation(std::move(settings)), radius, t_r};
  Simulation& sim = scene.simulation;
  // Exclusion diameter: the bounding sphere, rounded up (6.2 mm for the 5-sphere kernels).
  const double exclusion = spec.particle == "sphere" ? 3.64e-3 : 2.0 * type.shape.bounding_radius() * 1.013;
  const std::vector<Vec3> cloud = random_cloud(spec.count, radius, exclusion, spec.solid_fraction, spec.seed);
  double top = 0.0;
  for (const Vec3& p : cloud) top = std::max(top, p.z);
  if (spec.bottom_mesh_cells > 0) {  // the same floor as triangles (the mesh benchmark)
    sim.add_part(
        make_part("bottom", MeshSpec{square_mesh(diameter + 0.01, spec.bottom_mesh_cells), "square mesh"}, steel));
  } else {
    sim.add_part(plane_part("bottom", steel, {0, 0, 0}, {0, 0, 1}));
  }
  sim.add_part(make_part("side", CylinderSpec{radius, top + diameter, inside}, steel));
  const auto t = sim.add_type(std::move(type));
  std::mt19937_64 rng(spec.seed ^ 0x9e3779b97f4a7c15ULL);
  std::normal_distribution<double> n01;
  for (const Vec3& p : cloud) {
    const Quat q = normalized(Quat{n01(rng), n01(rng), n01(rng), n01(rng)});  // uniform random orientation
    const Vec3 v = spec.initial_speed * normalized(Vec3{n01(rng), n01(rng), n01(rng)});
    sim.add_body(t, {p, q, v, {}});
  }
  return scene;
}

void write_liggghts_data(const std::string& path, const ParticleSystem& particles, double container_radius) {
  std::ofstream out(path);
  if (!out) throw InputError("cannot open the file for writing").at(path);
  double z_max = 0.0;
  for (const auto& p : particles.position) z_max = std::max(z_max, p.z);
  const double box = container_radius + 0.002;
  out << fmt::format("bushel pour scene: N={} Dcyl={:.6f} m\n\n{} atoms\n2 atom types\n\n", particles.bodies(),
                     2 * container_radius, particles.bodies());
  out << fmt::format("{:.6f} {:.6f} xlo xhi\n{:.6f} {:.6f} ylo yhi\n{:.6f} {:.6f} zlo zhi\n\nAtoms\n\n", -box, box,
                     -box, box, -0.001, z_max + 0.01);
  for (std::size_t b = 0; b < particles.bodies(); ++b) {
    const auto& t = particles.types()[particles.body_type[b]];
    out << fmt::format("{} 1 {:.6g} {:.6g} {:.9f} {:.9f} {:.9f}\n", b + 1, t.shape.equivalent_diameter(),
                       t.material.density, particles.position[b].x, particles.position[b].y, particles.position[b].z);
  }
}

}  // namespace bushel
