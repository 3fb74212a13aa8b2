// `bushel preview SCENARIO --png FILE`: a picture of a scenario before it runs: the parts as
// they stand at the start (and those a stage puts in later, dashed), the factories' regions,
// the sinks, the sensors and the domain, in a vertical section through the axis (y = 0) and
// seen from above, so that a user sees where a sensor sits before spending hours. The
// geometry goes to a JSON file beside the PNG, which matplotlib draws (io::run_python).

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bushel/io/atomic_file.hpp"
#include "bushel/io/python_plot.hpp"
#include "bushel/scenario/scenario.hpp"
#include "bushel/scenario/scenario_document.hpp"
#include "commands.hpp"

namespace bushel::cli {
namespace {

using Json = nlohmann::ordered_json;

struct PreviewOptions {
  std::string scenario, png;
  std::vector<std::string> sets;
};

Json vec(const Vec3& v) { return Json::array({v.x, v.y, v.z}); }

Json region_json(const std::string& kind, const std::string& name, const Region& r) {
  Json j = {{"kind", kind}, {"name", name}, {"position", vec(r.position)}};
  if (r.kind == Region::Kind::cylinder) {
    j["shape"] = "cylinder", j["radius"] = r.radius, j["height"] = r.height;
  } else {
    j["shape"] = "box", j["size"] = vec(r.size);
  }
  return j;
}

Json mesh_json(const TriangleMesh& m) {
  Json points = Json::array(), triangles = Json::array();
  for (const Vec3& v : m.vertices) points.push_back(vec(v));
  for (const auto& t : m.triangles) triangles.push_back({t[0], t[1], t[2]});
  return {{"points", points}, {"triangles", triangles}};
}

// The parts, regions and domain of the scenario at its start, SI.
Json scene_json(const Scenario& sc) {
  Simulation sim(sc.settings);
  for (const auto& t : sc.types) sim.add_type(t);
  Json parts = Json::array(), regions = Json::array();
  for (const auto& p : sc.parts) {
    const std::size_t i = sim.add_part(p);
    Json j = mesh_json(sim.part_surface(i));
    j["name"] = p.name, j["enabled"] = p.enabled;
    parts.push_back(std::move(j));
  }
  for (const auto& f : sc.factories) {
    if (f.surface.size() > 0) {
      Json j = mesh_json(f.surface);
      j["kind"] = "factory", j["name"] = f.name, j["shape"] = "mesh";
      regions.push_back(std::move(j));
    } else {
      regions.push_back(region_json("factory", f.name, f.region));
    }
  }
  for (const auto& k : sc.sinks) regions.push_back(region_json("sink", k.name, k.region));
  for (const auto& s : sc.sensors) {
    if (const auto* r = s.as<RegionSensorSpec>()) regions.push_back(region_json("sensor", s.name, r->region));
    if (const auto* h = s.as<HeapSensorSpec>()) {
      regions.push_back({{"kind", "sensor"},
                         {"name", s.name},
                         {"shape", "axis"},
                         {"position", vec(h->centre)},
                         {"radius", h->outer}});
    }
    if (const auto* f = s.as<FlowSensorSpec>()) {
      regions.push_back({{"kind", "sensor"},
                         {"name", s.name},
                         {"shape", "plane"},
                         {"position", vec(f->point)},
                         {"normal", vec(f->normal)}});
    }
  }
  return {{"scenario", sc.document.file},
          {"parts", parts},
          {"regions", regions},
          {"domain", region_json("domain", "domain", sc.domain)}};
}

constexpr const char* preview_script = R"py(
import json, sys
import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.collections import LineCollection
from matplotlib.patches import Circle, Rectangle

scene = json.load(open(sys.argv[1])); out = sys.argv[2]
mm = 1e3
colour = {"factory": "tab:green", "sink": "tab:red", "sensor": "tab:blue", "domain": "0.5"}
fig, (side, top) = plt.subplots(1, 2, figsize=(11, 6), gridspec_kw={"width_ratios": [1, 1]})

def section(points, triangles):
    """The segments where the triangles cross the plane y = 0, in (x, z)."""
    v = np.asarray(points).reshape(-1, 3); segs = []
    for t in np.asarray(triangles, dtype=int).reshape(-1, 3):
        a = v[t]; ys = a[:, 1]
        if ys.min() > 0 or ys.max() < 0: continue
        ends = []
        for i, j in ((0, 1), (1, 2), (2, 0)):
            if (ys[i] <= 0) != (ys[j] <= 0):
                s = ys[i] / (ys[i] - ys[j]); q = a[i] + s * (a[j] - a[i]); ends.append((q[0] * mm, q[2] * mm))
        if len(ends) == 2: segs.append(ends)
    return segs

def outline(points, triangles):
    """The triangles' edges seen from above, in (x, y)."""
    v = np.asarray(points).reshape(-1, 3) * mm
    return [[tuple(v[t[i], :2]), tuple(v[t[(i + 1) % 3], :2])] for t in np.asarray(triangles, dtype=int).reshape(-1, 3)
            for i in range(3)]

walls = ["0.15", "tab:brown", "tab:purple", "tab:olive", "tab:cyan", "tab:pink", "tab:orange"]
for k, p in enumerate(scene["parts"]):
    c = walls[k % len(walls)]; style = "-" if p["enabled"] else "--"
    label = p["name"] + ("" if p["enabled"] else " (later)")
    side.add_collection(LineCollection(section(p["points"], p["triangles"]), colors=c, linestyles=style, lw=1.6, label=label))
    top.add_collection(LineCollection(outline(p["points"], p["triangles"]), colors=c, linestyles=style, lw=0.3, alpha=0.5))

for r in scene["regions"] + [scene["domain"]]:
    c = colour[r["kind"]]; x, y, z = (q * mm for q in r["position"]); label = f"{r['kind']} {r['name']}"
    ls = ":" if r["kind"] == "domain" else "-"
    fill = dict(fill=r["kind"] != "domain", fc=matplotlib.colors.to_rgba(c, 0.12), ec=c, ls=ls, lw=1.4)
    if r["shape"] == "cylinder":
        rad, h = r["radius"] * mm, r["height"] * mm
        side.add_patch(Rectangle((x - rad, z), 2 * rad, h, label=label, **fill))
        top.add_patch(Circle((x, y), rad, **fill))
    elif r["shape"] == "box":
        sx, sy, sz = (q * mm for q in r["size"])
        side.add_patch(Rectangle((x - sx / 2, z - sz / 2), sx, sz, label=label, **fill))
        top.add_patch(Rectangle((x - sx / 2, y - sy / 2), sx, sy, **fill))
    elif r["shape"] == "axis":  # a heap sensor: its axis and outer radius
        rad = r["radius"] * mm
        side.axvline(x, color=c, ls="-.", lw=1, label=label); top.add_patch(Circle((x, y), rad, fill=False, ec=c, ls="-.", lw=1))
    elif r["shape"] == "plane":  # a flow sensor: its plane through the point, seen edge-on if horizontal
        nx, ny, nz = r["normal"]
        if abs(nz) > 0.9: side.axhline(z, color=c, ls="--", lw=1, label=label)
        else: side.plot([x], [z], marker="x", color=c, label=label)
        top.plot([x], [y], marker="x", color=c)
    elif r["shape"] == "mesh":
        side.add_collection(LineCollection(section(r["points"], r["triangles"]), colors=c, lw=2, label=label))
        top.add_collection(LineCollection(outline(r["points"], r["triangles"]), colors=c, lw=0.5))

d = scene["domain"]; dx, dy, dz = (q * mm for q in d["position"]); sx, sy, sz = (q * mm for q in d["size"])
side.set(xlim=(dx - sx / 2, dx + sx / 2), ylim=(dz - sz / 2, dz + sz / 2), xlabel="x [mm]", ylabel="z [mm]",
         title="section y = 0", aspect="equal")
top.set(xlim=(dx - sx / 2, dx + sx / 2), ylim=(dy - sy / 2, dy + sy / 2), xlabel="x [mm]", ylabel="y [mm]",
        title="from above", aspect="equal")
side.legend(fontsize=7, loc="upper left", bbox_to_anchor=(0, -0.12), ncol=2, frameon=False)
fig.suptitle(scene["scenario"], fontsize=9)
fig.tight_layout(); fig.savefig(out, dpi=110)
print(out)
)py";

}  // namespace

