#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bushel/core/did_you_mean.hpp"
#include "scenario_reading.hpp"

namespace bushel::scenario_reading {

namespace dim = units::dim;

std::size_t index_named(const ScenarioNode& node, const std::string& name, const std::vector<std::string>& names,
                        const std::string& what) {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it != names.end()) return static_cast<std::size_t>(it - names.begin());
  std::string known;
  for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
  throw node.error("unknown " + what + " '" + name + "'" + did_you_mean(name, names) + "; the scenario has " +
                   (known.empty() ? std::string("none") : known));
}

std::size_t index_in(const ScenarioNode& node, const std::vector<std::string>& names, const std::string& what) {
  return index_named(node, node.text(), names, what);
}

Vec3 unit_vector(const ScenarioNode& node) {
  const Vec3 v = node.vector(dim::dimensionless);
  const double n = norm(v);
  if (!(n > 0.0) || !std::isfinite(n)) throw node.error("expected a non-zero direction, e.g. '0 0 -1'");
  return v / n;
}

Region read_region(const ScenarioNode& n) {
  const std::string shape = n.at("shape").choice({"cylinder", "box"});
  if (shape == "cylinder") {
    n.allow_only({"shape", "base", "radius", "height"});
    return Region::cylinder(n.vector_or("base", dim::length, {}), n.positive("radius", dim::length),
                            n.positive("height", dim::length));
  }
  n.allow_only({"shape", "centre", "size"});
  const Vec3 size = n.at("size").vector(dim::length);
  if (!(size.x > 0.0 && size.y > 0.0 && size.z > 0.0)) throw n.at("size").error("expected positive edge lengths");
  return Region::box(n.vector_or("centre", dim::length, {}), size);
}

void require_inside(const ScenarioNode& n, const Vec3& lo, const Vec3& hi, const Region& domain,
                    const std::string& what) {
  const Vec3 dl = domain.lo(), dh = domain.hi();
  const double eps = 1e-9;
  if (lo.x < dl.x - eps || lo.y < dl.y - eps || lo.z < dl.z - eps || hi.x > dh.x + eps || hi.y > dh.y + eps ||
      hi.z > dh.z + eps) {
    throw n.error(
        fmt::format("{} reaches from ({:.4g}, {:.4g}, {:.4g}) to ({:.4g}, {:.4g}, {:.4g}) m, outside the "
                    "domain ({:.4g}, {:.4g}, {:.4g}) to ({:.4g}, {:.4g}, {:.4g}) m (simulation.domain)",
                    what, lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, dl.x, dl.y, dl.z, dh.x, dh.y, dh.z));
  }
}

}  // namespace bushel::scenario_reading
