#include "bushel/scenario/scenario_node.hpp"

#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "bushel/core/did_you_mean.hpp"
#include "bushel/scenario/scenario_document.hpp"

namespace bushel {
namespace {

std::string join(const std::vector<std::string>& words) {
  std::string out;
  for (const auto& w : words) out += (out.empty() ? "" : ", ") + w;
  return out;
}

std::vector<std::string> strings(std::initializer_list<std::string_view> list) { return {list.begin(), list.end()}; }

}  // namespace

ScenarioNode::ScenarioNode(YAML::Node node, std::string path, std::string file,
                           const std::map<std::string, std::string>* set_by)
    : node_(std::move(node)), path_(std::move(path)), file_(std::move(file)), set_by_(set_by) {}

int ScenarioNode::line() const { return line_of(node_); }

InputError ScenarioNode::error(const std::string& problem) const {
  // A value set with --set has no line in the file: the error points at the command line.
  const int l = line();
  const auto set = set_by_ != nullptr ? set_by_->find(path_) : std::map<std::string, std::string>::const_iterator{};
  const std::string from =
      set_by_ != nullptr && set != set_by_->end() ? " (the value comes from " + set->second + ")" : "";
  InputError e = InputError(problem + from).at(l > 0 ? file_ : "command line (--set)", l);
  return path_.empty() ? e : e.with_key(path_);
}

ScenarioNode ScenarioNode::child(YAML::Node node, const std::string& key) const {
  return ScenarioNode(std::move(node), path_.empty() ? key : path_ + "." + key, file_, set_by_);
}

bool ScenarioNode::has(const std::string& key) const { return node_.IsMap() && node_[key]; }

ScenarioNode ScenarioNode::at(const std::string& key) const {
  if (!node_.IsMap()) throw error("expected a map with the key '" + key + "'");
  if (!node_[key]) throw error("the key '" + key + "' is missing");
  return child(node_[key], key);
}

std::optional<ScenarioNode> ScenarioNode::find(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return child(node_[key], key);
}

std::vector<std::pair<std::string, ScenarioNode>> ScenarioNode::entries() const {
  if (node_.IsNull()) return {};
  if (!node_.IsMap()) throw error("expected a map (key: value lines)");
  std::vector<std::pair<std::string, ScenarioNode>> out;
  for (const auto& kv : node_) {
    const auto key = kv.first.as<std::string>();
    out.emplace_back(key, child(kv.second, key));
  }
  return out;
}

void ScenarioNode::allow_only(std::span<const std::string_view> allowed, std::string_view what) const {
  if (!node_.IsMap()) throw error("expected a map (key: value lines)");
  const std::vector<std::string> known(allowed.begin(), allowed.end());
  for (const auto& kv : node_) {
    const auto key = kv.first.as<std::string>();
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    throw child(kv.second, key)
        .error("unknown key '" + key + "'" + (what.empty() ? "" : " for " + std::string(what)) +
               did_you_mean(key, known) + "; expected one of " + join(known));
  }
}

std::string ScenarioNode::one_of(std::initializer_list<std::string_view> keys) const {
  std::vector<std::string> present;
  for (const auto k : keys) {
    if (has(std::string(k))) present.emplace_back(k);
  }
  if (present.size() != 1) {
    throw error(fmt::format("expected exactly one of {}, got {}", join(strings(keys)),
                            present.empty() ? std::string("none") : join(present)));
  }
  return present.front();
}

std::vector<ScenarioNode> ScenarioNode::items() const {
  if (!node_.IsSequence()) throw error("expected a list (lines starting with '- ', or [a, b])");
  std::vector<ScenarioNode> out;
  for (std::size_t i = 0; i < node_.size(); ++i) out.push_back(child(node_[i], std::to_string(i)));
  return out;
}

std::string ScenarioNode::text() const {
  if (!node_.IsScalar()) throw error("expected a single value");
  return node_.Scalar();
}

double ScenarioNode::quantity(units::Dimension d) const {
  try {
    return units::parse(text(), d);
  } catch (const InputError& e) {
    throw error(e.problem());
  }
}

double ScenarioNode::number() const {
  try {
    return units::parse_number(text());
  } catch (const InputError& e) {
    throw error(e.problem());
  }
}

long ScenarioNode::integer(long lo, long hi) const {
  const double v = number();
  if (!(v >= static_cast<double>(lo) && v <= static_cast<double>(hi)) || v != std::floor(v)) {
    throw error(fmt::format("expected a whole number from {} to {}, got '{}'", lo, hi, text()));
  }
  return static_cast<long>(v);
}

bool ScenarioNode::boolean() const {
  const std::string t = text();
  if (t == "true" || t == "yes" || t == "on") return true;
  if (t == "false" || t == "no" || t == "off") return false;
  throw error("expected true or false, got '" + t + "'");
}

Vec3 ScenarioNode::vector(units::Dimension d) const {
  if (node_.IsSequence()) {
    if (node_.size() != 3) throw error(fmt::format("expected 3 values (x, y, z), got {}", node_.size()));
    const auto v = items();
    return {v[0].quantity(d), v[1].quantity(d), v[2].quantity(d)};
  }
  // "x y z unit": three numbers sharing one unit
  std::istringstream in(text());
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  const std::string unit = words.size() == 4 ? words[3] : "";
  if (words.size() != 4 && !(words.size() == 3 && d == units::dim::dimensionless)) {
    throw error(fmt::format("expected 'x y z unit' (e.g. '0 0 80 mm') or a list of three {}s, got '{}'",
                            units::dimension_name(d), text()));
  }
  Vec3 v;
  double* out[3] = {&v.x, &v.y, &v.z};
  for (int k = 0; k < 3; ++k) {
    try {
      *out[k] = units::parse(words[static_cast<std::size_t>(k)] + unit, d);
    } catch (const InputError& e) {
      throw error(e.problem());
    }
  }
  return v;
}

std::string ScenarioNode::choice(std::initializer_list<std::string_view> choices) const {
  return choice(strings(choices));
}

std::string ScenarioNode::choice(const std::vector<std::string>& known) const {
  const std::string t = text();
  if (std::find(known.begin(), known.end(), t) != known.end()) return t;
  throw error("unknown value '" + t + "'" + did_you_mean(t, known) + "; expected one of " + join(known));
}

double ScenarioNode::quantity_or(const std::string& key, units::Dimension d, double fallback) const {
  return has(key) ? at(key).quantity(d) : fallback;
}

double ScenarioNode::positive(const std::string& key, units::Dimension d) const {
  const ScenarioNode n = at(key);
  const double v = n.quantity(d);
  if (!(v > 0.0) || !std::isfinite(v))
    throw n.error("expected a positive " + units::dimension_name(d) + ", got '" + n.text() + "'");
  return v;
}

double ScenarioNode::positive_or(const std::string& key, units::Dimension d, double fallback) const {
  return has(key) ? positive(key, d) : fallback;
}

double ScenarioNode::non_negative_or(const std::string& key, units::Dimension d, double fallback) const {
  if (!has(key)) return fallback;
  const ScenarioNode n = at(key);
  const double v = n.quantity(d);
  if (!(v >= 0.0) || !std::isfinite(v)) {
    throw n.error("expected a " + units::dimension_name(d) + " >= 0, got '" + n.text() + "'");
  }
  return v;
}

std::string ScenarioNode::text_or(const std::string& key, const std::string& fallback) const {
  return has(key) ? at(key).text() : fallback;
}

bool ScenarioNode::boolean_or(const std::string& key, bool fallback) const {
  return has(key) ? at(key).boolean() : fallback;
}

Vec3 ScenarioNode::vector_or(const std::string& key, units::Dimension d, const Vec3& fallback) const {
  return has(key) ? at(key).vector(d) : fallback;
}

}  // namespace bushel
