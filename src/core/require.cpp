#include "bushel/core/require.hpp"

#include <fmt/format.h>
#include <cmath>
#include <string>

#include "bushel/core/input_error.hpp"

namespace bushel {

void require_positive(double value, std::string_view key, std::string_view example, std::string_view si_unit) {
  if (value > 0.0 && std::isfinite(value)) return;
  throw InputError(fmt::format("expected a positive value (e.g. {}), got {:g}{}{}", example, value,
                               si_unit.empty() ? "" : " ", si_unit))
      .with_key(std::string(key));
}

}  // namespace bushel
