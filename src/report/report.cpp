#include "bushel/report/report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>

#include "bushel/core/input_error.hpp"
#include "bushel/io/csv.hpp"
#include "bushel/scenario/scenario.hpp"

namespace bushel {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// Tables show pressures in kPa, lengths in mm, masses in g and volumes in cm3: the sizes of
// the laboratory; the CSV files keep the summary's units.
struct Display {
  double factor = 1.0;
  std::string unit;
};

Display display_of(const std::string& unit) {
  if (unit == "Pa") return {1e-3, "kPa"};
  if (unit == "m") return {1e3, "mm"};
  if (unit == "kg") return {1e3, "g"};
  if (unit == "m3") return {1e6, "cm3"};
  return {1.0, unit};
}

std::string number_text(double v) {
  if (!std::isfinite(v)) return "n/a";
  const double a = std::abs(v);
  if (a >= 100.0) return fmt::format("{:.1f}", v);
  if (a >= 1.0) return fmt::format("{:.3f}", v);
  return a == 0.0 ? "0" : fmt::format("{:.4g}", v);
}

std::string csv_number(double v) { return std::isfinite(v) ? fmt::format("{:.10g}", v) : ""; }

std::string labelled(const std::string& name, const std::string& unit) {
  return unit.empty() ? name : name + " [" + unit + "]";
}

// A CSV field, quoted when it holds a comma or a quote.
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string csv_line(const std::vector<std::string>& fields) {
  std::string line;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i) line += ',';
    line += csv_field(fields[i]);
  }
  return line + "\n";
}

// A file name from free text: letters, digits, '.', '_' and '-'.
std::string file_stem(const std::string& s) {
  std::string out;
  for (const char c : s) out += std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' ? c : '_';
  return out;
}

double value_of(const RunSummary& run, const std::string& result) {
  const RunResult* r = run.result(result);
  return r && r->value ? *r->value : nan;
}

std::string unit_of(const std::vector<const RunSummary*>& runs, const std::string& result) {
  for (const RunSummary* run : runs) {
    if (const RunResult* r = run->result(result); r && r->value) return r->unit;
  }
  return "";
}

struct Case {
  const RunSummary* run = nullptr;
  std::string label;
};

// Each run's label: its folder's name, or the path as given where two folders share a name.
std::vector<Case> label_cases(const std::vector<RunSummary>& runs) {
  std::vector<Case> cases;
  std::map<std::string, int> uses;
  for (const RunSummary& r : runs) {
    std::filesystem::path p = std::filesystem::path(r.directory).lexically_normal();
    if (p.filename().empty()) p = p.parent_path();
    if (p.extension() == ".json") p = p.parent_path();
    cases.push_back({&r, p.filename().string().empty() ? r.directory : p.filename().string()});
    ++uses[cases.back().label];
  }
  for (Case& c : cases) {
    if (uses[c.label] > 1) c.label = c.run->directory;
  }
  return cases;
}

struct Group {
  std::string scenario;  // name
  std::vector<Case> cases;
  std::vector<std::string> varied;   // parameters that differ between the runs
  std::vector<std::string> results;  // every result name, in order of first appearance

  std::vector<const RunSummary*> runs() const {
    std::vector<const RunSummary*> out;
    for (const Case& c : cases) out.push_back(c.run);
    return out;
  }
};

std::vector<Group> group_by_scenario(const std::vector<Case>& cases) {
  std::vector<Group> groups;
  for (const Case& c : cases) {
    auto g = std::find_if(groups.begin(), groups.end(),
                          [&](const Group& x) { return x.scenario == c.run->scenario_name(); });
    if (g == groups.end()) g = groups.insert(groups.end(), Group{c.run->scenario_name(), {}, {}, {}});
    g->cases.push_back(c);
  }
  for (Group& g : groups) {
    std::vector<std::string> names;
    for (const Case& c : g.cases) {
      for (const auto& [name, value] : c.run->parameters) {
        if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
      }
      for (const RunResult& r : c.run->results) {
        if (std::find(g.results.begin(), g.results.end(), r.name) == g.results.end()) g.results.push_back(r.name);
      }
    }
    for (const std::string& name : names) {
      const auto first = g.cases.front().run->parameter(name);
      const bool differs =
          std::any_of(g.cases.begin(), g.cases.end(), [&](const Case& c) { return c.run->parameter(name) != first; });
      if (differs) g.varied.push_back(name);
    }
  }
  return groups;
}

