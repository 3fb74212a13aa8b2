// `bushel demo funnel`: grain settles in a funnel closed by a hinged gate, the gate turns
// 180 degrees, and the discharge is timed. The funnel is the cone primitive or a mesh read
// from STL (--stl), so the two can be compared; --write-stl saves the cone as an STL.
#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>

#include "bushel/core/input_error.hpp"
#include "bushel/experiments/funnel_scene.hpp"
#include "bushel/io/atomic_file.hpp"
#include "bushel/io/stl.hpp"
#include "bushel/scenario/frame_writer.hpp"
#include "commands.hpp"

namespace bushel::cli {
namespace {

struct FunnelOptions {
  std::size_t count = 1000;
  std::string particle = "sphere";
  std::string top = "100mm", outlet = "16.5mm", angle = "60deg", gate_open = "0.6s", gate_speed = "7.85rad/s";
  std::string time = "2s", frame = "0.05s";
  std::string stl, write_stl, out;
  double stl_scale = 1.0;
  std::uint64_t seed = 12345;
  int threads = 0;
  bool json = false;
};

void run_funnel(const FunnelOptions& o) {
  set_threads(o.threads);
  FunnelSpec spec;
  spec.count = o.count;
  spec.particle = o.particle;
  spec.seed = o.seed;
  spec.top_diameter = option_quantity("--top", o.top, units::dim::length);
  spec.outlet_diameter = option_quantity("--outlet", o.outlet, units::dim::length);
  spec.wall_angle = option_quantity("--angle", o.angle, units::dim::angle);
  spec.gate_open_time = option_quantity("--gate-open", o.gate_open, units::dim::time);
  spec.gate_speed = option_quantity("--gate-speed", o.gate_speed, units::dim::angular_velocity);
  const double end_time = option_quantity("--time", o.time, units::dim::time);
  const double frame_every = option_quantity("--frame", o.frame, units::dim::time);
  if (!(end_time > 0.0)) throw InputError("expected a positive time, e.g. 2s").with_key("--time");
  if (!(frame_every > 0.0)) throw InputError("expected a positive interval, e.g. 0.05s").with_key("--frame");
  if (!o.write_stl.empty()) {
    const TriangleMesh m = funnel_mesh(spec);
    io::write_stl(o.write_stl, m);
    fmt::print(stderr, "wrote the cone funnel as {} triangles to {}\n", m.size(), o.write_stl);
  }
  if (!o.stl.empty()) {
    io::StlReport report;
    spec.mesh = io::read_stl(o.stl, o.stl_scale, &report);
    fmt::print(stderr, "funnel mesh {}: {} triangles, {} vertices, {} degenerate dropped\n", o.stl,
               report.triangles_read - report.degenerate_dropped, report.vertices, report.degenerate_dropped);
  }
  FunnelScene scene = make_funnel_scene(spec);
  Simulation& sim = scene.simulation;
  double total = 0.0;
  for (std::size_t b = 0; b < sim.particles().bodies(); ++b) total += sim.particles().mass(b);
  std::optional<io::FrameWriter> frames;
  if (!o.out.empty()) frames.emplace(o.out);
  const double dt = sim.settings().dt;
  fmt::print(stderr, "funnel: {} x {}, {} outlet {:.1f} mm, dt = {:.3f} us, gate opens at {:.2f} s\n", o.count,
             o.particle, spec.mesh ? "mesh" : "cone", spec.outlet_diameter * 1e3, dt * 1e6, spec.gate_open_time);
  const bool tty = isatty(fileno(stderr)) != 0;
  // The discharge is sampled every 5 ms (for the flow rate); rows, frames and progress come
  // every --frame.
  const double sample = std::min(frame_every, 0.005);
  std::string csv = "time_s,discharged_kg,gate_angle_rad,gate_touches,funnel_force_z_n\n";
  const auto start = std::chrono::steady_clock::now();
  double t10 = -1, t90 = -1;  // times at 10% and 90% discharged
  auto gate_angle = [&] {     // from the closed position, 0 .. 2 pi
    const Vec3 n = rotate(sim.part(scene.gate).pose.orientation, Vec3{0, 0, 1});
    const double a = std::atan2(-n.y, n.z);
    return a < -1e-9 ? a + 2 * std::numbers::pi : a;
  };
  if (frames) frames->write(sim);
  double next_frame = frame_every;
  while (sim.time() < end_time - 0.5 * dt) {
    const double until = std::min(end_time, sim.time() + sample);
    sim.step(std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround((until - sim.time()) / dt))));
    const double m = discharged_mass(scene);
    if (t10 < 0 && m >= 0.1 * total) t10 = sim.time();
    if (t90 < 0 && m >= 0.9 * total) t90 = sim.time();
    if (sim.time() < next_frame - 0.5 * dt && sim.time() < end_time - 0.5 * dt) continue;
    next_frame += frame_every;
    csv += fmt::format("{:.6f},{:.9g},{:.9g},{},{:.9g}\n", sim.time(), m, gate_angle(), sim.part(scene.gate).touches,
                       sim.part(scene.funnel).force.z);
    if (frames) frames->write(sim);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    fmt::print(stderr, "{}t = {:.2f} s  discharged {:.2f} g of {:.2f} g  gate {:.0f} deg  {:.2f} M sphere-steps/s{}",
               tty ? "\r" : "", sim.time(), m * 1e3, total * 1e3, gate_angle() * 180 / std::numbers::pi,
               static_cast<double>(sim.steps()) * static_cast<double>(sim.particles().spheres()) / wall * 1e-6,
               tty ? "   " : "\n");
  }
  if (tty) fmt::print(stderr, "\n");
  if (!o.out.empty()) io::write_file_atomically(o.out + "/discharge.csv", csv);
  const double m = discharged_mass(scene);
  const double rate = t90 > t10 && t10 >= 0 ? 0.8 * total / (t90 - t10) : 0.0;
  const nlohmann::ordered_json j = {{"particles", o.count},
                                    {"particle", o.particle},
                                    {"funnel", spec.mesh ? "mesh:" + o.stl : "cone"},
                                    {"outlet_diameter_m", spec.outlet_diameter},
                                    {"simulated_time_s", sim.time()},
                                    {"steps", sim.steps()},
                                    {"gate_angle_rad", gate_angle()},
                                    {"total_mass_kg", total},
                                    {"discharged_mass_kg", m},
                                    {"time_10_percent_s", t10},
                                    {"time_90_percent_s", t90},
                                    {"mass_flow_kg_s", rate}};
  if (o.json) {
    fmt::print("{}\n", j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace));
    return;
  }
  fmt::print("gate angle at the end         {:.1f} deg\n", gate_angle() * 180 / std::numbers::pi);
  fmt::print("discharged                    {:.2f} g of {:.2f} g\n", m * 1e3, total * 1e3);
  if (rate > 0) fmt::print("mass flow (10% to 90%)        {:.1f} g/s\n", rate * 1e3);
}

}  // namespace

