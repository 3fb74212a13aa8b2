#pragma once
// Particle templates by name: the wheat clumps shipped in data/wheat_clumps.csv (built into
// the binary) and templates read from user CSV files of the same format:
//
//   template,sphere,x_mm,y_mm,z_mm,radius_mm
//   large_5s,Sphere0,-2.149,0,0,0.911
//
// Coordinates may be given in mm (x_mm, ..., radius_mm) or in m (x_m, ..., radius_m).

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "bushel/particles/particle_template.hpp"

namespace bushel {

class TemplateLibrary {
 public:
  /// The templates shipped with bushel (data/wheat_clumps.csv).
  static const TemplateLibrary& builtin();
  /// Reads every template of a CSV file; throws InputError with file, line and column.
  static TemplateLibrary read_csv(const std::string& path, const TemplateOptions& options = {});
  /// Parses CSV text; `source` names it in errors.
  static TemplateLibrary parse_csv(std::string_view text, const std::string& source,
                                   const TemplateOptions& options = {});

  /// Template names in file order.
  const std::vector<std::string>& names() const { return names_; }
  bool contains(const std::string& name) const { return templates_.contains(name); }
  /// The template; throws InputError listing the known names (with a did-you-mean).
  const ParticleTemplate& get(const std::string& name) const;

 private:
  std::string source_;
  std::vector<std::string> names_;
  std::map<std::string, ParticleTemplate> templates_;
};

/// Resolves what a user typed: "large_5s" (built in), "file.csv" (its only template) or
/// "file.csv:name". Throws InputError when the name is unknown or a file holds several
/// templates and none was chosen.
ParticleTemplate resolve_template(const std::string& spec, const TemplateOptions& options = {});

}  // namespace bushel
