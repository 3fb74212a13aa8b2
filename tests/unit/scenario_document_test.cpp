#include "bushel/scenario/scenario_document.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "bushel/core/input_error.hpp"
#include "temp_dir_test.hpp"

namespace bushel {
namespace {

const char* const cup = R"(parameters:
  scale: 1
  drop: 5.1 cm
materials:
  wheat:
    density: 1373 kg/m3
factories:
  - mass: ${scale} kg
    height: ${drop} above ${drop}
stages:
  - name: fill
    time: 1 s
  - name: settle
    time: 0.5 s
)";

// The error a call throws (fails the test if none).
template <class F>
InputError error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError";
  return InputError("none");
}

TEST(ScenarioDocument, SubstitutesParametersKeepingLines) {
  const ScenarioDocument doc = parse_scenario_document(cup, "cup.yaml");
  EXPECT_EQ(doc.root["factories"][0]["mass"].as<std::string>(), "1 kg");
  EXPECT_EQ(doc.root["factories"][0]["height"].as<std::string>(), "5.1 cm above 5.1 cm");
  EXPECT_EQ(line_of(doc.root["factories"][0]["mass"]), 8);
  EXPECT_EQ(line_of(doc.root["stages"][1]["time"]), 14);
  EXPECT_EQ(doc.parameters.at("drop"), "5.1 cm");
  EXPECT_EQ(doc.root["parameters"]["scale"].as<std::string>(), "1");  // the section itself is kept
}

TEST(ScenarioDocument, OverridesParametersValuesListItemsAndNewKeys) {
  const std::vector<Override> sets = {
      parse_override("parameters.scale=0.1"), parse_override("materials.wheat.density=1400 kg/m3"),
      parse_override("stages.1.time=2 s"), parse_override("materials.wheat.poisson=0.3"),
      parse_override("materials.wheat.density=1410 kg/m3")};
  const ScenarioDocument doc = parse_scenario_document(cup, "cup.yaml", sets);
  EXPECT_EQ(doc.root["factories"][0]["mass"].as<std::string>(), "0.1 kg");
  EXPECT_EQ(doc.root["materials"]["wheat"]["density"].as<std::string>(), "1410 kg/m3");  // the last wins
  EXPECT_EQ(doc.root["stages"][1]["time"].as<std::string>(), "2 s");
  EXPECT_EQ(doc.root["stages"][0]["time"].as<std::string>(), "1 s");
  EXPECT_EQ(doc.root["materials"]["wheat"]["poisson"].as<std::string>(), "0.3");
  EXPECT_EQ(line_of(doc.root["stages"][1]["time"]), 0);  // from the command line
  EXPECT_EQ(doc.overrides.size(), sets.size());
  EXPECT_EQ(doc.parameters.at("scale"), "0.1");
}

TEST(ScenarioDocument, ExpressionsComputeWithUnitsFromParameters) {
  const std::string text =
      "parameters:\n  h: 101.6 mm\n  gap: 50.8 mm\n  n: 2\n  fraction: large\n"
      "a:\n  z: ${h + gap}\n  w: ${ n * h }\n  name: ${fraction}_5s\n  v: ${pi * (h/2) * (h/2) * h}\n";
  const ScenarioDocument doc =
      parse_scenario_document(text, "s.yaml", std::vector<Override>{parse_override("parameters.gap=2 in")});
  EXPECT_EQ(doc.root["a"]["z"].as<std::string>(), "0.1524 m");
  EXPECT_EQ(doc.root["a"]["w"].as<std::string>(), "0.2032 m");
  EXPECT_EQ(doc.root["a"]["name"].as<std::string>(), "large_5s");
  EXPECT_EQ(doc.root["a"]["v"].as<std::string>().substr(doc.root["a"]["v"].as<std::string>().size() - 3), " m3");

  const InputError word = error_of([] { parse_scenario_document("parameters:\n  f: large\na: ${f * 2}\n", "s.yaml"); });
  EXPECT_NE(std::string(word.what()).find("parameter 'f' is 'large', not a number or a quantity"), std::string::npos);
  EXPECT_EQ(word.line(), 3);
  const InputError mixed =
      error_of([] { parse_scenario_document("parameters:\n  h: 1 mm\na:\n  b: ${h + 1 s}\n", "s.yaml"); });
  EXPECT_NE(std::string(mixed.what()).find("cannot add a length and a time"), std::string::npos);
  EXPECT_EQ(mixed.key(), "a.b");
  const InputError typo =
      error_of([] { parse_scenario_document("parameters:\n  scale: 1\na: ${2 * scal}\n", "s.yaml"); });
  EXPECT_NE(std::string(typo.what()).find("unknown parameter 'scal' (did you mean 'scale'?)"), std::string::npos);
}

