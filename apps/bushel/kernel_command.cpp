#include <fmt/format.h>
#include <memory>
#include <nlohmann/json.hpp>

#include "bushel/analysis/kernel_shape.hpp"
#include "commands.hpp"

namespace bushel::cli {

namespace {

struct KernelOptions {
  std::string length, width, thickness;
  bool json = false;
};

void run_kernel(const KernelOptions& o) {
  const KernelDimensions d{option_quantity("--length", o.length, units::dim::length),
                           option_quantity("--width", o.width, units::dim::length),
                           option_quantity("--thickness", o.thickness, units::dim::length)};
  const ShapeFactors f = shape_factors(d);
  if (o.json) {
    const nlohmann::ordered_json j = {
        {"length_m", d.length},
        {"width_m", d.width},
        {"thickness_m", d.thickness},
        {"equivalent_diameter_m", f.equivalent_diameter},
        {"sphericity_mohsenin", f.sphericity_mohsenin},
        {"sphericity_wadell", f.sphericity_wadell},
        {"flatness", f.flatness},
        {"elongation", f.elongation},
    };
    fmt::print("{}\n", j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace));
    return;
  }
  fmt::print("kernel                 {:.3f} x {:.3f} x {:.3f} mm (length x width x thickness)\n", d.length * 1e3,
             d.width * 1e3, d.thickness * 1e3);
  fmt::print("equivalent diameter    {:.3f} mm   (l w t)^(1/3)\n", f.equivalent_diameter * 1e3);
  fmt::print("sphericity (Mohsenin)  {:.3f}      d_s / l\n", f.sphericity_mohsenin);
  fmt::print("sphericity (Wadell)    {:.3f}      equal-volume sphere / ellipsoid surface\n", f.sphericity_wadell);
  fmt::print("flatness               {:.3f}      w / t\n", f.flatness);
  fmt::print("elongation             {:.3f}      l / t\n", f.elongation);
}

}  // namespace

void add_kernel_command(CLI::App& app) {
  auto opts = std::make_shared<KernelOptions>();
  auto* cmd = app.add_subcommand("kernel", "Shape factors of a kernel from its length, width and thickness");
  cmd->add_option("--length", opts->length, "Kernel length with unit, e.g. 5.42mm")->required();
  cmd->add_option("--width", opts->width, "Kernel width with unit, e.g. 2.96mm")->required();
  cmd->add_option("--thickness", opts->thickness, "Kernel thickness with unit, e.g. 2.65mm")->required();
  cmd->add_flag("--json", opts->json, "Print JSON (SI units) instead of a table");
  cmd->callback([opts] { run_kernel(*opts); });
}

}  // namespace bushel::cli