ReportBlock heading_block(std::string text) { return {ReportBlock::Kind::heading, std::move(text), {}, {}, {}}; }
ReportBlock text_block(std::string text) { return {ReportBlock::Kind::text, std::move(text), {}, {}, {}}; }
ReportBlock list_block(std::string caption, std::vector<std::string> items) {
  return {ReportBlock::Kind::list, std::move(caption), std::move(items), {}, {}};
}
ReportBlock table_block(std::string caption, ReportTable table) {
  return {ReportBlock::Kind::table, std::move(caption), {}, std::move(table), {}};
}
ReportBlock figure_block(std::string caption, ReportFigure figure) {
  return {ReportBlock::Kind::figure, std::move(caption), {}, {}, std::move(figure)};
}

std::string varied_text(const Group& g, const RunSummary& run) {
  std::string out;
  for (const std::string& p : g.varied)
    out += (out.empty() ? "" : ", ") + p + " = " + run.parameter(p).value_or("(none)");
  return out;
}

// --- the runs ----------------------------------------------------------------------------------

// The build that ran a case (a summary names it since runs recorded their engine); several
// when a checkpoint was continued by another build, which its warnings explain.
std::string engine_text(const RunSummary& r) {
  if (r.engines.empty()) return "(not recorded)";
  if (r.engines.size() > 1) return fmt::format("{} builds (see warnings)", r.engines.size());
  return r.engines.front();
}

ReportSection runs_section(const std::vector<Group>& groups) {
  ReportSection s{"Runs", {}};
  ReportTable t{{"case", "scenario", "varied parameters", "status", "particles made", "simulated [s]", "wall [h]",
                 "particle-steps/s", "engine", "warnings"},
                {}};
  std::vector<std::string> warnings;
  for (const Group& g : groups) {
    for (const Case& c : g.cases) {
      const RunSummary& r = *c.run;
      std::size_t made = 0;
      for (const FactorySummary& f : r.factories) made += f.count;
      t.rows.push_back({c.label, g.scenario, varied_text(g, r),
                        r.interrupted ? fmt::format("interrupted at {:.3f} s", r.simulated_time) : "done",
                        std::to_string(made), fmt::format("{:.3f}", r.simulated_time),
                        fmt::format("{:.2f}", r.wall_time / 3600.0), fmt::format("{:.3g}", r.particle_steps_per_s),
                        engine_text(r), std::to_string(r.warnings.size())});
      constexpr std::size_t shown = 5;
      for (std::size_t i = 0; i < std::min(shown, r.warnings.size()); ++i)
        warnings.push_back(c.label + ": " + r.warnings[i]);
      if (r.warnings.size() > shown) {
        warnings.push_back(fmt::format("{}: and {} more (its summary.json)", c.label, r.warnings.size() - shown));
      }
    }
  }
  s.blocks.push_back(table_block("", std::move(t)));
  if (!warnings.empty()) s.blocks.push_back(list_block("Warnings", std::move(warnings)));
  return s;
}

// --- curves --------------------------------------------------------------------------------------

struct Curve {
  std::string x, y;
  std::vector<std::string> suffixes;  // K with X_K and Y_K in some run
  std::vector<std::string> others;    // NAME of the other results NAME_K
};

std::vector<Curve> find_curves(const Group& g, const ReportOptions& o) {
  std::vector<Curve> curves;
  for (const std::string& spec : o.curves) {
    const std::size_t colon = spec.find(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == spec.size()) {
      throw InputError("expected X:Y (results X_K and Y_K pair up by their suffix K), got '" + spec + "'")
          .with_key("--curve");
    }
    Curve c{spec.substr(0, colon), spec.substr(colon + 1), {}, {}};
    for (const std::string& name : g.results) {
      if (name.rfind(c.x + "_", 0) != 0) continue;
      const std::string k = name.substr(c.x.size() + 1);
      if (std::find(g.results.begin(), g.results.end(), c.y + "_" + k) != g.results.end()) c.suffixes.push_back(k);
    }
    if (c.suffixes.empty()) continue;
    for (const std::string& name : g.results) {
      for (const std::string& k : c.suffixes) {
        const std::string tail = "_" + k;
        if (name.size() <= tail.size() || name.compare(name.size() - tail.size(), tail.size(), tail) != 0) continue;
        const std::string stem = name.substr(0, name.size() - tail.size());
        if (stem != c.x && stem != c.y && std::find(c.others.begin(), c.others.end(), stem) == c.others.end()) {
          c.others.push_back(stem);
        }
      }
    }
    curves.push_back(std::move(c));
  }
  return curves;
}

