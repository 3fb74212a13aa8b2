#pragma once
// One of a fixed set of words (a model, a mode, a shape) read from the user, with the same
// error everywhere: "expected a, b or c, got 'x' (did you mean 'b'?)".

#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace bushel {

/// The InputError for `text` not being one of `names`.
[[noreturn]] void throw_bad_choice(std::string_view text, const std::vector<std::string>& names);

/// The value paired with `text`; throws InputError (with a did-you-mean) if there is none.
template <class T>
T parse_choice(std::string_view text, std::initializer_list<std::pair<const char*, T>> choices) {
  std::vector<std::string> names;
  for (const auto& [name, value] : choices) {
    if (text == name) return value;
    names.emplace_back(name);
  }
  throw_bad_choice(text, names);
}

}  // namespace bushel
