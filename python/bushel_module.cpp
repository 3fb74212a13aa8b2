// The compiled part of the Python package `bushel` (python/bushel/): scenarios validated and
// run, particle templates, units and grain formulas. Values are SI; every quantity may also be
// given as a string with its unit ("5.42 mm"). The package's Python modules read a run's
// outputs (runs.py, frames.py).
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "bushel/analysis/grain_trade.hpp"
#include "bushel/analysis/kernel_shape.hpp"
#include "bushel/contact/time_scales.hpp"
#include "bushel/core/build_info.hpp"
#include "bushel/core/choice.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/doe/design.hpp"
#include "bushel/doe/desirability.hpp"
#include "bushel/doe/regression.hpp"
#include "bushel/doe/row_filter.hpp"
#include "bushel/io/csv.hpp"
#include "bushel/particles/material.hpp"
#include "bushel/particles/pseudo_ellipsoid.hpp"
#include "bushel/particles/template_library.hpp"
#include "bushel/scenario/scenario.hpp"
#include "bushel/scenario/scenario_document.hpp"
#include "bushel/scenario/scenario_run.hpp"
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

// A quantity from Python: a number (SI) or a string with its unit, checked against `dim`.
double si(const py::handle& value, bushel::units::Dimension dim, const char* name) {
  if (py::isinstance<py::str>(value)) {
    try {
      return bushel::units::parse(value.cast<std::string>(), dim);
    } catch (const bushel::InputError& e) {
      throw bushel::InputError(e.problem()).with_key(name);
    }
  }
  if (py::isinstance<py::bool_>(value) || !(py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value))) {
    throw bushel::InputError(std::string("expected a number (SI) or a string with a unit, got ") +
                             py::str(py::type::of(value)).cast<std::string>())
        .with_key(name);
  }
  return value.cast<double>();
}
std::optional<double> si_or_none(const py::handle& value, bushel::units::Dimension dim, const char* name) {
  return value.is_none() ? std::nullopt : std::optional(si(value, dim, name));
}

// A scenario from a file path, or from its text (YAML or JSON) when `is_text`.
bushel::Scenario load_scenario(const std::string& source, bool is_text, const std::vector<std::string>& sets) {
  std::vector<bushel::Override> overrides;
  for (const auto& s : sets) overrides.push_back(bushel::parse_override(s));
  return bushel::read_scenario(is_text ? bushel::parse_scenario_document(source, "<python>", overrides)
                                       : bushel::load_scenario_document(source, overrides));
}

// The run (fresh, or continued from the checkpoint in `out` when `resume`) with the GIL
// released while it steps; `progress(dict)` is called at checks with the GIL held, and a true
// result or an exception stops the run there as Ctrl-C would (the exception is raised after).
py::dict run(const std::string& source, bool is_text, const std::vector<std::string>& sets, const std::string& out,
             bool resume, int threads, bool overwrite, const py::object& stop_at, double checkpoint_minutes,
             const py::object& progress) {
  bushel::RunOptions o;
  o.out_dir = out;
  o.threads = threads;
  o.overwrite = overwrite;
  o.progress = false;
  o.checkpoint_interval = 60.0 * checkpoint_minutes;
  if (!stop_at.is_none()) o.interrupt_at = si(stop_at, bushel::units::dim::time, "stop_at");
  bool raised = false;
  if (!progress.is_none()) {
    o.on_check = [&](const bushel::RunProgress& p) {
      py::gil_scoped_acquire gil;
      try {
        py::dict d;
        d["stage"] = p.stage;
        d["stage_index"] = p.stage_index;
        d["stages"] = p.stages;
        d["time_s"] = p.time;
        d["particles"] = p.particles;
        d["steps"] = p.steps;
        d["wall_time_s"] = p.wall_time;
        const py::object r = progress(d);
        return !r.is_none() && r.cast<bool>();
      } catch (py::error_already_set& e) {
        e.restore();  // (raised again below, once the run has stopped and the GIL is back)
        raised = true;
        return true;
      }
    };
  }
  bushel::RunReport r;
  if (resume) {
    py::gil_scoped_release released;
    r = bushel::resume_scenario(o);
  } else {
    const bushel::Scenario sc = load_scenario(source, is_text, sets);
    py::gil_scoped_release released;
    r = bushel::run_scenario(sc, o);
  }
  if (raised) throw py::error_already_set();
  py::dict d;
  d["out"] = out;
  d["interrupted"] = r.interrupted;
  d["at_stop_time"] = r.at_stop_time;
  d["signal"] = r.signal;
  d["failed"] = r.failed;
  return d;
}

