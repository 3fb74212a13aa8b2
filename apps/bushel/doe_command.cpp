// `bushel doe analyze|optimize`: the statistics of a designed experiment from any CSV with
// factor and response columns (doe/regression.hpp), as tables, JSON and PNG plots.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>

#include "bushel/core/choice.hpp"
#include "bushel/core/did_you_mean.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/doe/campaign.hpp"
#include "bushel/doe/design.hpp"
#include "bushel/doe/desirability.hpp"
#include "bushel/doe/distributions.hpp"
#include "bushel/doe/factor_table.hpp"
#include "bushel/doe/regression.hpp"
#include "bushel/io/atomic_file.hpp"
#include "bushel/io/csv.hpp"
#include "bushel/io/python_plot.hpp"
#include "bushel/scenario/scenario.hpp"
#include "bushel/units/units.hpp"
#include "commands.hpp"

namespace bushel::cli {

namespace {

struct DoeOptions {
  std::string file, factors, response, model = "main", levels, plots, fix, goals, block, where;
  // design
  std::string kind, ccd = "face", generators, out;
  int runs = 0, centre = -1, fraction = 0, blocks = 1;
  std::uint64_t seed = 1;
  bool no_randomize = false;
  // campaign
  std::vector<std::string> command;
  std::string scenario;
  std::vector<std::string> sets;
  int jobs = 1, threads = 0;
  double alpha = 0.1;
  double target = std::numeric_limits<double>::quiet_NaN();
  bool json = false;
};

// A design's columns that are not factors (doe design writes them).
const std::vector<std::string> bookkeeping_columns = {"std_order", "run_order", "center_pt", "pt_type", "block"};

// "name=low:high,..." -> levels; `option` names the option in errors.
std::map<std::string, std::pair<double, double>> parse_levels(const std::string& text, const std::string& option) {
  std::map<std::string, std::pair<double, double>> out;
  for (const std::string& item : split_list(text, ',')) {
    const auto eq = item.find('='), colon = item.find(':');
    if (eq == std::string::npos || colon == std::string::npos || colon < eq) {
      throw InputError(fmt::format("expected name=low:high, got '{}'", item)).with_key(option);
    }
    const std::string name = item.substr(0, eq);
    if (name.empty()) throw InputError(fmt::format("a factor without a name in '{}'", item)).with_key(option);
    if (out.contains(name)) {
      throw InputError(fmt::format("the factor '{}' is given twice; give each factor once", name)).with_key(option);
    }
    try {
      out[name] = {units::parse_number(item.substr(eq + 1, colon - eq - 1)),
                   units::parse_number(item.substr(colon + 1))};
    } catch (const InputError& e) {
      throw e.with_key(option);
    }
    if (!(out[name].first < out[name].second)) {
      throw InputError(fmt::format("the factor '{}' has its low level {:g} above or at its high {:g}", name,
                                   out[name].first, out[name].second))
          .with_key(option);
    }
  }
  return out;
}

struct Analysis {
  doe::FactorTable table;
  doe::Fit fit;
};

Analysis analyze(const DoeOptions& o) {
  const std::vector<std::string> factors = split_list(o.factors, ',');
  if (factors.empty()) throw InputError("expected factor columns, e.g. fr_ww,fs_ww").with_key("--factors");
  if (!(o.alpha > 0.0 && o.alpha < 1.0)) throw InputError("expected alpha in (0, 1)").with_key("--alpha");
  const doe::ModelKind kind = [&] {
    try {
      return doe::parse_model(o.model);
    } catch (const InputError& e) {
      throw e.with_key("--model");
    }
  }();
  doe::FactorTable table = doe::read_factor_table(o.file, factors, o.response, parse_levels(o.levels, "--levels"),
                                                  o.block, doe::RowFilter::parse(o.where));
  doe::Fit fit = doe::fit(table.coded, table.response, factors, kind, o.alpha, table.blocks);
  return {std::move(table), std::move(fit)};
}

nlohmann::ordered_json to_json(const Analysis& a, const DoeOptions& o) {
  auto number = [](double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr); };
  nlohmann::ordered_json j;
  j["file"] = o.file;
  j["response"] = o.response;
  j["model"] = o.model;
  j["alpha"] = o.alpha;
  j["runs"] = a.fit.runs;
  j["where"] = o.where;
  j["excluded_lines"] = a.table.excluded_lines;
  j["factors"] = nlohmann::ordered_json::array();
  for (const doe::Factor& f : a.table.factors)
    j["factors"].push_back({{"name", f.name}, {"low", f.low}, {"high", f.high}});
  j["terms"] = nlohmann::ordered_json::array();
  for (const doe::Coefficient& c : a.fit.coefficients) {
    j["terms"].push_back({{"term", c.term},
                          {"coefficient", c.coef},
                          {"effect", number(c.effect)},
                          {"se", c.se},
                          {"t", c.t},
                          {"p", c.p},
                          {"significant", c.significant}});
  }
  j["anova"] = nlohmann::ordered_json::array();
  for (const doe::AnovaRow& r : a.fit.anova) {
    std::string source = r.source;
    source.erase(0, source.find_first_not_of(' '));
    j["anova"].push_back(
        {{"source", source}, {"df", r.df}, {"ss", r.ss}, {"ms", number(r.ms)}, {"f", number(r.f)}, {"p", number(r.p)}});
  }
  j["s"] = a.fit.s;
  j["r2"] = a.fit.r2;
  j["r2_adjusted"] = a.fit.r2_adjusted;
  j["r2_predicted"] = a.fit.r2_predicted;
  j["t_critical"] = doe::t_critical(o.alpha, a.fit.error_df);
  j["observed"] = std::vector<double>(a.table.response.data(), a.table.response.data() + a.table.response.size());
  std::vector<double> fitted;
  for (Eigen::Index r = 0; r < a.table.coded.rows(); ++r)
    fitted.push_back(a.fit.predict(a.table.coded.row(r).transpose()));
  j["fitted"] = fitted;
  return j;
}

// Pareto chart of standardized effects, fitted vs observed, fitted main effects, and for
// models with squares the contours over the two strongest factors (others at their centre).
constexpr const char* plot_script = R"py(
import json, os, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
a = json.load(open(sys.argv[1])); out = sys.argv[2]
terms = [t for t in a["terms"] if t["term"] not in ("Constant",)]
terms.sort(key=lambda t: abs(t["t"]))
fig, ax = plt.subplots(figsize=(7, 0.4 * len(terms) + 1.5))
ax.barh([t["term"] for t in terms], [abs(t["t"]) for t in terms],
        color=["tab:red" if t["significant"] else "tab:gray" for t in terms])
ax.axvline(a["t_critical"], color="k", ls="--", lw=1)
ax.set_xlabel("standardized effect |t| (dashed: t critical, alpha %g)" % a["alpha"])
ax.set_title("Pareto chart: %s" % a["response"]); fig.tight_layout(); fig.savefig(os.path.join(out, "pareto.png"), dpi=120)
fig, ax = plt.subplots(figsize=(5, 5))
ax.scatter(a["fitted"], a["observed"]); lo = min(a["fitted"] + a["observed"]); hi = max(a["fitted"] + a["observed"])
ax.plot([lo, hi], [lo, hi], "k--", lw=1); ax.set_xlabel("fitted"); ax.set_ylabel("observed")
ax.set_title("%s: R2 %.4f" % (a["response"], a["r2"])); fig.tight_layout(); fig.savefig(os.path.join(out, "fitted_vs_observed.png"), dpi=120)
coef = {t["term"]: t["coefficient"] for t in a["terms"]}
names = [f["name"] for f in a["factors"]]
def predict(x):
    y = coef.get("Constant", 0.0)
    for i, n in enumerate(names):
        y += coef.get(n, 0.0) * x[i] + coef.get(n + "*" + n, 0.0) * x[i] ** 2
        for j in range(i + 1, len(names)):
            y += coef.get(n + "*" + names[j], 0.0) * x[i] * x[j]
    return y
grid = [-1 + 2 * k / 40 for k in range(41)]
fig, axes = plt.subplots(1, len(names), sharey=True, figsize=(2.5 * len(names), 3))
axes = axes if len(names) > 1 else [axes]
for i, (ax, f) in enumerate(zip(axes, a["factors"])):
    xs = [f["low"] + (c + 1) / 2 * (f["high"] - f["low"]) for c in grid]
    ax.plot(xs, [predict([c if k == i else 0 for k in range(len(names))]) for c in grid])
    ax.set_xlabel(f["name"]); ax.grid(alpha=0.3)
axes[0].set_ylabel(a["response"]); fig.suptitle("fitted main effects (others at the centre)")
fig.tight_layout(); fig.savefig(os.path.join(out, "main_effects.png"), dpi=120)
if any("*" in t["term"] and t["term"].split("*")[0] == t["term"].split("*")[1] for t in a["terms"]) and len(names) > 1:
    strongest = sorted(range(len(names)), key=lambda i: -abs(coef.get(names[i], 0.0)))[:2]
    i, j = strongest; fi, fj = a["factors"][i], a["factors"][j]
    z = [[predict([grid[c] if k == i else grid[r] if k == j else 0 for k in range(len(names))]) for c in range(41)] for r in range(41)]
    xs = [fi["low"] + (c + 1) / 2 * (fi["high"] - fi["low"]) for c in grid]
    ys = [fj["low"] + (c + 1) / 2 * (fj["high"] - fj["low"]) for c in grid]
    fig, ax = plt.subplots(figsize=(6, 5)); cs = ax.contourf(xs, ys, z, 15); fig.colorbar(cs, label=a["response"])
    ax.set_xlabel(fi["name"]); ax.set_ylabel(fj["name"]); ax.set_title("response surface (others at the centre)")
    fig.tight_layout(); fig.savefig(os.path.join(out, "contours.png"), dpi=120)
)py";

