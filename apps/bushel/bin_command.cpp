// `bushel bin`: the mass of grain in a round bin from its measured size, the grain's test
// weight (or an in-bin density) and how it compacts under the grain above it (bin_model.hpp).
#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <utility>

#include "bushel/analysis/bin_model.hpp"
#include "bushel/analysis/grain_trade.hpp"
#include "bushel/core/did_you_mean.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/io/atomic_file.hpp"
#include "bushel/io/python_plot.hpp"
#include "bushel/scenario/run_summary.hpp"
#include "bushel/units/units.hpp"
#include "commands.hpp"

namespace bushel::cli {

namespace {

struct BinOptions {
  std::string diameter, grain_height, test_weight, initial_density, grain = "wheat";
  std::string compressibility, wpacking, moisture, extrapolate = "error";
  bool incompressible = false;
  std::string wall_friction = "0.3", k, friction_angle, surcharge = "level", repose_angle, hopper_angle, outlet = "0m";
  int layers = 2000;
  std::string csv, plot;
  bool json = false;
};

// Pressure and density against depth, side by side, depth downwards.
constexpr const char* plot_script = R"py(
import csv, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
rows = list(csv.DictReader(open(sys.argv[1])))
z = [float(r["depth_m"]) for r in rows]
fig, (a, b) = plt.subplots(1, 2, sharey=True, figsize=(8, 5))
a.plot([float(r["pressure_kPa"]) for r in rows], z)
b.plot([float(r["bulk_density_kg_m3"]) for r in rows], z, color="tab:brown")
a.set_xlabel("vertical pressure (kPa)")
b.set_xlabel("bulk density (kg/m3)")
a.set_ylabel("depth below the grain at the wall (m)")
a.invert_yaxis()
for ax in (a, b):
    ax.grid(alpha=0.3)
fig.suptitle(sys.argv[3])
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=120)
)py";

// A run folder (or summary.json) named by --initial-density, with the result to take after a
// colon: "runs/drop:bulk_density_sensor". Not a path: nothing (the option is a quantity).
struct RunResultRef {
  std::string path, result;
};
std::optional<RunResultRef> run_result_ref(const std::string& text) {
  const auto colon = text.rfind(':');
  const std::string path = colon == std::string::npos ? text : text.substr(0, colon);
  if (!names_run(path)) return std::nullopt;
  return RunResultRef{path, colon == std::string::npos ? "bulk_density" : text.substr(colon + 1)};
}

// D_o: a density, or a density result of a finished run (a drop-height run's bulk density in
// the kettle stands for grain that has fallen into a bin). Also says where it came from.
std::pair<double, std::string> initial_density(const BinOptions& o) {
  if (o.test_weight.empty() == o.initial_density.empty()) {
    throw InputError("expected one of --test-weight (e.g. 60lb/bu) or --initial-density (e.g. 780kg/m3)")
        .with_key("--test-weight");
  }
  if (!o.test_weight.empty()) return {option_quantity("--test-weight", o.test_weight, units::dim::density), ""};
  const auto ref = run_result_ref(o.initial_density);
  if (!ref) return {option_quantity("--initial-density", o.initial_density, units::dim::density), ""};
  const RunSummary run = read_run_summary(ref->path);
  auto fail = [&](const std::string& problem) {
    return InputError(problem).at(run.file).with_key("--initial-density");
  };
  if (run.interrupted) throw fail("expected a finished run; this one was interrupted");
  const RunResult* r = run.result(ref->result);
  if (r == nullptr) {
    std::vector<std::string> names;
    std::string densities;
    for (const RunResult& x : run.results) {
      names.push_back(x.name);
      if (x.unit == "kg/m3") densities += (densities.empty() ? "" : ", ") + x.name;
    }
    throw fail(fmt::format("no result '{}'{}; the run's densities: {} (choose one with RUN_DIR:RESULT)", ref->result,
                           did_you_mean(ref->result, names), densities.empty() ? "none" : densities));
  }
  if (r->unit != "kg/m3") throw fail(fmt::format("expected a density, but result '{}' is in '{}'", r->name, r->unit));
  if (!r->value) throw fail(fmt::format("the run could not compute result '{}'", r->name));
  return {*r->value, fmt::format("result {} of {}", r->name, run.file)};
}

