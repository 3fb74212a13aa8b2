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

}  // namespace bushel::cli
