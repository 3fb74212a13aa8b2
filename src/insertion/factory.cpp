#include "bushel/insertion/factory.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include <fmt/format.h>

#include "bushel/core/input_error.hpp"
#include "bushel/io/binary_archive.hpp"

namespace bushel {

Factory::Factory(FactorySpec spec, const Simulation& sim) : spec_(std::move(spec)), rng_(spec_.seed) {
  const auto& types = sim.particles().types();
  if (spec_.types.empty()) throw InputError("expected at least one particle type").with_key("types");
  if (spec_.fractions.size() != spec_.types.size()) {
    throw InputError("expected one fraction per particle type").with_key("types");
  }
  double sum = 0.0;
  for (std::size_t k = 0; k < spec_.types.size(); ++k) {
    if (spec_.types[k] >= types.size()) throw InputError("unknown particle type").with_key("types");
    // (a share of 0 is allowed, so that a mixture can leave out a fraction by a parameter)
    if (!(spec_.fractions[k] >= 0.0)) throw InputError("expected a fraction >= 0").with_key("types");
    sum += spec_.fractions[k];
    const ParticleType& t = types[spec_.types[k]];
    type_mass_.push_back(t.mass());
    type_radius_.push_back(t.shape.bounding_radius());
  }
  if (std::abs(sum - 1.0) > 1e-6) {
    throw InputError(fmt::format("expected fractions that add up to 100%, got {:.4g}%", 100.0 * sum)).with_key("types");
  }
  if (!(spec_.total > 0.0) || !std::isfinite(spec_.total)) {
    throw InputError("expected a positive total (a mass in kg, or a count)").with_key("total");
  }
  if (!(spec_.rate >= 0.0) || !std::isfinite(spec_.rate)) throw InputError("expected a rate >= 0").with_key("rate");
  if (!(spec_.start >= 0.0) || !(spec_.stop > spec_.start)) {
    throw InputError("expected 0 <= start < stop").with_key("stop");
  }
  const double r_max = *std::max_element(type_radius_.begin(), type_radius_.end());
  report_.count.assign(spec_.types.size(), 0);
  report_.mass.assign(spec_.types.size(), 0.0);
  if (!spec_.surface.triangles.empty()) {
    double area = 0.0;
    for (std::size_t t = 0; t < spec_.surface.size(); ++t) {
      const TriangleMesh& m = spec_.surface;
      area += 0.5 * norm(cross(m.corner(t, 1) - m.corner(t, 0), m.corner(t, 2) - m.corner(t, 0)));
      cumulative_area_.push_back(area);
    }
    if (!(area > 0.0)) throw InputError("expected a surface of positive area").with_key("surface");
    return;
  }
  if (!(spec_.region.room() > r_max)) {
    throw InputError(
        fmt::format("the region is too small for the largest particle (bounding radius {:.3g} mm)", r_max * 1e3))
        .with_key("region");
  }
}

Vec3 Factory::place(std::size_t k, std::mt19937_64& rng) const {
  if (cumulative_area_.empty()) return spec_.region.sample(rng, type_radius_[k]);
  // A point of the surface by area, and the centre one bounding radius in front of it.
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto it = std::upper_bound(cumulative_area_.begin(), cumulative_area_.end(), u(rng) * cumulative_area_.back());
  const auto t = static_cast<std::size_t>(std::min<std::ptrdiff_t>(
      it - cumulative_area_.begin(), static_cast<std::ptrdiff_t>(cumulative_area_.size()) - 1));
  const TriangleMesh& m = spec_.surface;
  const Vec3 a = m.corner(t, 0), e1 = m.corner(t, 1) - a, e2 = m.corner(t, 2) - a;
  double s = u(rng), w = u(rng);
  if (s + w > 1.0) s = 1.0 - s, w = 1.0 - w;  // folded into the triangle: uniform over it
  return a + s * e1 + w * e2 + normalized(cross(e1, e2)) * (type_radius_[k] * (1.0 + 1e-9));
}

double Factory::created_measure() const {
  return spec_.total_by_mass ? report_.total_mass : static_cast<double>(report_.total_count);
}

bool Factory::done() const { return created_measure() >= spec_.total * (1.0 - 1e-12); }

std::size_t Factory::next_type() const {
  // The type whose share falls furthest short once one more particle of it is counted:
  // argmax_k f_k (T + w_k) - c_k, with T the total so far, w_k one particle's weight and c_k
  // what type k has (by mass or count).
  std::size_t best = 0;
  double best_gap = -INFINITY;
  const double total = spec_.fractions_by_mass ? report_.total_mass : static_cast<double>(report_.total_count);
  for (std::size_t k = 0; k < spec_.types.size(); ++k) {
    const double w = spec_.fractions_by_mass ? type_mass_[k] : 1.0;
    const double have = spec_.fractions_by_mass ? report_.mass[k] : static_cast<double>(report_.count[k]);
    const double gap = spec_.fractions[k] * (total + w) - have;
    if (gap > best_gap) best_gap = gap, best = k;
  }
  return best;
}

std::vector<double> Factory::achieved_fractions() const {
  std::vector<double> f(spec_.types.size(), 0.0);
  const double total = spec_.fractions_by_mass ? report_.total_mass : static_cast<double>(report_.total_count);
  if (!(total > 0.0)) return f;
  for (std::size_t k = 0; k < f.size(); ++k) {
    f[k] = (spec_.fractions_by_mass ? report_.mass[k] : static_cast<double>(report_.count[k])) / total;
  }
  return f;
}

std::size_t Factory::run(Simulation& sim, double active) {
  active_ += active;
  if (done()) return 0;
  auto due = [&] {
    if (done()) return false;
    if (spec_.rate == 0.0) return true;
    const double made = spec_.rate_by_mass ? report_.total_mass : static_cast<double>(report_.total_count);
    return made < spec_.rate * active_;
  };
  if (!due()) return 0;

  // The elements that a new particle could touch: those near the region (and, as they are
  // made, the new ones).
  const ParticleSystem& ps = sim.particles();
  const double r_new = *std::max_element(type_radius_.begin(), type_radius_.end());
  double r_old = 0.0;
  for (const double r : ps.radius) r_old = std::max(r_old, r);
  const Vec3 pad{r_new + r_old, r_new + r_old, r_new + r_old};
  Vec3 lo = spec_.region.lo(), hi = spec_.region.hi();
  if (!cumulative_area_.empty()) {
    lo = Vec3{INFINITY, INFINITY, INFINITY}, hi = -lo;
    for (const Vec3& v : spec_.surface.vertices) lo = min(lo, v), hi = max(hi, v);
    lo = lo - Vec3{r_new, r_new, r_new}, hi = hi + Vec3{r_new, r_new, r_new};  // (centres are r in front)
  }
  lo = lo - pad, hi = hi + pad;
  std::vector<Vec3> near_x;
  std::vector<double> near_r;
  for (std::size_t s = 0; s < ps.spheres(); ++s) {
    const Vec3& x = ps.sphere_position[s];
    if (x.x < lo.x || x.y < lo.y || x.z < lo.z || x.x > hi.x || x.y > hi.y || x.z > hi.z) continue;
    near_x.push_back(x);
    near_r.push_back(ps.radius[s]);
  }

  std::normal_distribution<double> n01;
  std::size_t made = 0;
  report_.waiting = 0;
  while (due()) {
    const std::size_t k = next_type();
    const ParticleType& type = ps.types()[spec_.types[k]];
    bool placed = false;
    for (int attempt = 0; attempt < spec_.attempts && !placed; ++attempt) {
      const Vec3 c = place(k, rng_);
      const Quat q = normalized(Quat{n01(rng_), n01(rng_), n01(rng_), n01(rng_)});
      bool clear = true;
      for (const auto& e : type.shape.spheres) {
        const Vec3 x = c + rotate(q, e.centre);
        for (std::size_t j = 0; j < near_x.size() && clear; ++j) {
          const double reach = e.radius + near_r[j];
          clear = norm2(x - near_x[j]) >= reach * reach;
        }
        if (!clear) break;
      }
      if (!clear) continue;
      sim.add_body(spec_.types[k], {c, q, spec_.velocity, {}});
      for (const auto& e : type.shape.spheres) {
        near_x.push_back(c + rotate(q, e.centre));
        near_r.push_back(e.radius);
      }
      placed = true;
    }
    if (!placed) {
      // No room now: the rest waits for the region to clear (the caller reports it).
      const double made_so_far = spec_.rate_by_mass ? report_.total_mass : static_cast<double>(report_.total_count);
      const double behind = spec_.rate > 0.0 ? spec_.rate * active_ - made_so_far : spec_.total - created_measure();
      const double per = spec_.rate_by_mass ? type_mass_[k] : 1.0;
      report_.waiting = static_cast<std::size_t>(std::ceil(behind / per));
      break;
    }
    ++report_.count[k];
    report_.mass[k] += type_mass_[k];
    ++report_.total_count;
    report_.total_mass += type_mass_[k];
    ++made;
  }
  return made;
}

void Factory::save(io::BinaryWriter& out) const {
  std::ostringstream rng;
  rng << rng_;
  out.put(rng.str());
  out.put(active_);
  out.put(report_.count);
  out.put(report_.mass);
  out.put(static_cast<std::uint64_t>(report_.total_count));
  out.put(report_.total_mass);
  out.put(static_cast<std::uint64_t>(report_.waiting));
}

void Factory::load(io::BinaryReader& in) {
  std::istringstream rng(in.get<std::string>());
  rng >> rng_;
  if (!rng) throw InputError("the checkpoint's factory state is damaged").with_key(spec_.name);
  in.get(active_);
  in.get(report_.count);
  in.get(report_.mass);
  report_.total_count = static_cast<std::size_t>(in.get<std::uint64_t>());
  in.get(report_.total_mass);
  report_.waiting = static_cast<std::size_t>(in.get<std::uint64_t>());
  if (report_.count.size() != spec_.types.size() || report_.mass.size() != spec_.types.size()) {
    throw InputError("the checkpoint's factory has other particle types than the scenario").with_key(spec_.name);
  }
}

}  // namespace bushel