// The runs a fit stands on, and those --where left out.
void print_runs(const Analysis& a, const DoeOptions& o) {
  fmt::print("{}: {} runs, model {}, response {}\n", o.file, a.fit.runs, o.model, o.response);
  if (!a.table.excluded_lines.empty()) {
    fmt::print("left out by --where {}: {} run(s), on line(s) {}\n", o.where, a.table.excluded_lines.size(),
               fmt::join(a.table.excluded_lines, ", "));
  }
}

void print_analysis(const Analysis& a, const DoeOptions& o) {
  const doe::Fit& f = a.fit;
  print_runs(a, o);
  fmt::print("\n");
  fmt::print("Coded coefficients (alpha {}; * significant)\n", o.alpha);
  fmt::print("{:<24} {:>10} {:>10} {:>9} {:>8} {:>8}\n", "Term", "Effect", "Coef", "SE Coef", "T", "P");
  for (const doe::Coefficient& c : f.coefficients) {
    fmt::print("{:<24} {:>10} {:>10.4f} {:>9.4f} {:>8.2f} {:>8.4f} {}\n", c.term,
               std::isfinite(c.effect) ? fmt::format("{:.4f}", c.effect) : "", c.coef, c.se, c.t, c.p,
               c.significant ? "*" : "");
  }
  fmt::print("\nS {:.5g}   R-sq {:.2f}%   R-sq(adj) {:.2f}%   R-sq(pred) {:.2f}%\n\n", f.s, 100 * f.r2,
             100 * f.r2_adjusted, 100 * f.r2_predicted);
  fmt::print("Analysis of variance\n{:<22} {:>4} {:>12} {:>12} {:>9} {:>8}\n", "Source", "DF", "Adj SS", "Adj MS", "F",
             "P");
  for (const doe::AnovaRow& r : f.anova) {
    auto cell = [](double v, const char* format) {
      return std::isfinite(v) ? fmt::format(fmt::runtime(format), v) : "";
    };
    fmt::print("{:<22} {:>4} {:>12.4f} {:>12} {:>9} {:>8}\n", r.source, r.df, r.ss, cell(r.ms, "{:.4f}"),
               cell(r.f, "{:.2f}"), cell(r.p, "{:.4f}"));
  }
}

