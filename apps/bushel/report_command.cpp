// `bushel report DIR...`: run folders turned into one page of tables and plots
// (report/report.hpp, docs/report.md).
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <memory>

#include "bushel/core/input_error.hpp"
#include "bushel/io/atomic_file.hpp"
#include "bushel/io/csv.hpp"
#include "bushel/io/python_plot.hpp"
#include "bushel/report/report.hpp"
#include "commands.hpp"

namespace bushel::cli {

namespace {

struct ReportCommandOptions {
  std::vector<std::string> dirs;
  std::string out = "report";
  std::vector<std::string> references = {"study"};
  std::vector<std::string> curves = {"pressure:bulk_density"};
  std::string heap_stage = "rest";
  std::string title = "bushel report";
  bool no_plots = false;
};

// Draws each figure of report_figures_json: "lines" (x, y per series), "categories" (a point
// per case and series; the first series filled, the references hollow), "stacked" (bars of
// shares), the legend beside the axes, and "frame" (a run's last frame, by the bushel package
// in argv[3]). Each PNG is written under a temporary name and renamed, so none is ever half
// written.
constexpr const char* plot_script = R"py(
import json, os, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
figures = json.load(open(sys.argv[1])); out = sys.argv[2]
if len(sys.argv) > 3 and sys.argv[3]:
    sys.path.insert(0, sys.argv[3])  # this build's bushel package, for the frames
val = lambda v: float("nan") if v is None else v
markers = ["o", "s", "D", "^", "v", "P", "X"]
for f in figures:
    if f["kind"] == "frame":
        from bushel.pictures import section_png
        section_png(f["frames"], os.path.join(out, f["file"]), title=f["title"], width=5.0, dpi=100)
        continue
    fig, ax = plt.subplots(figsize=(7.5, 4.5))
    n = len(f["categories"])
    if f["kind"] == "lines":
        for s in f["series"]:
            ax.plot([val(v) for v in s["x"]], [val(v) for v in s["y"]], marker="o", ms=3, label=s["label"])
    elif f["kind"] == "categories":
        for i, s in enumerate(f["series"]):
            # (error bars: the reference's standard deviation, where its source gives one)
            err = [val(v) for v in s.get("yerr") or []]
            err = err if any(e == e for e in err) else None  # (matplotlib fails on bars that are all NaN)
            ax.errorbar(range(n), [val(v) for v in s["y"]], yerr=err, linestyle="none", marker=markers[i % len(markers)],
                        ms=8, mfc=None if i == 0 else "none", capsize=4, label=s["label"])
    elif f["kind"] == "stacked":
        bottom = [0.0] * n
        for s in f["series"]:
            ys = [0.0 if v is None else v for v in s["y"]]
            ax.bar(range(n), ys, bottom=bottom, label=s["label"])
            bottom = [b + y for b, y in zip(bottom, ys)]
    if n:
        ax.set_xticks(range(n))
        ax.set_xticklabels(f["categories"], rotation=30 if n > 3 else 0, ha="right" if n > 3 else "center",
                           fontsize=8)
    ax.set_title(f["title"]); ax.set_xlabel(f["xlabel"]); ax.set_ylabel(f["ylabel"])
    ax.grid(alpha=0.3)
    many = len(f["series"]) > 16
    ax.legend(fontsize=6 if many else 8, ncol=2 if many else 1, loc="upper left", bbox_to_anchor=(1.01, 1))
    path = os.path.join(out, f["file"])
    fig.savefig(path + ".tmp.png", dpi=120, bbox_inches="tight")
    os.replace(path + ".tmp.png", path)
    plt.close(fig)
)py";

// The run folders: each argument is one (it has a summary.json) or holds them (a campaign's
// or a study's folder: its sub-folders with a summary.json, in name order).
std::vector<std::string> run_folders(const std::vector<std::string>& args) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  for (const std::string& a : args) {
    std::error_code ec;
    if (fs::is_directory(a, ec) && !fs::exists(fs::path(a) / "summary.json", ec)) {
      std::vector<std::string> inside;
      for (const auto& e : fs::directory_iterator(a)) {
        if (e.is_directory() && fs::exists(e.path() / "summary.json")) inside.push_back(e.path().string());
      }
      if (inside.empty()) {
        throw InputError("no summary.json here nor in its sub-folders: expected the output folder of `bushel run`")
            .at(a);
      }
      std::sort(inside.begin(), inside.end());
      out.insert(out.end(), inside.begin(), inside.end());
    } else {
      out.push_back(a);
    }
  }
  return out;
}

