// sensors: each kind's keys (sensor_spec.hpp).

#include "scenario_reading.hpp"

namespace bushel::scenario_reading {
namespace {

namespace dim = units::dim;

RegionSensorSpec read_region_sensor(const ScenarioNode& s, const Scenario& sc, const ReadContext& cx) {
  s.allow_only({"kind", "region", "volume", "top"});
  RegionSensorSpec spec;
  spec.region = read_region(s.at("region"));
  require_inside(s.at("region"), spec.region.lo(), spec.region.hi(), sc.domain, "the sensor's region");
  spec.reference_volume = s.positive_or("volume", dim::volume, 0.0);
  if (s.has("top")) {
    if (spec.reference_volume > 0.0) throw s.at("top").error("a region that follows a part has no fixed 'volume'");
    spec.top_part = index_in(s.at("top"), cx.part_names, "part");
  }
  return spec;
}

PartSensorSpec read_part_sensor(const ScenarioNode& s, const ReadContext& cx) {
  s.allow_only({"kind", "part", "axis", "area"});
  PartSensorSpec spec;
  spec.part = index_in(s.at("part"), cx.part_names, "part");
  spec.axis = s.has("axis") ? unit_vector(s.at("axis")) : Vec3{0, 0, -1};
  spec.area = s.positive_or("area", dim::area, 0.0);
  return spec;
}

FlowSensorSpec read_flow_sensor(const ScenarioNode& s) {
  s.allow_only({"kind", "point", "normal", "window"});
  FlowSensorSpec spec;
  spec.point = s.vector_or("point", dim::length, {});
  spec.normal = s.has("normal") ? unit_vector(s.at("normal")) : Vec3{0, 0, -1};
  spec.window = s.positive_or("window", dim::time, 0.05);
  return spec;
}

HeapSensorSpec read_heap_sensor(const ScenarioNode& s) {
  s.allow_only({"kind", "centre", "radius", "rings"});
  HeapSensorSpec spec;
  spec.centre = s.vector_or("centre", dim::length, {});
  spec.outer = s.positive("radius", dim::length);
  spec.rings = s.has("rings") ? static_cast<int>(s.at("rings").integer(2, 10000)) : 20;
  return spec;
}

SensorSpec read_sensor(const std::string& name, const ScenarioNode& s, const Scenario& sc, const ReadContext& cx) {
  const std::string kind = s.at("kind").choice({"region", "part", "heap", "flow"});
  if (kind == "region") return {name, read_region_sensor(s, sc, cx)};
  if (kind == "part") return {name, read_part_sensor(s, cx)};
  if (kind == "flow") return {name, read_flow_sensor(s)};
  return {name, read_heap_sensor(s)};
}

}  // namespace

void read_sensors(const ScenarioNode& sensors, Scenario& sc, const ReadContext& cx) {
  for (const auto& [name, s] : sensors.entries()) sc.sensors.push_back(read_sensor(name, s, sc, cx));
}

}  // namespace bushel::scenario_reading
