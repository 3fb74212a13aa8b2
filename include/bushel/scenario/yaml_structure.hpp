#pragma once
// Checks a YAML text's structure before it is loaded as a tree, so that what yaml-cpp accepts
// but a scenario must not contain is an InputError with its line, never a crash, a hang or a
// silent loss (docs/scenarios.md, "What a scenario file may not contain"):
//
//   - a key that appears twice in one map (both lines named): yaml-cpp keeps the first, so a
//     second `mass:` or a second material of one name would be silently ignored;
//   - a complex key (`? [a, b]`, `{a: 1}: x`) or an alias as a key: keys are plain names;
//   - a second document after `---`: everything after it would be dropped;
//   - an alias to a list or map that contains it (`a: &x [1, *x]`): an endless tree;
//   - aliases that expand to more than `max_yaml_values` values ("billion laughs").

#include <cstddef>
#include <string>
#include <string_view>

namespace bushel {

/// The most values (scalars, lists, maps) a scenario's YAML may hold once its aliases are
/// expanded; the largest shipped scenario holds about 400.
inline constexpr std::size_t max_yaml_values = 100'000;

/// Throws InputError at `source` and the offending line for the cases above, and for YAML
/// syntax errors.
void check_yaml_structure(std::string_view text, const std::string& source);

}  // namespace bushel
