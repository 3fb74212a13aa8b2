#pragma once
// Several responses at once (Derringer and Suich, 1980): each fitted response is mapped to a
// desirability d in [0, 1] by its goal, and the factor settings that maximise the weighted
// geometric mean D = (prod d_i^w_i)^(1 / sum w_i) within the design region are searched for.

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "bushel/doe/regression.hpp"

namespace bushel::doe {

enum class Goal {
  target,    ///< d = 1 at the target, falling linearly to 0 at the lower and upper limits
  minimize,  ///< d = 1 at or below the target, 0 at or above the upper limit
  maximize,  ///< d = 1 at or above the target, 0 at or below the lower limit
};

struct ResponseGoal {
  Goal goal = Goal::target;
  double lower = 0.0, target = 0.0, upper = 0.0;  ///< in the response's units
  double weight = 1.0;                            ///< importance in D (> 0)
};

/// "target:T:L:U", "minimize:T:U" or "maximize:L:T" (values in the response's units);
/// throws InputError saying which form was expected.
ResponseGoal parse_goal(const std::string& text);

/// The individual desirability of a predicted response y.
double desirability(const ResponseGoal& goal, double y);

struct Compromise {
  Eigen::VectorXd coded;           ///< factor settings
  double composite = 0.0;          ///< D
  std::vector<double> predicted;   ///< per response
  std::vector<double> individual;  ///< d per response
};

/// Maximises D over [-limit, limit]^k (factors with `fixed[i]` held at `start[i]`): a coarse
/// scan of the region (a grid for up to 4 free factors, else a seeded Latin hypercube), then
/// a pattern search from the best points. Deterministic.
Compromise maximize_desirability(const std::vector<Fit>& fits, const std::vector<ResponseGoal>& goals,
                                 double limit = 1.0, Eigen::VectorXd start = {}, const std::vector<bool>& fixed = {});

}  // namespace bushel::doe