TEST(ScenarioDocument, ParsesOverrides) {
  const Override o = parse_override("a.b=x=1 kg");
  EXPECT_EQ(o.path, "a.b");
  EXPECT_EQ(o.value, "x=1 kg");
  EXPECT_EQ(error_of([] { parse_override("a.b"); }).key(), "--set");
  EXPECT_NE(std::string(error_of([] { parse_override("a..b=1"); }).what()).find("empty key"), std::string::npos);
  EXPECT_NE(std::string(error_of([] { parse_override("=1"); }).what()).find("empty key"), std::string::npos);
}

TEST(ScenarioDocument, BadOverridesSayWhereThePathBreaks) {
  auto message = [](const char* set) {
    const std::vector<Override> sets = {parse_override(set)};
    return std::string(error_of([&] { parse_scenario_document(cup, "cup.yaml", sets); }).what());
  };
  EXPECT_NE(message("materials.wheet.density=1").find("no key 'wheet' (did you mean 'wheat'?)"), std::string::npos);
  EXPECT_NE(message("stages.2.time=1 s").find("'stages' is a list of 2"), std::string::npos);
  EXPECT_NE(message("stages.x.time=1 s").find("not an index"), std::string::npos);
  EXPECT_NE(message("materials.wheat=1").find("is a map; only single values"), std::string::npos);
  EXPECT_NE(message("materials.wheat.density.x=1").find("is a single value"), std::string::npos);
  EXPECT_NE(message("stages=1").find("is a list"), std::string::npos);
  EXPECT_NE(message("stages=1").find("command line"), std::string::npos);
}

TEST(ScenarioDocument, BadReferencesNameFileLineAndKey) {
  const std::string text = "parameters:\n  scale: 1\nfactories:\n  - mass: ${scal} kg\n";
  const InputError e = error_of([&] { parse_scenario_document(text, "cup.yaml"); });
  EXPECT_EQ(e.source(), "cup.yaml");
  EXPECT_EQ(e.line(), 4);
  EXPECT_EQ(e.key(), "factories.0.mass");
  EXPECT_NE(std::string(e.what()).find("unknown parameter 'scal' (did you mean 'scale'?)"), std::string::npos);

  const InputError open = error_of([] { parse_scenario_document("a:\n  b: ${x\n", "s.yaml"); });
  EXPECT_EQ(open.line(), 2);
  EXPECT_NE(std::string(open.what()).find("without its closing"), std::string::npos);
  const InputError nested = error_of([] { parse_scenario_document("parameters:\n  a: ${b}\n  b: 1\n", "s.yaml"); });
  EXPECT_EQ(nested.key(), "parameters.a");
  EXPECT_EQ(nested.line(), 2);
  const InputError none = error_of([] { parse_scenario_document("a: ${b}\n", "s.yaml"); });
  EXPECT_NE(std::string(none.what()).find("declares none"), std::string::npos);
}

TEST(ScenarioDocument, BadFilesAndSyntax) {
  const InputError syntax = error_of([] { parse_scenario_document("a: [1, 2\nb: 3\n", "s.yaml"); });
  EXPECT_EQ(syntax.source(), "s.yaml");
  EXPECT_GT(syntax.line(), 0);
  EXPECT_NE(std::string(syntax.what()).find("not valid YAML"), std::string::npos);
  EXPECT_NE(
      std::string(error_of([] { parse_scenario_document("- 1\n- 2\n", "s.yaml"); }).what()).find("map of sections"),
      std::string::npos);
  EXPECT_NE(std::string(error_of([] { load_scenario_document("/nonexistent/cup.yaml"); }).what()).find("cannot open"),
            std::string::npos);
}

