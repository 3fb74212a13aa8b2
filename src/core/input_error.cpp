#include "bushel/core/input_error.hpp"

#include <fmt/format.h>
#include <utility>

namespace bushel {

InputError::InputError(std::string problem) : InputError(std::move(problem), {}, 0, {}) {}

InputError::InputError(std::string problem, std::string source, int line, std::string key)
    : std::runtime_error(compose(problem, source, line, key)),
      problem_(std::move(problem)),
      source_(std::move(source)),
      line_(line),
      key_(std::move(key)) {}

InputError InputError::at(const std::string& source, int line) const {
  return {problem_, source_.empty() ? source : source_, line_ == 0 ? line : line_, key_};
}

InputError InputError::with_key(const std::string& key) const {
  if (key_.empty()) return {problem_, source_, line_, key};
  return {problem_, source_, line_, fmt::format("{}{}{}", key, key_.front() == '[' ? "" : ".", key_)};
}

// "file.csv:12: key 'radius_mm': expected ..." -- the compiler-style prefix lets editors
// jump to the place.
std::string InputError::compose(const std::string& problem, const std::string& source, int line,
                                const std::string& key) {
  std::string out;
  if (!source.empty()) out += line > 0 ? fmt::format("{}:{}: ", source, line) : fmt::format("{}: ", source);
  if (!key.empty()) out += fmt::format("key '{}': ", key);
  out += problem;
  return out;
}

}  // namespace bushel