bool in_curve(const Curve& c, const std::string& name) {
  for (const std::string& k : c.suffixes) {
    if (name == c.x + "_" + k || name == c.y + "_" + k) return true;
    for (const std::string& o : c.others) {
      if (name == o + "_" + k) return true;
    }
  }
  return false;
}

void add_curve(ReportSection& s, const Group& g, const Curve& c) {
  const auto runs = g.runs();
  const Display dx = display_of(unit_of(runs, c.x + "_" + c.suffixes.front()));
  const Display dy = display_of(unit_of(runs, c.y + "_" + c.suffixes.front()));
  ReportTable t{{"case", "level", labelled(c.x, dx.unit), labelled(c.y, dy.unit)}, {}};
  std::vector<Display> other_display;
  for (const std::string& o : c.others) {
    other_display.push_back(display_of(unit_of(runs, o + "_" + c.suffixes.front())));
    t.header.push_back(labelled(o, other_display.back().unit));
  }
  ReportFigure f{file_stem(g.scenario + "-" + c.y + "-" + c.x) + ".png",
                 "lines",
                 g.scenario,
                 labelled(c.x, dx.unit),
                 labelled(c.y, dy.unit),
                 {},
                 {}};
  for (const Case& cs : g.cases) {
    struct Point {
      double x, y;
      std::string k;
    };
    std::vector<Point> points;
    for (const std::string& k : c.suffixes) {
      points.push_back({value_of(*cs.run, c.x + "_" + k), value_of(*cs.run, c.y + "_" + k), k});
    }
    std::stable_sort(points.begin(), points.end(), [](const Point& a, const Point& b) { return a.x < b.x; });
    ReportSeries series{cs.label, {}, {}, {}};
    for (const Point& p : points) {
      std::vector<std::string> row{cs.label, p.k, number_text(p.x * dx.factor), number_text(p.y * dy.factor)};
      for (std::size_t i = 0; i < c.others.size(); ++i) {
        row.push_back(number_text(value_of(*cs.run, c.others[i] + "_" + p.k) * other_display[i].factor));
      }
      t.rows.push_back(std::move(row));
      if (std::isfinite(p.x) && std::isfinite(p.y)) {
        series.x.push_back(p.x * dx.factor);
        series.y.push_back(p.y * dy.factor);
      }
    }
    f.series.push_back(std::move(series));
  }
  s.blocks.push_back(heading_block(fmt::format("{} against {}", c.y, c.x)));
  s.blocks.push_back(figure_block(fmt::format("{} against {}, one line per case", c.y, c.x), std::move(f)));
  s.blocks.push_back(table_block(fmt::format("Results {0}_K and {1}_K{2}", c.x, c.y,
                                             c.others.empty() ? "" : " with the other results of each level"),
                                 std::move(t)));
}

// --- references ----------------------------------------------------------------------------------

// "826.1 ± 1.2": the value, and its standard deviation (if finite) to as many decimals.
std::string with_spread(double value, double sd) {
  const std::string v = number_text(value);
  if (!std::isfinite(sd)) return v;
  const std::size_t point = v.find('.');
  if (v.find_first_of("eE") != std::string::npos) return v + " ± " + number_text(sd);
  const int decimals = point == std::string::npos ? 0 : static_cast<int>(v.size() - point - 1);
  return v + fmt::format(" ± {:.{}f}", sd, decimals);
}

