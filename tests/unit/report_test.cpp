// `bushel report`: reading run summaries, matching reference values to runs, and the tables,
// curves, heap profiles and compositions built from hand-made summaries with known content.
#include "bushel/report/report.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "bushel/core/input_error.hpp"
#include "bushel/report/reference_values.hpp"
#include "bushel/scenario/run_summary.hpp"
#include "temp_dir_test.hpp"

namespace bushel {
namespace {

RunSummary summary(const std::string& dir, const std::string& scenario,
                   std::vector<std::pair<std::string, std::string>> parameters, std::vector<RunResult> results) {
  RunSummary s;
  s.directory = dir;
  s.scenario = "/scenarios/" + scenario + ".yaml";
  s.parameters = std::move(parameters);
  s.results = std::move(results);
  return s;
}

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

const ReportTable* table_with(const Report& r, const std::string& first_header_after_case) {
  for (const ReportSection& s : r.sections) {
    for (const ReportBlock& b : s.blocks) {
      if (b.kind == ReportBlock::Kind::table && b.table.header.size() > 1 &&
          b.table.header[1] == first_header_after_case) {
        return &b.table;
      }
    }
  }
  return nullptr;
}

const ReportFigure* figure_named(const Report& r, const std::string& file) {
  for (const ReportFigure* f : r.figures()) {
    if (f->file == file) return f;
  }
  return nullptr;
}

const char* reference_csv = R"(# comment lines are skipped
scenario,result,fraction,drop,value,unit,sd,source
cup,bulk_density,large,,826.1,kg/m3,1.2,lab
tw,bulk_density,,5.1 cm,62.69,lb/bu,0.5,lab tw
cup,heap_angle,,,30,deg,,photo
)";

TEST(ReferenceValues, MatchRunsByScenarioAndParametersAsQuantities) {
  const auto refs = parse_reference_values(reference_csv, "refs.csv");
  ASSERT_EQ(refs.size(), 3u);
  EXPECT_EQ(refs[0].origin, "refs.csv:3");
  EXPECT_NEAR(refs[0].value, 826.1, 1e-12);
  EXPECT_EQ(refs[0].dimension, units::dim::density);
  ASSERT_EQ(refs[0].conditions.size(), 1u);
  EXPECT_EQ(refs[0].conditions[0], (std::pair<std::string, std::string>{"fraction", "large"}));
  // the standard deviation in the value's unit (not a condition); none where the cell is empty
  EXPECT_NEAR(*refs[0].sd, 1.2, 1e-12);
  EXPECT_NEAR(*refs[1].sd, 0.5 * 12.8719, 0.5 * 1e-4);
  EXPECT_FALSE(refs[2].sd.has_value());

  const RunSummary cup = summary("c", "cup", {{"fraction", "Large"}, {"drop", "5.1cm"}}, {});
  const RunSummary cup_small = summary("c", "cup", {{"fraction", "small"}}, {});
  const RunSummary tw = summary("t", "tw", {{"drop", "51mm"}}, {});
  const RunSummary tw_high = summary("t", "tw", {{"drop", "10.2 cm"}}, {});
  const RunSummary tw_none = summary("t", "tw", {}, {});
  EXPECT_TRUE(reference_applies(refs[0], cup));  // text compared without case
  EXPECT_FALSE(reference_applies(refs[0], cup_small));
  EXPECT_FALSE(reference_applies(refs[1], cup));  // another scenario
  EXPECT_TRUE(reference_applies(refs[1], tw));    // 5.1 cm = 51 mm
  EXPECT_FALSE(reference_applies(refs[1], tw_high));
  EXPECT_FALSE(reference_applies(refs[1], tw_none));   // a condition on a parameter the run lacks
  EXPECT_TRUE(reference_applies(refs[2], cup_small));  // no condition

  // 62.69 lb/bu in kg/m3 (1 lb/bu = 12.8719 kg/m3 to the digits docs/wheat.md gives), an angle in degrees
  EXPECT_NEAR(reference_in_unit_of(refs[1], {"bulk_density", 800.0, "kg/m3"}), 62.69 * 12.8719, 62.69 * 1e-4);
  EXPECT_NEAR(reference_in_unit_of(refs[2], {"heap_angle", 25.0, "deg"}), 30.0, 1e-12);
  const std::string e = error_of([&] { reference_in_unit_of(refs[1], {"bulk_density", 1.0, "Pa"}); });
  EXPECT_NE(e.find("refs.csv:4"), std::string::npos) << e;
  EXPECT_NE(e.find("is a density, the run's result a pressure"), std::string::npos) << e;
}

TEST(ReferenceValues, BadTablesNameTheFileLineAndColumn) {
  std::string e = error_of([] { parse_reference_values("scenario,result,value\ncup,x,1\n", "r.csv"); });
  EXPECT_NE(e.find("r.csv"), std::string::npos) << e;
  EXPECT_NE(e.find("source"), std::string::npos) << e;
  e = error_of([] { parse_reference_values("result,value,unit,source\nbd,826.1,kg/m4,lab\n", "r.csv"); });
  EXPECT_NE(e.find("r.csv:2"), std::string::npos) << e;
  EXPECT_NE(e.find("key 'value'"), std::string::npos) << e;
  e = error_of([] { parse_reference_values("result,value,unit,sd,source\nbd,826.1,kg/m3,-1,lab\n", "r.csv"); });
  EXPECT_NE(e.find("r.csv:2"), std::string::npos) << e;
  EXPECT_NE(e.find("key 'sd'"), std::string::npos) << e;
  EXPECT_NE(e.find("at least 0"), std::string::npos) << e;
  e = error_of([] { parse_reference_values("result,value,source\n,1,lab\n", "r.csv"); });
  EXPECT_NE(e.find("r.csv:2"), std::string::npos) << e;
  EXPECT_NE(e.find("expected the name of a result"), std::string::npos) << e;
}

TEST(ReferenceValues, TheStudyTableHoldsTheCupMeasurementsAndEdemResults) {
  const RunSummary large5 = summary("c", "calibration-cup", {{"fraction", "large"}, {"model", "5s"}}, {});
  const RunSummary small1 = summary("c", "calibration-cup", {{"fraction", "small"}, {"model", "1s"}}, {});
  std::vector<double> for_large5, for_small1;
  for (const ReferenceValue& r : study_reference_values()) {
    if (r.result != "bulk_density") continue;
    if (reference_applies(r, large5)) for_large5.push_back(r.value);
    if (reference_applies(r, small1)) for_small1.push_back(r.value);
  }
  EXPECT_EQ(for_large5, (std::vector<double>{826.1, 828.7}));  // lab, EDEM 5 spheres
  EXPECT_EQ(for_small1, (std::vector<double>{778.5}));         // lab only: EDEM was 5 spheres
}

TEST(Report, LabelsCasesComparesWithReferencesAndWritesCsv) {
  const auto refs = parse_reference_values(reference_csv, "refs.csv");
  const std::vector<RunSummary> runs = {
      summary("a/cup-1", "cup", {{"fraction", "large"}, {"mass", "325 g"}}, {{"bulk_density", 817.8, "kg/m3"}}),
      summary("b/cup-1/", "cup", {{"fraction", "large"}, {"mass", "80 g"}}, {{"bulk_density", std::nullopt, ""}}),
      summary("c/cup-2", "cup", {{"fraction", "medium"}, {"mass", "325 g"}}, {{"bulk_density", 790.0, "kg/m3"}}),
  };
  const Report r = build_report(runs, refs, {});
  ASSERT_EQ(r.sections.size(), 2u);  // the runs, then one scenario
  const ReportTable* results = table_with(r, "fraction");
  ASSERT_NE(results, nullptr);
  // both parameters vary; two folders share the name cup-1, so their paths label them
  EXPECT_EQ(results->header, (std::vector<std::string>{"case", "fraction", "mass", "bulk_density [kg/m3]"}));
  EXPECT_EQ(results->rows[0], (std::vector<std::string>{"a/cup-1", "large", "325 g", "817.8"}));
  EXPECT_EQ(results->rows[1], (std::vector<std::string>{"b/cup-1/", "large", "80 g", "n/a"}));
  EXPECT_EQ(results->rows[2][0], "cup-2");

  // two runs of the large fraction against 826.1: one with a value, one without
  ASSERT_EQ(r.comparisons.size(), 2u);
  EXPECT_EQ(r.comparisons[0].case_label, "a/cup-1");
  EXPECT_NEAR(r.comparisons[0].difference, (817.8 - 826.1) / 826.1, 1e-12);
  EXPECT_TRUE(std::isnan(r.comparisons[1].bushel));
  const ReportFigure* f = figure_named(r, "cup-bulk_density.png");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->categories, (std::vector<std::string>{"a/cup-1", "b/cup-1/", "cup-2"}));
  ASSERT_EQ(f->series.size(), 2u);  // bushel, lab
  EXPECT_EQ(f->series[1].label, "lab");
  EXPECT_NEAR(f->series[1].y[0], 826.1, 1e-12);
  EXPECT_NEAR(f->series[1].yerr[0], 1.2, 1e-12);  // its error bar
  EXPECT_TRUE(std::isnan(f->series[1].y[2]));     // the medium fraction has no reference here
  EXPECT_TRUE(std::isnan(f->series[0].yerr[0]));  // bushel's points have none
  EXPECT_NEAR(r.comparisons[0].reference_sd, 1.2, 1e-12);

