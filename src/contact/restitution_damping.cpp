#include "bushel/contact/restitution_damping.hpp"

#include <cmath>
#include <map>
#include <mutex>
#include <numbers>
#include <stdexcept>

namespace bushel {

double edem_damping_factor(double restitution) {
  const double l = std::log(restitution);
  const double beta = l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi);
  return -2.0 * std::sqrt(5.0 / 6.0) * beta;
}

double hertz_restitution(double gamma, bool clamp_attraction) {
  // Units with m* = 1, 4/3 E* sqrt(R*) = 1 and impact speed 1: the contact lasts about 3.2.
  // Velocity Verlet with the force evaluated at the half-step velocity.
  const double dt = 2e-5, c = gamma * std::sqrt(1.5);
  auto accel = [&](double x, double v) {
    const double f = x * std::sqrt(x) + c * std::sqrt(std::sqrt(x)) * v;
    return -(clamp_attraction ? std::max(0.0, f) : f);
  };
  double x = 0.0, v = 1.0;
  for (int k = 0; k < 10'000'000; ++k) {
    const double vh = v + 0.5 * dt * accel(x, v);
    const double xn = x + dt * vh;
    if (xn <= 0.0) return -vh;  // the drift velocity that carried x through 0
    v = vh + 0.5 * dt * accel(xn, vh);
    x = xn;
  }
  throw std::runtime_error("hertz_restitution: the impact did not end");
}

double damping_for_restitution(double restitution) {
  if (!(restitution > 0.0 && restitution <= 1.0)) throw std::invalid_argument("restitution must be in (0, 1]");
  if (restitution == 1.0) return 0.0;
  static std::mutex mutex;
  static std::map<double, double> cache;
  const std::lock_guard lock(mutex);
  if (const auto it = cache.find(restitution); it != cache.end()) return it->second;
  // e(gamma) falls monotonically; the clamped law needs at least EDEM's factor.
  double lo = edem_damping_factor(restitution), hi = 2.0 * lo + 1.0;
  while (hertz_restitution(hi) > restitution) hi *= 2.0;
  for (int it = 0; it < 60 && hi - lo > 1e-9 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (hertz_restitution(mid) > restitution ? lo : hi) = mid;
  }
  return cache[restitution] = 0.5 * (lo + hi);
}

}  // namespace bushel
