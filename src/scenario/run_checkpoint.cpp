#include "run_checkpoint.hpp"

#include <filesystem>
#include <map>

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

void put_run(io::BinaryWriter& run, const RunState& st, const Position& pos, const io::FrameWriter* frames,
             double wall) {
  each_checkpointed(pos, [&](const auto& m) { run.put(m); });
  run.put(wall);
  run.put(pos.series_bytes);
  run.put(static_cast<std::uint64_t>(pos.done.size()));
  for (const auto& r : pos.done) put(run, r);
  run.put(static_cast<std::uint64_t>(pos.warnings.size()));
  for (const auto& w : pos.warnings) run.put(w);
  run.put(st.factory_on);
  for (const auto& f : st.factories) f.save(run);
  for (const Sink* k : sinks_and_lost(st)) each_checkpointed(*k, [&](const auto& m) { run.put(m); });
  for (const auto& f : st.flows) f.save(run);
  if (frames) frames->save(run);
  run.put(pos.peak_overlap);
  run.put(static_cast<std::uint64_t>(pos.deep_overlaps.size()));
  for (const auto& [name, peak] : pos.deep_overlaps) run.put(name), run.put(peak);
  run.put(static_cast<std::uint64_t>(pos.engines.size()));
  for (const auto& e : pos.engines) run.put(e);
  pos.guards.save(run);
  run.put(pos.failed);
}

void get_run(io::BinaryReader& in, RunState& st, Position& pos, io::FrameWriter* frames) {
  each_checkpointed(pos, [&](auto& m) { in.get(m); });
  in.get(pos.wall_before);
  in.get(pos.series_bytes);
  const auto n_done = in.get_count(8);
  for (std::uint64_t k = 0; k < n_done; ++k) pos.done.push_back(get_report(in));
  const auto n_warn = in.get_count(8);
  for (std::uint64_t k = 0; k < n_warn; ++k) pos.warnings.push_back(in.get<std::string>());
  in.get(st.factory_on);
  if (st.factory_on.size() != st.factories.size() || pos.stage > st.sc.stages.size()) {
    in.damaged("it does not match its scenario");
  }
  for (auto& f : st.factories) f.load(in);
  for (Sink* k : sinks_and_lost(st)) each_checkpointed(*k, [&](auto& m) { in.get(m); });
  for (auto& f : st.flows) f.load(in);
  if (frames) frames->load(in);
  in.get(pos.peak_overlap);
  pos.deep_overlaps.resize(in.get_count(16));
  for (auto& [name, peak] : pos.deep_overlaps) in.get(name), in.get(peak);
  pos.engines.resize(in.get_count(8));
  for (auto& e : pos.engines) in.get(e);
  pos.guards.load(in);
  in.get(pos.failed);
  if (!in.done()) in.damaged("unexpected data at the end of section 'run'");
}

}  // namespace

void save_checkpoint(const std::string& out_dir, const RunState& st, const Position& pos, const io::FrameWriter* frames,
                     double wall) {
  io::BinaryWriter out, build, scenario, run, engine;
  out.put(checkpoint_magic(Simulation::checkpoint_format));
  build.put(build_description());
  out.put_section("build", build);
  put_scenario(scenario, st.sc.document);
  put_run(run, st, pos, frames, wall);
  st.sim.save_state(engine);
  st.sim.save_force_sums(engine);
  st.sim.save_skin_clock(engine);
  out.put_section("scenario", scenario);
  out.put_section("run", run);
  out.put_section("engine", engine);
  io::write_file_atomically((std::filesystem::path(out_dir) / "checkpoint.bin").string(), out.bytes());
}

void load_checkpoint(io::BinaryReader& file, RunState& st, Position& pos, io::FrameWriter* frames) {
  io::BinaryReader in = file.section("run");
  io::BinaryReader engine = file.section("engine");
  if (!file.done()) file.damaged("data after its last section");
  get_run(in, st, pos, frames);
  st.sim.load_state(engine);
  st.sim.load_force_sums(engine);
  st.sim.load_skin_clock(engine);
  if (!engine.done()) engine.damaged("unexpected data at the end of section 'engine'");
}

ScenarioDocument read_checkpoint_head(io::BinaryReader& in, const std::string& path) {
  const std::string magic = checkpoint_magic(Simulation::checkpoint_format);
  std::string found;
  try {
    found = in.get<std::string>();
  } catch (const InputError&) {  // (too short for even the magic line)
  }
  if (!found.starts_with("bushel checkpoint ")) throw InputError("not a bushel checkpoint").at(path);
  const auto writer = in.section("build").get<std::string>();
  if (found != magic) {
    throw InputError(fmt::format("a checkpoint of format {}, written by bushel {}; this build ({}) reads format {}: "
                                 "continue it with the build that wrote it, or start the run again",
                                 found.substr(magic.size() - 1), writer, build_description(),
                                 Simulation::checkpoint_format))
        .at(path);
  }
  // The scenario as it was resolved (overrides applied, parameters substituted), read again
  // as if from its file, so that relative paths (meshes, templates) still resolve.
  io::BinaryReader head = in.section("scenario");
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
  if (!head.done()) head.damaged("unexpected data at the end of section 'scenario'");
  ScenarioDocument doc = parse_scenario_document(text, file);
  doc.overrides = std::move(overrides);
  doc.parameters = std::move(parameters);
  return doc;
}

}  // namespace bushel::scenario_running