  const auto csv = std::find_if(r.csv_files.begin(), r.csv_files.end(),
                                [](const ReportCsv& c) { return c.file == "cup-results.csv"; });
  ASSERT_NE(csv, r.csv_files.end());
  EXPECT_EQ(csv->text,
            "case,directory,status,fraction,mass,bulk_density\n"
            "a/cup-1,a/cup-1,done,large,325 g,817.8\n"
            "b/cup-1/,b/cup-1/,done,large,80 g,\n"
            "cup-2,c/cup-2,done,medium,325 g,790\n");

  const std::string md = report_markdown(r);
  EXPECT_NE(md.find("| a/cup-1 | large | 325 g | 817.8 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| a/cup-1 | bulk_density [kg/m3] | 817.8 | 826.1 ± 1.2 | lab | -1.0 % |"), std::string::npos) << md;
  EXPECT_NE(md.find("![bulk_density of each case"), std::string::npos);
  const auto figures = nlohmann::json::parse(report_figures_json(r));
  EXPECT_EQ(figures.size(), r.figures().size());
  EXPECT_TRUE(figures[0]["series"][1]["y"][2].is_null());
}

TEST(RunSummary, CurvesPairResultsBySuffixSortedAlongX) {
  const RunSummary run = summary("c", "compression", {},
                                 {{"pressure_b", 20.0, "Pa"},
                                  {"bulk_density_b", 810.0, "kg/m3"},
                                  {"pressure_a", 7.0, "Pa"},
                                  {"bulk_density_a", 800.0, "kg/m3"},
                                  {"pressure_c", 30.0, "Pa"},
                                  {"bulk_density_c", std::nullopt, ""},
                                  {"pressure_d", 40.0, "Pa"}});
  using Points = std::vector<std::pair<double, double>>;
  EXPECT_EQ(run.curve("pressure", "bulk_density"), (Points{{7.0, 800.0}, {20.0, 810.0}}));  // c: no value; d: no pair
  EXPECT_TRUE(run.curve("bulk", "pressure").empty());
}

