// factories: and sinks:.

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "scenario_reading.hpp"

namespace bushel::scenario_reading {
namespace {

namespace dim = units::dim;

// Where a factory creates particles: in a region, or on the front side of a mesh (STL) moved
// to `position`.
void read_factory_place(const ScenarioNode& f, FactorySpec& spec, const Scenario& sc, const ReadContext& cx) {
  if (f.one_of({"region", "surface"}) == "region") {
    spec.region = read_region(f.at("region"));
    require_inside(f.at("region"), spec.region.lo(), spec.region.hi(), sc.domain, "the factory's region");
  } else {
    const ScenarioNode surface = f.at("surface");
    surface.allow_only({"file", "unit", "position"});
    spec.surface = std::get<MeshSpec>(read_shape(surface, "mesh", cx.dir)).mesh;
    const Vec3 shift = surface.vector_or("position", dim::length, {});
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi = -lo;
    for (Vec3& v : spec.surface.vertices) v = v + shift, lo = min(lo, v), hi = max(hi, v);
    require_inside(surface, lo, hi, sc.domain, "the factory's surface");
  }
}

// Its rate (by mass or count) and its total (a mass or a count).
void read_factory_amount(const ScenarioNode& f, FactorySpec& spec) {
  if (f.has("rate")) {
    const ScenarioNode r = f.at("rate");
    const bool per_second = r.text().ends_with("/s") && !r.text().ends_with("kg/s") && !r.text().ends_with("g/s");
    spec.rate_by_mass = !per_second;
    spec.rate = r.quantity(per_second ? dim::frequency : dim::mass_flow);
    if (!(spec.rate > 0.0)) throw r.error("expected a positive rate, e.g. '1 kg/s' or '500 /s'");
  }
  if (f.one_of({"mass", "count"}) == "mass") {
    spec.total = f.positive("mass", dim::mass);
  } else {
    spec.total_by_mass = false;
    spec.total = static_cast<double>(f.at("count").integer(1, 100'000'000));
  }
}

// Its particle types: one, or several with their shares (by mass or count).
void read_factory_types(const ScenarioNode& f, FactorySpec& spec, const ReadContext& cx) {
  spec.fractions_by_mass = !f.has("fractions_by") || f.at("fractions_by").choice({"mass", "count"}) == "mass";
  const ScenarioNode types = f.at("types");
  if (types.is_scalar()) {
    spec.types.push_back(static_cast<std::uint32_t>(index_in(types, cx.type_names, "particle type")));
    spec.fractions.push_back(1.0);
    return;
  }
  double sum = 0.0;
  for (const auto& [tname, frac] : types.entries()) {
    spec.types.push_back(static_cast<std::uint32_t>(index_named(frac, tname, cx.type_names, "particle type")));
    const double v = frac.quantity(dim::dimensionless);
    if (!(v >= 0.0)) throw frac.error("expected a share >= 0, e.g. 81.5%");
    spec.fractions.push_back(v);
    sum += v;
  }
  if (spec.types.empty()) throw types.error("expected at least one particle type");
  if (std::abs(sum - 1.0) > 1e-3) throw types.error(fmt::format("the shares add up to {:.4g}%, not 100%", 100 * sum));
  for (double& v : spec.fractions) v /= sum;
}

// Factory number `k` of the scenario.
FactorySpec read_factory(const std::string& name, const ScenarioNode& f, std::uint64_t k, const Scenario& sc,
                         const ReadContext& cx) {
  f.allow_only({"region", "surface", "rate", "mass", "count", "types", "fractions_by", "velocity", "start", "stop",
                "enabled", "seed"});
  FactorySpec spec;
  spec.name = name;
  read_factory_place(f, spec, sc, cx);
  read_factory_amount(f, spec);
  read_factory_types(f, spec, cx);
  spec.velocity = f.vector_or("velocity", dim::velocity, {});
  if (norm(spec.velocity) > sc.guards.max_speed) {
    throw f.at("velocity")
        .error(fmt::format("a speed of {:.4g} m/s, above the guard's {:g} m/s "
                           "(simulation.guards.max_speed): the run would stop at once",
                           norm(spec.velocity), sc.guards.max_speed));
  }
  spec.start = f.non_negative_or("start", dim::time, 0.0);
  spec.stop = f.has("stop") ? f.positive("stop", dim::time) : std::numeric_limits<double>::infinity();
  if (!(spec.stop > spec.start)) throw f.at("stop").error("expected a stop time after the start");
  spec.seed = f.has("seed") ? static_cast<std::uint64_t>(f.at("seed").integer(0, 1L << 40)) : cx.seed * 1000003ULL + k;
  // The region must hold the largest particle (the factory checks; the error points here).
  double r_max = 0.0;
  for (const auto t : spec.types) r_max = std::max(r_max, sc.types[t].shape.bounding_radius());
  if (f.has("region") && !(spec.region.room() > r_max)) {
    throw f.at("region").error(
        fmt::format("too small for the largest particle (bounding radius {:.3g} mm)", r_max * 1e3));
  }
  return spec;
}

}  // namespace

void read_factories(const ScenarioNode& factories, Scenario& sc, ReadContext& cx) {
  std::uint64_t k = 0;
  for (const auto& [name, f] : factories.entries()) {
    sc.factories.push_back(read_factory(name, f, k, sc, cx));
    sc.factory_enabled.push_back(f.boolean_or("enabled", true));
    cx.factory_names.push_back(name);
    ++k;
  }
}

void read_sinks(const ScenarioNode& sinks, Scenario& sc, ReadContext& cx) {
  for (const auto& [name, s] : sinks.entries()) {
    s.allow_only({"region", "enabled"});
    sc.sinks.push_back({name, read_region(s.at("region")), s.boolean_or("enabled", true)});
    cx.sink_names.push_back(name);
  }
}

}  // namespace bushel::scenario_reading