void add_demo_funnel_command(CLI::App& demo) {
  auto o = std::make_shared<FunnelOptions>();
  auto* f = demo.add_subcommand("funnel", "Discharge grain from a funnel through a turning gate");
  f->add_option("--count", o->count, "Number of particles")->capture_default_str()->check(CLI::Range(1, 10'000'000));
  f->add_option("--particle", o->particle, "sphere (d 3.64 mm) or a template name")->capture_default_str();
  f->add_option("--top", o->top, "Funnel top inner diameter")->capture_default_str();
  f->add_option("--outlet", o->outlet, "Funnel outlet inner diameter")->capture_default_str();
  f->add_option("--angle", o->angle, "Funnel wall angle from the horizontal")->capture_default_str();
  f->add_option("--gate-open", o->gate_open, "Time the gate starts to turn")->capture_default_str();
  f->add_option("--gate-speed", o->gate_speed, "Gate angular speed (180 degrees in pi/speed)")->capture_default_str();
  f->add_option("--time", o->time, "Simulated time")->capture_default_str();
  f->add_option("--frame", o->frame, "Time between progress lines, CSV rows and frames")->capture_default_str();
  f->add_option("--stl", o->stl, "Use this STL as the funnel (outlet at z = 0, axis +z)");
  f->add_option("--stl-scale", o->stl_scale, "Factor to metres for --stl (0.001 for mm)")->capture_default_str();
  f->add_option("--write-stl", o->write_stl, "Write the cone funnel as a binary STL first");
  f->add_option("--out", o->out, "Directory for ParaView frames (VTU, PVD) and discharge.csv");
  f->add_option("--seed", o->seed, "Random seed")->capture_default_str();
  f->add_option("--threads", o->threads, "OpenMP threads (0 = default)")->capture_default_str();
  f->add_flag("--json", o->json, "Print the result as JSON");
  f->callback([o] { run_funnel(*o); });
}

}  // namespace bushel::cli
