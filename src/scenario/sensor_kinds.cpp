// Each sensor kind's columns (sensor_spec.hpp) and its reading (sensor_readings.hpp), side
// by side: a reading appends its values in the order of its kind's columns.

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bushel/scenario/sensor_spec.hpp"
#include "bushel/sensors/heap_profile.hpp"
#include "bushel/sensors/region_sensor.hpp"
#include "sensor_readings.hpp"

namespace bushel {

namespace dim = units::dim;

// --- region -----------------------------------------------------------------------------------

std::vector<ValueColumn> columns(const RegionSensorSpec&, const std::vector<std::string>& type_names) {
  std::vector<ValueColumn> v = {{"mass", dim::mass},
                                {"count", dim::dimensionless},
                                {"bulk_density", dim::density},
                                {"bulk_density_exact", dim::density},
                                {"packing_fraction", dim::dimensionless},
                                {"coordination", dim::dimensionless},
                                {"volume", dim::volume},
                                {"surface_margin", dim::length}};
  for (const auto& t : type_names) v.push_back({"fraction_" + t, dim::dimensionless});
  return v;
}

namespace scenario_running {

Region region_now(const RegionSensorSpec& s, const Simulation& sim) {
  Region r = s.region;
  if (!s.top_part) return r;
  const double top = std::max(sim.part(*s.top_part).pose.position.z, r.lo().z);
  if (r.kind == Region::Kind::cylinder) return Region::cylinder(r.position, r.radius, top - r.position.z);
  const Vec3 lo = r.lo(), hi{r.hi().x, r.hi().y, top};
  return Region::box(0.5 * (lo + hi), hi - lo);
}

void append_values(const RegionSensorSpec& s, const SensorInputs& in, std::vector<double>& v) {
  const Region region = region_now(s, in.sim);
  const RegionReading r = read_region(in.sim, region);
  // per the reference volume, where one is given (a heaped kettle over its own volume)
  const double per = s.reference_volume > 0.0 ? region.volume() / s.reference_volume : 1.0;
  v.insert(v.end(), {r.mass, static_cast<double>(r.count), r.bulk_density * per, r.bulk_density_exact * per,
                     r.packing_fraction * per, r.coordination, region.volume(), r.surface_margin});
  v.insert(v.end(), r.mass_fraction.begin(), r.mass_fraction.end());
}

}  // namespace scenario_running

// --- part -------------------------------------------------------------------------------------

std::vector<ValueColumn> columns(const PartSensorSpec& s, const std::vector<std::string>&) {
  std::vector<ValueColumn> v = {{"force", dim::force}};
  if (s.area > 0.0) v.push_back({"pressure", dim::pressure});
  v.insert(v.end(), {{"force_x", dim::force},
                     {"force_y", dim::force},
                     {"force_z", dim::force},
                     {"torque_x", dim::energy},  // N m
                     {"torque_y", dim::energy},
                     {"torque_z", dim::energy},
                     {"position_z", dim::length},
                     {"angle", dim::angle}});  // [deg] from its starting orientation
  return v;
}

namespace scenario_running {

void append_values(const PartSensorSpec& s, const SensorInputs& in, std::vector<double>& v) {
  const Part& p = in.sim.part(s.part);
  const double along = dot(p.force, s.axis);
  v.push_back(along);
  if (s.area > 0.0) v.push_back(along / s.area);
  // the angle turned from the part's starting orientation [deg]
  const Quat &q = p.pose.orientation, &q0 = in.sc.parts[s.part].pose.orientation;
  const double w = std::min(1.0, std::abs(q.w * q0.w + q.x * q0.x + q.y * q0.y + q.z * q0.z));
  v.insert(v.end(), {p.force.x, p.force.y, p.force.z, p.torque.x, p.torque.y, p.torque.z, p.pose.position.z,
                     2.0 * std::acos(w) * 180.0 / std::numbers::pi});
}

}  // namespace scenario_running

// --- heap -------------------------------------------------------------------------------------

std::vector<ValueColumn> columns(const HeapSensorSpec&, const std::vector<std::string>&) {
  return {{"height", dim::length}, {"angle", dim::angle}};
}

namespace scenario_running {

void append_values(const HeapSensorSpec& s, const SensorInputs& in, std::vector<double>& v) {
  const HeapProfile h = heap_profile(in.sim, s.centre.x, s.centre.y, s.outer, s.rings);
  double top = 0.0;
  for (const double x : h.height) top = std::isfinite(x) ? std::max(top, x) : top;
  v.insert(v.end(), {top, h.angle * 180.0 / std::numbers::pi});
}

}  // namespace scenario_running

// --- flow -------------------------------------------------------------------------------------

std::vector<ValueColumn> columns(const FlowSensorSpec&, const std::vector<std::string>&) {
  return {{"mass", dim::mass}, {"rate", dim::mass_flow}};
}

namespace scenario_running {

void append_values(const FlowSensorSpec&, const SensorInputs& in, std::vector<double>& v) {
  v.insert(v.end(), {in.flow->mass(), in.flow->rate()});
}

}  // namespace scenario_running

// --- any kind ---------------------------------------------------------------------------------

std::vector<ValueColumn> SensorSpec::columns(const std::vector<std::string>& type_names) const {
  return std::visit([&](const auto& k) { return bushel::columns(k, type_names); }, kind);
}

std::vector<std::string> SensorSpec::values(const std::vector<std::string>& type_names) const {
  std::vector<std::string> names;
  for (const ValueColumn& c : columns(type_names)) names.push_back(c.name);
  return names;
}

namespace scenario_running {

void append_values(const SensorSpec& s, const SensorInputs& in, std::vector<double>& v) {
  std::visit([&](const auto& k) { append_values(k, in, v); }, s.kind);
}

}  // namespace scenario_running

}  // namespace bushel
