// Scenario files: validation errors name the file, line and key; a small run writes its
// summary, time series and frames, and its stages end on the conditions they name.
#include "bushel/scenario/scenario.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <numeric>
#include <random>
#include <sstream>

#include "bushel/core/build_info.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/geometry/motion.hpp"
#include "bushel/geometry/shapes.hpp"
#include "bushel/io/binary_archive.hpp"
#include "bushel/io/csv.hpp"
#include "bushel/io/stl.hpp"
#include "bushel/scenario/run_summary.hpp"
#include "bushel/scenario/scenario_run.hpp"
#include "temp_dir_test.hpp"

namespace bushel {
namespace {

// Wheat spheres 3.64 mm across, and steel.
const std::string wheat_and_steel = R"(materials:
  wheat: {shear_modulus: 22.4 MPa, poisson_ratio: 0.22, density: 1373 kg/m3}
  steel: {shear_modulus: 37 GPa, poisson_ratio: 0.25, density: 8560 kg/m3}
particle_types:
  grain: {diameter: 3.64 mm, material: wheat}
contacts:
  default: {restitution: 0.5, static_friction: 0.27, rolling_friction: 0.01}
)";

// A small scenario: 300 spheres poured into a cylindrical cup with a sink under it.
const std::string small = R"(parameters:
  count: 300
simulation:
  time_step: 0.2 rayleigh
  domain: {min: -40 -40 -30 mm, max: 40 40 120 mm}
)" + wheat_and_steel + R"(parts:
  cup: {shape: cylinder, radius: 15 mm, height: 40 mm, side: inside, cap_bottom: true, material: steel}
factories:
  pour:
    region: {shape: box, centre: 0 0 60 mm, size: 24 24 30 mm}
    count: ${count}
    types: grain
    velocity: 0 0 -0.3 m/s
sinks:
  under: {region: {shape: box, centre: 0 0 -20 mm, size: 80 80 20 mm}}
sensors:
  cup: {kind: region, region: {shape: cylinder, radius: 15 mm, height: 10 mm}}
  bottom: {kind: part, part: cup, axis: 0 0 -1, area: 706.86 mm2}
  inflow: {kind: flow, point: 0 0 42 mm, normal: 0 0 -1}
  surface: {kind: heap, radius: 15 mm, rings: 5}
stages:
  - name: fill
    until: {factories_done: true, max_time: 0.1 s}
  - name: settle
    until: {kinetic_energy: 1 nJ, min_time: 20 ms, max_time: 0.3 s}
outputs:
  timeseries: {interval: 10 ms}
  frames: {interval: 50 ms}
)";

Scenario read(const std::string& text, std::vector<Override> overrides = {}) {
  return read_scenario(parse_scenario_document(text, "s.yaml", overrides));
}