// The YAML a scenario may not contain, though yaml-cpp would load it: each an error at its line.
TEST(ScenarioDocument, RefusesWhatYamlAllowsButAScenarioMustNotHold) {
  auto refused = [](const std::string& text) { return error_of([&] { parse_scenario_document(text, "s.yaml"); }); };
  const InputError twice = refused("parameters:\n  mass: 1 kg\n  rate: 1 kg/s\n  mass: 2 kg\n");
  EXPECT_EQ(twice.line(), 4);
  EXPECT_NE(std::string(twice.what()).find("the key 'mass' appears twice in one map (lines 2 and 4)"),
            std::string::npos);
  // the same key in two maps is fine
  EXPECT_NO_THROW(parse_scenario_document("a: {x: 1}\nb: {x: 2}\n", "s.yaml"));
  EXPECT_NE(std::string(refused("? [a, b]\n: 1\n").what()).find("a list as a key"), std::string::npos);
  EXPECT_NE(std::string(refused("{a: 1}: 1\n").what()).find("a map as a key"), std::string::npos);
  EXPECT_NE(std::string(refused("a: &k b\n*k : 1\n").what()).find("an alias (*name) as a key"), std::string::npos);
  const InputError second = refused("a: 1\n---\nb: 2\n");
  EXPECT_EQ(second.line(), 2);
  EXPECT_NE(std::string(second.what()).find("a second YAML document"), std::string::npos);
  EXPECT_NE(std::string(refused("a: &x [1, *x]\n").what()).find("to the list or map that contains it"),
            std::string::npos);
  // aliases are fine while they stay small, and counted expanded: 9^5 values are too many
  EXPECT_NO_THROW(parse_scenario_document("a: &x [1, 2]\nb: *x\nc: *x\n", "s.yaml"));
  std::string laughs = "a0: &a0 [x, x, x, x, x, x, x, x, x]\n";
  for (int k = 1; k <= 5; ++k) {
    laughs += "a" + std::to_string(k) + ": &a" + std::to_string(k) + " [";
    for (int j = 0; j < 9; ++j) laughs += (j ? ", *a" : "*a") + std::to_string(k - 1);
    laughs += "]\n";
  }
  EXPECT_NE(std::string(refused(laughs).what()).find("more than 100000 values"), std::string::npos);
  // a parameter nobody declared cannot be set; a --set behind a value is named in its errors
  const InputError undeclared = error_of([] {
    parse_scenario_document("parameters:\n  mass: 1 kg\n", "s.yaml",
                            std::vector<Override>{parse_override("parameters.mas=2")});
  });
  EXPECT_NE(std::string(undeclared.what()).find("declares no parameter 'mas' (did you mean 'mass'?)"),
            std::string::npos);
  const ScenarioDocument doc = parse_scenario_document("parameters:\n  m: 1 kg\nf:\n  mass: ${m}\n  n: 2\n", "s.yaml",
                                                       std::vector<Override>{parse_override("parameters.m=3x")});
  EXPECT_EQ(doc.set_by.at("f.mass"), "--set parameters.m=3x");
  EXPECT_FALSE(doc.set_by.contains("f.n"));
}

class ScenarioFile : public TempDirTest {};

TEST_F(ScenarioFile, ReadsTheFileWithOverrides) {
  const std::string file = path("cup.yaml");
  std::ofstream(file) << cup;
  const ScenarioDocument doc =
      load_scenario_document(file, std::vector<Override>{parse_override("parameters.drop=1 m")});
  EXPECT_EQ(doc.file, file);
  EXPECT_EQ(doc.root["factories"][0]["height"].as<std::string>(), "1 m above 1 m");
}

TEST_F(ScenarioFile, RefusesDevicesFoldersAndFilesTooLarge) {
  EXPECT_NE(std::string(error_of([] { load_scenario_document("/dev/zero"); }).what()).find("this is a device"),
            std::string::npos);
  EXPECT_NE(std::string(error_of([&] { load_scenario_document(path("")); }).what()).find("this is a folder"),
            std::string::npos);
  const std::string big = path("big.yaml");
  std::ofstream(big) << "a: " << std::string((16u << 20) + 1, 'x') << "\n";
  EXPECT_NE(std::string(error_of([&] { load_scenario_document(big); }).what()).find("16 MiB at most"),
            std::string::npos);
}

}  // namespace
}  // namespace bushel
