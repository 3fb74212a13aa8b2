// libFuzzer target: bytes as a run's checkpoint.bin, continued by resume_scenario as
// `bushel run --restart` does (fuzz_inputs.hpp, CheckpointInput). A damaged checkpoint must
// end as an InputError. The seed is made at start-up by a small run; with
// BUSHEL_FUZZ_SEED_DIR set, it is also written there (tests/fuzz/run.sh puts it into the
// corpus, so that the seed always has this build's format). Half of the mutants get their
// section checksums made anew (reseal_checkpoint), so that the readers behind the checksums
// are fuzzed too, unless BUSHEL_FUZZ_RESEAL=0. Its run folders are in $TMPDIR/bushel_checkpoint_fuzz_<pid> (libFuzzer's
// exit does not always remove them; tests/fuzz/run.sh points TMPDIR into build/fuzz/runs/).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include "fuzz/fuzz_inputs.hpp"

namespace {
std::unique_ptr<bushel::fuzz::CheckpointInput> harness;
// BUSHEL_FUZZ_RESEAL=0: mutants keep their broken checksums (damage, which must always be
// refused); otherwise half are resealed (forgeries that reach the readers behind them).
const bool reseal = [] {
  const char* v = std::getenv("BUSHEL_FUZZ_RESEAL");
  return v == nullptr || std::string_view(v) != "0";
}();
}

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  harness = std::make_unique<bushel::fuzz::CheckpointInput>(std::filesystem::temp_directory_path() /
                                                            ("bushel_checkpoint_fuzz_" + std::to_string(::getpid())));
  if (const char* dir = std::getenv("BUSHEL_FUZZ_SEED_DIR")) {
    std::filesystem::create_directories(dir);
    bushel::fuzz::CheckpointInput::write_file(std::filesystem::path(dir) / "seed.bin", harness->seed());
  }
  return 0;
}

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  size = LLVMFuzzerMutate(data, size, max_size);
  if (reseal && seed % 2 == 0) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    if (bushel::fuzz::reseal_checkpoint(bytes)) std::memcpy(data, bytes.data(), size);
  }
  return size;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)harness->feed(std::string_view(reinterpret_cast<const char*>(data), size));
  } catch (const bushel::InputError&) {
  }
  return 0;
}
