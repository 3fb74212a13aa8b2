// contacts: the default contact parameters and those of pairs of types or materials.

#include "scenario_reading.hpp"

namespace bushel::scenario_reading {
namespace {

namespace dim = units::dim;

ContactParameters read_contact(const ScenarioNode& n, const ContactParameters& base) {
  ContactParameters p = base;
  if (n.has("restitution")) p.restitution = n.at("restitution").quantity(dim::dimensionless);
  if (n.has("static_friction")) p.static_friction = n.at("static_friction").quantity(dim::dimensionless);
  if (n.has("rolling_friction")) p.rolling_friction = n.at("rolling_friction").quantity(dim::dimensionless);
  try {
    validate(p);
  } catch (const InputError& e) {
    throw n.at(e.key().empty() ? std::string("restitution") : e.key()).error(e.problem());
  }
  return p;
}

}  // namespace

void read_contacts(const ScenarioNode& c, Scenario& sc, const ReadContext& cx) {
  SimulationSettings& st = sc.settings;
  c.allow_only({"default", "pairs"});
  ContactParameters defaults;
  if (const auto d = c.find("default")) {
    d->allow_only({"restitution", "static_friction", "rolling_friction"});
    defaults = read_contact(*d, defaults);
  }
  st.contacts = ContactTable(defaults);
  if (const auto pairs = c.find("pairs")) {
    for (const ScenarioNode& p : pairs->items()) {
      p.allow_only({"between", "restitution", "static_friction", "rolling_friction"});
      const auto two = p.at("between").items();
      if (two.size() != 2) throw p.at("between").error("expected two names: [a, b] (particle types or materials)");
      std::vector<std::string> names = cx.type_names;
      names.insert(names.end(), cx.material_names.begin(), cx.material_names.end());
      const std::string a = names[index_in(two[0], names, "particle type or material")];
      const std::string b = names[index_in(two[1], names, "particle type or material")];
      st.contacts.set(a, b, read_contact(p, defaults));
    }
  }
}

}  // namespace bushel::scenario_reading
