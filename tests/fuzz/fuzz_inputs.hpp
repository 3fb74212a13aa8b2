#pragma once
// What each fuzz target does with one input, shared by the libFuzzer targets (tests/fuzz/
// *_fuzz.cpp) and by the test that replays their reproducers without clang (tests/unit/
// fuzz_regression_test.cpp). Every function here may throw InputError, the readers' answer to
// bad input; anything else (another exception, a sanitizer report, a failed check below, a
// signal, a hang) is a bug. docs/fuzzing.md.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <utility>

#include "bushel/core/input_error.hpp"
#include "bushel/io/binary_archive.hpp"
#include "bushel/io/csv.hpp"
#include "bushel/io/stl.hpp"
#include "bushel/particles/template_library.hpp"
#include "bushel/scenario/scenario.hpp"
#include "bushel/scenario/scenario_document.hpp"
#include "bushel/scenario/scenario_run.hpp"
#include "bushel/units/expression.hpp"

namespace bushel::fuzz {

/// A property every accepted input must have; a failure is reported as a crash.
inline void check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "fuzz check failed: %s\n", what);
    std::abort();
  }
}

/// The scenario reader: a scenario file's text, as `bushel run` and `bushel validate` read it.
inline void scenario_input(std::string_view bytes) {
  ScenarioDocument doc = parse_scenario_document(std::string(bytes), "fuzz.yaml");
  (void)read_scenario(std::move(doc));
}

/// The expression parser: the text as an expression over two names, and as a plain
/// quantity; both are tried (the second even when the first is refused), each result written
/// back in SI as a summary would.
inline void expression_input(std::string_view bytes) {
  const units::NameLookup lookup = [](const std::string& name) -> units::Quantity {
    if (name == "height") return {0.1016, units::dim::length};
    if (name == "fill.cup.mass") return {0.2, units::dim::mass};
    if (name == "scale") return {0.5, units::dim::dimensionless};
    throw InputError("unknown name '" + name + "' (known: height, fill.cup.mass, scale)");
  };
  try {
    (void)units::format_si(units::evaluate(bytes, lookup));
  } catch (const InputError&) {
  }
  (void)units::format_si(units::parse_quantity(bytes));
}

/// Particle template CSVs (`bushel particle file.csv`, scenario particle types): every
/// template read must then be found by its name.
inline void template_csv_input(std::string_view bytes) {
  const TemplateLibrary library = TemplateLibrary::parse_csv(bytes, "fuzz.csv", {});
  for (const std::string& name : library.names()) (void)library.get(name);
}

/// STL meshes (scenario parts of shape mesh): the mesh read must be consistent.
inline void stl_input(std::string_view bytes) {
  io::StlReport report;
  const TriangleMesh mesh = io::parse_stl(bytes, "fuzz.stl", 1.0, &report);
  check(!mesh.triangles.empty(), "a mesh without triangles was accepted");
  check(report.vertices == mesh.vertices.size(), "StlReport::vertices differs from the mesh's");
  check(report.triangles_read == mesh.triangles.size() + report.degenerate_dropped, "triangles read != kept + dropped");
  for (const auto& t : mesh.triangles) {
    for (const auto v : t) check(v < mesh.vertices.size(), "a triangle indexes a missing vertex");
  }
  for (const Vec3& v : mesh.vertices) {
    check(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z), "a vertex is not finite");
  }
}

/// The checkpoint reader, by the path of `bushel run --restart`: resume_scenario over a
/// folder holding the input as checkpoint.bin beside a valid timeseries.csv. A small run
/// (30 spheres poured into a cup, every kind of sensor, a sink, frames) is stopped after 20 ms
/// when the object is made: its checkpoint is the seed, its time series the one every input
/// is resumed against, and a valid checkpoint is continued only to its next check.
class CheckpointInput {
 public:
  /// The scenario of the seed run.
  static constexpr const char* scenario_text = R"(parameters:
  count: 30
simulation:
  time_step: 0.2 rayleigh
  domain: {min: -40 -40 -30 mm, max: 40 40 120 mm}
materials:
  wheat: {shear_modulus: 22.4 MPa, poisson_ratio: 0.22, density: 1373 kg/m3}
  steel: {shear_modulus: 37 GPa, poisson_ratio: 0.25, density: 8560 kg/m3}
particle_types:
  grain: {diameter: 3.64 mm, material: wheat}
contacts:
  default: {restitution: 0.5, static_friction: 0.27, rolling_friction: 0.01}
parts:
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