// The tables as CSV (coefficients.csv, anova.csv), everything as analysis.json, and the
// PNG plots, in the output directory.
void write_outputs(const Analysis& a, const DoeOptions& o) {
  if (o.plots.empty()) return;
  const std::filesystem::path dir(o.plots);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir, ec)) {
    throw InputError("expected a folder for the tables and plots" + (ec ? ": " + ec.message() : std::string()))
        .with_key("--out")
        .at(o.plots);
  }
  auto cell = [](double v) { return std::isfinite(v) ? fmt::format("{:.10g}", v) : std::string(); };
  std::string coefficients = "term,effect,coefficient,se,t,p,significant\n";
  for (const doe::Coefficient& c : a.fit.coefficients) {
    coefficients += fmt::format("{},{},{},{},{},{},{}\n", c.term, cell(c.effect), cell(c.coef), cell(c.se), cell(c.t),
                                cell(c.p), c.significant ? 1 : 0);
  }
  io::write_file_atomically((dir / "coefficients.csv").string(), coefficients);
  std::string anova = "source,df,adj_ss,adj_ms,f,p\n";
  for (const doe::AnovaRow& r : a.fit.anova) {
    std::string source = r.source;
    source.erase(0, source.find_first_not_of(' '));
    anova += fmt::format("{},{},{},{},{},{}\n", source, r.df, cell(r.ss), cell(r.ms), cell(r.f), cell(r.p));
  }
  io::write_file_atomically((dir / "anova.csv").string(), anova);
  const std::string json_path = (dir / "analysis.json").string();
  io::write_file_atomically(json_path, to_json(a, o).dump(2, ' ', false, nlohmann::json::error_handler_t::replace));
  io::run_python(plot_script, {json_path, o.plots});
  if (!o.json) {
    fmt::print(
        "\nwritten to {}/: coefficients.csv, anova.csv, analysis.json, pareto.png, fitted_vs_observed.png, "
        "main_effects.png{}\n",
        o.plots, o.model == "quadratic" ? ", contours.png" : "");
  }
}