void add_references(ReportSection& s, Report& report, const Group& g, const std::vector<ReferenceValue>& references) {
  const std::size_t first = report.comparisons.size();
  std::vector<std::string> results;  // with a reference in some run, in the order of the results
  std::map<std::string, std::vector<std::string>> sources;
  const auto runs = g.runs();
  for (const std::string& name : g.results) {
    // Where no run has a value (all interrupted, say), none says its unit: the reference's is used.
    const bool known =
        std::any_of(runs.begin(), runs.end(), [&](const RunSummary* r) { return std::isfinite(value_of(*r, name)); });
    const std::string unit_of_runs = known ? unit_of(runs, name) : std::string();
    for (const Case& c : g.cases) {
      if (!c.run->result(name)) continue;
      for (const ReferenceValue& ref : references) {
        if (ref.result != name || !reference_applies(ref, *c.run)) continue;
        const std::string unit = known ? unit_of_runs : std::string(result_unit(ref.dimension));
        const RunResult in_unit{name, std::nullopt, unit, ""};
        const double reference = reference_in_unit_of(ref, in_unit);
        ReferenceValue spread = ref;  // (the standard deviation, converted as the value is)
        spread.value = ref.sd.value_or(nan);
        const double sim = value_of(*c.run, name);
        report.comparisons.push_back({c.label, name, unit, sim, reference, reference_in_unit_of(spread, in_unit),
                                      ref.source, (sim - reference) / reference});
        if (std::find(results.begin(), results.end(), name) == results.end()) results.push_back(name);
        auto& src = sources[name];
        if (std::find(src.begin(), src.end(), ref.source) == src.end()) src.push_back(ref.source);
      }
    }
  }
  if (report.comparisons.size() == first) return;

  ReportTable t{{"case", "result", "bushel", "reference", "source", "difference"}, {}};
  std::string text = "case,result,unit,bushel,reference,reference_sd,source,difference_pct\n";
  for (std::size_t i = first; i < report.comparisons.size(); ++i) {
    const ReportComparison& c = report.comparisons[i];
    const Display d = display_of(c.unit);
    t.rows.push_back({c.case_label, labelled(c.result, d.unit), number_text(c.bushel * d.factor),
                      with_spread(c.reference * d.factor, c.reference_sd * d.factor), c.source,
                      std::isfinite(c.difference) ? fmt::format("{:+.1f} %", 100.0 * c.difference) : "n/a"});
    text += csv_line({c.case_label, c.result, c.unit, csv_number(c.bushel), csv_number(c.reference),
                      std::isfinite(c.reference_sd) ? csv_number(c.reference_sd) : "", c.source,
                      csv_number(100.0 * c.difference)});
  }
  s.blocks.push_back(heading_block("Against measurements"));
  for (const std::string& name : results) {
    const auto first_of =
        std::find_if(report.comparisons.begin() + static_cast<std::ptrdiff_t>(first), report.comparisons.end(),
                     [&](const ReportComparison& c) { return c.result == name; });
    const Display d = display_of(first_of->unit);
    ReportFigure f{
        file_stem(g.scenario + "-" + name) + ".png", "categories", g.scenario, "case", labelled(name, d.unit), {}, {}};
    f.series.push_back({"bushel", {}, {}, {}});
    for (const std::string& src : sources[name]) f.series.push_back({src, {}, {}, {}});
    for (const Case& c : g.cases) {
      f.categories.push_back(c.label);
      for (ReportSeries& series : f.series) series.y.push_back(nan), series.yerr.push_back(nan);
      f.series[0].y.back() = value_of(*c.run, name) * d.factor;
    }
    for (std::size_t i = first; i < report.comparisons.size(); ++i) {
      const ReportComparison& c = report.comparisons[i];
      if (c.result != name) continue;
      const auto row = std::find(f.categories.begin(), f.categories.end(), c.case_label) - f.categories.begin();
      for (ReportSeries& series : f.series) {
        if (series.label != c.source) continue;
        series.y[static_cast<std::size_t>(row)] = c.reference * d.factor;
        series.yerr[static_cast<std::size_t>(row)] = c.reference_sd * d.factor;  // (an error bar where it has one)
      }
    }
    s.blocks.push_back(figure_block(name + " of each case beside the measured and published values", std::move(f)));
  }
  s.blocks.push_back(table_block("difference = (bushel - reference) / reference", std::move(t)));
  report.csv_files.push_back({file_stem(g.scenario) + "-references.csv", text});
}

// --- heap profiles -------------------------------------------------------------------------------

