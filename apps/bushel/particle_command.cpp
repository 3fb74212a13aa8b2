#include <fmt/format.h>
#include <algorithm>
#include <memory>
#include <nlohmann/json.hpp>

#include "bushel/contact/time_scales.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/particles/material.hpp"
#include "bushel/particles/pseudo_ellipsoid.hpp"
#include "bushel/particles/template_library.hpp"
#include "commands.hpp"

namespace bushel::cli {
namespace {

struct ParticleOptions {
  std::string spec;  // template name or CSV path
  bool ellipsoid = false;
  std::string length, width, mass, end_radius;
  int spheres = 5;
  std::string density = "1373kg/m3", shear_modulus = "22.4MPa", poisson_ratio = "0.22";
  int resolution = TemplateOptions{}.resolution;
  bool json = false, list = false, csv = false;
};

struct Row {
  const ParticleTemplate& t;
  const Material& m;
  double mass() const { return t.mass(m.density); }
  double rayleigh() const {
    return rayleigh_time_step(t.min_sphere_radius(), m.density, m.shear_modulus, m.poisson_ratio);
  }
};

nlohmann::ordered_json to_json(const Row& r, bool with_spheres) {
  const Vec3 e = r.t.extents(), inertia = r.t.principal_inertia(r.m.density);
  nlohmann::ordered_json j = {
      {"template", r.t.name},
      {"spheres", r.t.spheres.size()},
      {"volume_m3", r.t.volume},
      {"mass_kg", r.mass()},
      {"mass_g", r.mass() * 1e3},
      {"equivalent_diameter_m", r.t.equivalent_diameter()},
      {"extents_m", {e.x, e.y, e.z}},
      {"aspect_ratio", r.t.aspect_ratio()},
      {"principal_inertia_kg_m2", {inertia.x, inertia.y, inertia.z}},
      {"rayleigh_time_step_s", r.rayleigh()},
  };
  if (with_spheres) {
    auto spheres = nlohmann::ordered_json::array();
    for (const auto& s : r.t.spheres) {
      spheres.push_back({{"x_m", s.centre.x}, {"y_m", s.centre.y}, {"z_m", s.centre.z}, {"radius_m", s.radius}});
    }
    j["sphere_elements"] = spheres;
    j["material"] = {{"density_kg_m3", r.m.density},
                     {"shear_modulus_pa", r.m.shear_modulus},
                     {"poisson_ratio", r.m.poisson_ratio},
                     {"youngs_modulus_pa", r.m.youngs_modulus()}};
  }
  return j;
}

void print_table(const Row& r) {
  const Vec3 e = r.t.extents(), inertia = r.t.principal_inertia(r.m.density);
  fmt::print("template             {}\n", r.t.name);
  fmt::print("material             {:g} kg/m3, G {:g} MPa, nu {:g}\n", r.m.density, r.m.shear_modulus * 1e-6,
             r.m.poisson_ratio);
  fmt::print("spheres              {} (principal frame, centre of mass at the origin)\n", r.t.spheres.size());
  fmt::print("    #     x [mm]     y [mm]     z [mm]     r [mm]\n");
  for (std::size_t i = 0; i < r.t.spheres.size(); ++i) {
    const auto& s = r.t.spheres[i];
    fmt::print("  {:3d} {:10.4f} {:10.4f} {:10.4f} {:10.4f}\n", i, s.centre.x * 1e3, s.centre.y * 1e3, s.centre.z * 1e3,
               s.radius * 1e3);
  }
  fmt::print("volume               {:.4f} mm3 ({:.4e} m3)\n", r.t.volume * 1e9, r.t.volume);
  fmt::print("mass                 {:.5f} g\n", r.mass() * 1e3);
  fmt::print("equivalent diameter  {:.3f} mm\n", r.t.equivalent_diameter() * 1e3);
  fmt::print("extents (l x w x t)  {:.3f} x {:.3f} x {:.3f} mm\n", e.x * 1e3, e.y * 1e3, e.z * 1e3);
  fmt::print("aspect ratio         {:.3f}\n", r.t.aspect_ratio());
  fmt::print("principal inertia    {:.4e} {:.4e} {:.4e} kg m2\n", inertia.x, inertia.y, inertia.z);
  fmt::print("Rayleigh time step   {:.4f} us (smallest sphere, r = {:.3f} mm)\n", r.rayleigh() * 1e6,
             r.t.min_sphere_radius() * 1e3);
}

void print_list(const Material& m, bool json, bool csv) {
  const auto& lib = TemplateLibrary::builtin();
  if (json) {
    auto all = nlohmann::ordered_json::array();
    for (const auto& name : lib.names()) all.push_back(to_json({lib.get(name), m}, false));
    fmt::print("{}\n", all.dump(2, ' ', false, nlohmann::json::error_handler_t::replace));
  } else if (csv) {
    fmt::print(
        "template,spheres,volume_m3,mass_kg,equivalent_diameter_m,aspect_ratio,inertia_x_kg_m2,"
        "inertia_y_kg_m2,inertia_z_kg_m2,rayleigh_time_step_s\n");
    for (const auto& name : lib.names()) {
      const Row r{lib.get(name), m};
      const Vec3 i = r.t.principal_inertia(m.density);
      fmt::print("{},{},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}\n", name, r.t.spheres.size(),
                 r.t.volume, r.mass(), r.t.equivalent_diameter(), r.t.aspect_ratio(), i.x, i.y, i.z, r.rayleigh());
    }
  } else {
    fmt::print("{:<16} {:>7} {:>11} {:>9} {:>8} {:>7} {:>9}\n", "template", "spheres", "volume[mm3]", "mass[g]",
               "d_eq[mm]", "aspect", "T_R[us]");
    for (const auto& name : lib.names()) {
      const Row r{lib.get(name), m};
      fmt::print("{:<16} {:>7} {:>11.4f} {:>9.5f} {:>8.3f} {:>7.3f} {:>9.3f}\n", name, r.t.spheres.size(),
                 r.t.volume * 1e9, r.mass() * 1e3, r.t.equivalent_diameter() * 1e3, r.t.aspect_ratio(),
                 r.rayleigh() * 1e6);
    }
  }
}

void run_particle(const ParticleOptions& o) {
  const Material m{"cli", option_quantity("--shear-modulus", o.shear_modulus, units::dim::pressure),
                   option_quantity("--poisson-ratio", o.poisson_ratio, units::dim::dimensionless),
                   option_quantity("--density", o.density, units::dim::density)};
  try {
    validate(m);
  } catch (const InputError& e) {
    // Material fields map one-to-one onto options: poisson_ratio -> --poisson-ratio.
    std::string field = e.key().substr(e.key().find('.') + 1);
    std::replace(field.begin(), field.end(), '_', '-');
    throw InputError(e.problem()).with_key("--" + field);
  }
  const TemplateOptions options{o.resolution};
  if (o.list) return print_list(m, o.json, o.csv);
  if (o.csv) throw InputError("--csv applies to --list only").with_key("--csv");

  ParticleTemplate t;
  if (o.ellipsoid) {
    if (!o.spec.empty()) throw InputError("give a TEMPLATE or --ellipsoid, not both").with_key("--ellipsoid");
    if (o.length.empty() || o.width.empty()) {
      throw InputError("--ellipsoid needs --length and --width (e.g. --length 6.12mm --width 3.05mm)")
          .with_key("--ellipsoid");
    }
    PseudoEllipsoidSpec spec;
    spec.length = option_quantity("--length", o.length, units::dim::length);
    spec.width = option_quantity("--width", o.width, units::dim::length);
    spec.spheres = o.spheres;
    spec.density = m.density;
    if (!o.mass.empty()) spec.mass = option_quantity("--mass", o.mass, units::dim::mass);
    if (!o.end_radius.empty()) spec.end_radius = option_quantity("--end-radius", o.end_radius, units::dim::length);
    try {
      t = make_pseudo_ellipsoid(spec, fmt::format("ellipsoid_{}s", spec.spheres), options);
    } catch (const InputError& e) {
      throw e.with_key("--ellipsoid");
    }
  } else {
    if (o.spec.empty())
      throw InputError("give a TEMPLATE name or CSV path, --ellipsoid or --list").with_key("TEMPLATE");
    t = resolve_template(o.spec, options);
  }
  const Row r{t, m};
  if (o.json) {
    fmt::print("{}\n", to_json(r, true).dump(2, ' ', false, nlohmann::json::error_handler_t::replace));
  } else {
    print_table(r);
  }
}

}  // namespace

void add_particle_command(CLI::App& app) {
  auto o = std::make_shared<ParticleOptions>();
  auto* cmd = app.add_subcommand("particle", "Mass properties and time step of a particle template");
  cmd->add_option("TEMPLATE", o->spec, "Built-in template name (e.g. large_5s), CSV path, or PATH.csv:NAME");
  cmd->add_flag("--list", o->list, "List the built-in templates");
  cmd->add_flag("--ellipsoid", o->ellipsoid, "Generate a pseudo-ellipsoid clump instead of reading a template");
  cmd->add_option("--length", o->length, "Kernel length, e.g. 6.12mm (with --ellipsoid)");
  cmd->add_option("--width", o->width, "Kernel width, e.g. 3.05mm (with --ellipsoid)");
  cmd->add_option("--spheres", o->spheres, "Number of spheres: 1, or 3 and more (with --ellipsoid)")
      ->capture_default_str();
  cmd->add_option("--mass", o->mass, "Target kernel mass, e.g. 0.0346g (with --ellipsoid)");
  cmd->add_option("--end-radius", o->end_radius,
                  "Radius of the end spheres (with --ellipsoid); default width^2/(2 length)");
  cmd->add_option("--density", o->density, "Solid density")->capture_default_str();
  cmd->add_option("--shear-modulus", o->shear_modulus, "Shear modulus G")->capture_default_str();
  cmd->add_option("--poisson-ratio", o->poisson_ratio, "Poisson's ratio")->capture_default_str();
  cmd->add_option("--resolution", o->resolution, "Grid columns across the clump for the union integration")
      ->check(CLI::Range(16, 4000))
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "Print JSON (SI units)");
  cmd->add_flag("--csv", o->csv, "Print CSV (SI units; with --list)");
  cmd->callback([o] { run_particle(*o); });
}

}  // namespace bushel::cli
