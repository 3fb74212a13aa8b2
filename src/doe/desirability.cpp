#include "bushel/doe/desirability.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "bushel/core/choice.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/doe/design.hpp"
#include "bushel/units/units.hpp"

namespace bushel::doe {

ResponseGoal parse_goal(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  for (std::string p; std::getline(in, p, ':');) parts.push_back(p);
  ResponseGoal g;
  g.goal = parse_choice<Goal>(parts.empty() ? "" : parts[0],
                              {{"target", Goal::target}, {"minimize", Goal::minimize}, {"maximize", Goal::maximize}});
  const std::size_t want = g.goal == Goal::target ? 4 : 3;
  if (parts.size() != want) {
    throw InputError(fmt::format("expected {}, got '{}'",
                                 g.goal == Goal::target     ? "target:T:L:U (target, lower and upper limits)"
                                 : g.goal == Goal::minimize ? "minimize:T:U (target and upper limit)"
                                                            : "maximize:L:T (lower limit and target)",
                                 text));
  }
  std::vector<double> v;
  for (std::size_t i = 1; i < parts.size(); ++i) v.push_back(units::parse_number(parts[i]));
  if (g.goal == Goal::target) g.target = v[0], g.lower = v[1], g.upper = v[2];
  if (g.goal == Goal::minimize) g.target = v[0], g.upper = v[1], g.lower = v[0];
  if (g.goal == Goal::maximize) g.lower = v[0], g.target = v[1], g.upper = v[1];
  if (!(g.lower <= g.target && g.target <= g.upper && g.lower < g.upper)) {
    throw InputError(fmt::format("expected lower <= target <= upper with lower < upper in '{}'", text));
  }
  return g;
}

double desirability(const ResponseGoal& g, double y) {
  if (y < g.lower || y > g.upper)
    return g.goal == Goal::minimize && y < g.lower ? 1.0 : g.goal == Goal::maximize && y > g.upper ? 1.0 : 0.0;
  if (y <= g.target) return g.goal == Goal::minimize ? 1.0 : (y - g.lower) / (g.target - g.lower);
  return g.goal == Goal::maximize ? 1.0 : (g.upper - y) / (g.upper - g.target);
}

Compromise maximize_desirability(const std::vector<Fit>& fits, const std::vector<ResponseGoal>& goals, double limit,
                                 Eigen::VectorXd start, const std::vector<bool>& fixed) {
  if (fits.empty() || fits.size() != goals.size()) throw InputError("expected one goal per response");
  const auto k = static_cast<Eigen::Index>(fits.front().factors.size());
  if (start.size() != k) start = Eigen::VectorXd::Zero(k);
  std::vector<Eigen::Index> free;
  for (Eigen::Index i = 0; i < k; ++i) {
    if (static_cast<std::size_t>(i) >= fixed.size() || !fixed[static_cast<std::size_t>(i)]) free.push_back(i);
  }
  double weight_sum = 0.0;
  for (const ResponseGoal& g : goals) weight_sum += g.weight;
  auto composite = [&](const Eigen::VectorXd& x) {
    double log_d = 0.0;
    for (std::size_t r = 0; r < fits.size(); ++r) {
      const double d = desirability(goals[r], fits[r].predict(x));
      if (d <= 0.0) return 0.0;
      log_d += goals[r].weight * std::log(d);
    }
    return std::exp(log_d / weight_sum);
  };
  // The scan.
  std::vector<Eigen::VectorXd> candidates;
  const auto nf = static_cast<int>(free.size());
  if (nf <= 4) {
    const int per = 11;
    int total = 1;
    for (int i = 0; i < nf; ++i) total *= per;
    for (int n = 0; n < total; ++n) {
      Eigen::VectorXd x = start;
      for (int i = 0, m = n; i < nf; ++i, m /= per)
        x(free[static_cast<std::size_t>(i)]) = limit * (-1.0 + 0.2 * (m % per));
      candidates.push_back(x);
    }
  } else {
    const Design lhs = latin_hypercube(nf, 4000, 12345);
    for (Eigen::Index r = 0; r < lhs.coded.rows(); ++r) {
      Eigen::VectorXd x = start;
      for (int i = 0; i < nf; ++i) x(free[static_cast<std::size_t>(i)]) = limit * lhs.coded(r, i);
      candidates.push_back(x);
    }
  }
  std::vector<std::pair<double, std::size_t>> scored;
  for (std::size_t c = 0; c < candidates.size(); ++c) scored.push_back({composite(candidates[c]), c});
  std::stable_sort(scored.begin(), scored.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  // Pattern search (Hooke-Jeeves without the acceleration step) from the best few.
  Compromise best;
  best.coded = candidates[scored.front().second];
  best.composite = scored.front().first;
  for (std::size_t s = 0; s < std::min<std::size_t>(5, scored.size()); ++s) {
    Eigen::VectorXd x = candidates[scored[s].second];
    double value = scored[s].first;
    for (double step = 0.1 * limit; step > 1e-7 * limit; step *= 0.5) {
      for (bool moved = true; moved;) {
        moved = false;
        for (const Eigen::Index i : free) {
          for (const double sign : {1.0, -1.0}) {
            Eigen::VectorXd trial = x;
            trial(i) = std::clamp(trial(i) + sign * step, -limit, limit);
            const double v = composite(trial);
            if (v > value) x = trial, value = v, moved = true;
          }
        }
      }
    }
    if (value > best.composite) best.coded = x, best.composite = value;
  }
  for (std::size_t r = 0; r < fits.size(); ++r) {
    best.predicted.push_back(fits[r].predict(best.coded));
    best.individual.push_back(desirability(goals[r], best.predicted.back()));
  }
  return best;
}

}  // namespace bushel::doe