void run_analyze(const DoeOptions& o) {
  const Analysis a = analyze(o);
  if (o.json) {
    fmt::print("{}\n", to_json(a, o).dump(2, ' ', false, nlohmann::json::error_handler_t::replace));
  } else {
    print_analysis(a, o);
  }
  write_outputs(a, o);
}

void run_optimize(const DoeOptions& o) {
  DoeOptions first = o;
  if (const auto responses = split_list(o.response); !responses.empty()) first.response = responses.front();
  const Analysis a = analyze(first);
  // Factors held at given values (physical units), the others free.
  const auto k = static_cast<Eigen::Index>(a.table.factors.size());
  Eigen::VectorXd start = Eigen::VectorXd::Zero(k);
  std::vector<bool> fixed(a.table.factors.size(), false);
  for (const std::string& item : split_list(o.fix, ',')) {
    const auto eq = item.find('=');
    const std::string name = item.substr(0, eq);
    const auto it = std::find_if(a.table.factors.begin(), a.table.factors.end(),
                                 [&](const doe::Factor& f) { return f.name == name; });
    if (eq == std::string::npos || it == a.table.factors.end()) {
      throw InputError(fmt::format("expected factor=value with one of the --factors, got '{}'", item))
          .with_key("--fix");
    }
    const auto i = static_cast<std::size_t>(it - a.table.factors.begin());
    try {
      start(static_cast<Eigen::Index>(i)) = it->code(units::parse_number(item.substr(eq + 1)));
    } catch (const InputError& e) {
      throw e.with_key("--fix");
    }
    fixed[i] = true;
  }
  if (!o.goals.empty()) {  // several responses: the best compromise by desirability
    const std::vector<std::string> responses = split_list(o.response, ','), goal_texts = split_list(o.goals, ',');
    if (responses.size() != goal_texts.size()) {
      throw InputError(
          fmt::format("expected one goal per response ({} responses, {} goals)", responses.size(), goal_texts.size()))
          .with_key("--goal");
    }
    std::vector<doe::Fit> fits;
    std::vector<doe::ResponseGoal> goals;
    for (std::size_t r = 0; r < responses.size(); ++r) {
      DoeOptions one = o;
      one.response = responses[r];
      fits.push_back(r == 0 ? a.fit : analyze(one).fit);  // (the first is fitted already)
      try {
        goals.push_back(doe::parse_goal(goal_texts[r]));
      } catch (const InputError& e) {
        throw e.with_key("--goal");
      }
    }
    const doe::Compromise c = doe::maximize_desirability(fits, goals, 1.0, start, fixed);
    if (o.json) {
      nlohmann::ordered_json j;
      j["composite_desirability"] = c.composite;
      j["settings"] = nlohmann::ordered_json::object();
      for (std::size_t i = 0; i < a.table.factors.size(); ++i) {
        j["settings"][a.table.factors[i].name] = a.table.factors[i].decode(c.coded(static_cast<Eigen::Index>(i)));
      }
      for (std::size_t r = 0; r < responses.size(); ++r) {
        j["responses"][responses[r]] = {{"predicted", c.predicted[r]}, {"desirability", c.individual[r]}};
      }
      fmt::print("{}\n", j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace));
      return;
    }
    fmt::print("best compromise, composite desirability {:.4f}\n", c.composite);
    for (std::size_t i = 0; i < a.table.factors.size(); ++i) {
      const doe::Factor& f = a.table.factors[i];
      fmt::print("  {:<16} {:.5g}   (coded {:+.3f})\n", f.name, f.decode(c.coded(static_cast<Eigen::Index>(i))),
                 c.coded(static_cast<Eigen::Index>(i)));
    }
    for (std::size_t r = 0; r < responses.size(); ++r) {
      fmt::print("  {:<16} predicted {:.5g}, desirability {:.3f}\n", responses[r], c.predicted[r], c.individual[r]);
    }
    return;
  }
  if (std::isnan(o.target))
    throw InputError("expected --target (one response) or --goal (several)").with_key("--target");
  const Eigen::VectorXd x = doe::solve_for_target(a.fit, o.target, 1.0, start, fixed);
  const double predicted = a.fit.predict(x), half = a.fit.prediction_half_width(x, 0.05);
  if (o.json) {
    nlohmann::ordered_json j;
    j["target"] = o.target;
    j["settings"] = nlohmann::ordered_json::object();
    for (std::size_t i = 0; i < a.table.factors.size(); ++i) {
      j["settings"][a.table.factors[i].name] = a.table.factors[i].decode(x(static_cast<Eigen::Index>(i)));
    }
    j["predicted"] = predicted;
    j["prediction_interval_95"] = {predicted - half, predicted + half};
    j["runs"] = a.fit.runs;
    j["excluded_lines"] = a.table.excluded_lines;
    fmt::print("{}\n", j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace));
    return;
  }
  print_runs(a, o);
  fmt::print("settings that give {} = {} (the point of the solution set reached from the centre)\n", o.response,
             o.target);
  for (std::size_t i = 0; i < a.table.factors.size(); ++i) {
    const doe::Factor& f = a.table.factors[i];
    fmt::print("  {:<16} {:.5g}   (coded {:+.3f})\n", f.name, f.decode(x(static_cast<Eigen::Index>(i))),
               x(static_cast<Eigen::Index>(i)));
  }
  fmt::print("predicted {:.5g}, 95% prediction interval {:.5g} to {:.5g}\n", predicted, predicted - half,
             predicted + half);
}

