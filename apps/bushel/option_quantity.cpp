#include <sstream>

#include "bushel/core/input_error.hpp"
#include "commands.hpp"

namespace bushel::cli {

double option_quantity(const std::string& option, const std::string& text, units::Dimension expected) {
  try {
    return units::parse(text, expected);
  } catch (const InputError& e) {
    throw e.with_key(option);
  }
}

std::vector<std::string> split_list(const std::string& text, char sep) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, sep);) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace bushel::cli