Compressibility choose_model(const BinOptions& o) {
  const int chosen = static_cast<int>(!o.compressibility.empty()) + static_cast<int>(!o.wpacking.empty()) +
                     static_cast<int>(o.incompressible);
  if (chosen != 1) {
    throw InputError("expected exactly one of --compressibility FILE, --wpacking a,b,c or --incompressible")
        .with_key("--compressibility");
  }
  const Extrapolation beyond = [&] {
    try {
      return parse_extrapolation(o.extrapolate);
    } catch (const InputError& e) {
      throw e.with_key("--extrapolate");
    }
  }();
  if (!o.compressibility.empty()) {
    if (!names_run(o.compressibility)) {
      return Compressibility::read_csv(o.compressibility, beyond);
    }
    // A compression run (scenarios/compression.yaml): its results pressure_K and bulk_density_K.
    const RunSummary run = read_run_summary(o.compressibility);
    const auto points = run.curve("pressure", "bulk_density");
    if (run.interrupted || points.size() < 2) {
      throw InputError(fmt::format("expected a finished compression run with results pressure_K and bulk_density_K "
                                   "(K = 0, 1, ...), found {} level{}{}",
                                   points.size(), points.size() == 1 ? "" : "s",
                                   run.interrupted ? " (the run was interrupted)" : ""))
          .at(run.file)
          .with_key("--compressibility");
    }
    // The loose sample carries no load: its level is pressure 0 (the lid rests above it), as
    // measured to within 1 Pa.
    if (std::abs(points[0].first) > 1.0) {
      throw InputError(
          fmt::format("expected the first level at 0 pressure (the loose sample), found {:.4g} Pa", points[0].first))
          .at(run.file)
          .with_key("--compressibility");
    }
    std::vector<double> pressure{0.0}, density{points[0].second};
    for (std::size_t i = 1; i < points.size(); ++i) {
      pressure.push_back(points[i].first);
      density.push_back(points[i].second);
    }
    return Compressibility::density_table(pressure, density, beyond, run.file);
  }
  if (o.incompressible) return Compressibility::none();
  if (o.moisture.empty())
    throw InputError("the WPACKING form needs the moisture content, e.g. 12%").with_key("--moisture");
  std::vector<double> c;
  for (const std::string& item : split_list(o.wpacking)) {
    try {
      c.push_back(units::parse_number(item));
    } catch (const InputError& e) {
      throw e.with_key("--wpacking");
    }
  }
  if (c.size() != 3) {
    throw InputError(fmt::format("expected three coefficients a,b,c (kg/m3 per kPa, per sqrt(kPa), per kPa per % "
                                 "moisture), got '{}'",
                                 o.wpacking))
        .with_key("--wpacking");
  }
  const double moisture = option_quantity("--moisture", o.moisture, units::dim::dimensionless) * 100.0;
  try {
    return Compressibility::wpacking(c[0], c[1], c[2], moisture);
  } catch (const InputError& e) {
    throw e.with_key(e.key() == "moisture" ? "--moisture" : "--wpacking");
  }
}

BinSpec choose_bin(const BinOptions& o) {
  BinSpec s;
  s.diameter = option_quantity("--diameter", o.diameter, units::dim::length);
  s.grain_height = option_quantity("--grain-height", o.grain_height, units::dim::length);
  s.wall_friction = option_quantity("--wall-friction", o.wall_friction, units::dim::dimensionless);
  if (!o.k.empty() && !o.friction_angle.empty()) {
    throw InputError("expected --k or --friction-angle (Jaky: K = 1 - sin phi), not both").with_key("--k");
  }
  if (!o.k.empty()) s.lateral_ratio = option_quantity("--k", o.k, units::dim::dimensionless);
  if (!o.friction_angle.empty()) {
    try {
      s.lateral_ratio = jaky_lateral_ratio(option_quantity("--friction-angle", o.friction_angle, units::dim::angle));
    } catch (const InputError& e) {
      throw InputError(e.problem()).with_key("--friction-angle");
    }
  }
  try {
    s.surcharge = parse_surcharge(o.surcharge);
  } catch (const InputError& e) {
    throw e.with_key("--surcharge");
  }
  if (s.surcharge != Surcharge::level) {
    if (o.repose_angle.empty())
      throw InputError("a surcharge cone needs its angle, e.g. 25deg").with_key("--repose-angle");
    s.repose_angle = option_quantity("--repose-angle", o.repose_angle, units::dim::angle);
  }
  if (!o.hopper_angle.empty()) s.hopper_angle = option_quantity("--hopper-angle", o.hopper_angle, units::dim::angle);
  s.outlet_diameter = option_quantity("--outlet", o.outlet, units::dim::length);
  s.layers = o.layers;
  try {
    validate(s);
  } catch (const InputError& e) {
    // The spec's field names as the options are spelt.
    static const std::pair<const char*, const char*> names[] = {
        {"diameter", "--diameter"},           {"grain_height", "--grain-height"},
        {"repose_angle", "--repose-angle"},   {"hopper_angle", "--hopper-angle"},
        {"outlet_diameter", "--outlet"},      {"lateral_ratio", "--k"},
        {"wall_friction", "--wall-friction"}, {"layers", "--layers"}};
    for (const auto& [field, option] : names) {
      if (e.key() == field) throw InputError(e.problem()).with_key(option);
    }
    throw;
  }
  return s;
}

