#include "bushel/scenario/scenario_document.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>

#include <fmt/format.h>

#include "bushel/core/did_you_mean.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/io/csv.hpp"
#include "bushel/scenario/yaml_structure.hpp"
#include "bushel/units/expression.hpp"

namespace bushel {
namespace {

constexpr const char* command_line = "command line";

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> segments;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = path.find('.', start);
    segments.push_back(path.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
    if (dot == std::string::npos) return segments;
    start = dot + 1;
  }
}

std::vector<std::string> keys_of(const YAML::Node& map) {
  std::vector<std::string> keys;
  for (const auto& kv : map) keys.push_back(kv.first.as<std::string>());
  return keys;
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

// The list index a segment names, or -1 if it is not a whole number.
long index_of(const std::string& segment) {
  long k = -1;
  const auto [end, ec] = std::from_chars(segment.data(), segment.data() + segment.size(), k);
  return ec == std::errc{} && end == segment.data() + segment.size() ? k : -1;
}

// Applies one override: the path leads through existing maps and lists to a single value
// (or to a new key of a map). The value becomes a node of its own, without a line in the
// file, so that errors about it point at the command line.
void apply(YAML::Node root, const Override& o) {
  const std::vector<std::string> segments = split_path(o.path);
  auto fail = [&](const std::string& problem) {
    return InputError("--set " + o.path + ": " + problem).at(command_line);
  };
  YAML::Node node = root;
  std::string prefix, walked = "the scenario";  // the path so far, and how errors name it
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const std::string& seg = segments[s];
    const bool last = s + 1 == segments.size();
    YAML::Node child;
    bool exists = true;
    long k = -1;  // the list index, where node is a list
    if (node.IsSequence()) {
      k = index_of(seg);
      if (k < 0 || static_cast<std::size_t>(k) >= node.size()) {
        throw fail(walked + " is a list of " + std::to_string(node.size()) + "; '" + seg +
                   "' is not an index into it (from 0)");
      }
      child.reset(node[static_cast<std::size_t>(k)]);
    } else if (node.IsMap()) {
      if (!node[seg] && !last) throw fail(walked + " has no key '" + seg + "'" + did_you_mean(seg, keys_of(node)));
      exists = static_cast<bool>(node[seg]);
      if (exists) child.reset(node[seg]);
      // A new key elsewhere meets read_scenario's check of known keys; a parameter nobody
      // declared would be used nowhere, and the run would silently keep the default.
      if (!exists && s == 1 && segments[0] == "parameters") {
        throw fail("the scenario declares no parameter '" + seg + "'" + did_you_mean(seg, keys_of(node)) +
                   "; it declares: " + join(keys_of(node)));
      }
    } else {
      throw fail(walked + " is a single value; it has no '" + seg + "'");
    }
    if (last) {
      if (exists && (child.IsMap() || child.IsSequence())) {
        throw fail("'" + o.path + "' is a " + (child.IsMap() ? "map" : "list") + "; only single values can be set");
      }
      if (node.IsSequence()) {
        node[static_cast<std::size_t>(k)] = YAML::Node(o.value);
      } else {
        node[seg] = YAML::Node(o.value);
      }
      return;
    }
    node.reset(child);
    if (s > 0) prefix += '.';
    prefix += seg;
    walked = "'" + prefix + "'";
  }
}

// The text a ${...} stands for: a parameter's own text for a bare name ("${drop}" gives
// "5.1 cm"), else the expression's value in SI with its unit ("${2 * drop}" gives "0.102 m").
std::string expand(const std::string& inside, const std::map<std::string, std::string>& parameters,
                   const std::vector<std::string>& names) {
  auto unknown = [&](const std::string& name) {
    return InputError("unknown parameter '" + name + "'" + did_you_mean(name, names) +
                      "; the parameters: section declares " + join(names));
  };
  std::string bare = inside;
  while (!bare.empty() && bare.front() == ' ') bare.erase(bare.begin());
  while (!bare.empty() && bare.back() == ' ') bare.pop_back();
  if (const auto it = parameters.find(bare); it != parameters.end()) return it->second;
  const bool is_name = !bare.empty() && std::all_of(bare.begin(), bare.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
  });
  if (is_name) throw unknown(bare);
  const units::NameLookup lookup = [&](const std::string& name) {
    const auto it = parameters.find(name);
    if (it == parameters.end()) throw unknown(name);
    try {
      return units::parse_quantity(it->second);
    } catch (const InputError&) {
      throw InputError("parameter '" + name + "' is '" + it->second + "', not a number or a quantity");
    }
  };
  return units::format_si(units::evaluate(bare, lookup));
}

// Replaces each ${...} in a scalar's text.
std::string substitute(const std::string& text, const std::map<std::string, std::string>& parameters,
                       const std::vector<std::string>& names) {
  std::string out;
  std::size_t at = 0;
  while (true) {
    const std::size_t open = text.find("${", at);
    if (open == std::string::npos) return out + text.substr(at);
    const std::size_t close = text.find('}', open);
    if (close == std::string::npos) throw InputError("'${' without its closing '}' in \"" + text + "\"");
    out += text.substr(at, open - at) + expand(text.substr(open + 2, close - open - 2), parameters, names);
    at = close + 1;
  }
}