void add_heap_profiles(ReportSection& s, std::vector<ReportCsv>& csv, const Group& g, const ReportOptions& o) {
  ReportFigure f{
      file_stem(g.scenario) + "-heap.png", "lines", g.scenario, "radius [mm]", "surface height [mm]", {}, {}};
  std::string text = "case,sensor,stage,radius_m,height_m\n";
  std::vector<std::string> used;  // "case: stage" where a run had no stage of the chosen name
  for (const Case& c : g.cases) {
    const StageReport* stage = o.heap_stage.empty() ? nullptr : c.run->stage(o.heap_stage);
    if (!stage || stage->profiles.empty()) {
      stage = nullptr;
      for (const StageReport& st : c.run->stages) {
        if (!st.profiles.empty()) stage = &st;
      }
      if (stage) used.push_back(c.label + ": '" + stage->name + "'");
    }
    if (!stage) continue;
    for (const StageReport::Profile& p : stage->profiles) {
      ReportSeries series{stage->profiles.size() > 1 ? c.label + " " + p.sensor : c.label, {}, {}, {}};
      for (std::size_t i = 0; i < p.radius.size(); ++i) {
        series.x.push_back(p.radius[i] * 1e3);
        series.y.push_back(p.height[i] * 1e3);
        text += csv_line({c.label, p.sensor, stage->name, csv_number(p.radius[i]), csv_number(p.height[i])});
      }
      f.series.push_back(std::move(series));
    }
  }
  if (f.series.empty()) return;
  std::string caption = o.heap_stage.empty() ? "Heap profiles at the end of each run's last stage with one"
                                             : "Heap profiles at the end of stage '" + o.heap_stage + "'";
  if (!used.empty()) {
    caption += "; runs without it, at their last stage with one (";
    for (std::size_t i = 0; i < used.size(); ++i) caption += (i ? ", " : "") + used[i];
    caption += ")";
  }
  s.blocks.push_back(heading_block("Heap profiles"));
  s.blocks.push_back(figure_block(caption + ". Height of the highest grain over each ring.", std::move(f)));
  csv.push_back({file_stem(g.scenario) + "-heap.csv", text});
}

// --- composition ---------------------------------------------------------------------------------

void add_composition(ReportSection& s, const Group& g, const ReportOptions& o) {
  std::vector<std::string> types;
  for (const std::string& name : g.results) {
    if (name.rfind(o.composition_prefix, 0) == 0 && name.size() > o.composition_prefix.size()) {
      types.push_back(name.substr(o.composition_prefix.size()));
    }
  }
  if (types.empty()) return;
  ReportTable t{{"case", "type", "made [mass share]", "in the sample [mass share]"}, {}};
  ReportFigure f{file_stem(g.scenario) + "-composition.png", "stacked", g.scenario, "", "mass share", {}, {}};
  for (const std::string& type : types) f.series.push_back({type, {}, {}, {}});
  for (const Case& c : g.cases) {
    double total = 0.0;
    std::map<std::string, double> made;
    for (const FactorySummary& fa : c.run->factories) {
      for (const FactoryTypeSummary& ft : fa.types) {
        made[ft.type] += ft.mass;
        total += ft.mass;
      }
    }
    f.categories.push_back(c.label + " made");
    f.categories.push_back(c.label + " sample");
    for (std::size_t i = 0; i < types.size(); ++i) {
      const double m = total > 0.0 ? made[types[i]] / total : nan;
      const double in = value_of(*c.run, o.composition_prefix + types[i]);
      t.rows.push_back({c.label, types[i], number_text(m), number_text(in)});
      f.series[i].y.push_back(m);
      f.series[i].y.push_back(in);
    }
  }
  s.blocks.push_back(heading_block("Composition"));
  s.blocks.push_back(
      figure_block("Mass shares of the particle types: made by the factories, and in the sample (results " +
                       o.composition_prefix + "TYPE)",
                   std::move(f)));
  s.blocks.push_back(table_block("", std::move(t)));
}

// --- time series ---------------------------------------------------------------------------------

