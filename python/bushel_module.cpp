// Python access to bushel's particle templates, units and grain formulas, for notebooks and
// scripts that post-process runs. Values are SI; quantities may be given as strings with units.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "bushel/analysis/grain_trade.hpp"
#include "bushel/analysis/kernel_shape.hpp"
#include "bushel/contact/time_scales.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/particles/material.hpp"
#include "bushel/particles/pseudo_ellipsoid.hpp"
#include "bushel/particles/template_library.hpp"
#include "bushel/units/units.hpp"

namespace py = pybind11;

namespace {

bushel::units::Dimension dimension_named(const std::string& name) {
  namespace d = bushel::units::dim;
  for (const auto dim :
       {d::dimensionless, d::length, d::area, d::volume, d::mass, d::time, d::frequency, d::velocity, d::acceleration,
        d::density, d::mass_flow, d::force, d::pressure, d::angle, d::angular_velocity}) {
    if (bushel::units::dimension_name(dim) == name) return dim;
  }
  throw bushel::InputError("unknown dimension '" + name + "' (e.g. 'length', 'mass', 'density', 'pressure')");
}

py::dict describe(const bushel::ParticleTemplate& t, double density) {
  py::list spheres;
  for (const auto& s : t.spheres) spheres.append(py::make_tuple(s.centre.x, s.centre.y, s.centre.z, s.radius));
  const auto e = t.extents();
  const auto inertia = t.principal_inertia(density);
  py::dict d;
  d["name"] = t.name;
  d["spheres"] = spheres;
  d["volume_m3"] = t.volume;
  d["mass_kg"] = t.mass(density);
  d["equivalent_diameter_m"] = t.equivalent_diameter();
  d["extents_m"] = py::make_tuple(e.x, e.y, e.z);
  d["aspect_ratio"] = t.aspect_ratio();
  d["principal_inertia_kg_m2"] = py::make_tuple(inertia.x, inertia.y, inertia.z);
  return d;
}

}  // namespace

PYBIND11_MODULE(bushel, m) {
  m.doc() = "bushel: DEM of grain bulk density -- templates, units and grain formulas";
  py::register_exception<bushel::InputError>(m, "InputError", PyExc_ValueError);

  m.def(
      "parse",
      [](const std::string& text, const std::string& dimension) {
        return bushel::units::parse(text, dimension_named(dimension));
      },
      py::arg("text"), py::arg("dimension"), "Quantity with unit -> SI value, e.g. parse('6.12mm', 'length')");

  m.def(
      "template",
      [](const std::string& spec, double density) { return describe(bushel::resolve_template(spec), density); },
      py::arg("spec"), py::arg("density") = bushel::materials::wheat().density,
      "Built-in template name, CSV path or 'path.csv:name' -> dict of SI mass properties");

  m.def("template_names", [] { return bushel::TemplateLibrary::builtin().names(); });

  m.def(
      "pseudo_ellipsoid",
      [](double length, double width, int spheres, std::optional<double> mass, double density,
         std::optional<double> end_radius) {
        bushel::PseudoEllipsoidSpec s{length, width, spheres, mass, density, end_radius};
        return describe(bushel::make_pseudo_ellipsoid(s, "ellipsoid"), density);
      },
      py::arg("length"), py::arg("width"), py::arg("spheres") = 5, py::arg("mass") = py::none(),
      py::arg("density") = bushel::materials::wheat().density, py::arg("end_radius") = py::none(),
      "Pseudo-ellipsoid clump (SI inputs)");

  m.def(
      "shape_factors",
      [](double l, double w, double t) {
        const auto f = bushel::shape_factors({l, w, t});
        py::dict d;
        d["equivalent_diameter"] = f.equivalent_diameter;
        d["sphericity_mohsenin"] = f.sphericity_mohsenin;
        d["sphericity_wadell"] = f.sphericity_wadell;
        d["flatness"] = f.flatness;
        d["elongation"] = f.elongation;
        return d;
      },
      py::arg("length"), py::arg("width"), py::arg("thickness"));

  m.def("rayleigh_time_step", &bushel::rayleigh_time_step, py::arg("radius"), py::arg("density"),
        py::arg("shear_modulus"), py::arg("poisson_ratio"));
  m.def("packing_ratio", &bushel::packing_ratio, py::arg("packed_density"), py::arg("initial_density"));
  m.def("compressibility", &bushel::compressibility, py::arg("tapped_density"), py::arg("loose_density"));
  m.def("mass_in_bin", &bushel::mass_in_bin, py::arg("initial_density"), py::arg("packing_ratio"), py::arg("volume"));
  m.def("pack_factor", &bushel::pack_factor, py::arg("packing_ratio"), py::arg("initial_density"),
        py::arg("standard_test_weight"));
}
