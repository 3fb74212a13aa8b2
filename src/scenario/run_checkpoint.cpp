#include "run_checkpoint.hpp"

#include <filesystem>
#include <map>
#include <optional>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "bushel/core/build_info.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/io/atomic_file.hpp"

namespace bushel::scenario_running {
namespace {

// "bushel checkpoint N", N = Simulation::checkpoint_format.
std::string checkpoint_magic(int format) { return "bushel checkpoint " + std::to_string(format); }

// The members of a Position, then of a Sink, that a checkpoint holds, in file order: one list
// for writing and reading (P is Position or const Position; the rest of the position has
// its own format).
template <class P, class F>
requires std::is_same_v<std::remove_const_t<P>, Position>
void each_checkpointed(P& p, F&& f) {
  f(p.stage);
  f(p.stage_started);
  f(p.t0);
  f(p.steps0);
  f(p.history.time);
  f(p.history.value);
  f(p.next_row);
  f(p.next_frame);
  f(p.particle_steps);
}
template <class K, class F>
requires std::is_same_v<std::remove_const_t<K>, Sink>
void each_checkpointed(K& k, F&& f) {
  f(k.enabled);
  f(k.count);
  f(k.mass);
}

void put(io::BinaryWriter& out, const StageReport& r) {
  out.put(r.name);
  out.put(r.ended_by);
  out.put(r.start);
  out.put(r.end);
  out.put(r.steps);
  out.put(static_cast<std::uint64_t>(r.values.size()));
  for (const auto& [k, v] : r.values) out.put(k), out.put(v);
  out.put(static_cast<std::uint64_t>(r.profiles.size()));
  for (const auto& p : r.profiles) out.put(p.sensor), out.put(p.radius), out.put(p.height);
}

StageReport get_report(io::BinaryReader& in) {
  StageReport r;
  in.get(r.name);
  in.get(r.ended_by);
  in.get(r.start);
  in.get(r.end);
  in.get(r.steps);
  const auto n = in.get_count(16);
  for (std::uint64_t k = 0; k < n; ++k) {
    auto name = in.get<std::string>();
    r.values.emplace_back(std::move(name), in.get<double>());
  }
  r.profiles.resize(in.get_count(24));
  for (auto& p : r.profiles) in.get(p.sensor), in.get(p.radius), in.get(p.height);
  return r;
}

std::vector<const Sink*> sinks_and_lost(const RunState& st) {
  std::vector<const Sink*> all{&st.lost};
  for (const Sink& k : st.sinks) all.push_back(&k);
  return all;
}

std::vector<Sink*> sinks_and_lost(RunState& st) {
  std::vector<Sink*> all{&st.lost};
  for (Sink& k : st.sinks) all.push_back(&k);
  return all;
}

void put_scenario(io::BinaryWriter& scenario, const ScenarioDocument& doc) {
  scenario.put(doc.file);
  scenario.put(echo_text(doc));
  scenario.put(static_cast<std::uint64_t>(doc.overrides.size()));
  for (const auto& ov : doc.overrides) scenario.put(ov.path), scenario.put(ov.value);
  scenario.put(static_cast<std::uint64_t>(doc.parameters.size()));
  for (const auto& [k, v] : doc.parameters) scenario.put(k), scenario.put(v);
}

// The run's sections and their versions: where the run stands (run), and each component's
// own: factories, sinks, flows, frames and guards.
constexpr std::uint32_t build_version = 1, scenario_version = 1, run_version = 1, factories_version = 1,
                        sinks_version = 1, flows_version = 1, frames_version = 1, guards_version = 1;

void put_run(io::BinaryWriter& run, const Position& pos, double wall) {
  each_checkpointed(pos, [&](const auto& m) { run.put(m); });
  run.put(wall);
  run.put(pos.series_bytes);
  run.put(static_cast<std::uint64_t>(pos.done.size()));
  for (const auto& r : pos.done) put(run, r);
  run.put(static_cast<std::uint64_t>(pos.warnings.size()));
  for (const auto& w : pos.warnings) run.put(w);
  run.put(pos.peak_overlap);
  run.put(static_cast<std::uint64_t>(pos.deep_overlaps.size()));
  for (const auto& [name, peak] : pos.deep_overlaps) run.put(name), run.put(peak);
  run.put(static_cast<std::uint64_t>(pos.engines.size()));
  for (const auto& e : pos.engines) run.put(e);
  run.put(pos.failed);
}

void get_run(io::BinaryReader& in, const RunState& st, Position& pos) {
  each_checkpointed(pos, [&](auto& m) { in.get(m); });
  if (pos.stage > st.sc.stages.size()) in.damaged("it does not match its scenario");
  in.get(pos.wall_before);
  in.get(pos.series_bytes);
  const auto n_done = in.get_count(8);
  for (std::uint64_t k = 0; k < n_done; ++k) pos.done.push_back(get_report(in));
  const auto n_warn = in.get_count(8);
  for (std::uint64_t k = 0; k < n_warn; ++k) pos.warnings.push_back(in.get<std::string>());
  in.get(pos.peak_overlap);
  pos.deep_overlaps.resize(in.get_count(16));
  for (auto& [name, peak] : pos.deep_overlaps) in.get(name), in.get(peak);
  pos.engines.resize(in.get_count(8));
  for (auto& e : pos.engines) in.get(e);
  in.get(pos.failed);
}

void put_components(io::BinaryWriter& out, const RunState& st, const Position& pos, const io::FrameWriter* frames) {
  io::BinaryWriter factories, sinks, flows, frame_count, guards;
  factories.put(st.factory_on);
  for (const auto& f : st.factories) f.save(factories);
  for (const Sink* k : sinks_and_lost(st)) each_checkpointed(*k, [&](const auto& m) { sinks.put(m); });
  for (const auto& f : st.flows) f.save(flows);
  pos.guards.save(guards);
  out.put_section("factories", factories_version, factories);
  out.put_section("sinks", sinks_version, sinks);
  out.put_section("flows", flows_version, flows);
  if (frames) {
    frames->save(frame_count);
    out.put_section("frames", frames_version, frame_count);
  }
  out.put_section("guards", guards_version, guards);
}

void get_components(const io::SectionTable& t, RunState& st, Position& pos, io::FrameWriter* frames) {
  t.read("factories", factories_version, true, [&](io::BinaryReader& in) {
    in.get(st.factory_on);
    if (st.factory_on.size() != st.factories.size()) in.damaged("it does not match its scenario");
    for (auto& f : st.factories) f.load(in);
  });
  t.read("sinks", sinks_version, true, [&](io::BinaryReader& in) {
    for (Sink* k : sinks_and_lost(st)) each_checkpointed(*k, [&](auto& m) { in.get(m); });
  });
  t.read("flows", flows_version, true, [&](io::BinaryReader& in) {
    for (auto& f : st.flows) f.load(in);
  });
  // Without these a run continues with their defaults: frames numbered afresh, guard clocks
  // that start now.
  if (frames) t.read("frames", frames_version, false, [&](io::BinaryReader& in) { frames->load(in); });
  t.read("guards", guards_version, false, [&](io::BinaryReader& in) { pos.guards.load(in); });
}

// The build named in another format's first section, "build" (formats 3 and 4: its name, in
// format 4 a version, its length and checksum, then the build's name), or "an unknown build".
std::string writer_of(const io::BinaryReader& at) {
  for (const bool versioned : {true, false}) {
    io::BinaryReader in = at;  // (a copy: each try reads from the same place)
    try {
      if (in.get<std::string>() != "build") break;
      if (versioned) (void)in.get<std::uint32_t>();
      const auto length = in.get<std::uint64_t>();
      const auto sum = in.get<std::uint64_t>();
      const std::string_view body = in.take(length);
      if (io::checksum(body) == sum) return io::BinaryReader(body, "").get<std::string>();
    } catch (const InputError&) {
    }
  }
  return "an unknown build";
}

}  // namespace

void save_checkpoint(const std::string& out_dir, const RunState& st, const Position& pos, const io::FrameWriter* frames,
                     double wall) {
  io::BinaryWriter out, build, scenario, run;
  out.put(checkpoint_magic(Simulation::checkpoint_format));
  build.put(build_description());
  out.put_section("build", build_version, build);
  put_scenario(scenario, st.sc.document);
  out.put_section("scenario", scenario_version, scenario);
  put_run(run, pos, wall);
  out.put_section("run", run_version, run);
  put_components(out, st, pos, frames);
  st.sim.save_state(out);
  io::write_file_atomically((std::filesystem::path(out_dir) / "checkpoint.bin").string(), out.bytes());
}

void load_checkpoint(const io::SectionTable& t, RunState& st, Position& pos, io::FrameWriter* frames) {
  t.read("run", run_version, true, [&](io::BinaryReader& in) { get_run(in, st, pos); });
  get_components(t, st, pos, frames);
  st.sim.load_state(t);
}

ScenarioDocument read_checkpoint_head(io::BinaryReader& in, const std::string& path,
                                      std::optional<io::SectionTable>& sections) {
  const std::string magic = checkpoint_magic(Simulation::checkpoint_format);
  std::string found;
  try {
    found = in.get<std::string>();
  } catch (const InputError&) {  // (too short for even the magic line)
  }
  if (!found.starts_with("bushel checkpoint ")) throw InputError("not a bushel checkpoint").at(path);
  if (found != magic) {
    const std::string writer = writer_of(in);
    throw InputError(fmt::format("a checkpoint of format {}, written by bushel {}; this build ({}) reads format {}: "
                                 "continue it with the build that wrote it, or start the run again",
                                 found.substr(magic.size() - 1), writer, build_description(),
                                 Simulation::checkpoint_format))
        .at(path);
  }
  sections.emplace(in);
  std::vector<std::string_view> known{"build", "scenario", "run", "factories", "sinks", "flows", "frames", "guards"};
  known.insert(known.end(), Simulation::state_sections.begin(), Simulation::state_sections.end());
  sections->expect_known(known);
  (void)sections->get("build", build_version);
  // The scenario as it was resolved (overrides applied, parameters substituted), read again
  // as if from its file, so that relative paths (meshes, templates) still resolve.
  io::BinaryReader head = sections->get("scenario", scenario_version).body;
  const auto file = head.get<std::string>();
  const auto text = head.get<std::string>();
  std::vector<Override> overrides(head.get_count(16));
  for (auto& ov : overrides) head.get(ov.path), head.get(ov.value);
  std::map<std::string, std::string> parameters;
  const auto n_parameters = head.get_count(16);
  for (std::uint64_t k = 0; k < n_parameters; ++k) {
    auto name = head.get<std::string>();
    parameters[name] = head.get<std::string>();
  }
  io::SectionTable::expect_end(head, "scenario");
  ScenarioDocument doc = parse_scenario_document(text, file);
  doc.overrides = std::move(overrides);
  doc.parameters = std::move(parameters);
  return doc;
}

}  // namespace bushel::scenario_running