  /// Makes `dir` (emptied first) and runs the seed run in it.
  explicit CheckpointInput(std::filesystem::path dir) : dir_(std::move(dir)) {
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    RunOptions o;
    o.out_dir = (dir_ / "seed").string();
    o.progress = false;
    o.checkpoint_interval = 0;
    o.interrupt_at = 0.02;
    const RunReport r = run_scenario(read_scenario(parse_scenario_document(scenario_text, "checkpoint_seed.yaml")), o);
    check(r.interrupted, "the seed run was not stopped at 20 ms");
    seed_ = read_file(dir_ / "seed" / "checkpoint.bin");
    series_ = read_file(dir_ / "seed" / "timeseries.csv");
  }
  ~CheckpointInput() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  CheckpointInput(const CheckpointInput&) = delete;
  CheckpointInput& operator=(const CheckpointInput&) = delete;

  /// The seed run's checkpoint.
  const std::string& seed() const { return seed_; }

  /// Resumes from `bytes` as checkpoint.bin, to the first check.
  RunReport feed(std::string_view bytes) const {
    const std::filesystem::path run = dir_ / "run";
    std::filesystem::create_directories(run);
    write_file(run / "checkpoint.bin", bytes);
    write_file(run / "timeseries.csv", series_);
    RunOptions o;
    o.out_dir = run.string();
    o.progress = false;
    o.checkpoint_interval = 0;
    o.interrupt_at = 0.0;
    return resume_scenario(o);
  }

  static std::string read_file(const std::filesystem::path& path) { return io::read_text_file(path.string()); }
  static void write_file(const std::filesystem::path& path, std::string_view bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    check(static_cast<bool>(out.flush()), "cannot write the fuzz input's file");
  }

 private:
  std::filesystem::path dir_;
  std::string seed_, series_;
};

/// Makes every section checksum of a checkpoint (binary_archive.hpp: a length-prefixed magic
/// string, then sections of name, version, length, XXH3 checksum and body) match its body again, as far
/// as the layout can be followed; returns false if nothing could be resealed. The checkpoint
/// target's mutator applies it to half of its mutants, so that the fuzzer also reaches the
/// readers behind the checksums (a file damaged in a way no checksum shows).
inline bool reseal_checkpoint(std::string& bytes) {
  auto u64_at = [&](std::size_t at, std::uint64_t& v) {
    if (at > bytes.size() || bytes.size() - at < sizeof v) return false;
    std::memcpy(&v, bytes.data() + at, sizeof v);
    return true;
  };
  std::size_t at = 0;
  std::uint64_t n = 0;
  if (!u64_at(at, n) || n > bytes.size() - at - 8) return false;
  at += 8 + n;  // the magic line
  bool resealed = false;
  while (at < bytes.size()) {
    std::uint64_t name = 0, length = 0;
    if (!u64_at(at, name) || name > bytes.size() - at - 8) break;
    at += 8 + name + sizeof(std::uint32_t);  // (the name, the version)
    if (!u64_at(at, length) || !u64_at(at + 8, n)) break;
    at += 16;
    if (length > bytes.size() - at) break;
    const std::uint64_t sum = io::checksum(std::string_view(bytes).substr(at, length));
    std::memcpy(bytes.data() + at - 8, &sum, sizeof sum);
    at += length;
    resealed = true;
  }
  return resealed;
}

}  // namespace bushel::fuzz