// The kinetic energy (in all or per particle) and the mass in each sensor over time, a line
// per case, from the runs' timeseries.csv (where it is beside the summary and has those
// columns), at most max_points points a line.
void add_time_series(ReportSection& s, const Group& g) {
  constexpr std::size_t max_points = 2000;
  std::vector<std::string> names;  // the columns drawn, in the order first met
  std::map<std::string, ReportFigure> figures;
  for (const Case& c : g.cases) {
    const std::filesystem::path path = std::filesystem::path(c.run->directory) / "timeseries.csv";
    std::error_code missing;
    if (!std::filesystem::exists(path, missing)) continue;
    const io::CsvTable t = io::CsvTable::read(path.string());
    if (!t.has_column("time") || t.rows().empty()) continue;
    const std::size_t c_time = t.column("time"), step = (t.rows().size() + max_points - 1) / max_points;
    for (std::size_t k = 0; k < t.header().size(); ++k) {
      const std::string& name = t.header()[k];
      const bool mass = name.size() > 5 && name.ends_with(".mass");
      const bool energy = name == "kinetic_energy" || name == "kinetic_energy_per_particle";
      if (!energy && !mass) continue;
      auto [it, fresh] = figures.try_emplace(name);
      ReportFigure& f = it->second;
      if (fresh) {
        names.push_back(name);
        const std::string unit = mass ? " [g]" : " [J]";
        f = {file_stem(g.scenario + "-series-" + name) + ".png", "lines", g.scenario, "time [s]", name + unit, {}, {}};
      }
      ReportSeries line{c.label, {}, {}, {}};
      for (std::size_t r = 0; r < t.rows().size(); r += step) {
        line.x.push_back(t.number(t.rows()[r], c_time));
        line.y.push_back(t.number(t.rows()[r], k) * (mass ? 1e3 : 1.0));
      }
      f.series.push_back(std::move(line));
    }
  }
  if (names.empty()) return;
  s.blocks.push_back(heading_block("Time series"));
  for (const std::string& name : names) {
    const std::string what = name.ends_with(".mass") ? "Mass in sensor " + name.substr(0, name.size() - 5)
                                                     : std::string("Kinetic energy of the grain");
    s.blocks.push_back(figure_block(what + " (timeseries.csv: " + name + ")", std::move(figures[name])));
  }
}

// The last frame of each case that wrote frames (outputs.frames), at most o.max_frames cases: a
// section through the axis, drawn by the bushel Python package where the program has it.
void add_last_frames(ReportSection& s, const Group& g, const ReportOptions& o) {
  std::vector<const Case*> with;
  for (const Case& c : g.cases) {
    const std::filesystem::path frames = std::filesystem::path(c.run->directory) / "frames";
    std::error_code missing;
    if (std::filesystem::exists(frames / "particles.pvd", missing) &&
        std::filesystem::exists(frames / "geometry.pvd", missing)) {
      with.push_back(&c);
    }
  }
  if (with.empty()) return;
  s.blocks.push_back(heading_block("Last frames"));
  if (!o.frames) {
    s.blocks.push_back(text_block(
        "The last frames are not drawn: this build of bushel has no Python package (it needs pybind11, which "
        "scripts/setup.sh installs). ParaView opens the runs' frames/particles.pvd."));
    return;
  }
  if (with.size() > o.max_frames) {
    s.blocks.push_back(text_block(fmt::format("The first {} of the {} runs with frames.", o.max_frames, with.size())));
    with.resize(o.max_frames);
  }
  for (const Case* c : with) {
    ReportFigure f{
        file_stem(g.scenario + "-frame-" + c->label) + ".png",         "frame", c->label, "x [mm]", "z [mm]", {}, {},
        (std::filesystem::path(c->run->directory) / "frames").string()};
    s.blocks.push_back(figure_block(
        fmt::format("{}: the last frame (frames/particles.pvd) cut by the plane y = 0; walls as lines, the grains "
                    "the plane cuts as discs, coloured by type",
                    c->label),
        std::move(f)));
  }
}

// --- one scenario --------------------------------------------------------------------------------

