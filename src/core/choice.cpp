#include "bushel/core/choice.hpp"

#include <fmt/format.h>

#include "bushel/core/did_you_mean.hpp"
#include "bushel/core/input_error.hpp"

namespace bushel {

void throw_bad_choice(std::string_view text, const std::vector<std::string>& names) {
  std::string list;
  for (std::size_t i = 0; i < names.size(); ++i) {
    list += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  }
  throw InputError(fmt::format("expected {}, got '{}'{}", list, text, did_you_mean(text, names)));
}

}  // namespace bushel