void run_design(const DoeOptions& o) {
  const auto levels = parse_levels(o.factors, "--factors");
  // parse_levels sorts by name; keep the order given.
  std::vector<doe::Factor> factors;
  for (const std::string& item : split_list(o.factors, ',')) {
    const std::string name = item.substr(0, item.find('='));
    factors.push_back({name, levels.at(name).first, levels.at(name).second});
  }
  const int k = static_cast<int>(factors.size());
  auto keyed = [](const InputError& e) {
    static const std::pair<const char*, const char*> names[] = {
        {"runs", "--runs"},     {"center", "--center"},  {"fraction", "--fraction"}, {"generators", "--generators"},
        {"blocks", "--blocks"}, {"factors", "--factors"}};
    for (const auto& [field, option] : names) {
      if (e.key() == field) return InputError(e.problem()).with_key(option);
    }
    return e;
  };
  doe::Design d;
  try {
    if (o.kind == "pb") {
      d = doe::plackett_burman(k, o.runs == 0 ? 12 : o.runs);
    } else if (o.kind == "factorial") {
      d = doe::factorial(k, o.fraction, std::max(o.centre, 0), split_list(o.generators, ','));
    } else if (o.kind == "ccd") {
      d = doe::central_composite(k, doe::parse_ccd_type(o.ccd), o.centre < 0 ? 6 : o.centre, o.blocks);
    } else if (o.kind == "bb") {
      d = doe::box_behnken(k, o.centre < 0 ? 3 : o.centre);
    } else if (o.kind == "lhs") {
      d = doe::latin_hypercube(k, o.runs == 0 ? 10 * k : o.runs, o.seed);
    } else {
      try {
        throw_bad_choice(o.kind, {"pb", "factorial", "ccd", "bb", "lhs"});
      } catch (const InputError& e) {
        throw e.with_key("design");
      }
    }
  } catch (const InputError& e) {
    throw keyed(e);
  }
  if (!o.no_randomize) doe::randomize(d, o.seed);
  const std::string csv = doe::design_csv(d, factors);
  if (o.out.empty()) {
    fmt::print("{}", csv);
    return;
  }
  io::write_file_atomically(o.out, csv);
  fmt::print("{} design, {} runs, {} factors, run order {} -> {}\n", d.kind, d.runs(), k,
             o.no_randomize ? "standard" : fmt::format("random (seed {})", o.seed), o.out);
}