// The message of the InputError that reading `text` with `overrides` throws.
std::string error_of(const std::string& text, std::vector<Override> overrides = {}) {
  try {
    read(text, overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

// The message of the InputError that `f` throws.
template <class F>
std::string thrown_by(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(Scenario, ReadsEverySectionInSI) {
  const Scenario sc = read(small);
  ASSERT_EQ(sc.types.size(), 1u);
  EXPECT_NEAR(sc.types[0].shape.spheres[0].radius, 1.82e-3, 1e-15);
  EXPECT_NEAR(sc.settings.dt, 0.2 * sc.rayleigh_step, 1e-18);
  ASSERT_EQ(sc.parts.size(), 1u);
  EXPECT_NEAR(std::get<CylinderSpec>(sc.parts[0].shape).radius, 0.015, 1e-15);
  ASSERT_EQ(sc.factories.size(), 1u);
  EXPECT_FALSE(sc.factories[0].total_by_mass);
  EXPECT_EQ(sc.factories[0].total, 300.0);
  EXPECT_NEAR(sc.factories[0].velocity.z, -0.3, 1e-15);
  ASSERT_EQ(sc.stages.size(), 2u);
  EXPECT_TRUE(sc.stages[0].factories_done);
  EXPECT_NEAR(*sc.stages[1].kinetic_energy, 1e-9, 1e-24);
  EXPECT_NEAR(sc.stages[1].min_time, 0.02, 1e-15);
  EXPECT_NEAR(sc.sensors[1].as<PartSensorSpec>()->area, 7.0686e-4, 1e-15);
  // --set reaches any value, and parameters
  const Scenario big =
      read(small, {parse_override("parameters.count=300"), parse_override("simulation.time_step=1 us")});
  EXPECT_EQ(big.factories[0].total, 300.0);
  EXPECT_NEAR(big.settings.dt, 1e-6, 1e-18);
}

TEST(Scenario, RollingModelsComeFromTheRegistry) {
  const std::string with =
      replaced(small, "time_step: 0.2 rayleigh", "time_step: 0.2 rayleigh\n  rolling: liggghts_cdt");
  EXPECT_EQ(read(with).settings.rolling, "liggghts_cdt");
  const std::string error = error_of(replaced(with, "rolling: liggghts_cdt", "rolling: ligghts_cdt"));
  EXPECT_NE(error.find("(did you mean 'liggghts_cdt'?); expected one of cdt, epsd, liggghts_cdt, none"),
            std::string::npos)
      << error;
}

TEST(Scenario, ThreadsAreAutoOrACount) {
  // absent or auto: measured while running, up to OpenMP's count; a number: exactly that many
  EXPECT_TRUE(read(small).settings.threads.adaptive);
  EXPECT_EQ(read(small).settings.threads.max, 0);
  const auto with = [](const std::string& value) {
    return replaced(small, "time_step: 0.2 rayleigh", "time_step: 0.2 rayleigh\n  threads: " + value);
  };
  EXPECT_TRUE(read(with("auto")).settings.threads.adaptive);
  EXPECT_TRUE(read(with("0")).settings.threads.adaptive);
  const ThreadPolicy three = read(with("3")).settings.threads;
  EXPECT_FALSE(three.adaptive);
  EXPECT_EQ(three.max, 3);
  for (const std::string bad : {"-1", "two", "1.5", "2000"}) {
    EXPECT_NE(error_of(with(bad)).find("s.yaml:5: key 'simulation.threads': expected 'auto' or a thread count from 1 "
                                       "to 1024"),
              std::string::npos)
        << bad << ": " << error_of(with(bad));
  }
}

TEST(Scenario, AnglesAreDegreesInTheRunAndRadiansInExpressions) {
  // (each sensor kind declares its values' dimensions: a part's and a heap's angle are angles)
  const Scenario sc = read(small);
  EXPECT_EQ(sc.value_dimension("bottom.angle"), units::dim::angle);
  EXPECT_EQ(sc.value_dimension("surface.angle"), units::dim::angle);
  EXPECT_EQ(sc.value_dimension("cup.packing_fraction"), units::dim::dimensionless);
  EXPECT_EQ(sc.value_dimension("bottom.pressure"), units::dim::pressure);
  EXPECT_EQ(sc.value_dimension("inflow.rate"), units::dim::mass_flow);
  EXPECT_EQ(sc.value_dimension("kinetic_energy"), units::dim::energy);
  EXPECT_EQ(sc.value_dimension("duration"), units::dim::time);
  EXPECT_NEAR(sc.value_to_si("bottom.angle", 180.0), std::numbers::pi, 1e-15);
  EXPECT_NEAR(sc.value_from_si("surface.angle", std::numbers::pi / 4), 45.0, 1e-12);
  EXPECT_EQ(sc.value_to_si("cup.mass", 0.25), 0.25);
  EXPECT_EQ(to_string(StageEnd::factories_done), "factories_done");
  EXPECT_EQ(result_unit(units::dim::angle), "deg");
  EXPECT_EQ(result_unit(units::dim::density), "kg/m3");
  EXPECT_NEAR(result_value({std::numbers::pi / 2, units::dim::angle}), 90.0, 1e-12);
}

TEST(Scenario, ErrorsNameTheFileLineAndKey) {
  EXPECT_NE(error_of(replaced(small, "shear_modulus: 22.4 MPa", "shear_modulus: 22.4 mm"))
                .find("s.yaml:7: key 'materials.wheat.shear_modulus': expected a pressure"),
            std::string::npos)
      << error_of(replaced(small, "shear_modulus: 22.4 MPa", "shear_modulus: 22.4 mm"));
  EXPECT_NE(error_of(replaced(small, "static_friction: 0.27", "static_fricton: 0.27"))
                .find("unknown key 'static_fricton' (did you mean 'static_friction'?)"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(small, "types: grain", "types: grainn"))
                .find("s.yaml:19: key 'factories.pour.types': "
                      "unknown particle type 'grainn' (did you "
                      "mean 'grain'?)"),
            std::string::npos)
      << error_of(replaced(small, "types: grain", "types: grainn"));
  EXPECT_NE(error_of(replaced(small, "size: 24 24 30 mm", "size: 24 24 -30 mm")).find("expected positive edge lengths"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(small, "height: 40 mm", "height: 140 mm")).find("outside the domain"), std::string::npos);
  EXPECT_NE(error_of(replaced(small, "poisson_ratio: 0.22", "poisson_ratio: 0.7")).find("poisson"), std::string::npos);
  // the engine's own checks of a part come before the run: a plane cannot turn
  EXPECT_NE(error_of(replaced(small, "parts:\n",
                              "parts:\n  floor: {shape: plane, position: 0 0 -5 mm, material: steel, "
                              "motion: [{rotate: {axis: 1 0 0, speed: 1 rad/s}}]}\n"))
                .find("key 'parts.floor'"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(small, "time_step: 0.2 rayleigh", "time_step: 1 ms")).find("above the Rayleigh step"),
            std::string::npos);
  // a time step that is neither a time nor a Rayleigh fraction names both forms
  const std::string typo = error_of(replaced(small, "time_step: 0.2 rayleigh", "time_step: 0.2 rayleighs"));
  EXPECT_NE(typo.find("s.yaml:4: key 'simulation.time_step': expected a time with a unit (s, ms, us, min, h), got "
                      "'0.2 rayleighs': unknown unit 'rayleighs'; or a fraction of the smallest element's Rayleigh "
                      "step, e.g. '0.2 rayleigh'"),
            std::string::npos)
      << typo;
  // a stage's own time step is checked as the simulation's is, at its line
  EXPECT_NE(error_of(replaced(small, "  - name: settle\n", "  - name: settle\n    time_step: 1 ms\n"))
                .find("s.yaml:32: key 'stages.1.time_step': a time step of 1000 us is above the Rayleigh step"),
            std::string::npos)
      << error_of(replaced(small, "  - name: settle\n", "  - name: settle\n    time_step: 1 ms\n"));
  EXPECT_NE(error_of(replaced(small, "  - name: settle\n", "  - name: settle\n    time_step: 1.5 rayleigh\n"))
                .find("expected a fraction of the Rayleigh step in (0, 1]"),
            std::string::npos);
  const std::string limit = "  time_step: 0.2 rayleigh\n  tangential_damping_limit: 2\n";
  EXPECT_NE(error_of(replaced(small, "  time_step: 0.2 rayleigh\n", limit))
                .find("s.yaml:5: key 'simulation.tangential_damping_limit': expected a fraction in (0, 1]"),
            std::string::npos)
      << error_of(replaced(small, "  time_step: 0.2 rayleigh\n", limit));
  EXPECT_EQ(read(replaced(small, "  time_step: 0.2 rayleigh\n",
                          "  time_step: 0.2 rayleigh\n  tangential_damping_limit: off\n"))
                .settings.tangential_damping_limit,
            std::numeric_limits<double>::infinity());
  EXPECT_EQ(read(small).settings.tangential_damping_limit, 0.5);
  EXPECT_NE(error_of(replaced(small, "  - name: settle\n", "  - name: fill\n"))
                .find("s.yaml:31: key 'stages.1.name': a second stage named 'fill'"),
            std::string::npos)
      << error_of(replaced(small, "  - name: settle\n", "  - name: fill\n"));
  // a value set on the command line is named as such; a parameter at the line that uses it
  EXPECT_NE(error_of(small, {parse_override("factories.pour.count=12.5")})
                .find("command line (--set): key 'factories.pour.count': expected a whole number"),
            std::string::npos)
      << error_of(small, {parse_override("factories.pour.count=12.5")});
  EXPECT_NE(error_of(small, {parse_override("parameters.count=0")}).find("s.yaml:18: key 'factories.pour.count'"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(small, "kinetic_energy: 1 nJ", "kinetic_energy: 1 nN")).find("expected an energy"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(small, "  - name: fill\n    until: {factories_done: true, max_time: 0.1 s}",
                              "  - name: fill\n    until: {factories_done: true}"))
                .find("every stage needs a time limit"),
            std::string::npos);
}

class ScenarioRun : public TempDirTest {
 protected:
  // Runs the scenario into path("out"), quietly.
  RunReport run(const Scenario& sc) {
    RunOptions o;
    o.out_dir = path("out");
    o.progress = false;
    o.overwrite = true;  // (a test runs several scenarios in turn)
    return run_scenario(sc, o);
  }
  // Runs the scenario into path(dir), stopped halfway through the second stage of the whole
  // run `whole` (as Ctrl-C would) and continued from its checkpoint.
  RunReport stopped_in_the_settling_and_continued(const Scenario& sc, const std::string& dir, const RunReport& whole) {
    RunOptions o;
    o.out_dir = path(dir);
    o.progress = false;
    o.interrupt_at = 0.5 * (whole.stages[1].start + whole.stages[1].end);
    EXPECT_TRUE(run_scenario(sc, o).interrupted);
    o.interrupt_at = std::numeric_limits<double>::infinity();
    return resume_scenario(o);
  }
};

TEST_F(ScenarioRun, ReadsAFactorySurfaceFromAnStlNextToTheScenario) {
  io::write_stl(path("sheet.stl"), square_mesh(20.0, 2));  // 20 mm, in mm
  const std::string text = replaced(small, "    region: {shape: box, centre: 0 0 60 mm, size: 24 24 30 mm}\n",
                                    "    surface: {file: sheet.stl, unit: mm, position: 0 0 60 mm}\n");
  std::ofstream(path("s.yaml")) << text;
  const Scenario sc = read_scenario(load_scenario_document(path("s.yaml")));
  ASSERT_EQ(sc.factories[0].surface.size(), 8u);
  for (const Vec3& v : sc.factories[0].surface.vertices) {
    EXPECT_NEAR(v.z, 0.06, 1e-12);
    EXPECT_LE(std::abs(v.x), 0.01 + 1e-12);
  }
  EXPECT_NE(error_of(replaced(text, "file: sheet.stl", "file: nosuch.stl")).find("nosuch.stl"), std::string::npos);
}

TEST_F(ScenarioRun, FillsSettlesAndWritesItsOutputs) {
  const Scenario sc = read(small);
  const RunReport r = run(sc);
  ASSERT_EQ(r.stages.size(), 2u);
  EXPECT_EQ(r.stages[0].ended_by, "factories_done");
  EXPECT_EQ(r.stages[1].ended_by, "kinetic_energy");
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();

  std::ifstream in(path("out/summary.json"));
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["factories"][0]["count"], 300);
  EXPECT_EQ(j["stages"][1]["ended_by"], "kinetic_energy");
  const auto& end = j["final"];
  // All the grain is in the cup (30 mm wide) or spilled into the sink; the lower 10 mm of the
  // cup holds a random packing of spheres: packing fraction 0.5 to 0.64.
  const double in_cup = end["particles"].get<double>();
  EXPECT_EQ(in_cup + j["sinks"][0]["count"].get<double>(), 300.0);
  // One format: the summary the run returned, and the one read back, write the file's bytes.
  const std::string file = io::read_text_file(path("out/summary.json"));
  auto text = [](const RunSummary& s) {
    return nlohmann::ordered_json(s).dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  };
  EXPECT_EQ(text(r.summary), file);
  EXPECT_EQ(text(read_run_summary(path("out"))), file);
  EXPECT_EQ(r.summary.file, path("out/summary.json"));
  EXPECT_GT(end["cup.packing_fraction"].get<double>(), 0.45);
  EXPECT_LT(end["cup.packing_fraction"].get<double>(), 0.66);
  EXPECT_NEAR(end["cup.bulk_density"].get<double>(), end["cup.packing_fraction"].get<double>() * 1373.0, 1e-6);
  // the cup's bottom carries the weight of the grain in it (it is also its walls' sensor)
  // (a snapshot when the kinetic energy first falls below 1 nJ: over seeds 1 to 8 it is -2 %
  // to +8 % of the weight)
  const double weight = in_cup * sc.types[0].mass() * 9.81;
  EXPECT_NEAR(end["bottom.force"].get<double>(), weight, 0.1 * weight);
  EXPECT_GT(end["cup.coordination"].get<double>(), 3.0);
  EXPECT_EQ(end["lost_count"], 0.0);
  // every particle crossed the plane above the cup once, downwards
  EXPECT_NEAR(end["inflow.mass"].get<double>(), end["created_mass"].get<double>(), 1e-12);
  EXPECT_EQ(end["inflow.rate"].get<double>(), 0.0);  // nothing crossed in the last 50 ms
  // the heap's surface: every ring of the cup holds grain, below the highest point
  const auto& profile = j["stages"][1]["heap_profiles"]["surface"];
  ASSERT_EQ(profile["height_m"].size(), 5u);
  for (const auto& h : profile["height_m"]) {
    EXPECT_GT(h.get<double>(), 0.005);
    EXPECT_LE(h.get<double>(), end["surface.height"].get<double>());
  }

  const auto table = io::read_text_file(path("out/timeseries.csv"));
  std::istringstream lines(table);
  std::string header;
  std::getline(lines, header);
  EXPECT_EQ(header.rfind("stage,time,particles,kinetic_energy,", 0), 0u) << header;
  int rows = 0;
  for (std::string l; std::getline(lines, l);) {
    ++rows;
    EXPECT_EQ(std::count(l.begin(), l.end(), ','), std::count(header.begin(), header.end(), ',')) << l;
  }
  EXPECT_GE(rows, static_cast<int>(r.simulated_time / 0.01));
  // the units beside it, a row per column in the same order
  const std::string units = io::read_text_file(path("out/timeseries.units.csv"));
  std::string names = "stage";
  for (std::size_t pos = units.find("\n", units.find("stage,-")); pos + 1 < units.size();
       pos = units.find('\n', pos + 1)) {
    names += "," + units.substr(pos + 1, units.find(',', pos + 1) - pos - 1);
  }
  EXPECT_EQ(names, header);
  EXPECT_EQ(units.rfind("column,unit\nstage,-\ntime,s\nparticles,-\nkinetic_energy,J\n", 0), 0u) << units;
  EXPECT_NE(units.find("\ncup.bulk_density,kg/m3\n"), std::string::npos) << units;
  EXPECT_TRUE(std::filesystem::exists(path("out/frames/particles.pvd")));
  // every sensor kind (region, part, flow, heap) reads as many values as its columns declare
  EXPECT_EQ(r.summary.final_values.size(), sc.value_names().size());
  EXPECT_EQ(r.summary.final_values.size(), sc.value_columns().size());
}

TEST_F(ScenarioRun, StagesEndOnTimeAndMoveParts) {
  // The cup is lifted 5 mm in the second stage, which ends on its time.
  const std::string text = replaced(small, "  - name: settle\n", R"(  - name: lift
    motions:
      cup: [{translate: 0 0 50 mm/s, end: 0.1 s}]
    until: {time: 0.1 s}
  - name: settle
)");
  const Scenario sc = read(text, {parse_override("parameters.count=20")});
  const RunReport r = run(sc);
  ASSERT_EQ(r.stages.size(), 3u);
  EXPECT_EQ(r.stages[1].ended_by, "time");
  EXPECT_NEAR(r.stages[1].end - r.stages[1].start, 0.1, sc.settings.dt);
  double z = 0.0;
  for (const auto& [name, v] : r.stages[1].values) z = name == "bottom.position_z" ? v : z;
  EXPECT_NEAR(z, 0.005, 0.05 * sc.settings.dt + 1e-12);  // (the stage may end within a step of it)
}

TEST_F(ScenarioRun, StagesEndOnAStableValueAndOnAHeldServo) {
  // Settle until the cup's mass is stable, then a lid (disabled until then) is lowered onto
  // the grain by a servo to 0.5 N, until it has held the force for 10 ms. (The gain is
  // chosen for stability: gain x contact stiffness x dt well below 1.)
  std::string text = replaced(small, "parts:\n", R"(parts:
  lid:
    shape: disc
    radius: 14 mm
    position: 0 0 24 mm
    material: steel
    enabled: false
)");
  text = replaced(text, "    until: {kinetic_energy: 1 nJ, min_time: 20 ms, max_time: 0.3 s}\n",
                  R"(    until: {stable: {value: cup.mass, tolerance: 0.1%, window: 30 ms}, max_time: 0.4 s}
  - name: press
    enable: [lid]
    motions:
      lid: [{servo: {axis: 0 0 -1, force: 0.5 N, gain: 0.02, max_speed: 0.05 m/s, tolerance: 5%}}]
    until: {servo_held: {part: lid, hold: 10 ms}, max_time: 0.8 s}
)");
  const Scenario sc = read(text);
  const RunReport r = run(sc);
  ASSERT_EQ(r.stages.size(), 3u);
  EXPECT_EQ(r.stages[1].ended_by, "stable");
  EXPECT_GE(r.stages[1].end - r.stages[1].start, 0.03);
  EXPECT_EQ(r.stages[2].ended_by, "servo_held");
}

TEST_F(ScenarioRun, StagesEndWhenAValueIsReachedAndResultsAreComputed) {
  // After the settling a lid comes down at constant speed until the grain pushes it up with
  // 0.3 N; a region follows the lid (its volume is the sample's), another is weighed against
  // a volume of its own, a flap turns by 90 degrees, and the results combine stage values.
  std::string text = replaced(small, "parts:\n", R"(parts:
  lid: {shape: disc, radius: 14 mm, position: 0 0 30 mm, material: steel, enabled: false}
  flap:
    shape: plate
    length: 10 mm
    width: 10 mm
    position: 30 30 100 mm
    material: steel
    motion: [{rotate: {axis: 1 0 0, point: 30 30 100 mm, speed: 10 rad/s, angle: 90 deg}}]
)");
  text = replaced(text, "sensors:\n", R"(sensors:
  sample: {kind: region, region: {shape: cylinder, radius: 15 mm, height: 40 mm}, top: lid}
  heaped: {kind: region, region: {shape: cylinder, radius: 15 mm, height: 60 mm}, volume: 10 cm3}
  push: {kind: part, part: lid, axis: 0 0 1}
  turn: {kind: part, part: flap}
)");
  text = replaced(text, "outputs:\n", R"(  - name: press
    enable: [lid]
    motions:
      lid: [{translate: 0 0 -50 mm/s}]
    until: {reached: {value: push.force, above: 0.3 N}, max_time: 0.5 s}
  - name: extra
    enabled: false
    until: {time: 1 s}
results:
  skipped: extra.duration
  stop_force: press.push.force
  heaped_density: settle.heaped.mass / (10 cm3)
  press_time: press.duration
  sample_density: press.sample.mass / press.sample.volume
  flap_angle: settle.turn.angle
  flap_sine: sin(settle.turn.angle)
outputs:
)");
  const Scenario sc = read(text, {parse_override("parameters.count=120")});
  const RunReport r = run(sc);
  ASSERT_EQ(r.stages.size(), 3u);
  EXPECT_EQ(r.stages[2].ended_by, "reached");
  std::map<std::string, double> settle, press;
  for (const auto& [name, v] : r.stages[1].values) settle[name] = v;
  for (const auto& [name, v] : r.stages[2].values) press[name] = v;
  EXPECT_GE(press["push.force"], 0.3);
  EXPECT_NEAR(press["sample.volume"], std::numbers::pi * 0.015 * 0.015 * press["push.position_z"], 1e-12);
  EXPECT_LT(press["push.position_z"], 0.03);
  EXPECT_NEAR(settle["heaped.bulk_density"], settle["heaped.mass"] / 10e-6, 1e-9);
  EXPECT_NEAR(settle["turn.angle"], 90.0, 1e-6);
  EXPECT_NEAR(settle["push.angle"], 0.0, 1e-9);

  std::ifstream in(path("out/summary.json"));
  const auto j = nlohmann::json::parse(in);
  const auto& res = j["results"];
  EXPECT_EQ(res["stop_force"]["value"].get<double>(), press["push.force"]);
  EXPECT_EQ(res["stop_force"]["unit"], "N");
  EXPECT_NEAR(res["heaped_density"]["value"].get<double>(), settle["heaped.bulk_density"], 1e-9);
  EXPECT_EQ(res["heaped_density"]["unit"], "kg/m3");
  EXPECT_NEAR(res["press_time"]["value"].get<double>(), r.stages[2].end - r.stages[2].start, 1e-15);
  EXPECT_EQ(res["press_time"]["unit"], "s");
  EXPECT_NEAR(res["sample_density"]["value"].get<double>(), press["sample.bulk_density"], 1e-9);
  // angles are read in degrees, computed with in radians and written in degrees
  EXPECT_NEAR(res["flap_angle"]["value"].get<double>(), 90.0, 1e-6);
  EXPECT_EQ(res["flap_angle"]["unit"], "deg");
  EXPECT_NEAR(res["flap_sine"]["value"].get<double>(), 1.0, 1e-9);
  EXPECT_EQ(res["flap_sine"]["unit"], "");
  // a skipped stage does not run: its result is null, without a warning
  EXPECT_TRUE(res["skipped"].is_null());
  for (const auto& w : j["warnings"]) EXPECT_EQ(w.get<std::string>().find("skipped"), std::string::npos) << w;
  // the summary reads back as it was written (scenario/run_summary.hpp)
  const RunSummary back = read_run_summary(path("out"));
  EXPECT_EQ(back.scenario_name(), "s");
  EXPECT_EQ(back.parameter("count"), "120");
  EXPECT_EQ(back.parameter("nothing"), std::nullopt);
  EXPECT_FALSE(back.interrupted);
  ASSERT_EQ(back.stages.size(), r.stages.size());
  for (std::size_t i = 0; i < r.stages.size(); ++i) {
    const StageReport &a = r.stages[i], &b = back.stages[i];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.ended_by, b.ended_by);
    EXPECT_EQ(a.end, b.end);
    ASSERT_EQ(a.values.size(), b.values.size());
    for (std::size_t k = 0; k < a.values.size(); ++k) {
      EXPECT_EQ(a.values[k].first, b.values[k].first);
      if (std::isfinite(a.values[k].second))
        EXPECT_EQ(a.values[k].second, b.values[k].second) << a.values[k].first;
      else
        EXPECT_TRUE(std::isnan(b.values[k].second)) << a.values[k].first;
    }
    ASSERT_EQ(a.profiles.size(), b.profiles.size());
    for (std::size_t k = 0; k < a.profiles.size(); ++k) EXPECT_EQ(a.profiles[k].radius, b.profiles[k].radius);
  }
  ASSERT_NE(back.result("stop_force"), nullptr);
  EXPECT_EQ(back.result("stop_force")->value, press["push.force"]);
  EXPECT_EQ(back.result("stop_force")->unit, "N");
  EXPECT_EQ(back.result("flap_angle")->unit, "deg");
  EXPECT_FALSE(back.result("skipped")->value.has_value());
  ASSERT_EQ(back.factories.size(), 1u);
  EXPECT_EQ(back.factories[0].count, 120u);
  EXPECT_EQ(back.stage("press"), &back.stages[2]);

  // a result that cannot be computed is null, with a warning
  const Scenario zero = read(replaced(text, "  stop_force: press.push.force\n",
                                      "  stop_force: press.push.force\n  per_lost: 1 / settle.lost_mass\n"),
                             {parse_override("parameters.count=120")});
  run(zero);
  std::ifstream in2(path("out/summary.json"));
  const auto j2 = nlohmann::json::parse(in2);
  EXPECT_TRUE(j2["results"]["per_lost"].is_null());
  bool warned = false;
  for (const auto& w : j2["warnings"]) warned = warned || w.get<std::string>().find("per_lost") != std::string::npos;
  EXPECT_TRUE(warned) << j2["warnings"];

  // bad results and conditions are caught before the run
  EXPECT_NE(error_of(replaced(text, "press.push.force\n", "pres.push.force\n"))
                .find("unknown stage 'pres' (did you mean 'press'?)"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(text, "settle.heaped.mass / (10 cm3)", "settle.heaped.mass + 1 s"))
                .find("cannot add a mass and a time"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(text, "above: 0.3 N", "above: 0.3 kPa")).find("expected a force"), std::string::npos);
  EXPECT_NE(error_of(replaced(text, "above: 0.3 N", "above: 0.3 N, below: 1 N")).find("above"), std::string::npos);
  EXPECT_NE(error_of(replaced(text, "top: lid", "top: lod")).find("did you mean 'lid'"), std::string::npos);
  std::string none = replaced(text, "  - name: fill\n", "  - name: fill\n    enabled: false\n");
  none = replaced(replaced(none, "  - name: settle\n", "  - name: settle\n    enabled: false\n"), "  - name: press\n",
                  "  - name: press\n    enabled: false\n");
  EXPECT_NE(error_of(none).find("at least one stage that is not skipped"), std::string::npos);
}

TEST_F(ScenarioRun, AStageCanTakeAPartAway) {
  // With the cup disabled after the fill, all the grain falls into the sink under it.
  const std::string text = replaced(small, "  - name: settle\n", R"(  - name: drop
    disable: [cup]
    until: {time: 0.15 s}
  - name: settle
)");
  const Scenario sc = read(text, {parse_override("parameters.count=40")});
  const RunReport r = run(sc);
  double left = -1.0;
  for (const auto& [name, v] : r.stages[1].values) left = name == "particles" ? v : left;
  EXPECT_EQ(left, 0.0);
  // the frames draw the cup while it is there, and not after: two geometry files (one is
  // written only when the parts change), named by every frame between them
  int files = 0;
  while (std::filesystem::exists(path(fmt::format("out/frames/geometry_{:05d}.vtu", files)))) ++files;
  ASSERT_EQ(files, 2);
  EXPECT_EQ(io::read_text_file(path("out/frames/geometry_00000.vtu")).find("NumberOfCells=\"0\""), std::string::npos);
  EXPECT_NE(io::read_text_file(path("out/frames/geometry_00001.vtu")).find("NumberOfCells=\"0\""), std::string::npos);
  const std::string pvd = io::read_text_file(path("out/frames/geometry.pvd"));
  auto count = [](const std::string& in, const std::string& what) {
    int n = 0;
    for (std::size_t pos = in.find(what); pos != std::string::npos; pos = in.find(what, pos + 1)) ++n;
    return n;
  };
  EXPECT_GE(count(pvd, "<DataSet "), 4);
  EXPECT_EQ(count(pvd, "<DataSet "), count(io::read_text_file(path("out/frames/particles.pvd")), "<DataSet "));
  EXPECT_EQ(count(pvd, "file=\"geometry_00000.vtu\"") + count(pvd, "file=\"geometry_00001.vtu\""),
            count(pvd, "<DataSet "));
}

TEST_F(ScenarioRun, FramesHoldTheContactsAskedFor) {
  // ASCII frames with every optional field, of 5-sphere clumps: the contact lines and the
  // per-element counts agree (each line counts once at either end), each line joins two
  // elements of two bodies that overlap, and every such pair has its line.
  const std::string text = replaced(
      replaced(
          small, "  frames: {interval: 50 ms}\n",
          "  frames: {interval: 50 ms, format: ascii, fields: [angular_velocity, force, coordination, contacts]}\n"),
      "grain: {diameter: 3.64 mm, material: wheat}", "grain: {template: large_5s, material: wheat}");
  run(read(text, {parse_override("parameters.count=120")}));
  const std::string pvd = io::read_text_file(path("out/frames/contacts.pvd"));
  const std::size_t at = pvd.rfind("file=\"") + 6;
  const std::string last = pvd.substr(at, pvd.find('"', at) - at);
  const std::string lines = io::read_text_file(path("out/frames/" + last));
  const std::string particles = io::read_text_file(path("out/frames/" + std::string(last).replace(0, 8, "particles")));
  auto values = [](const std::string& xml, const std::string& name) {
    const std::size_t tag = xml.find("Name=\"" + name + "\"");
    EXPECT_NE(tag, std::string::npos) << name;
    const std::size_t open = xml.find('>', tag) + 1;
    std::istringstream in(xml.substr(open, xml.find("</DataArray>", open) - open));
    std::vector<double> v;
    for (double x; in >> x;) v.push_back(x);
    return v;
  };
  const std::vector<double> counts = values(particles, "contacts"), radius = values(particles, "radius_m");
  const std::vector<double> connectivity = values(lines, "connectivity"), overlap = values(lines, "overlap_m");
  const std::vector<double> force = values(lines, "normal_force_elastic_N");
  ASSERT_GT(overlap.size(), 50u);
  EXPECT_EQ(connectivity.size(), 2 * overlap.size());
  EXPECT_EQ(std::accumulate(counts.begin(), counts.end(), 0.0), 2.0 * static_cast<double>(overlap.size()));
  for (std::size_t c = 0; c < overlap.size(); ++c) {
    EXPECT_GT(overlap[c], 0.0);
    EXPECT_LT(overlap[c], 0.05 * radius[static_cast<std::size_t>(connectivity[2 * c])]);
    EXPECT_GT(force[c], 0.0);
  }
  // against brute force over the frame's own positions: every pair of bodies that overlaps
  const std::size_t at_points = particles.find('>', particles.find("<DataArray", particles.find("<Points>"))) + 1;
  std::istringstream xyz(particles.substr(at_points, particles.find("</DataArray>", at_points) - at_points));
  std::vector<double> x;
  for (double v; xyz >> v;) x.push_back(v);
  const std::vector<double> body = values(particles, "body_id");
  ASSERT_EQ(x.size(), 3 * radius.size());
  std::size_t brute = 0;
  for (std::size_t i = 0; i < radius.size(); ++i) {
    for (std::size_t j = i + 1; j < radius.size(); ++j) {
      const double d = std::hypot(x[3 * i] - x[3 * j], x[3 * i + 1] - x[3 * j + 1], x[3 * i + 2] - x[3 * j + 2]);
      brute += body[i] != body[j] && d < radius[i] + radius[j] ? 1 : 0;
    }
  }
  EXPECT_EQ(brute, overlap.size());
  EXPECT_EQ(values(particles, "angular_velocity_rad_s").size(), 3 * radius.size());
  EXPECT_EQ(values(particles, "force_N").size(), 3 * radius.size());
  EXPECT_NE(particles.find("<DataArray type=\"UInt32\" Name=\"body_id\""), std::string::npos);
  EXPECT_NE(particles.find("Name=\"type_names\" NumberOfTuples=\"1\""), std::string::npos);
}

TEST(ScenarioFrames, FieldsAndFormatAreCheckedWords) {
  auto error_of = [](const std::string& frames) {
    try {
      read(replaced(small, "  frames: {interval: 50 ms}\n", "  frames: " + frames + "\n"));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string unknown = error_of("{interval: 50 ms, fields: [forces]}");
  EXPECT_NE(unknown.find("did you mean 'force'"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("s.yaml:"), std::string::npos) << unknown;
  EXPECT_NE(error_of("{interval: 50 ms, format: vtk}").find("binary"), std::string::npos);
  EXPECT_NE(error_of("{interval: 50 ms, fields: force}").find("expected a list"), std::string::npos);
  const Scenario sc = read(replaced(small, "  frames: {interval: 50 ms}\n",
                                    "  frames: {interval: 50 ms, format: ascii, fields: [contacts]}\n"));
  EXPECT_EQ(sc.outputs.frames.encoding, io::VtuEncoding::ascii);
  EXPECT_TRUE(sc.outputs.frames.contacts);
  EXPECT_FALSE(sc.outputs.frames.force);
  EXPECT_EQ(read(small).outputs.frames.encoding, io::VtuEncoding::zlib);
}

TEST_F(ScenarioRun, SaysHowManyKernelsLeftTheDomainAndInWhichStage) {
  // The cup is taken away after the fill with the sink off: the grain, still falling from the
  // factory, passes through the domain's floor in the 'drop' stage, none before. The warning
  // counts them, gives their mass (a 3.64 mm wheat sphere: 34.7 mg) and the stage, so that
  // kernels lost after a measurement are told from those lost before it.
  const std::string dropped = replaced(replaced(small, "  - name: settle\n", R"(  - name: drop
    disable: [cup]
    until: {time: 0.15 s}
  - name: settle
)"),
                                       "size: 80 80 20 mm}}", "size: 80 80 20 mm}, enabled: false}");
  // (every kernel leaves: the lost guard, which stops a run at half, is told to let them)
  const std::string all_lost =
      replaced(dropped, "  time_step: 0.2 rayleigh\n", "  time_step: 0.2 rayleigh\n  guards: {max_lost: 100%}\n");
  const double kernel_g = 1e3 * 1373.0 * std::numbers::pi / 6.0 * std::pow(3.64e-3, 3);
  auto lost_warnings = [](const RunReport& r) {
    std::vector<std::string> out;
    for (const std::string& w : r.warnings)
      if (w.find("left the domain") != std::string::npos) out.push_back(w);
    return out;
  };
  const RunReport many = run(read(all_lost, {parse_override("parameters.count=40")}));
  ASSERT_EQ(lost_warnings(many).size(), 1u);
  EXPECT_EQ(lost_warnings(many)[0],
            fmt::format("40 particles ({:.3g} g) left the domain, all in stage 'drop'", 40 * kernel_g));
  const RunReport one = run(read(all_lost, {parse_override("parameters.count=1")}));
  ASSERT_EQ(lost_warnings(one).size(), 1u);
  EXPECT_EQ(lost_warnings(one)[0], fmt::format("1 particle ({:.3g} g) left the domain, in stage 'drop'", kernel_g));
  // 150 kernels, made over a taller column, leave between about 95 and 120 ms after the cup
  // goes (none by 90 ms, all by 120), so a stage boundary at 105 ms splits them (58 and 92),
  // and the warning names both stages with their counts.
  const RunReport split = run(read(replaced(all_lost, "until: {time: 0.15 s}\n", R"(until: {time: 105 ms}
  - name: fall
    until: {time: 65 ms}
)"),
                                   {parse_override("parameters.count=150")}));
  ASSERT_EQ(lost_warnings(split).size(), 1u);
  const std::string w = lost_warnings(split)[0];
  int in_drop = 0, in_fall = 0;
  ASSERT_EQ(std::sscanf(w.c_str() + w.find(':'), ": %d in 'drop', %d in 'fall'", &in_drop, &in_fall), 2) << w;
  EXPECT_GT(in_drop, 0) << w;
  EXPECT_GT(in_fall, 0) << w;
  EXPECT_EQ(in_drop + in_fall, 150) << w;
  EXPECT_EQ(w.rfind("150 particles (", 0), 0u) << w;
  // With the sink on, none is lost and there is no warning.
  EXPECT_TRUE(
      lost_warnings(run(read(replaced(all_lost, ", enabled: false}", "}"), {parse_override("parameters.count=40")})))
          .empty());
}

TEST_F(ScenarioRun, AStrikerOnAServoRidesOverKernelsInsteadOfCrushingThem) {
  // Kernels on a cup's bottom stand 1.14 mm above its rim. A bar whose lower face is at the
  // rim pushes them to the far wall, where nothing can give: a bar driven along the rim
  // presses them deep (the bottom and the wall hold them); pressed onto the rim by a servo
  // with 0.5 N, it rises over them and comes back down to the rim. How deep 25 kernels jam
  // is chaotic (0.11 to 0.56 radii as the skin or the seed changes the order of the sums),
  // so three seeds are run and the driven bar is judged by their median.
  const std::string text = R"(simulation:
  time_step: 0.2 rayleigh
  domain: {min: -40 -40 -10 mm, max: 40 40 40 mm}
  seed: SEED
)" + wheat_and_steel + R"(parts:
  cup: {shape: cylinder, radius: 15 mm, height: 2.5 mm, side: inside, cap_bottom: true, material: steel}
  striker: {shape: box, size: 70 10 10 mm, side: outside, position: 0 -25 7.5 mm, material: steel, enabled: false}
factories:
  pour: {region: {shape: box, centre: 0 0 8 mm, size: 24 24 6 mm}, count: 25, types: grain}
sensors:
  bar: {kind: part, part: striker}
stages:
  - name: fill
    until: {factories_done: true, max_time: 0.1 s}
  - name: settle
    until: {kinetic_energy: 1 nJ, min_time: 20 ms, max_time: 0.5 s}
  - name: strike
    enable: [striker]
    motions:
      striker: [{translate: 0 0.2 0 m/s}, SERVO]
    until: {time: 0.25 s}
outputs:
  timeseries: {interval: 1 ms, values: [time, particles, max_overlap_ratio, bar.position_z]}
)";
  // the largest overlap over the smaller radius in the strike, and the bar's lowest, highest
  // and last height [m]
  auto strike = [&](const std::string& servo, int seed, const std::string& dir) {
    RunOptions o;
    o.out_dir = path(dir);
    o.progress = false;
    run_scenario(read(replaced(replaced(text, "SERVO", servo), "SEED", std::to_string(seed))), o);
    std::istringstream rows(io::read_text_file(path(dir + "/timeseries.csv")));
    std::string row;
    std::getline(rows, row);
    double deepest = 0.0, low = 1.0, top = 0.0, last = 0.0;
    while (std::getline(rows, row)) {
      double t = 0.0, n = 0.0, overlap = 0.0, z = 0.0;
      if (row.rfind("strike,", 0) != 0) continue;
      EXPECT_EQ(std::sscanf(row.c_str(), "strike,%lf,%lf,%lf,%lf", &t, &n, &overlap, &z), 4) << row;
      deepest = std::max(deepest, overlap), low = std::min(low, z), top = std::max(top, z), last = z;
    }
    return std::array{deepest, low, top, last};
  };
  const std::string servo = "{servo: {axis: 0 0 -1, force: 0.5 N, max_speed: 0.5 m/s, gain: 0.5, stop: 0 0 7.5 mm}}";
  std::vector<double> driven_deepest;
  int back_on_the_stop = 0;
  for (int seed = 1; seed <= 3; ++seed) {
    const auto driven = strike("{translate: 0 0 0 m/s}", seed, "driven" + std::to_string(seed));
    EXPECT_EQ(driven[1], 0.0075);
    EXPECT_EQ(driven[2], 0.0075);
    driven_deepest.push_back(driven[0]);
    const auto riding = strike(servo, seed, "riding" + std::to_string(seed));
    EXPECT_LT(riding[0], 0.1) << seed;              // (about 7 %: the kernels caught under it carry 0.5 N and the push)
    EXPECT_EQ(riding[1], 0.0075) << seed;           // never below its stop
    EXPECT_GT(riding[2], 0.0075 + 0.5e-3) << seed;  // it rose over the kernels
    back_on_the_stop += std::abs(riding[3] - 0.0075) < 1e-9 ? 1 : 0;
  }
  std::sort(driven_deepest.begin(), driven_deepest.end());
  EXPECT_GT(driven_deepest[1], 0.3);  // (0.17, 0.45, 0.55)
  // and came back down onto its stop (in one seed of three a kernel pushed onto the far rim
  // still holds it up when the stage ends)
  EXPECT_GE(back_on_the_stop, 2);
}

TEST_F(ScenarioRun, WarnsOnceOfDeepOverlapsAcrossACheckpoint) {
  // docs/physics.md section 3: a warning when the largest overlap exceeds a few percent of the
  // radius. Kernels 1000 times softer than wheat sink into each other under their own weight
  // in the cup, about 7 % at rest (500 times: 4.5 %; the default ones,
  // FillsSettlesAndWritesItsOutputs, stay far below: no warning). One warning names the
  // stages, their peaks and the deepest.
  const Scenario sc = read(replaced(small, "shear_modulus: 22.4 MPa", "shear_modulus: 22.4 kPa"),
                           {parse_override("parameters.count=150")});
  RunOptions whole;
  whole.out_dir = path("whole");
  whole.progress = false;
  const RunReport a = run_scenario(sc, whole);
  ASSERT_FALSE(a.interrupted);
  std::vector<std::string> overlaps;
  for (const std::string& w : a.warnings)
    if (w.find("the largest overlap passed 5 % of the smaller radius in ") != std::string::npos) overlaps.push_back(w);
  ASSERT_EQ(overlaps.size(), 1u);
  EXPECT_NE(overlaps[0].find("'settle' ("), std::string::npos) << overlaps[0];
  // They end on it too: what the settling measures includes them interpenetrating.
  EXPECT_NE(overlaps[0].find("and at the end of 'settle' ("), std::string::npos) << overlaps[0];
  EXPECT_NE(overlaps[0].find("it still was: what"), std::string::npos) << overlaps[0];
  // Stopped in the settling and continued: the stage's deepest overlap before the checkpoint
  // still counts, so the warnings are the same, as are the unbalanced force ratios.
  const RunReport b = stopped_in_the_settling_and_continued(sc, "cut", a);
  EXPECT_EQ(b.warnings, a.warnings);
  EXPECT_EQ(io::read_text_file(path("whole/timeseries.csv")), io::read_text_file(path("cut/timeseries.csv")));
}

TEST_F(ScenarioRun, SaysWhenDeepOverlapsWereImpactsOnly) {
  // Wheat thrown into the steel cup at 6 m/s: the impacts pass 5 % of the radius (Hertz:
  // about 10 % for a kernel on steel; 13.5 % here, in the settling, when they land), the
  // packing at rest is far below it (0.1 %). The warning says so, with the largest overlap
  // at the stage's end (the stage's own value), instead of calling the packing
  // interpenetrating.
  const Scenario sc =
      read(replaced(small, "velocity: 0 0 -0.3 m/s", "velocity: 0 0 -6 m/s"), {parse_override("parameters.count=150")});
  const RunReport r = run(sc);
  double settle_end = -1.0;
  for (const auto& [name, v] : r.stages.back().values) settle_end = name == "max_overlap_ratio" ? v : settle_end;
  ASSERT_GE(settle_end, 0.0);
  EXPECT_LT(settle_end, 0.05);
  std::vector<std::string> overlaps;
  for (const std::string& w : r.warnings)
    if (w.find("the largest overlap passed 5 % of the smaller radius in ") != std::string::npos) overlaps.push_back(w);
  ASSERT_EQ(overlaps.size(), 1u);
  EXPECT_NE(overlaps[0].find("in stage 'settle' ("), std::string::npos) << overlaps[0];
  EXPECT_NE(overlaps[0].find(fmt::format("but at the stage's end it was {:.1f} %, so the packing it ends on is not "
                                         "interpenetrating",
                                         100.0 * settle_end)),
            std::string::npos)
      << overlaps[0];
  EXPECT_EQ(overlaps[0].find("still"), std::string::npos) << overlaps[0];
}

TEST_F(ScenarioRun, ContinuesBitForBitFromACheckpoint) {
  // The same run whole, and stopped twice (as by Ctrl-C: in the fill, then in the settling)
  // and continued from its checkpoint each time: the same final state to the bit, the same
  // time series and frames.
  const Scenario sc = read(small, {parse_override("parameters.count=150")});
  RunOptions whole;
  whole.out_dir = path("whole");
  whole.progress = false;
  const RunReport a = run_scenario(sc, whole);
  ASSERT_FALSE(a.interrupted);

  RunOptions cut = whole;
  cut.out_dir = path("cut");
  cut.interrupt_at = 0.02;
  EXPECT_TRUE(run_scenario(sc, cut).interrupted);
  EXPECT_TRUE(std::filesystem::exists(path("cut/checkpoint.bin")));
  cut.interrupt_at = 0.09;
  EXPECT_TRUE(resume_scenario(cut).interrupted);
  cut.interrupt_at = std::numeric_limits<double>::infinity();
  const RunReport b = resume_scenario(cut);
  ASSERT_FALSE(b.interrupted);

  auto summary = [&](const std::string& dir) {
    std::ifstream in(path(dir + "/summary.json"));
    return nlohmann::json::parse(in);
  };
  const auto ja = summary("whole"), jb = summary("cut");
  EXPECT_EQ(ja["final_state_hash"], jb["final_state_hash"]);
  EXPECT_EQ(ja["final"], jb["final"]);
  EXPECT_EQ(ja["stages"], jb["stages"]);
  EXPECT_EQ(ja["factories"], jb["factories"]);
  EXPECT_EQ(ja["steps"], jb["steps"]);
  EXPECT_EQ(ja["warnings"], jb["warnings"]);
  // one build ran every sitting: the summary names it once
  EXPECT_EQ(ja["engine"], jb["engine"]);
  EXPECT_EQ(jb["engine"]["builds"], nlohmann::json::array({build_description()}));
  EXPECT_EQ(io::read_text_file(path("whole/timeseries.csv")), io::read_text_file(path("cut/timeseries.csv")));
  EXPECT_EQ(io::read_text_file(path("whole/frames/particles.pvd")),
            io::read_text_file(path("cut/frames/particles.pvd")));
  // a damaged checkpoint is an error, not a crash
  const std::string bytes = io::read_text_file(path("cut/checkpoint.bin"));
  std::ofstream(path("cut/checkpoint.bin"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  EXPECT_THROW(resume_scenario(cut), InputError);
}

TEST_F(ScenarioRun, OutputsNeverChangeWhatIsSimulated) {
  // Rows every 1 ms instead of 10, frames every 2.5 ms or none: the same run to the bit. (Steps
  // that stopped at each output's time moved the checks, at which factories, sinks and stage
  // conditions act, after every stage's start.)
  // (poured at a rate: the factory acts at the checks)
  const std::string base = replaced(replaced(small, "  count: 300", "  count: 150"), "    count: ${count}\n",
                                    "    count: ${count}\n    rate: 0.1 kg/s\n");
  auto final_state = [&](const std::string& text, const std::string& dir) {
    RunOptions o;
    o.out_dir = path(dir);
    o.progress = false;
    run_scenario(read(text), o);
    std::ifstream in(path(dir + "/summary.json"));
    const auto j = nlohmann::json::parse(in);
    return std::make_pair(j["final_state_hash"], j["stages"]);
  };
  const auto plain = final_state(base, "plain");
  const auto dense =
      final_state(replaced(replaced(base, "timeseries: {interval: 10 ms}", "timeseries: {interval: 1 ms}"),
                           "frames: {interval: 50 ms}", "frames: {interval: 2.5 ms}"),
                  "dense");
  const auto no_frames = final_state(replaced(base, "  frames: {interval: 50 ms}\n", ""), "no_frames");
  EXPECT_EQ(plain, dense);
  EXPECT_EQ(plain, no_frames);
  // Outputs are written at checks: one more often than they could not be kept.
  EXPECT_NE(error_of(replaced(base, "timeseries: {interval: 10 ms}", "timeseries: {interval: 0.5 ms}"))
                .find("key 'outputs.timeseries.interval': expected an interval of at least "
                      "simulation.check_interval (1 ms), got 0.5 ms"),
            std::string::npos)
      << error_of(replaced(base, "timeseries: {interval: 10 ms}", "timeseries: {interval: 0.5 ms}"));
  EXPECT_NE(error_of(replaced(base, "frames: {interval: 50 ms}", "frames: {interval: 0.2 ms}"))
                .find("outputs.frames.interval"),
            std::string::npos);
  EXPECT_EQ(error_of(replaced(base, "timeseries: {interval: 10 ms}", "timeseries: {interval: 0.5 ms}"),
                     {parse_override("simulation.check_interval=0.5ms")}),
            "(no error)");
}

TEST_F(ScenarioRun, AGuardStopsARunGoneWrongWithACheckpointAndAFailedSummary) {
  // A plane that appears inside the settled grain (a part enabled in the wrong place): the
  // overlaps pass 100 % of a radius at once, the run stops in that stage with its checkpoint
  // and a summary marked failed, and it cannot be continued.
  const std::string text =
      replaced(replaced(small, "  cup: {shape: cylinder",
                        "  slab: {shape: plane, position: 0 0 3 mm, normal: 0 0 1, "
                        "material: steel, enabled: false}\n  cup: {shape: cylinder"),
               "outputs:\n", "  - name: squash\n    enable: [slab]\n    until: {time: 20 ms}\noutputs:\n");
  const Scenario sc = read(text, {parse_override("parameters.count=60")});
  const RunReport r = run(sc);
  EXPECT_FALSE(r.interrupted);
  EXPECT_NE(r.failed.find("in stage 'squash': "), std::string::npos) << r.failed;
  ASSERT_EQ(r.stages.size(), 2u);  // fill and settle finished; squash did not
  std::ifstream in(path("out/summary.json"));
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["failed"], r.failed);
  EXPECT_TRUE(j["results"].is_object());
  RunOptions o;
  o.out_dir = path("out");
  o.progress = false;
  EXPECT_NE(thrown_by([&] { resume_scenario(o); }).find("this run failed at t = "), std::string::npos);

  // Every particle leaving through a missing floor: the lost guard at half of them.
  const std::string floorless = replaced(replaced(small, "cap_bottom: true", "cap_bottom: false"),
                                         "size: 80 80 20 mm}}", "size: 80 80 20 mm}, enabled: false}");
  const RunReport lost = run(read(floorless, {parse_override("parameters.count=40")}));
  EXPECT_NE(lost.failed.find("of the 40 particles created have left the domain, more than the guard's 50 %"),
            std::string::npos)
      << lost.failed;
  // and the same run with the guard at 100 % goes to its end
  const RunReport allowed = run(read(
      replaced(floorless, "  time_step: 0.2 rayleigh\n", "  time_step: 0.2 rayleigh\n  guards: {max_lost: 100%}\n"),
      {parse_override("parameters.count=40")}));
  EXPECT_TRUE(allowed.failed.empty()) << allowed.failed;
}

TEST_F(ScenarioRun, RefusesAnOutputFolderOfAnotherRunUnlessToldToReplaceIt) {
  const Scenario sc =
      read(small, {parse_override("parameters.count=20"), parse_override("stages.1.until.max_time=30ms")});
  RunOptions o;
  o.out_dir = path("out");
  o.progress = false;
  run_scenario(sc, o);
  std::ofstream(path("out/frames/stale.vtu")) << "an old frame";
  EXPECT_NE(thrown_by([&] { run_scenario(sc, o); }).find("the folder holds another run (summary.json)"),
            std::string::npos);
  o.overwrite = true;
  run_scenario(sc, o);
  EXPECT_FALSE(std::filesystem::exists(path("out/frames/stale.vtu")));
  EXPECT_TRUE(std::filesystem::exists(path("out/summary.json")));
}

TEST_F(ScenarioRun, RefusesEveryDamagedCheckpointAndOneOfAnotherFormat) {
  // A checkpoint with a flipped bit anywhere, or cut anywhere, is a clear InputError: never a
  // crash, never a run that continues into different results.
  const Scenario sc = read(small, {parse_override("parameters.count=30")});
  RunOptions o;
  o.progress = false;
  o.out_dir = path("cut");
  o.interrupt_at = 0.02;
  ASSERT_TRUE(run_scenario(sc, o).interrupted);
  const std::string good = io::read_text_file(path("cut/checkpoint.bin"));
  o.interrupt_at = std::numeric_limits<double>::infinity();
  auto refused = [&](const std::string& bytes) {
    std::ofstream(path("cut/checkpoint.bin"), std::ios::binary | std::ios::trunc) << bytes;
    try {
      resume_scenario(o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(continued)");
  };
  std::mt19937_64 random(7);
  for (int k = 0; k < 40; ++k) {
    std::string flipped = good;
    const std::size_t at = random() % good.size();
    flipped[at] = static_cast<char>(flipped[at] ^ (1 << (random() % 8)));
    const std::string why = refused(flipped);
    EXPECT_TRUE(why.find("damaged checkpoint") != std::string::npos ||
                why.find("not a bushel checkpoint") != std::string::npos ||
                why.find("a checkpoint of format") != std::string::npos)
        << "bit flipped at byte " << at << ": " << why;
    const std::size_t cut = random() % good.size();
    EXPECT_NE(refused(good.substr(0, cut)).find("checkpoint"), std::string::npos) << "cut at " << cut;
  }
  EXPECT_NE(refused(good + "x").find("damaged checkpoint (it ends early"), std::string::npos);
  EXPECT_NE(refused(std::string(8, '\xff')).find("not a bushel checkpoint"), std::string::npos);
  std::string other = good;
  other[other.find("checkpoint 4") + 11] = '2';
  EXPECT_NE(refused(other).find("a checkpoint of format 2, written by bushel " + build_description()),
            std::string::npos)
      << refused(other);
  // the good one still continues
  std::ofstream(path("cut/checkpoint.bin"), std::ios::binary | std::ios::trunc) << good;
  EXPECT_FALSE(resume_scenario(o).interrupted);
}

TEST_F(ScenarioRun, NamesItsEngineAndSaysWhenAnotherBuildContinuedIt) {
  // Every summary names the build that produced it, so that results of different engine
  // versions can be told apart (include/bushel/core/build_info.hpp).
  const Scenario sc = read(small, {parse_override("parameters.count=60")});
  RunOptions o;
  o.out_dir = path("out");
  o.progress = false;
  o.interrupt_at = 0.02;
  ASSERT_TRUE(run_scenario(sc, o).interrupted);
  const auto engine = [&] {
    std::ifstream in(path("out/summary.json"));
    return nlohmann::json::parse(in)["engine"];
  };
  const BuildInfo& b = build_info();
  EXPECT_EQ(engine()["version"], std::string(b.version));
  EXPECT_EQ(engine()["commit"], std::string(b.commit));
  EXPECT_EQ(engine()["uncommitted_changes"], b.dirty);
  EXPECT_TRUE(b.commit == "unknown" ||
              (b.commit.size() == 40 && b.commit.find_first_not_of("0123456789abcdef") == std::string_view::npos))
      << b.commit;
  EXPECT_EQ(build_description(),
            fmt::format("{} (commit {}{})", b.version, b.commit.substr(0, 12), b.dirty ? ", uncommitted changes" : ""));

  // A checkpoint written by another build (its name in the run section rewritten, the
  // section's checksum made anew): the continued run says its results mix builds.
  std::string bytes = io::read_text_file(path("out/checkpoint.bin"));
  const std::string other(build_description().size(), 'X');
  const std::string name = std::string("\x03\0\0\0\0\0\0\0", 8) + "run";
  // (after the name: its version, length and checksum)
  const std::size_t head = bytes.find(name) + name.size() + sizeof(std::uint32_t);
  const std::size_t body = head + 2 * sizeof(std::uint64_t);
  std::uint64_t length = 0;
  std::memcpy(&length, bytes.data() + head, sizeof length);
  const std::size_t at = bytes.find(build_description(), body);
  ASSERT_LT(at, body + length);
  bytes.replace(at, other.size(), other);
  const std::uint64_t sum = io::checksum(std::string_view(bytes).substr(body, length));
  std::memcpy(bytes.data() + head + sizeof length, &sum, sizeof sum);
  std::ofstream(path("out/checkpoint.bin"), std::ios::binary | std::ios::trunc) << bytes;
  o.interrupt_at = std::numeric_limits<double>::infinity();
  const RunReport r = resume_scenario(o);
  ASSERT_FALSE(r.interrupted);
  EXPECT_EQ(engine()["builds"], nlohmann::json::array({other, build_description()}));
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings.back().find("continued from a checkpoint by another engine build"), std::string::npos)
      << r.warnings.back();
  // and `bushel report` reads the builds back
  EXPECT_EQ(read_run_summary(path("out")).engines.size(), 2u);
}

TEST_F(ScenarioRun, AStageRunsWithItsOwnTimeStep) {
  // The settling at a quarter of the fill's step (as compression.yaml presses at 0.05 of the
  // Rayleigh step after a fill at 0.2): the fill is the same run as without it, the settling
  // takes 4 times the steps per second simulated, and a run stopped in the settling goes on
  // at its step, not the scenario's.
  const std::vector<Override> n{parse_override("parameters.count=150")};
  const Scenario plain = read(small, n);
  const Scenario sc =
      read(replaced(small, "  - name: settle\n", "  - name: settle\n    time_step: 0.05 rayleigh\n"), n);
  ASSERT_TRUE(sc.stages[1].dt.has_value());
  EXPECT_NEAR(*sc.stages[1].dt, 0.05 * sc.rayleigh_step, 1e-18);
  EXPECT_NEAR(sc.settings.dt, 0.2 * sc.rayleigh_step, 1e-18);

  RunOptions whole;
  whole.out_dir = path("whole");
  whole.progress = false;
  const RunReport a = run_scenario(sc, whole);
  ASSERT_FALSE(a.interrupted);
  RunOptions same_step = whole;
  same_step.out_dir = path("plain");
  const RunReport p = run_scenario(plain, same_step);
  ASSERT_EQ(a.stages.size(), 2u);
  EXPECT_EQ(a.stages[0].steps, p.stages[0].steps);
  EXPECT_EQ(a.stages[0].values, p.stages[0].values);
  for (const auto& [report, dt] : {std::pair{&a, *sc.stages[1].dt}, std::pair{&p, sc.settings.dt}}) {
    const StageReport& settle = report->stages[1];
    EXPECT_NEAR(static_cast<double>(settle.steps), (settle.end - settle.start) / dt, 1.0);
  }
  std::ifstream in(path("whole/summary.json"));
  const auto j = nlohmann::json::parse(in);
  EXPECT_DOUBLE_EQ(j["stages"][0]["dt_s"].get<double>(), sc.settings.dt);
  EXPECT_DOUBLE_EQ(j["stages"][1]["dt_s"].get<double>(), *sc.stages[1].dt);
  EXPECT_DOUBLE_EQ(j["dt_s"].get<double>(), sc.settings.dt);

  const RunReport b = stopped_in_the_settling_and_continued(sc, "cut", a);
  EXPECT_EQ(b.steps, a.steps);
  EXPECT_EQ(io::read_text_file(path("whole/timeseries.csv")), io::read_text_file(path("cut/timeseries.csv")));
}

TEST_F(ScenarioRun, WarnsWhenAPackingThatShouldRestJitters) {
  // Restitution 0.05 (strong damping) with sticky friction at 0.2 of the Rayleigh step: with
  // the tangential damping unbounded, the settled cup jitters (unbalanced force about 0.36
  // over three seeds: explicit damping overshoots) and the run says so; with the default
  // bound it comes to rest (0.03 to 0.08), as the default restitution of 0.5 does (0.01 to
  // 0.14 over seeds 1 to 8): below the warning's 0.2.
  const std::vector<Override> sticky{parse_override("contacts.default.restitution=0.05"),
                                     parse_override("contacts.default.static_friction=0.486"),
                                     parse_override("contacts.default.rolling_friction=0.05")};
  auto settle_of = [&](const std::string& dir, std::vector<Override> overrides) {
    RunOptions o;
    o.out_dir = path(dir);
    o.progress = false;
    const RunReport r = run_scenario(read(small, overrides), o);
    const auto& values = r.stages.at(1).values;
    const auto u =
        std::find_if(values.begin(), values.end(), [](const auto& v) { return v.first == "unbalanced_force"; });
    const bool warned = std::any_of(r.warnings.begin(), r.warnings.end(), [](const std::string& w) {
      return w.find("stage 'settle' ended with the packing not at rest") != std::string::npos;
    });
    return std::pair{u->second, warned};
  };
  auto unbounded = sticky;
  unbounded.push_back(parse_override("simulation.tangential_damping_limit=off"));
  const auto [jitter, warned] = settle_of("unbounded", unbounded);
  EXPECT_GT(jitter, 0.25);
  EXPECT_TRUE(warned);
  const auto [rest, quiet] = settle_of("bounded", sticky);
  EXPECT_LT(rest, 0.15);
  EXPECT_FALSE(quiet);
  const auto [usual, usual_warned] = settle_of("usual", {});
  EXPECT_LT(usual, 0.15);
  EXPECT_FALSE(usual_warned);
}

}  // namespace
}  // namespace bushel
