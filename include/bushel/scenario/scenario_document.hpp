#pragma once
// A scenario file as a YAML tree, before any of it is interpreted: the command line's
// overrides (`--set path.to.key=value`) applied and the `${name}` references to the
// `parameters:` section resolved, every node read from the file still carrying its line for
// error messages. The scenario's sections are read from this tree (docs/scenarios.md).
//
//   parameters:            # name: default value (a scalar)
//     scale: 1
//     drop: 5.1 cm
//   factories:
//     - mass: ${scale} kg  # -> "1 kg", or "0.1 kg" after --set parameters.scale=0.1

#include <cstddef>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace bushel {

/// One `--set path.to.key=value`. The path's segments are map keys, or indices (from 0) into
/// lists: `stages.1.time=2 s`. The value replaces a scalar or adds a key to an existing map.
struct Override {
  std::string path;   ///< e.g. "materials.wheat.density"
  std::string value;  ///< the new scalar, as text: "1400 kg/m3"
};

/// Parses "path=value" (text after the first '='); throws InputError for a missing '=', an
/// empty path or an empty segment.
Override parse_override(std::string_view text);

/// The largest scenario file bushel reads [bytes]; shipped ones are under 16 KiB.
inline constexpr std::size_t max_scenario_bytes = std::size_t{16} << 20;

/// A scenario file with its overrides applied and its parameters substituted.
struct ScenarioDocument {
  std::string file;                               ///< the path it was read from (errors name it)
  YAML::Node root;                                ///< the resolved tree: a map
  std::vector<Override> overrides;                ///< as given, in order (the run's summary echoes them)
  std::map<std::string, std::string> parameters;  ///< name -> value after overrides
  /// Key path -> the `--set parameters.NAME=...` its value was made from ("${NAME}" in it), so
  /// that an error about the value names the command line's part in it.
  std::map<std::string, std::string> set_by;
};

/// Reads a scenario file. Overrides are applied in order, then `${name}` in every scalar
/// outside `parameters:` is replaced by that parameter's value. Throws InputError naming the
/// file, line and key: unreadable file, YAML syntax, a root that is not a map, an override
/// path that does not exist (with a did-you-mean), an unknown or malformed reference.
ScenarioDocument load_scenario_document(const std::string& path, std::span<const Override> overrides = {});
/// The same from text; `source` names it in errors.
ScenarioDocument parse_scenario_document(const std::string& text, const std::string& source,
                                         std::span<const Override> overrides = {});

/// Line (from 1) of a node in its file; 0 for a value set on the command line.
int line_of(const YAML::Node& node);

}  // namespace bushel