// A designed experiment in coded units (bushel/doe/design.hpp), its runs in standard order.
py::dict design(const std::string& kind, const std::vector<bushel::doe::Factor>& factor_levels, int runs, int centre,
                const std::string& ccd, int blocks, const py::object& seed) {
  const int factors = static_cast<int>(factor_levels.size());
  namespace doe = bushel::doe;
  const auto seed_or = [&](const char* what) {
    if (seed.is_none()) throw bushel::InputError(std::string("a ") + what + " needs a seed").with_key("seed");
    return seed.cast<std::uint64_t>();
  };
  doe::Design d = bushel::parse_choice<std::function<doe::Design()>>(
      kind, {{"plackett-burman", [&] { return doe::plackett_burman(factors, runs); }},
             {"factorial", [&] { return doe::factorial(factors, 0, centre); }},
             {"ccd", [&] { return doe::central_composite(factors, doe::parse_ccd_type(ccd), centre, blocks); }},
             {"box-behnken", [&] { return doe::box_behnken(factors, centre); }},
             {"lhs", [&] { return doe::latin_hypercube(factors, runs, seed_or("latin hypercube")); }}})();
  // (a shuffle of the run order only; the runs stay in standard order)
  if (!seed.is_none() && kind != "lhs") doe::randomize(d, seed.cast<std::uint64_t>());
  py::dict out;
  out["kind"] = d.kind;
  out["coded"] = d.coded;
  out["block"] = d.block;
  out["centre"] = d.centre;
  out["run_order"] = d.run_order;
  std::vector<int> types;
  for (Eigen::Index r = 0; r < d.runs(); ++r) types.push_back(doe::point_type(d, r));
  out["point_type"] = types;
  out["csv"] = doe::design_csv(d, factor_levels);
  return out;
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

PYBIND11_MODULE(_bushel, m) {
  namespace dim = bushel::units::dim;
  m.doc() = "bushel's compiled part: scenarios, templates, units and grain formulas (use the package `bushel`)";
  py::register_exception<bushel::InputError>(m, "InputError", PyExc_ValueError);

  m.def(
      "parse",
      [](const std::string& text, const std::string& dimension) {
        return bushel::units::parse(text, dimension_named(dimension));
      },
      py::arg("text"), py::arg("dimension"), "Quantity with unit -> SI value, e.g. parse('6.12mm', 'length')");

  m.def(
      "template",
      [](const std::string& spec, const py::object& density) {
        return describe(bushel::resolve_template(spec), si(density, dim::density, "density"));
      },
      py::arg("spec"), py::arg("density") = bushel::materials::wheat().density,
      "Built-in template name, CSV path or 'path.csv:name' -> dict of SI mass properties");

  m.def("template_names", [] { return bushel::TemplateLibrary::builtin().names(); });

  m.def(
      "pseudo_ellipsoid",
      [](const py::object& length, const py::object& width, int spheres, const py::object& mass,
         const py::object& density, const py::object& end_radius) {
        const double rho = si(density, dim::density, "density");
        bushel::PseudoEllipsoidSpec s{si(length, dim::length, "length"),
                                      si(width, dim::length, "width"),
                                      spheres,
                                      si_or_none(mass, dim::mass, "mass"),
                                      rho,
                                      si_or_none(end_radius, dim::length, "end_radius")};
        return describe(bushel::make_pseudo_ellipsoid(s, "ellipsoid"), rho);
      },
      py::arg("length"), py::arg("width"), py::arg("spheres") = 5, py::arg("mass") = py::none(),
      py::arg("density") = bushel::materials::wheat().density, py::arg("end_radius") = py::none(),
      "Pseudo-ellipsoid clump (numbers in SI, or strings with units)");

  m.def(
      "shape_factors",
      [](const py::object& l, const py::object& w, const py::object& t) {
        // (the factors are ratios: any one length unit serves, numbers in mm as well as m)
        const auto f = bushel::shape_factors(
            {si(l, dim::length, "length"), si(w, dim::length, "width"), si(t, dim::length, "thickness")});
        py::dict d;
        d["equivalent_diameter"] = f.equivalent_diameter;
        d["sphericity_mohsenin"] = f.sphericity_mohsenin;
        d["sphericity_wadell"] = f.sphericity_wadell;
        d["flatness"] = f.flatness;
        d["elongation"] = f.elongation;
        return d;
      },
      py::arg("length"), py::arg("width"), py::arg("thickness"));

  m.def(
      "rayleigh_time_step",
      [](const py::object& r, const py::object& rho, const py::object& g, double nu) {
        return bushel::rayleigh_time_step(si(r, dim::length, "radius"), si(rho, dim::density, "density"),
                                          si(g, dim::pressure, "shear_modulus"), nu);
      },
      py::arg("radius"), py::arg("density"), py::arg("shear_modulus"), py::arg("poisson_ratio"));
  m.def(
      "packing_ratio",
      [](const py::object& packed, const py::object& initial) {
        return bushel::packing_ratio(si(packed, dim::density, "packed_density"),
                                     si(initial, dim::density, "initial_density"));
      },
      py::arg("packed_density"), py::arg("initial_density"));
  m.def(
      "compressibility",
      [](const py::object& tapped, const py::object& loose) {
        return bushel::compressibility(si(tapped, dim::density, "tapped_density"),
                                       si(loose, dim::density, "loose_density"));
      },
      py::arg("tapped_density"), py::arg("loose_density"));
  m.def(
      "mass_in_bin",
      [](const py::object& initial, double ratio, const py::object& volume) {
        return bushel::mass_in_bin(si(initial, dim::density, "initial_density"), ratio,
                                   si(volume, dim::volume, "volume"));
      },
      py::arg("initial_density"), py::arg("packing_ratio"), py::arg("volume"));
  m.def(
      "pack_factor",
      [](double ratio, const py::object& initial, const py::object& standard) {
        return bushel::pack_factor(ratio, si(initial, dim::density, "initial_density"),
                                   si(standard, dim::density, "standard_test_weight"));
      },
      py::arg("packing_ratio"), py::arg("initial_density"), py::arg("standard_test_weight"));

  m.def(
      "_validate",
      [](const std::string& source, bool is_text, const std::vector<std::string>& sets) {
        const bushel::Scenario sc = load_scenario(source, is_text, sets);
        py::dict d;
        py::list stages;
        for (const auto& st : sc.stages) stages.append(st.name);
        d["stages"] = stages;
        d["values"] = sc.value_names();
        d["dt_s"] = sc.settings.dt;
        d["rayleigh_step_s"] = sc.rayleigh_step;
        d["critical_step_s"] = sc.critical_step.dt;
        d["critical_pair"] = sc.critical_step.pair;
        return d;
      },
      py::arg("source"), py::arg("is_text"), py::arg("sets"));
  namespace doe = bushel::doe;
  py::class_<doe::Factor>(m, "_Factor").def(py::init([](std::string name, double low, double high) {
    return doe::Factor{std::move(name), low, high};
  }));
  m.def("_design", &design, py::arg("kind"), py::arg("factors"), py::arg("runs"), py::arg("centre"), py::arg("ccd"),
        py::arg("blocks"), py::arg("seed"));
  py::class_<doe::Fit>(m, "_Fit")
      .def_readonly("factors", &doe::Fit::factors)
      .def_readonly("s", &doe::Fit::s)
      .def_readonly("r2", &doe::Fit::r2)
      .def_readonly("r2_adjusted", &doe::Fit::r2_adjusted)
      .def_readonly("r2_predicted", &doe::Fit::r2_predicted)
      .def_readonly("runs", &doe::Fit::runs)
      .def_readonly("error_df", &doe::Fit::error_df)
      .def_property_readonly(
          "coefficients",
          [](const doe::Fit& f) {
            py::list out;
            for (const auto& c : f.coefficients) {
              out.append(py::dict(py::arg("term") = c.term, py::arg("coef") = c.coef, py::arg("se") = c.se,
                                  py::arg("t") = c.t, py::arg("p") = c.p, py::arg("effect") = c.effect,
                                  py::arg("significant") = c.significant));
            }
            return out;
          })
      .def_property_readonly(
          "anova",
          [](const doe::Fit& f) {
            py::list out;
            for (const auto& a : f.anova) {
              out.append(py::dict(py::arg("source") = a.source, py::arg("df") = a.df, py::arg("ss") = a.ss,
                                  py::arg("ms") = a.ms, py::arg("f") = a.f, py::arg("p") = a.p));
            }
            return out;
          })
      .def("predict", &doe::Fit::predict, py::arg("coded"))
      .def("prediction_half_width", &doe::Fit::prediction_half_width, py::arg("coded"), py::arg("alpha"))
      .def(
          "solve_for_target",
          [](const doe::Fit& f, double target, double limit, const Eigen::VectorXd& start,
             const std::vector<bool>& fixed) { return doe::solve_for_target(f, target, limit, start, fixed); },
          py::arg("target"), py::arg("limit"), py::arg("start"), py::arg("fixed"));
  m.def(
      "_fit",
      [](const Eigen::MatrixXd& coded, const Eigen::VectorXd& y, const std::vector<std::string>& factors,
         const std::string& model,
         double alpha) { return doe::fit(coded, y, factors, doe::parse_model(model), alpha); },
      py::arg("coded"), py::arg("y"), py::arg("factors"), py::arg("model"), py::arg("alpha"));
  m.def("_build", [] { return bushel::build_description(); });
  m.def(
      "_rows_kept",
      [](const std::string& path, const std::string& where) {
        // (the same conditions, and errors, as `bushel doe analyze --where`)
        const doe::RowFilter filter = doe::RowFilter::parse(where);
        const bushel::io::CsvTable table = bushel::io::CsvTable::read(path);
        filter.check_columns(table);
        std::vector<bool> kept;
        for (const bushel::io::CsvRow& row : table.rows()) kept.push_back(filter.keeps(table, row));
        return kept;
      },
      py::arg("path"), py::arg("where"));
  m.def(
      "_maximize_desirability",
      [](const std::vector<const doe::Fit*>& fits, const std::vector<std::string>& goals,
         const std::vector<double>& weights, double limit, const Eigen::VectorXd& start,
         const std::vector<bool>& fixed) {
        std::vector<doe::Fit> models;
        std::vector<doe::ResponseGoal> parsed;
        for (std::size_t i = 0; i < fits.size(); ++i) {
          models.push_back(*fits[i]);
          parsed.push_back(doe::parse_goal(goals[i]));
          parsed.back().weight = weights[i];
        }
        const doe::Compromise c = doe::maximize_desirability(models, parsed, limit, start, fixed);
        return py::dict(py::arg("coded") = c.coded, py::arg("composite") = c.composite,
                        py::arg("predicted") = c.predicted, py::arg("individual") = c.individual);
      },
      py::arg("fits"), py::arg("goals"), py::arg("weights"), py::arg("limit"), py::arg("start"), py::arg("fixed"));
  m.def("_run", &run, py::arg("source"), py::arg("is_text"), py::arg("sets"), py::arg("out"), py::arg("resume"),
        py::arg("threads"), py::arg("overwrite"), py::arg("stop_at"), py::arg("checkpoint_minutes"),
        py::arg("progress"));
}