// A campaign over a scenario file: each row runs `bushel run SCENARIO --json` with the row's
// factors as parameters (--set parameters.F=value) and the fixed --set overrides; the responses
// are the scenario's results. Every row's scenario is read and validated before anything runs.
std::vector<std::string> scenario_command(const DoeOptions& o, const std::vector<std::string>& responses) {
  const io::CsvTable design = io::CsvTable::read(o.file);
  std::vector<std::string> factors = split_list(o.factors, ',');
  if (factors.empty()) {
    for (const std::string& h : design.header()) {
      if (std::find(bookkeeping_columns.begin(), bookkeeping_columns.end(), h) == bookkeeping_columns.end()) {
        factors.push_back(h);
      }
    }
  }
  for (const std::string& f : factors) (void)design.column(f);  // each is a column of the design
  std::vector<std::string> command = {"{bushel}",  "run",         o.scenario, "--out",
                                      "{run_dir}", "--overwrite", "--quiet",  "--json"};
  for (const std::string& s : o.sets) command.insert(command.end(), {"--set", s});
  for (const std::string& f : factors) command.insert(command.end(), {"--set", "parameters." + f + "={" + f + "}"});

  std::vector<Override> fixed;
  for (const std::string& s : o.sets) fixed.push_back(parse_override(s));
  for (const io::CsvRow& row : design.rows()) {
    std::vector<Override> overrides = fixed;
    for (const std::string& f : factors) {
      overrides.push_back(parse_override("parameters." + f + "=" + row.fields[design.column(f)]));
    }
    try {
      const Scenario sc = read_scenario(load_scenario_document(o.scenario, overrides));
      std::vector<std::string> names;
      for (const ResultSpec& r : sc.results) names.push_back(r.name);
      for (const std::string& r : responses) {
        if (std::find(names.begin(), names.end(), r) == names.end()) {
          throw InputError("the scenario has no result '" + r + "'" + did_you_mean(r, names) +
                           " (its results: section)")
              .with_key("--response");
        }
      }
    } catch (const InputError& e) {
      throw InputError(fmt::format("{} (design row on line {} of {})", e.what(), row.line, o.file));
    }
  }
  return command;
}

