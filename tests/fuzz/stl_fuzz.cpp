// libFuzzer target: STL bytes (ASCII or binary) through io::parse_stl, the mesh checked
// (fuzz_inputs.hpp). An InputError is the answer to bad input; anything else is a bug.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz/fuzz_inputs.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    bushel::fuzz::stl_input(std::string_view(reinterpret_cast<const char*>(data), size));
  } catch (const bushel::InputError&) {
  }
  return 0;
}
