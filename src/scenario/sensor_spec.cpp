#include "bushel/scenario/sensor_spec.hpp"

namespace bushel {

namespace dim = units::dim;

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

std::vector<ValueColumn> columns(const HeapSensorSpec&, const std::vector<std::string>&) {
  return {{"height", dim::length}, {"angle", dim::angle}};
}

std::vector<ValueColumn> columns(const FlowSensorSpec&, const std::vector<std::string>&) {
  return {{"mass", dim::mass}, {"rate", dim::mass_flow}};
}

std::vector<ValueColumn> SensorSpec::columns(const std::vector<std::string>& type_names) const {
  return std::visit([&](const auto& k) { return bushel::columns(k, type_names); }, kind);
}

std::vector<std::string> SensorSpec::values(const std::vector<std::string>& type_names) const {
  std::vector<std::string> names;
  for (const ValueColumn& c : columns(type_names)) names.push_back(c.name);
  return names;
}

}  // namespace bushel