// A command that uses none of the design's factor columns would run every row the same: an
// error. One that leaves some out runs the rows that differ only in them the same: said.
void check_command_uses_factors(const DoeOptions& o) {
  const io::CsvTable design = io::CsvTable::read(o.file);
  std::string joined;
  for (const std::string& a : o.command) joined += a + ' ';
  std::vector<std::string> unused, used;
  for (const std::string& h : design.header()) {
    if (std::find(bookkeeping_columns.begin(), bookkeeping_columns.end(), h) != bookkeeping_columns.end()) continue;
    (joined.find('{' + h + '}') == std::string::npos ? unused : used).push_back(h);
  }
  if (used.empty() && !unused.empty()) {
    throw InputError(fmt::format("the command uses none of the design's factors ({}) as {{NAME}}: every row would "
                                 "run the same",
                                 fmt::join(unused, ", ")))
        .with_key("command")
        .at(o.file);
  }
  if (!unused.empty()) {
    fmt::print(stderr,
               "bushel: warning: the command leaves out the design's factor{} {}: rows that differ only in {} "
               "run the same\n",
               unused.size() == 1 ? "" : "s", fmt::join(unused, ", "), unused.size() == 1 ? "it" : "them");
  }
}

void run_campaign(const DoeOptions& o) {
  doe::CampaignSpec spec;
  spec.design = o.file;
  spec.out = o.out;
  spec.responses = split_list(o.response, ',');
  if (!o.scenario.empty()) {
    if (!o.command.empty()) {
      throw InputError("expected --scenario FILE or a command after --, not both").with_key("--scenario");
    }
    spec.command = scenario_command(o, spec.responses);
    spec.response_root = "results";
  } else {
    if (!o.sets.empty()) throw InputError("--set goes with --scenario").with_key("--set");
    spec.command = o.command;
    check_command_uses_factors(o);
  }
  spec.jobs = o.jobs;
  spec.threads = o.threads;
  const doe::CampaignReport r = doe::run_campaign(spec);
  if (!r.coordinator) return;  // an MPI rank that only ran rows
  fmt::print("{} runs: {} already done, {} ran, {} failed -> {}\n", r.runs, r.skipped, r.ran, r.failed, r.results);
  if (r.failed > 0) {
    throw InputError(
        fmt::format("{} runs failed (see their stderr.txt); run the campaign again to retry them", r.failed));
  }
}

void add_common(CLI::App* cmd, DoeOptions& o) {
  cmd->add_option("file", o.file, "CSV with factor and response columns")->required();
  cmd->add_option("--factors", o.factors, "Factor columns, comma-separated")->required();
  cmd->add_option("--response", o.response, "Response column")->required();
  cmd->add_option("--model", o.model, "main, interactions or quadratic")->capture_default_str();
  cmd->add_option("--alpha", o.alpha, "Significance level")->capture_default_str();
  cmd->add_option("--levels", o.levels, "Low and high levels, name=low:high,... (default: each column's range)");
  cmd->add_option("--block", o.block, "Column of block labels: block terms in the model (Minitab's Blocks)");
  cmd->add_option("--where", o.where,
                  "Only the rows where these hold, e.g. overflow_mass>0.001,status==done (a run without the value is "
                  "left out)");
  cmd->add_flag("--json", o.json, "Print JSON");
}

}  // namespace

