#pragma once
// A scenario's sensors, one type per kind: what each is given in the scenario (sensors:), and
// the values it reports with their units, declared by the kind (not guessed from a name).
// Each kind's reader is in src/scenario/read_sensors.cpp; its columns and its reading
// (src/scenario/sensor_readings.hpp) side by side in src/scenario/sensor_kinds.cpp.

#include <cstddef>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "bushel/geometry/region.hpp"
#include "bushel/units/units.hpp"

namespace bushel {

/// One value a run reports (a column of timeseries.csv): its name and dimension. Values are
/// SI, except angles, which are in degrees (value_to_si converts).
struct ValueColumn {
  std::string name;
  units::Dimension dimension;
};

/// The grain in a region: its mass, count, bulk density, ...
struct RegionSensorSpec {
  Region region;
  double reference_volume = 0.0;        ///< bulk density = mass / this [m3]; 0 = the region's volume
  std::optional<std::size_t> top_part;  ///< its top follows this part's position (a lid)
};

/// The force on a part along an axis (and the pressure over an area), its position and angle.
struct PartSensorSpec {
  std::size_t part = 0;  ///< index of the part
  Vec3 axis{0, 0, -1};   ///< the force is measured along this unit vector
  double area = 0.0;     ///< pressure = force / area [m2]; 0 = no pressure
};

/// The surface of a heap around a vertical axis: its height and angle.
struct HeapSensorSpec {
  Vec3 centre;         ///< a point on the vertical axis [m]
  double outer = 0.0;  ///< outer radius [m]
  int rings = 20;      ///< number of rings
};

/// The grain through a plane: the mass through it and its rate.
struct FlowSensorSpec {
  Vec3 point;             ///< a point of the plane [m]
  Vec3 normal{0, 0, -1};  ///< unit normal, the direction counted positive
  double window = 0.05;   ///< the rate's averaging time [s]
};

/// Each kind's values, without the sensor's name ("bulk_density", ...); a region sensor has a
/// share of each particle type, named after it.
std::vector<ValueColumn> columns(const RegionSensorSpec& s, const std::vector<std::string>& type_names);
std::vector<ValueColumn> columns(const PartSensorSpec& s, const std::vector<std::string>& type_names);
std::vector<ValueColumn> columns(const HeapSensorSpec& s, const std::vector<std::string>& type_names);
std::vector<ValueColumn> columns(const FlowSensorSpec& s, const std::vector<std::string>& type_names);

struct SensorSpec {
  using Kind = std::variant<RegionSensorSpec, PartSensorSpec, HeapSensorSpec, FlowSensorSpec>;
  std::string name;
  Kind kind;
  /// Its kind's spec, or nullptr if it is of another kind.
  template <class K>
  const K* as() const {
    return std::get_if<K>(&kind);
  }
  /// Its values, without its name, with their dimensions.
  std::vector<ValueColumn> columns(const std::vector<std::string>& type_names) const;
  /// The names of its values ("bulk_density", ...), without the sensor's name.
  std::vector<std::string> values(const std::vector<std::string>& type_names) const;
};

}  // namespace bushel
