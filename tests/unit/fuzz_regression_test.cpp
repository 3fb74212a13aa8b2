// The fuzz targets' inputs replayed without clang (docs/fuzzing.md): every seed in
// tests/fuzz/corpus/<target>/ and every reproducer of a fixed crash in
// tests/fuzz/regressions/<target>/ goes through the same function as the libFuzzer target
// (tests/fuzz/fuzz_inputs.hpp) and must be read or refused with an InputError.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <exception>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "bushel/core/input_error.hpp"
#include "fuzz/fuzz_inputs.hpp"

namespace bushel {
namespace {

namespace fs = std::filesystem;

// The seeds and reproducers of a target, in name order.
std::vector<fs::path> inputs_of(const std::string& target) {
  std::vector<fs::path> found;
  for (const char* kind : {"corpus", "regressions"}) {
    const fs::path dir = fs::path(BUSHEL_TEST_DATA_DIR) / "fuzz" / kind / target;
    if (!fs::is_directory(dir)) continue;
    for (const auto& entry : fs::directory_iterator(dir)) {
      if (entry.is_regular_file()) found.push_back(entry.path());
    }
  }
  std::sort(found.begin(), found.end());
  return found;
}

// Feeds every input of `target` to `feed`; returns how many were read without an error.
int replay(const std::string& target, const std::function<void(std::string_view)>& feed) {
  const auto inputs = inputs_of(target);
  EXPECT_FALSE(inputs.empty()) << "no seeds for " << target;
  int accepted = 0;
  for (const fs::path& p : inputs) {
    SCOPED_TRACE(p.string());
    const std::string bytes = fuzz::CheckpointInput::read_file(p);
    try {
      feed(bytes);
      ++accepted;
    } catch (const InputError&) {
      // the answer to bad input
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not an InputError: " << e.what();
    }
  }
  return accepted;
}

TEST(FuzzRegression, ScenarioReader) {
  // (the shipped scenarios among the seeds are read without an error)
  EXPECT_GE(replay("scenario", fuzz::scenario_input), 5);
}

TEST(FuzzRegression, Expressions) { EXPECT_GE(replay("expression", fuzz::expression_input), 1); }

TEST(FuzzRegression, TemplateCsv) { EXPECT_GE(replay("template_csv", fuzz::template_csv_input), 2); }

TEST(FuzzRegression, Stl) { EXPECT_GE(replay("stl", fuzz::stl_input), 2); }

TEST(FuzzRegression, Checkpoint) {
  const fuzz::CheckpointInput checkpoint(fs::temp_directory_path() /
                                         ("bushel_" + std::to_string(::getpid()) + "_FuzzRegression_Checkpoint"));
  // The seed made by this build continues (to its next check, where it stops again).
  EXPECT_TRUE(checkpoint.feed(checkpoint.seed()).interrupted);
  // The committed seed may be of an older format: then it is refused, as every reproducer
  // may be.
  replay("checkpoint", [&](std::string_view bytes) { (void)checkpoint.feed(bytes); });
}

TEST(FuzzRegression, RunWithANameThatIsNotUtf8) {
  // Found by the checkpoint target (tests/fuzz/regressions/checkpoint/value-name-not-utf8.bin):
  // a name that is not UTF-8 reached summary.json's writer, whose JSON library threw a
  // type_error (an "internal error" after the whole run). A scenario file in Latin-1 gets
  // there without any checkpoint: it must be refused when read, or its run must end with its
  // summary written.
  std::string text = fuzz::CheckpointInput::scenario_text;
  text.replace(text.find("name: fill"), 10, "name: f\xe9ll");
  const fs::path dir = fs::temp_directory_path() / ("bushel_" + std::to_string(::getpid()) + "_FuzzRegression_Utf8");
  RunOptions o;
  o.out_dir = dir.string();
  o.progress = false;
  o.overwrite = true;
  o.interrupt_at = 0.0;  // (the summary is written when the run stops, as at its end)
  try {
    const Scenario sc = read_scenario(parse_scenario_document(text, "latin1.yaml"));
    (void)run_scenario(sc, o);
    EXPECT_TRUE(fs::exists(dir / "summary.json"));
  } catch (const InputError&) {
    // refused as bad input: fine
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
}

}  // namespace
}  // namespace bushel