std::string describe(const BinSpec& s) {
  constexpr double deg = std::numbers::pi / 180.0;
  std::string top = s.surcharge == Surcharge::level    ? "level surface"
                    : s.surcharge == Surcharge::peaked ? fmt::format("peaked at {:.1f} deg", s.repose_angle / deg)
                                                       : fmt::format("drawn down at {:.1f} deg", s.repose_angle / deg);
  std::string bottom = s.hopper_angle > 0.0 ? fmt::format("hopper at {:.1f} deg to a {:.3f} m outlet",
                                                          s.hopper_angle / deg, s.outlet_diameter)
                                            : "flat floor";
  return fmt::format("{:.3f} m diameter, {:.3f} m of grain at the wall, {}, {}", s.diameter, s.grain_height, top,
                     bottom);
}

void run_bin(const BinOptions& o) {
  const BinSpec spec = choose_bin(o);
  const auto [d0, d0_source] = initial_density(o);
  const StandardBushel& standard = [&]() -> const StandardBushel& {
    try {
      return standard_bushel(o.grain);
    } catch (const InputError& e) {
      throw e.with_key("--grain");
    }
  }();
  const Compressibility model = choose_model(o);
  const BinResult r = fill_bin(spec, model, d0);

  const double lb_bu = units::parse("1lb/bu", units::dim::density), bushel = units::parse("1bu", units::dim::volume);
  const double p = r.packing_ratio(), d_s = standard.test_weight();
  if (!o.csv.empty() || !o.plot.empty()) {
    std::string csv = "depth_m,pressure_kPa,bulk_density_kg_m3,area_m2\n";
    for (const BinLevel& l : r.levels) {
      csv += fmt::format("{:.6f},{:.6f},{:.6f},{:.6f}\n", l.depth, l.pressure * 1e-3, l.density, l.area);
    }
    const std::string csv_path = o.csv.empty() ? o.plot + ".csv" : o.csv;
    io::write_file_atomically(csv_path, csv);
    if (!o.plot.empty()) {
      io::run_python(plot_script, {csv_path, o.plot, fmt::format("{} bin: {}", standard.grain, describe(spec))});
    }
  }
  if (o.json) {
    const nlohmann::ordered_json j = {
        {"bin", describe(spec)},
        {"diameter_m", spec.diameter},
        {"grain_height_m", spec.grain_height},
        {"lateral_ratio", spec.lateral_ratio},
        {"wall_friction", spec.wall_friction},
        {"layers", spec.layers},
        {"compressibility", model.describe()},
        {"grain", standard.grain},
        {"initial_density_kg_m3", d0},
        {"initial_density_from", d0_source},
        {"standard_test_weight_kg_m3", d_s},
        {"volume_m3", r.volume},
        {"volume_bu", r.volume / bushel},
        {"mass_kg", r.mass},
        {"standard_bushels", r.mass / standard.mass()},
        {"average_density_kg_m3", r.average_density()},
        {"bottom_pressure_Pa", r.bottom_pressure()},
        {"packing_ratio", p},
        {"compaction_factor", compaction_factor(p)},
        {"pack_factor", pack_factor(p, d0, d_s)},
    };
    fmt::print("{}\n", j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace));
    return;
  }
  fmt::print("bin                     {}\n", describe(spec));
  fmt::print("grain                   {}, initial bulk density {:.1f} kg/m3 ({:.2f} lb/bu); standard {:.0f} lb/bu\n",
             standard.grain, d0, d0 / lb_bu, standard.pounds);
  if (!d0_source.empty()) fmt::print("initial density from    {}\n", d0_source);
  fmt::print("compressibility         {}\n", model.describe());
  fmt::print("Janssen                 K {:.3f}, mu_w {:.3f}, {} layers\n", spec.lateral_ratio, spec.wall_friction,
             spec.layers);
  fmt::print("volume                  {:.2f} m3   {:.0f} bu\n", r.volume, r.volume / bushel);
  fmt::print("mass                    {:.0f} kg   {:.2f} t\n", r.mass, r.mass * 1e-3);
  fmt::print("standard bushels        {:.0f}   ({:.0f} lb each)\n", r.mass / standard.mass(), standard.pounds);
  fmt::print("average bulk density    {:.1f} kg/m3   {:.2f} lb/bu\n", r.average_density(), r.average_density() / lb_bu);
  fmt::print("pressure at the bottom  {:.2f} kPa\n", r.bottom_pressure() * 1e-3);
  fmt::print("packing ratio           {:.4f}\n", p);
  fmt::print("compaction factor       {:.4f}\n", compaction_factor(p));
  fmt::print("pack factor             {:.4f}\n", pack_factor(p, d0, d_s));
  if (!o.csv.empty()) fmt::print("profile                 {}\n", o.csv);
  if (!o.plot.empty()) fmt::print("plot                    {}\n", o.plot);
}

}  // namespace