TEST(Report, CurvesPairResultsBySuffixInOrderOfTheAxis) {
  const std::vector<RunSummary> runs = {summary("comp", "compression", {},
                                                {
                                                    {"pressure_2", 20000.0, "Pa"},
                                                    {"bulk_density_2", 810.0, "kg/m3"},
                                                    {"drift_2", -50.0, "Pa"},
                                                    {"pressure_1", 7000.0, "Pa"},
                                                    {"bulk_density_1", 800.0, "kg/m3"},
                                                    {"drift_1", -10.0, "Pa"},
                                                    {"pressure_0", 0.0, "Pa"},
                                                    {"bulk_density_0", 780.0, "kg/m3"},
                                                    {"mass", 0.1, "kg"},
                                                })};
  const Report r = build_report(runs, {}, {});
  const ReportTable* curve = table_with(r, "level");
  ASSERT_NE(curve, nullptr);
  EXPECT_EQ(curve->header,
            (std::vector<std::string>{"case", "level", "pressure [kPa]", "bulk_density [kg/m3]", "drift [kPa]"}));
  ASSERT_EQ(curve->rows.size(), 3u);
  EXPECT_EQ(curve->rows[0], (std::vector<std::string>{"comp", "0", "0", "780.0", "n/a"}));
  EXPECT_EQ(curve->rows[1], (std::vector<std::string>{"comp", "1", "7.000", "800.0", "-0.01"}));
  EXPECT_EQ(curve->rows[2][1], "2");
  const ReportFigure* f = figure_named(r, "compression-bulk_density-pressure.png");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->series[0].x, (std::vector<double>{0.0, 7.0, 20.0}));
  EXPECT_EQ(f->series[0].y, (std::vector<double>{780.0, 800.0, 810.0}));
  // the main table keeps what is not on the curve, in g
  const ReportTable* main = table_with(r, "mass [g]");
  ASSERT_NE(main, nullptr);
  EXPECT_EQ(main->rows[0], (std::vector<std::string>{"comp", "100.0"}));

  ReportOptions bad;
  bad.curves = {"pressure"};
  EXPECT_NE(error_of([&] { build_report(runs, {}, bad); }).find("key '--curve': expected X:Y"), std::string::npos);
}

