#pragma once
// Least-squares response models of designed experiments, with the statistics Minitab reports
// (so users can compare): in coded units (each factor's low and high level at -1 and +1),
// coefficients with standard errors, t and p values, effects (twice the coefficient of a
// linear or interaction term), S, R2, adjusted and predicted R2 (from PRESS), an ANOVA table
// with adjusted sums of squares per group of terms, lack of fit against pure error where
// runs are replicated, and the curvature test of a two-level design with centre points (a
// centre-point indicator term, as Minitab's "Ct Pt").

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace bushel::doe {

enum class ModelKind {
  main,          ///< constant + linear terms
  interactions,  ///< + all two-way interactions
  quadratic,     ///< + interactions + squares (response surface)
};
/// "main", "interactions", "quadratic"; throws InputError (with a did-you-mean) otherwise.
ModelKind parse_model(const std::string& text);

/// A term: the factors it multiplies (empty: the constant; {i, i}: a square).
struct Term {
  std::string name;  ///< "fr_ww", "fr_ww*fs_ww", "fr_ww*fr_ww", "Constant", "Ct Pt", "Block 1"
  std::vector<int> factors;
  bool centre_indicator = false;  ///< 1 at centre points, 0 elsewhere (curvature)
  int block = -1;                 ///< a block term (effect coding: 1 in this block, -1 in the last, 0 else)
  /// The term's column entry for a run at `coded`; 0 for centre and block terms, so that a
  /// prediction is the average over blocks.
  double value(const Eigen::VectorXd& coded) const;
};

struct Coefficient {
  std::string term;
  double coef = 0.0;  ///< in coded units
  double se = 0.0;    ///< standard error
  double t = 0.0;
  double p = 1.0;
  double effect = 0.0;       ///< 2 coef for linear and interaction terms (NaN otherwise)
  bool significant = false;  ///< p < alpha (the constant: never)
};

struct AnovaRow {
  std::string source;
  double df = 0.0, ss = 0.0, ms = 0.0;
  double f = 0.0, p = 0.0;  ///< NaN where no test applies
};

struct Fit {
  std::vector<std::string> factors;
  std::vector<Term> terms;
  std::vector<Coefficient> coefficients;
  std::vector<AnovaRow> anova;
  double s = 0.0;  ///< root mean square error
  double r2 = 0.0, r2_adjusted = 0.0, r2_predicted = 0.0;
  double alpha = 0.1;
  int runs = 0, error_df = 0;
  Eigen::VectorXd beta;
  Eigen::MatrixXd xtx_inverse;

  /// The fitted response at a point in coded units (centre indicator 0).
  double predict(const Eigen::VectorXd& coded) const;
  /// Gradient of predict in coded units.
  Eigen::VectorXd gradient(const Eigen::VectorXd& coded) const;
  /// Half-width of the (1 - alpha) prediction interval for a new run at `coded`.
  double prediction_half_width(const Eigen::VectorXd& coded, double alpha) const;
};

/// Fits `model` to responses `y` at runs `coded` (one row per run, one column per factor,
/// coded units). A centre-point indicator is added to models without squares when the design
/// has both centre points and factorial points; with `blocks` (a label per run, two or more
/// distinct) effect-coded block terms are added (Minitab's "Blocks"). Throws InputError when there are fewer runs
/// than terms, or the terms are not estimable (a singular design for this model).
Fit fit(const Eigen::MatrixXd& coded, const Eigen::VectorXd& y, const std::vector<std::string>& factors,
        ModelKind model, double alpha = 0.1, const std::vector<int>& blocks = {});

/// Factor settings (coded) within [-limit, limit] on every factor at which the fitted
/// response equals `target`, found by descending (predict - target)^2 from `start` (the
/// centre if empty); factors with `fixed[i]` true keep their value in `start`. The point of
/// the solution set reached from there. Throws InputError if the target is out of the
/// model's reach within the region (reports the closest value).
Eigen::VectorXd solve_for_target(const Fit& fit, double target, double limit = 1.0, Eigen::VectorXd start = {},
                                 const std::vector<bool>& fixed = {});

}  // namespace bushel::doe
