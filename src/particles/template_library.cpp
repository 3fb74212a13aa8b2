#include "bushel/particles/template_library.hpp"

#include <filesystem>

#include "bushel/core/did_you_mean.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/io/csv.hpp"
#include "bushel/units/units.hpp"

namespace bushel {
namespace embedded {
std::string_view wheat_clumps_csv();  // generated from data/wheat_clumps.csv
}

namespace {

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace

TemplateLibrary TemplateLibrary::parse_csv(std::string_view text, const std::string& source,
                                           const TemplateOptions& options) {
  const io::CsvTable table = io::CsvTable::parse(text, source);
  // The unit is part of the column name: x_mm or x_m.
  const std::string unit = table.has_column("x_mm") ? "mm" : "m";
  const double scale = units::from_unit(1.0, unit);
  const std::size_t c_name = table.column("template");
  const std::size_t c_x = table.column("x_" + unit), c_y = table.column("y_" + unit), c_z = table.column("z_" + unit);
  const std::size_t c_r = table.column("radius_" + unit);

  TemplateLibrary lib;
  lib.source_ = source;
  std::map<std::string, std::vector<SphereElement>> spheres;
  std::map<std::string, int> first_line;
  for (const auto& row : table.rows()) {
    const std::string& name = row.fields[c_name];
    if (name.empty()) throw InputError("expected a template name").with_key("template").at(source, row.line);
    const double r = table.number(row, c_r) * scale;
    if (!(r > 0.0)) {
      throw InputError("expected a positive radius in " + unit + ", got " + row.fields[c_r])
          .with_key(table.header()[c_r])
          .at(source, row.line);
    }
    if (!spheres.contains(name)) {
      lib.names_.push_back(name);
      first_line[name] = row.line;
    }
    spheres[name].push_back(
        {{table.number(row, c_x) * scale, table.number(row, c_y) * scale, table.number(row, c_z) * scale}, r});
  }
  if (lib.names_.empty()) throw InputError("expected at least one template row").at(source);
  for (const auto& name : lib.names_) {
    try {
      lib.templates_.emplace(name, make_template(name, std::move(spheres[name]), options));
    } catch (const InputError& e) {
      throw e.at(source, first_line[name]);
    }
  }
  return lib;
}

TemplateLibrary TemplateLibrary::read_csv(const std::string& path, const TemplateOptions& options) {
  return parse_csv(io::read_text_file(path), path, options);
}

const TemplateLibrary& TemplateLibrary::builtin() {
  // The study's single-sphere models: the sphere of each fraction's kernel mass (equivalent
  // diameters 3.64 / 3.25 / 2.81 mm, docs/wheat.md), next to the clumps, so that a scenario picks
  // a model by name ("${fraction}_${model}").
  static const std::string single_spheres =
      "large_1s,Sphere0,0,0,0,1.82\nmedium_1s,Sphere0,0,0,0,1.625\nsmall_1s,Sphere0,0,0,0,1.405\n";
  static const TemplateLibrary lib = [] {
    std::string text(embedded::wheat_clumps_csv());
    if (!text.empty() && text.back() != '\n') text += '\n';
    return parse_csv(text + single_spheres, "bushel's built-in templates (data/wheat_clumps.csv and *_1s)");
  }();
  return lib;
}

const ParticleTemplate& TemplateLibrary::get(const std::string& name) const {
  const auto it = templates_.find(name);
  if (it != templates_.end()) return it->second;
  throw InputError("unknown particle template '" + name + "'" + did_you_mean(name, names_) + "; " + source_ +
                   " has: " + join(names_));
}

ParticleTemplate resolve_template(const std::string& spec, const TemplateOptions& options) {
  std::string path = spec, name;
  if (const auto colon = spec.rfind(':'); colon != std::string::npos && spec.find(".csv") < colon) {
    path = spec.substr(0, colon);
    name = spec.substr(colon + 1);
  }
  std::error_code ec;  // (a name too long for a path is a name, not an error of the file system)
  const bool is_file = path.ends_with(".csv") || std::filesystem::exists(path, ec);
  if (!is_file) return TemplateLibrary::builtin().get(spec);
  const TemplateLibrary lib = TemplateLibrary::read_csv(path, options);
  if (name.empty()) {
    if (lib.names().size() != 1) {
      throw InputError("holds " + std::to_string(lib.names().size()) + " templates (" + join(lib.names()) +
                       "); choose one as " + path + ":NAME")
          .at(path);
    }
    name = lib.names().front();
  }
  return lib.get(name);
}

}  // namespace bushel
