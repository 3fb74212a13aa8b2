#pragma once
// Each sensor kind's reading (sensor_spec.hpp): its values now, in the order of its columns
// (defined next to them, in sensor_kinds.cpp). Internal to src/scenario.

#include <vector>

#include "bushel/integrate/simulation.hpp"
#include "bushel/scenario/scenario.hpp"
#include "bushel/sensors/plane_flow.hpp"

namespace bushel::scenario_running {

/// What a sensor reads: the simulation, the scenario (its parts' starting poses), and for a
/// flow sensor its count of the grain through its plane.
struct SensorInputs {
  const Simulation& sim;
  const Scenario& sc;
  const PlaneFlow* flow = nullptr;
};

/// A region sensor's region now: its top at its part's position, if it follows one.
Region region_now(const RegionSensorSpec& s, const Simulation& sim);

void append_values(const RegionSensorSpec& s, const SensorInputs& in, std::vector<double>& v);
void append_values(const PartSensorSpec& s, const SensorInputs& in, std::vector<double>& v);
void append_values(const HeapSensorSpec& s, const SensorInputs& in, std::vector<double>& v);
void append_values(const FlowSensorSpec& s, const SensorInputs& in, std::vector<double>& v);
/// Any kind's.
void append_values(const SensorSpec& s, const SensorInputs& in, std::vector<double>& v);

}  // namespace bushel::scenario_running
