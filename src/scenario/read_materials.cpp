// materials: and particle_types:.

#include <filesystem>

#include "bushel/particles/template_library.hpp"
#include "scenario_reading.hpp"

namespace bushel::scenario_reading {
namespace {

namespace dim = units::dim;

Material read_material(const std::string& name, const ScenarioNode& m) {
  m.allow_only({"shear_modulus", "poisson_ratio", "density"});
  Material mat{name, m.positive("shear_modulus", dim::pressure), m.at("poisson_ratio").number(),
               m.positive("density", dim::density)};
  try {
    validate(mat);
  } catch (const InputError& e) {  // (its key is "NAME.field")
    const std::string field = e.key().substr(e.key().find('.') + 1);
    throw m.at(field.empty() || field == e.key() ? std::string("poisson_ratio") : field).error(e.problem());
  }
  return mat;
}

// A particle type's shape: a sphere of a diameter, or a template (by name or a CSV file).
ParticleTemplate read_template(const std::string& name, const ScenarioNode& t, const std::string& dir) {
  ParticleTemplate shape;
  if (t.one_of({"template", "diameter"}) == "diameter") {
    shape = make_template(name, {{{0, 0, 0}, 0.5 * t.positive("diameter", dim::length)}});
  } else {
    std::string spec = t.at("template").text();
    // A CSV file is found next to the scenario.
    if (spec.find(".csv") != std::string::npos && !std::filesystem::path(spec).is_absolute() && !dir.empty()) {
      spec = (std::filesystem::path(dir) / spec).string();
    }
    try {
      shape = resolve_template(spec);
    } catch (const InputError& e) {
      throw t.at("template").error(e.source().empty() ? e.problem() : e.what());  // (a CSV's file and line)
    }
  }
  return shape;
}

}  // namespace

void read_materials(const ScenarioNode& root, ReadContext& cx) {
  for (const auto& [name, m] : root.at("materials").entries()) {
    cx.materials[name] = read_material(name, m);
    cx.material_names.push_back(name);
  }
  if (cx.materials.empty()) throw root.at("materials").error("expected at least one material");
}

void read_particle_types(const ScenarioNode& root, Scenario& sc, ReadContext& cx) {
  for (const auto& [name, t] : root.at("particle_types").entries()) {
    t.allow_only({"template", "diameter", "material"});
    const Material& mat = cx.materials.at(cx.material_names[index_in(t.at("material"), cx.material_names, "material")]);
    ParticleTemplate shape = read_template(name, t, cx.dir);
    sc.types.push_back({name, std::move(shape), mat});
    cx.type_names.push_back(name);
  }
  if (sc.types.empty()) throw root.at("particle_types").error("expected at least one particle type");
}

}  // namespace bushel::scenario_reading