// What substitution needs: the parameters, their names, the file, and the parameters set on
// the command line with their overrides, so that an error in a value made from one names it.
struct Substitution {
  const std::map<std::string, std::string>& parameters;
  const std::vector<std::string>& names;
  const std::string& file;
  std::map<std::string, std::string> from_command_line;  // parameter -> "--set parameters.p=v"
  std::map<std::string, std::string>& set_by;            // filled: key path -> that --set
};

// The `--set` behind a scalar's ${...}, if one of the parameters it names was set so; "".
std::string set_behind(const std::string& text, const Substitution& s) {
  for (const auto& [name, set] : s.from_command_line) {
    for (std::size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + 1)) {
      const std::size_t open = text.rfind("${", at), close = text.rfind('}', at);
      const bool inside = open != std::string::npos && (close == std::string::npos || close < open);
      const auto part_of_name = [&](std::size_t k) {
        return k < text.size() && (std::isalnum(static_cast<unsigned char>(text[k])) != 0 || text[k] == '_');
      };
      if (inside && !part_of_name(at + name.size()) && (at == 0 || !part_of_name(at - 1))) return set;
    }
  }
  return "";
}

void substitute_all(YAML::Node node, const std::string& path, const Substitution& s) {
  if (node.IsScalar()) {
    const std::string text = node.Scalar();
    if (text.find("${") == std::string::npos) return;
    try {
      node = substitute(text, s.parameters, s.names);
    } catch (const InputError& e) {
      throw e.with_key(path).at(s.file, line_of(node));
    }
    if (std::string set = set_behind(text, s); !set.empty()) s.set_by[path] = std::move(set);
    return;
  }
  if (node.IsSequence()) {
    for (std::size_t k = 0; k < node.size(); ++k) substitute_all(node[k], path + "." + std::to_string(k), s);
  } else if (node.IsMap()) {
    for (auto kv : node) {
      const std::string key = kv.first.as<std::string>();
      substitute_all(kv.second, path.empty() ? key : path + "." + key, s);
    }
  }
}

}  // namespace

Override parse_override(std::string_view text) {
  const std::size_t eq = text.find('=');
  auto fail = [&](const std::string& problem) {
    return InputError(fmt::format("'{}': {}; expected path.to.key=value", text, problem)).with_key("--set");
  };
  if (eq == std::string_view::npos) throw fail("no '='");
  Override o{std::string(text.substr(0, eq)), std::string(text.substr(eq + 1))};
  for (const std::string& seg : split_path(o.path)) {
    if (seg.empty()) throw fail("an empty key in the path");
  }
  return o;
}

int line_of(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? 0 : mark.line + 1;
}

ScenarioDocument parse_scenario_document(const std::string& text, const std::string& source,
                                         std::span<const Override> overrides) {
  ScenarioDocument doc{source, {}, {overrides.begin(), overrides.end()}, {}, {}};
  if (text.size() > max_scenario_bytes) {
    throw InputError(fmt::format("a scenario file is at most {} MiB", max_scenario_bytes >> 20)).at(source);
  }
  check_yaml_structure(text, source);
  try {
    doc.root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError("not valid YAML: " + e.msg).at(source, e.mark.is_null() ? 0 : e.mark.line + 1);
  }
  if (!doc.root.IsMap())
    throw InputError("a scenario is a map of sections (materials:, parts:, stages:, ...)").at(source, 1);
  for (const Override& o : overrides) apply(doc.root, o);

  std::vector<std::string> names;
  if (const YAML::Node params = doc.root["parameters"]) {
    if (!params.IsMap()) {
      throw InputError("expected a map of name: default value").with_key("parameters").at(source, line_of(params));
    }
    for (const auto& kv : params) {
      const std::string name = kv.first.as<std::string>();
      if (!kv.second.IsScalar() || kv.second.Scalar().find("${") != std::string::npos) {
        throw InputError("a parameter's value is a single value without ${...}")
            .with_key("parameters." + name)
            .at(source, line_of(kv.second));
      }
      doc.parameters[name] = kv.second.Scalar();
      names.push_back(name);
    }
  }
  Substitution sub{doc.parameters, names, source, {}, doc.set_by};
  for (const Override& o : overrides) {
    if (o.path.starts_with("parameters.")) sub.from_command_line[o.path.substr(11)] = "--set " + o.path + "=" + o.value;
  }
  for (auto kv : doc.root) {
    const std::string key = kv.first.as<std::string>();
    if (key != "parameters") substitute_all(kv.second, key, sub);
  }
  return doc;
}

ScenarioDocument load_scenario_document(const std::string& path, std::span<const Override> overrides) {
  return parse_scenario_document(io::read_text_file(path, max_scenario_bytes), path, overrides);
}

}  // namespace bushel
