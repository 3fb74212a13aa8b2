// simulation: its settings, guards, domain and time step.

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "bushel/contact/contact_model.hpp"
#include "bushel/contact/time_scales.hpp"
#include "bushel/integrate/critical_step.hpp"
#include "scenario_reading.hpp"

namespace bushel::scenario_reading {
namespace {

namespace dim = units::dim;

// The strongest gravity a scenario may set [m/s2]: 100 times the Earth's, far beyond any
// centrifuge test of grain; more is a typo (a unit or an exponent).
constexpr double max_gravity = 1000.0;

// simulation: guards: each limit a fraction or quantity in its range (run_guards.hpp).
RunGuards read_guards(const ScenarioNode& g) {
  g.allow_only({"max_overlap", "overlap_time", "max_speed", "max_travel", "max_lost", "max_steps"});
  RunGuards r;
  auto fraction = [&](const char* key, double fallback, double hi) {
    if (!g.has(key)) return fallback;
    const double v = g.at(key).quantity(dim::dimensionless);
    if (!(v > 0.0 && v <= hi)) throw g.at(key).error(fmt::format("expected a fraction in (0, {:g}], e.g. 50%", hi));
    return v;
  };
  r.max_overlap = fraction("max_overlap", r.max_overlap, 1.0);
  r.max_travel = fraction("max_travel", r.max_travel, 1.0);
  r.max_lost = fraction("max_lost", r.max_lost, 1.0);
  r.overlap_time = g.positive_or("overlap_time", dim::time, r.overlap_time);
  r.max_speed = g.positive_or("max_speed", dim::velocity, r.max_speed);
  if (g.has("max_steps")) r.max_steps = static_cast<double>(g.at("max_steps").integer(1, 1L << 50));
  return r;
}

// The engine's settings: gravity, integrator, rolling model, skin, tangential damping limit.
void read_engine_settings(const ScenarioNode& sim, SimulationSettings& st) {
  st.gravity = sim.vector_or("gravity", dim::acceleration, {0, 0, -9.81});
  if (norm(st.gravity) > max_gravity) {
    throw sim.at("gravity").error(
        fmt::format("expected at most {:g} m/s2 (about 100 g), got {:.4g} m/s2", max_gravity, norm(st.gravity)));
  }
  if (sim.has("integrator")) {
    st.integrator = sim.at("integrator").choice({"symplectic_euler", "velocity_verlet"}) == "velocity_verlet"
                        ? Integrator::velocity_verlet
                        : Integrator::symplectic_euler;
  }
  if (sim.has("rolling")) st.rolling = sim.at("rolling").choice(rolling_model_names());
  st.skin = sim.positive_or("skin", dim::length, 0.0);
  if (const auto limit = sim.find("tangential_damping_limit")) {  // a fraction, or off
    if (limit->text() == "off") {
      st.tangential_damping_limit = std::numeric_limits<double>::infinity();
    } else {
      st.tangential_damping_limit = limit->number();
      if (!(st.tangential_damping_limit > 0.0 && st.tangential_damping_limit <= 1.0)) {
        throw limit->error("expected a fraction in (0, 1] of the relative tangential velocity per step, or off");
      }
    }
  }
}

// simulation.domain: a box from min to max.
Region read_domain(const ScenarioNode& d) {
  d.allow_only({"min", "max"});
  const Vec3 lo = d.at("min").vector(dim::length), hi = d.at("max").vector(dim::length);
  if (!(hi.x > lo.x && hi.y > lo.y && hi.z > lo.z)) throw d.at("max").error("expected max above min on every axis");
  return Region::box(0.5 * (lo + hi), hi - lo);
}

// `threads: auto` (the default): as many as OpenMP has (OMP_NUM_THREADS or the cores), fewer
// while fewer run faster; a number: exactly that many.
ThreadPolicy read_threads(const ScenarioNode& sim) {
  const auto t = sim.find("threads");
  if (!t || t->text() == "auto" || t->text() == "0")
    return {.max = 0, .adaptive = true};  // (0: auto's former spelling)
  try {
    return {.max = static_cast<int>(t->integer(1, 1024)), .adaptive = false};
  } catch (const InputError&) {
    throw t->error("expected 'auto' or a thread count from 1 to 1024");
  }
}

}  // namespace

void read_simulation(const ScenarioNode& sim, Scenario& sc, ReadContext& cx) {
  sim.allow_only({"time_step", "gravity", "integrator", "rolling", "skin", "domain", "seed", "threads",
                  "check_interval", "tangential_damping_limit", "guards"});
  read_engine_settings(sim, sc.settings);
  cx.seed = sim.has("seed") ? static_cast<std::uint64_t>(sim.at("seed").integer(0, 1L << 40)) : 1;
  sc.settings.threads = read_threads(sim);
  sc.check_interval = sim.positive_or("check_interval", dim::time, 1e-3);
  if (const auto g = sim.find("guards")) sc.guards = read_guards(*g);
  sc.domain = read_domain(sim.at("domain"));
}

namespace {

// "0.2 rayleigh" or "0.3 critical": the fraction, or nothing if the text is not of that form.
std::optional<double> fraction_of(const ScenarioNode& ts, const std::string& basis) {
  const std::string text = ts.text();
  if (text.size() <= basis.size() || !text.ends_with(basis)) return std::nullopt;
  double fraction = 0.0;
  try {
    fraction = units::parse(text.substr(0, text.size() - basis.size()), dim::dimensionless);
  } catch (const InputError& e) {
    throw ts.error(e.problem());
  }
  if (!(fraction > 0.0 && fraction <= 1.0)) {
    throw ts.error(fmt::format("expected a fraction of the {} step in (0, 1], e.g. '0.2 {}' or '20% {}'",
                               basis == "rayleigh" ? "Rayleigh" : "critical", basis, basis));
  }
  return fraction;
}

}  // namespace

double read_time_step(const ScenarioNode& parent, const Scenario& sc, TimeStepRule& rule) {
  using Basis = TimeStepRule::Basis;
  const ScenarioNode ts = parent.at("time_step");
  if (const auto f = fraction_of(ts, "rayleigh")) {
    rule = {Basis::rayleigh, *f};
    return *f * sc.rayleigh_step;
  }
  if (const auto f = fraction_of(ts, "critical")) {
    rule = {Basis::critical, *f};
    return *f * sc.critical_step.dt;
  }
  rule = {};
  double dt = 0.0;
  try {
    dt = parent.positive("time_step", dim::time);
  } catch (const InputError& e) {  // (say the other forms too: "0.2 rayleighs" is a typo of one)
    throw ts.error(e.problem() +
                   "; or a fraction of the smallest element's Rayleigh step, e.g. '0.2 rayleigh', or of the "
                   "contacts' critical step, e.g. '0.3 critical'");
  }
  if (dt > sc.rayleigh_step) {
    throw ts.error(fmt::format(
        "a time step of {:.4g} us is above the Rayleigh step of the smallest element ({:.4g} us): the contacts "
        "would be unstable",
        dt * 1e6, sc.rayleigh_step * 1e6));
  }
  return dt;
}

void read_simulation_time_step(const ScenarioNode& sim, Scenario& sc) {
  sc.rayleigh_step = INFINITY;
  for (const auto& t : sc.types) {
    sc.rayleigh_step =
        std::min(sc.rayleigh_step, rayleigh_time_step(t.shape.min_sphere_radius(), t.material.density,
                                                      t.material.shear_modulus, t.material.poisson_ratio));
  }
  try {
    sc.critical_step = critical_time_step(sc.types, sc.parts, sc.settings.contacts);
  } catch (const InputError& e) {
    throw sim.error(e.problem());
  }
  sc.settings.dt = read_time_step(sim, sc, sc.time_step_rule);
}

}  // namespace bushel::scenario_reading
