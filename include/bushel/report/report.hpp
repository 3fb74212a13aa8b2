#pragma once
// `bushel report`: run directories turned into the tables and plots a researcher puts in a
// paper (docs/report.md). Runs are grouped by scenario; for each group:
//   - the results of every case (a case is a run; the parameters that differ between the
//     runs of the group label it), next to measured values where a reference table has them;
//   - curves from results that pair up by suffix: `pressure_K` with `bulk_density_K` (K any
//     suffix; other results `NAME_K` join the curve's table, such as `drift_K`);
//   - heap profiles at the end of a chosen stage;
//   - the composition: results `fraction_TYPE` (in a vessel) beside what the factories made.
// The model here is plain text and numbers; report_markup.cpp writes it as Markdown or HTML
// and the figures' data as JSON for the plot script.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bushel/report/reference_values.hpp"
#include "bushel/scenario/run_summary.hpp"

namespace bushel {

struct ReportOptions {
  std::string title = "bushel report";
  /// Curves as "X:Y": results X_K and Y_K of the same suffix K are the points (X on the axis).
  std::vector<std::string> curves = {"pressure:bulk_density"};
  /// The stage at whose end the heap profiles are drawn; a run without it (or "") uses its
  /// last stage with a profile.
  std::string heap_stage = "rest";
  /// Results named PREFIX + type name are the composition in a vessel.
  std::string composition_prefix = "fraction_";
  /// Draw each run's last frame (kind "frame"): needs the bushel Python package, which the
  /// program says whether it has (io::python_package_path). Without it the report says so.
  bool frames = true;
  /// At most this many runs of a scenario get their last frame drawn (the first, by case).
  std::size_t max_frames = 6;
};

struct ReportTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  ///< cells as text, as many as the header
};

/// A figure's data; the plot script (apps/bushel/report_command.cpp) draws it.
struct ReportSeries {
  std::string label;
  std::vector<double> x, y;  ///< x ignored for category plots; NaN: no point
  std::vector<double> yerr;  ///< per point, its standard deviation for an error bar (NaN: none); empty: none
};
struct ReportFigure {
  std::string file;  ///< PNG file name, in the report's folder
  std::string kind;  ///< "categories" (points per case), "lines" (x, y), "stacked" (bars of shares per case),
                     ///< "frame" (a section of a run's last frame, drawn by the bushel Python package)
  std::string title, xlabel, ylabel;
  std::vector<std::string> categories;  ///< for "categories" and "stacked"
  std::vector<ReportSeries> series;
  std::string frames{};  ///< for "frame": the run's frames folder (particles.pvd, geometry.pvd)
};

/// One block of a section: a sub-heading, a paragraph, a list, a table or a figure.
struct ReportBlock {
  enum class Kind { heading, text, list, table, figure } kind = Kind::text;
  std::string text;                ///< the heading, the paragraph, or a table's or figure's caption
  std::vector<std::string> items;  ///< a list's items
  ReportTable table;
  ReportFigure figure;
};

struct ReportSection {
  std::string title;
  std::vector<ReportBlock> blocks;
};

/// A machine-readable table written beside the report.
struct ReportCsv {
  std::string file;
  std::string text;
};

/// A result set beside a reference value.
struct ReportComparison {
  std::string case_label, result;
  std::string unit;     ///< of both values: the summary's (SI, degrees for angles)
  double bushel = 0.0;  ///< the run's value; NaN if it has none
  double reference = 0.0;
  double reference_sd = 0.0;  ///< the reference's standard deviation; NaN if its source gives none
  std::string source;
  double difference = 0.0;  ///< (bushel - reference) / reference
};

struct Report {
  std::string title;
  std::vector<ReportSection> sections;
  std::vector<ReportCsv> csv_files;
  std::vector<ReportComparison> comparisons;

  /// Every figure of the report, in order.
  std::vector<const ReportFigure*> figures() const;
};

/// Builds the report. Throws InputError for an option it cannot use (a curve not "X:Y").
Report build_report(const std::vector<RunSummary>& runs, const std::vector<ReferenceValue>& references,
                    const ReportOptions& options);

/// The Markdown page (figures as relative links to their PNG files).
std::string report_markdown(const Report& report);
/// The HTML page, one file: each figure whose PNG `figure_bytes(file)` gives is embedded in it
/// (a data: URL), the others are links to their files.
std::string report_html(const Report& report,
                        const std::function<std::optional<std::string>(const std::string&)>& figure_bytes = {});
/// The data of the figures as JSON, for the plot script.
std::string report_figures_json(const Report& report);

}  // namespace bushel