void run_report(const ReportCommandOptions& o) {
  namespace fs = std::filesystem;
  std::vector<RunSummary> runs;
  for (const std::string& dir : run_folders(o.dirs)) runs.push_back(read_run_summary(dir));
  std::vector<ReferenceValue> references;
  for (const std::string& r : o.references) {
    if (r == "none") continue;
    const auto table = r == "study" ? study_reference_values() : read_reference_values(r);
    references.insert(references.end(), table.begin(), table.end());
  }
  ReportOptions options;
  options.title = o.title;
  options.curves = o.curves;
  options.heap_stage = o.heap_stage;
  const std::string package = io::python_package_path();
  options.frames = !package.empty();
  const Report report = build_report(runs, references, options);

  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) throw InputError("cannot create the folder: " + ec.message()).at(o.out).with_key("--out");
  const auto path = [&](const std::string& file) { return (fs::path(o.out) / file).string(); };
  for (const ReportCsv& c : report.csv_files) io::write_file_atomically(path(c.file), c.text);
  io::write_file_atomically(path("figures.json"), report_figures_json(report));
  if (!o.no_plots && !report.figures().empty()) io::run_python(plot_script, {path("figures.json"), o.out, package});
  io::write_file_atomically(path("report.md"), report_markdown(report));
  // The page holds its figures (a single file to send or archive); without plots it links them.
  const auto png = [&](const std::string& file) -> std::optional<std::string> {
    std::error_code missing;
    if (!fs::exists(path(file), missing)) return std::nullopt;
    return io::read_text_file(path(file));
  };
  io::write_file_atomically(path("report.html"), report_html(report, png));

  std::size_t scenarios = report.sections.size() - 1;
  fmt::print("report   {}  {}\n", path("report.md"), path("report.html"));
  fmt::print("runs     {} of {} scenario{}\n", runs.size(), scenarios, scenarios == 1 ? "" : "s");
  fmt::print("figures  {}{}\n", report.figures().size(), o.no_plots ? " (data only: --no-plots)" : "");
  for (const ReportCsv& c : report.csv_files) fmt::print("table    {}\n", path(c.file));
  // The comparisons with measurements, the lines a reader looks for first.
  for (const ReportComparison& c : report.comparisons) {
    fmt::print("  {:<24} {:<16} {:>10.6g} vs {:>10.6g} {:<6} {:>+7.1f} %  {}\n", c.case_label, c.result, c.bushel,
               c.reference, c.unit, 100.0 * c.difference, c.source);
  }
}

}  // namespace

void add_report_command(CLI::App& app) {
  auto o = std::make_shared<ReportCommandOptions>();
  auto* cmd = app.add_subcommand("report",
                                 "Tables and plots of run folders: results beside measurements, curves, "
                                 "heap profiles, composition (Markdown + HTML + PNG + CSV)");
  cmd->add_option("dirs", o->dirs, "Run folders (with summary.json), or folders holding them")->required();
  cmd->add_option("--out", o->out, "Folder for report.md, report.html, the PNG figures and CSV tables")
      ->capture_default_str();
  cmd->add_option("--reference", o->references,
                  "Values to compare with: a CSV (scenario, result, value, unit, source, parameter columns), "
                  "'study' (built in: the reference wheat study) or 'none'; repeatable")
      ->capture_default_str();
  cmd->add_option("--curve", o->curves, "Results X_K and Y_K drawn as a curve Y against X; repeatable")
      ->capture_default_str();
  cmd->add_option("--heap-stage", o->heap_stage,
                  "Heap profiles at the end of this stage (a run without it: its last stage with a profile)")
      ->capture_default_str();
  cmd->add_option("--title", o->title, "The report's title")->capture_default_str();
  cmd->add_flag("--no-plots", o->no_plots, "Write the figures' data (figures.json) but draw no PNG");
  cmd->callback([o] { run_report(*o); });
}

}  // namespace bushel::cli