ReportSection scenario_section(const Group& g, const std::vector<ReferenceValue>& references, const ReportOptions& o,
                               Report& report) {
  std::vector<ReportCsv>& csv = report.csv_files;
  ReportSection s{g.scenario, {}};
  const RunSummary& first = *g.cases.front().run;
  // The scenario's path as seen from here, where it lies below (a report travels with its project).
  std::error_code ec;
  const std::filesystem::path here = std::filesystem::current_path(ec);
  const std::filesystem::path relative = std::filesystem::path(first.scenario).lexically_proximate(here);
  const bool below = !ec && !relative.empty() && *relative.begin() != "..";
  const std::string scenario = below ? relative.string() : first.scenario;
  std::string intro = fmt::format("{} run{} of `{}`.", g.cases.size(), g.cases.size() == 1 ? "" : "s", scenario);
  if (!g.varied.empty()) {
    intro += " Varied:";
    for (std::size_t i = 0; i < g.varied.size(); ++i) intro += (i ? ", " : " ") + g.varied[i];
    intro += ".";
  }
  std::string same;
  for (const auto& [name, value] : first.parameters) {
    if (std::find(g.varied.begin(), g.varied.end(), name) == g.varied.end()) {
      same += (same.empty() ? "" : ", ") + name + " = " + value;
    }
  }
  if (!same.empty()) intro += " The same in every run: " + same + ".";
  s.blocks.push_back(text_block(intro));

  const std::vector<Curve> curves = find_curves(g, o);
  std::vector<std::string> plain;  // results for the main table
  for (const std::string& name : g.results) {
    const bool curve = std::any_of(curves.begin(), curves.end(), [&](const Curve& c) { return in_curve(c, name); });
    const bool share = name.rfind(o.composition_prefix, 0) == 0;
    if (!curve && !share) plain.push_back(name);
  }
  const auto runs = g.runs();
  if (!plain.empty()) {
    ReportTable t{{"case"}, {}};
    for (const std::string& p : g.varied) t.header.push_back(p);
    std::vector<Display> displays;
    for (const std::string& name : plain) {
      displays.push_back(display_of(unit_of(runs, name)));
      t.header.push_back(labelled(name, displays.back().unit));
    }
    for (const Case& c : g.cases) {
      std::vector<std::string> row{c.label};
      for (const std::string& p : g.varied) row.push_back(c.run->parameter(p).value_or(""));
      for (std::size_t i = 0; i < plain.size(); ++i) {
        const RunResult* r = c.run->result(plain[i]);
        row.push_back(number_text(value_of(*c.run, plain[i]) * displays[i].factor) +
                      (r != nullptr && !r->not_full.empty() ? " (not full)" : ""));
      }
      t.rows.push_back(std::move(row));
    }
    s.blocks.push_back(table_block(
        "Results (n/a: not computed, e.g. an interrupted run; not full: a density over a sensor the grain did not "
        "fill, see the warnings)",
        std::move(t)));
  }

  // Every result of every case, in the summary's units, for other tools.
  std::vector<std::string> header{"case", "directory", "status"};
  header.insert(header.end(), g.varied.begin(), g.varied.end());
  header.insert(header.end(), g.results.begin(), g.results.end());
  std::string text = csv_line(header);
  for (const Case& c : g.cases) {
    std::vector<std::string> row{c.label, c.run->directory, c.run->interrupted ? "interrupted" : "done"};
    for (const std::string& p : g.varied) row.push_back(c.run->parameter(p).value_or(""));
    for (const std::string& name : g.results) row.push_back(csv_number(value_of(*c.run, name)));
    text += csv_line(row);
  }
  csv.push_back({file_stem(g.scenario) + "-results.csv", text});

  add_references(s, report, g, references);
  for (const Curve& c : curves) add_curve(s, g, c);
  add_heap_profiles(s, csv, g, o);
  add_composition(s, g, o);
  add_time_series(s, g);
  add_last_frames(s, g, o);
  return s;
}

}  // namespace

std::vector<const ReportFigure*> Report::figures() const {
  std::vector<const ReportFigure*> out;
  for (const ReportSection& s : sections) {
    for (const ReportBlock& b : s.blocks) {
      if (b.kind == ReportBlock::Kind::figure) out.push_back(&b.figure);
    }
  }
  return out;
}

Report build_report(const std::vector<RunSummary>& runs, const std::vector<ReferenceValue>& references,
                    const ReportOptions& options) {
  if (runs.empty()) throw InputError("expected at least one run folder");
  Report report{options.title, {}, {}, {}};
  const std::vector<Group> groups = group_by_scenario(label_cases(runs));
  report.sections.push_back(runs_section(groups));
  for (const Group& g : groups) report.sections.push_back(scenario_section(g, references, options, report));
  return report;
}

}  // namespace bushel