TEST(Report, HeapProfilesAtTheChosenStageOrTheLastWithOne) {
  RunSummary a = summary("a", "cup", {}, {}), b = summary("b", "cup", {}, {});
  StageReport fill{"fill", "time", 0, 1, 0, {}, {{"heap", {0.001, 0.003}, {0.050, 0.040}}}};
  StageReport rest{"rest", "time", 1, 2, 0, {}, {{"heap", {0.001, 0.003}, {0.030, std::nan("")}}}};
  a.stages = {fill, rest};
  b.stages = {fill};
  const Report r = build_report({a, b}, {}, {});
  const ReportFigure* f = figure_named(r, "cup-heap.png");
  ASSERT_NE(f, nullptr);
  ASSERT_EQ(f->series.size(), 2u);
  EXPECT_EQ(f->series[0].label, "a");
  EXPECT_NEAR(f->series[0].y[0], 30.0, 1e-12);  // rest, in mm
  EXPECT_TRUE(std::isnan(f->series[0].y[1]));   // an empty ring
  EXPECT_NEAR(f->series[1].y[0], 50.0, 1e-12);  // b has no rest: its fill
  const std::string md = report_markdown(r);
  EXPECT_NE(md.find("at the end of stage 'rest'; runs without it, at their last stage with one (b: 'fill')"),
            std::string::npos)
      << md;
}

TEST(Report, CompositionMadeAndInTheSample) {
  RunSummary run = summary("tw", "test-weight", {}, {{"fraction_large", 0.75, ""}, {"fraction_small", 0.25, ""}});
  run.factories = {{"fill", true, 10, 1.0, {{"large", 8, 0.8, 0.8, 0.8}, {"small", 2, 0.2, 0.2, 0.2}}}};
  const Report r = build_report({run}, {}, {});
  const ReportFigure* f = figure_named(r, "test-weight-composition.png");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->categories, (std::vector<std::string>{"tw made", "tw sample"}));
  ASSERT_EQ(f->series.size(), 2u);
  EXPECT_EQ(f->series[0].label, "large");
  EXPECT_NEAR(f->series[0].y[0], 0.8, 1e-12);
  EXPECT_NEAR(f->series[0].y[1], 0.75, 1e-12);
  const ReportTable* t = table_with(r, "type");
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(t->rows[1], (std::vector<std::string>{"tw", "small", "0.2", "0.25"}));
}

TEST(Report, HtmlIsEscapedAndNumbersAlignRight) {
  const Report r =
      build_report({summary("a<b", "cup", {{"note", "x & y"}}, {{"bulk_density", 800.0, "kg/m3"}})}, {}, {});
  const std::string html = report_html(r);
  EXPECT_NE(html.find("<td>a&lt;b</td>"), std::string::npos) << html;
  EXPECT_NE(html.find("note = x &amp; y"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"n\">800.0</td>"), std::string::npos);
  EXPECT_EQ(html.find("a<b"), std::string::npos);
}

class RunSummaryFiles : public TempDirTest {};

TEST_F(RunSummaryFiles, ErrorsNameTheFolderFileAndKey) {
  EXPECT_NE(error_of([&] { read_run_summary(path("none")); }).find("none: no such run folder"), std::string::npos);
  std::filesystem::create_directories(path("empty"));
  EXPECT_NE(error_of([&] { read_run_summary(path("empty")); }).find("empty: no summary.json here"), std::string::npos);
  std::filesystem::create_directories(path("bad"));
  std::ofstream(path("bad/summary.json")) << "{ not json";
  EXPECT_NE(error_of([&] { read_run_summary(path("bad")); }).find("summary.json: not valid JSON"), std::string::npos);
  std::ofstream(path("bad/other.json")) << R"({"scenario": "s.yaml", "parameters": {}, "interrupted": false,
      "stages": [], "results": {}, "steps": 1, "simulated_time_s": 1, "wall_time_s": 1, "particle_steps_per_s": 1})";
  const std::string e = error_of([&] { read_run_summary(path("bad/other.json")); });
  EXPECT_NE(e.find("other.json"), std::string::npos) << e;
  EXPECT_NE(e.find("key 'dt_s': expected a number, found none"), std::string::npos) << e;
}

}  // namespace
}  // namespace bushel
