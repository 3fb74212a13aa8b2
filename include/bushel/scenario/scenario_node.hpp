#pragma once
// One node of a scenario file, read with the checks every section needs: values with units
// (into SI), vectors, choices, unknown keys with a did-you-mean, missing keys. Every error
// names the file, the line and the key path ("cup.yaml:12: key 'parts.cup.radius': ...").

#include <initializer_list>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "bushel/core/input_error.hpp"
#include "bushel/core/vec3.hpp"
#include "bushel/units/units.hpp"

namespace bushel {

class ScenarioNode {
 public:
  /// `path` is the key path of `node` from the root ("" for the root); `file` names the
  /// scenario in errors.
  /// `set_by` (may be null, else it must outlive the node and its children) maps key paths to
  /// the `--set` their value was made from, which errors about them name.
  ScenarioNode(YAML::Node node, std::string path, std::string file,
               const std::map<std::string, std::string>* set_by = nullptr);

  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }
  int line() const;  ///< from 1; 0 for a value set on the command line
  bool is_map() const { return node_.IsMap(); }
  bool is_list() const { return node_.IsSequence(); }
  bool is_scalar() const { return node_.IsScalar(); }

  /// An InputError at this node: file, line and key path.
  InputError error(const std::string& problem) const;

  // --- maps ----------------------------------------------------------------------------------
  bool has(const std::string& key) const;
  /// The value under `key`; an error naming the key if it is missing.
  ScenarioNode at(const std::string& key) const;
  std::optional<ScenarioNode> find(const std::string& key) const;
  /// Keys and values in file order; an error unless this is a map.
  std::vector<std::pair<std::string, ScenarioNode>> entries() const;
  /// An error for the first key not in `allowed` (with a did-you-mean and the list of keys);
  /// `what` names the kind of map in the message ("for a cylinder"), if given.
  void allow_only(std::span<const std::string_view> allowed, std::string_view what = "") const;
  void allow_only(std::initializer_list<std::string_view> allowed) const {
    allow_only(std::span<const std::string_view>(allowed.begin(), allowed.size()));
  }
  /// An error unless exactly one of `keys` is present; returns it.
  std::string one_of(std::initializer_list<std::string_view> keys) const;

  // --- lists ---------------------------------------------------------------------------------
  /// The items; an error unless this is a list.
  std::vector<ScenarioNode> items() const;

  // --- single values -------------------------------------------------------------------------
  std::string text() const;
  /// A quantity with its unit, in SI (units.hpp).
  double quantity(units::Dimension d) const;
  /// A plain number (no unit).
  double number() const;
  /// A whole number in [lo, hi].
  long integer(long lo, long hi) const;
  bool boolean() const;
  /// Three values: "x y z unit" or a list of three quantities ([0 mm, 0 mm, 80 mm]).
  Vec3 vector(units::Dimension d) const;
  /// One of `choices` (an error listing them, with a did-you-mean).
  std::string choice(std::initializer_list<std::string_view> choices) const;
  std::string choice(const std::vector<std::string>& choices) const;

  // --- shorthands on maps: the value under `key`, or `fallback` where the key is absent ---
  double quantity(const std::string& key, units::Dimension d) const { return at(key).quantity(d); }
  double quantity_or(const std::string& key, units::Dimension d, double fallback) const;
  /// The same with checks: > 0 (positive) or >= 0 (non-negative), finite.
  double positive(const std::string& key, units::Dimension d) const;
  double positive_or(const std::string& key, units::Dimension d, double fallback) const;
  double non_negative_or(const std::string& key, units::Dimension d, double fallback) const;
  std::string text_or(const std::string& key, const std::string& fallback) const;
  bool boolean_or(const std::string& key, bool fallback) const;
  Vec3 vector_or(const std::string& key, units::Dimension d, const Vec3& fallback) const;

 private:
  ScenarioNode child(YAML::Node node, const std::string& key) const;
  YAML::Node node_;
  std::string path_, file_;
  const std::map<std::string, std::string>* set_by_ = nullptr;
};

}  // namespace bushel