void add_doe_command(CLI::App& app) {
  auto o = std::make_shared<DoeOptions>();
  auto* doe = app.add_subcommand("doe", "Designed experiments: designs, analysis and optimisation of responses");
  doe->require_subcommand(1);
  auto* analyze_cmd = doe->add_subcommand("analyze", "Fit a model and report coefficients, tests and ANOVA");
  add_common(analyze_cmd, *o);
  analyze_cmd->add_option("--out", o->plots,
                          "Write the tables (CSV), the analysis (JSON) and PNG plots (Pareto, fitted vs observed, "
                          "main effects, contours) to this directory");
  analyze_cmd->callback([o] { run_analyze(*o); });
  auto* design_cmd = doe->add_subcommand("design", "A design table: pb, factorial, ccd, bb (Box-Behnken) or lhs");
  design_cmd->add_option("design", o->kind, "pb, factorial, ccd, bb or lhs")->required();
  design_cmd->add_option("--factors", o->factors, "Factors and their levels, name=low:high,...")->required();
  design_cmd->add_option("--runs", o->runs, "Runs: 12, 20 or 24 for pb (12); any for lhs (10 per factor)")
      ->check(CLI::Range(1, 100000));
  design_cmd->add_option("--center", o->centre, "Centre points (per block for ccd; default factorial 0, ccd 6, bb 3)")
      ->check(CLI::Range(0, 1000));
  design_cmd->add_option("--fraction", o->fraction, "Factorial fraction p: 2^(k-p) runs")
      ->capture_default_str()
      ->check(CLI::Range(0, 30));
  design_cmd->add_option("--generators", o->generators, "Fraction generators, e.g. E=ABCD (default: standard)");
  design_cmd->add_option("--ccd", o->ccd, "face, circumscribed or inscribed")->capture_default_str();
  design_cmd->add_option("--blocks", o->blocks, "ccd: 1, or 2 (cube and axial blocks)")->capture_default_str();
  design_cmd->add_option("--seed", o->seed, "Seed of the run order and of lhs")->capture_default_str();
  design_cmd->add_flag("--no-randomize", o->no_randomize, "Keep the standard order");
  design_cmd->add_option("--out", o->out, "Write the table here (CSV, atomically) instead of printing it");
  design_cmd->callback([o] { run_design(*o); });
  auto* run_cmd = doe->add_subcommand("run", "Run a command per design row (resumable), collecting JSON responses");
  run_cmd->add_option("design", o->file, "Design CSV (std_order and factor columns)")->required();
  run_cmd->add_option("--out", o->out, "Campaign directory: run_<std_order>/ per row, results.csv")->required();
  run_cmd
      ->add_option("--response", o->response,
                   "Keys of the command's JSON output to collect, e.g. mass_kg (with --scenario: its results)")
      ->required();
  run_cmd->add_option("--jobs", o->jobs, "Runs at a time")->capture_default_str()->check(CLI::Range(1, 1024));
  run_cmd->add_option("--threads", o->threads, "OpenMP threads per run (0: cores / jobs)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1024));
  run_cmd->add_option("--scenario", o->scenario,
                      "Run this scenario per row: the design's factor columns are its parameters, the responses its "
                      "results");
  run_cmd->add_option("--set", o->sets, "With --scenario: a fixed override for every row, path.to.key=value");
  run_cmd->add_option("--factors", o->factors,
                      "With --scenario: the design's columns that are parameters (default: all but std_order, "
                      "run_order, center_pt, pt_type, block)");
  run_cmd->add_option("command", o->command,
                      "After --: the command per row; {column} is the row's value, {run_dir} its directory, "
                      "{bushel} this program");
  run_cmd->callback([o] { run_campaign(*o); });
  auto* optimize_cmd = doe->add_subcommand("optimize", "Factor settings at which the fitted response hits a target");
  add_common(optimize_cmd, *o);
  optimize_cmd->add_option("--target", o->target, "Target response (one response)");
  optimize_cmd->add_option("--goal", o->goals,
                           "Several responses (--response a,b): a goal each, target:T:L:U, minimize:T:U or "
                           "maximize:L:T, comma-separated; maximises the composite desirability");
  optimize_cmd->add_option("--fix", o->fix, "Factors held at a value, name=value,... (physical units)");
  optimize_cmd->callback([o] { run_optimize(*o); });
}

}  // namespace bushel::cli