void add_bin_command(CLI::App& app) {
  auto o = std::make_shared<BinOptions>();
  auto* cmd = app.add_subcommand("bin", "Mass of grain in a round bin: Janssen pressure, compaction, pack factor");
  cmd->add_option("--diameter", o->diameter, "Bin inside diameter, e.g. 9.14m or 30ft")->required();
  cmd->add_option("--grain-height", o->grain_height, "Grain height at the wall (eave height if full), e.g. 7.3m")
      ->required();
  cmd->add_option("--test-weight", o->test_weight, "Initial density as a test weight, e.g. 60lb/bu");
  cmd->add_option("--initial-density", o->initial_density,
                  "Initial (uncompacted) in-bin density instead: e.g. 790kg/m3, or a drop-height run's folder and "
                  "result, RUN_DIR[:RESULT] (default result bulk_density)");
  cmd->add_option("--grain", o->grain, "Grain of the standard bushel (wheat, corn, soybeans, ...)")
      ->capture_default_str();
  cmd->add_option("--compressibility", o->compressibility,
                  "CSV of pressure and bulk_density (or packing_ratio), values with units, from 0 pressure; or the "
                  "folder of a compression run (its results pressure_K, bulk_density_K)");
  cmd->add_option("--wpacking", o->wpacking, "WPACKING coefficients a,b,c: D - D_o = a P + b sqrt(P) + c P MC");
  cmd->add_option("--moisture", o->moisture, "Moisture content (wet basis) for --wpacking, e.g. 12%");
  cmd->add_flag("--incompressible", o->incompressible, "No compaction: the density stays the initial one");
  cmd->add_option("--extrapolate", o->extrapolate, "Beyond a table's pressures: error, hold or linear")
      ->capture_default_str();
  cmd->add_option("--wall-friction", o->wall_friction, "Grain-on-wall friction coefficient mu_w")
      ->capture_default_str();
  cmd->add_option("--k", o->k, "Janssen's lateral pressure ratio K (default 0.5)");
  cmd->add_option("--friction-angle", o->friction_angle, "Internal friction angle: K = 1 - sin(phi) (Jaky)");
  cmd->add_option("--surcharge", o->surcharge, "Grain surface: level, peaked or inverted")->capture_default_str();
  cmd->add_option("--repose-angle", o->repose_angle, "Angle of the peaked or inverted cone, e.g. 25deg");
  cmd->add_option("--hopper-angle", o->hopper_angle, "Hopper bottom: wall angle from the horizontal, e.g. 45deg");
  cmd->add_option("--outlet", o->outlet, "Hopper outlet diameter")->capture_default_str();
  cmd->add_option("--layers", o->layers, "Layers over the grain height")->capture_default_str();
  cmd->add_option("--csv", o->csv, "Write pressure and density against depth to this CSV");
  cmd->add_option("--plot", o->plot, "Draw pressure and density against depth to this PNG (needs matplotlib)");
  cmd->add_flag("--json", o->json, "Print JSON (SI units) instead of a table");
  cmd->callback([o] { run_bin(*o); });
}

}  // namespace bushel::cli