void add_preview_command(CLI::App& app) {
  auto o = std::make_shared<PreviewOptions>();
  auto* p =
      app.add_subcommand("preview", "Draw a scenario before running it: parts, factories, sinks, sensors, domain");
  p->add_option("scenario", o->scenario, "Scenario file (YAML)")->required();
  p->add_option("--png", o->png, "The picture to write (PNG); its geometry goes beside it as .json")->required();
  p->add_option("--set", o->sets, "Override a value: path.to.key=value (repeatable)");
  p->callback([o] {
    std::vector<Override> overrides;
    for (const auto& s : o->sets) overrides.push_back(parse_override(s));
    const Scenario sc = read_scenario(load_scenario_document(o->scenario, overrides));
    const std::filesystem::path png(o->png);
    if (png.has_parent_path()) std::filesystem::create_directories(png.parent_path());
    const std::string json_path = std::filesystem::path(png).replace_extension(".json").string();
    io::write_file_atomically(json_path, scene_json(sc).dump(1));
    io::run_python(preview_script, {json_path, o->png});
    fmt::print("{}: {} parts, {} factories, {} sinks, {} sensors\n", o->png, sc.parts.size(), sc.factories.size(),
               sc.sinks.size(), sc.sensors.size());
  });
}

}  // namespace bushel::cli
