#pragma once
// Input checks shared by every module, so that the same mistake gets the same message.

#include <string_view>

namespace bushel {

/// Throws InputError keyed by `key` unless `value` is finite and > 0. `example` shows a valid
/// value with its unit, e.g. "6.12mm"; `si_unit` is the unit the offending value is shown in.
void require_positive(double value, std::string_view key, std::string_view example, std::string_view si_unit = "");

}  // namespace bushel
