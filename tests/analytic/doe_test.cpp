// Design-of-experiments statistics: the distributions against tabulated critical values, and
// the study's screening and response-surface designs (data/pb_*, data/rsm_*) against what the
// study found and against an independent computation (an orthogonal design's coefficients
// are X^T y / N).

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "bushel/core/input_error.hpp"
#include "bushel/doe/desirability.hpp"
#include "bushel/doe/distributions.hpp"
#include "bushel/doe/factor_table.hpp"
#include "bushel/doe/regression.hpp"

namespace bushel::doe {
namespace {

// The study's tables, each factor coded from its own range (the design's low and high).
FactorTable read(const std::string& file, const std::vector<std::string>& factors, const std::string& response) {
  return read_factor_table(std::string(BUSHEL_DATA_DIR) + "/" + file, factors, response);
}

TEST(Distributions, TabulatedCriticalValues) {
  EXPECT_NEAR(t_two_sided_p(2.228, 10), 0.05, 5e-4);  // t(0.025, 10) = 2.228
  EXPECT_NEAR(t_critical(0.05, 5), 2.5706, 1e-4);     // t(0.025, 5)
  EXPECT_NEAR(t_critical(0.10, 5), 2.0150, 1e-4);     // t(0.05, 5)
  EXPECT_NEAR(f_upper_p(4.10, 2, 10), 0.05, 1e-3);    // F(0.05; 2, 10) = 4.10
  EXPECT_NEAR(f_upper_p(3.33, 5, 10), 0.05, 1e-3);    // F(0.05; 5, 10) = 3.33
  EXPECT_NEAR(incomplete_beta(3.5, 3.5, 0.5), 0.5, 1e-14);
  EXPECT_NEAR(t_two_sided_p(0.0, 7), 1.0, 1e-14);
}

TEST(Screening, PlackettBurmanRanksTheStudysFourEffects) {
  const std::vector<std::string> f{"fr_ww", "fr_ws", "fs_ww", "fs_ws", "e_ww", "e_ws"};
  const FactorTable t = read("pb_5sphere_large_table3_9.csv", f, "bulk_density");
  const Fit fit = doe::fit(t.coded, t.response, f, ModelKind::main, 0.1);
  // The study kept fr_ww, fs_ww, e_ww and fs_ws (alpha 0.1): friction lowers the bulk
  // density, restitution raises it.
  std::set<std::string> significant;
  for (const Coefficient& c : fit.coefficients) {
    if (c.significant) significant.insert(c.term);
  }
  EXPECT_EQ(significant, (std::set<std::string>{"fr_ww", "fs_ww", "fs_ws", "e_ww"}));
  auto coef = [&](const std::string& name) {
    for (const Coefficient& c : fit.coefficients) {
      if (c.term == name) return c;
    }
    ADD_FAILURE() << name;
    return Coefficient{};
  };
  EXPECT_LT(coef("fr_ww").effect, 0.0);
  EXPECT_LT(coef("fs_ww").effect, 0.0);
  EXPECT_LT(coef("fs_ws").effect, 0.0);
  EXPECT_GT(coef("e_ww").effect, 0.0);
  // Independent: the design is orthogonal, so b = X^T y / N and se = s / sqrt(N).
  const double n = static_cast<double>(t.response.size());
  EXPECT_NEAR(fit.coefficients[0].coef, t.response.mean(), 1e-10);
  for (std::size_t i = 0; i < f.size(); ++i) {
    const Coefficient& c = fit.coefficients[i + 1];
    EXPECT_NEAR(c.coef, t.coded.col(static_cast<Eigen::Index>(i)).dot(t.response) / n, 1e-10) << c.term;
    EXPECT_NEAR(c.se, fit.s / std::sqrt(n), 1e-10) << c.term;
  }
  EXPECT_NEAR(coef("fs_ww").coef, -29.733, 1e-3);  // (numpy normal equations, same data)
  EXPECT_NEAR(coef("e_ww").t, 7.041, 1e-3);
  EXPECT_EQ(fit.error_df, 5);
}

TEST(ResponseSurface, QuadraticFitAndTheStudysCalibratedPoint) {
  const std::vector<std::string> f{"fs_ww", "fr_ww", "e_ww", "fs_ws"};
  const FactorTable t = read("rsm_5sphere_large_table3_10.csv", f, "bulk_density");
  const Fit fit = doe::fit(t.coded, t.response, f, ModelKind::quadratic, 0.1);
  EXPECT_GT(fit.r2, 0.998);
  EXPECT_NEAR(fit.r2, 0.99920, 1e-4);  // numpy: 0.9991957
  EXPECT_NEAR(fit.s, 0.8484, 1e-3);
  EXPECT_GT(fit.r2_predicted, 0.98);
  // Curvature: the squares matter.
  bool square_group = false;
  for (const AnovaRow& a : fit.anova) {
    if (a.source == "  Square") {
      square_group = true;
      EXPECT_LT(a.p, 0.1);
    }
  }
  EXPECT_TRUE(square_group);
  // The study's calibrated set (fs_ww 0.27, fr_ww 0.01, e_ww 0.5, fs_ws 0.17) lies on the
  // solution set of 826.1 kg/m3 within the model's prediction interval.
  auto code = [](double v, double lo, double hi) { return (v - 0.5 * (lo + hi)) / (0.5 * (hi - lo)); };
  Eigen::VectorXd study(4);
  study << code(0.27, 0.17, 0.40), code(0.01, 0.01, 0.10), code(0.5, 0.2, 0.5), code(0.17, 0.17, 0.40);
  EXPECT_LT(std::abs(fit.predict(study) - 826.1), fit.prediction_half_width(study, 0.05));
  const Eigen::VectorXd x = solve_for_target(fit, 826.1);
  EXPECT_NEAR(fit.predict(x), 826.1, 1e-6);
  EXPECT_LE(x.cwiseAbs().maxCoeff(), 1.0 + 1e-12);
  EXPECT_THROW(solve_for_target(fit, 1000.0), InputError);
  // As the study: fr_ww, e_ww and fs_ws held at their calibrated values, fs_ww solved for.
  Eigen::VectorXd held = study;
  held(0) = 0.0;
  const Eigen::VectorXd fs = solve_for_target(fit, 826.1, 1.0, held, {false, true, true, true});
  EXPECT_NEAR(fit.predict(fs), 826.1, 1e-6);
  EXPECT_EQ(fs.tail(3), study.tail(3));
  EXPECT_NEAR(0.285 + fs(0) * 0.115, 0.27, 0.01);  // fs_ww in physical units: the study's 0.27
}

TEST(Regression, CurvatureFromCentrePointsAndLackOfFit) {
  // A 2^2 factorial with 3 centre points on y = 10 + 2 a - b + 3 a^2 (curved), plus noise-free
  // replicates: the centre-point term finds the curvature; pure error is 0 except at the centre.
  Eigen::MatrixXd x(7, 2);
  x << -1, -1, 1, -1, -1, 1, 1, 1, 0, 0, 0, 0, 0, 0;
  Eigen::VectorXd y(7);
  for (int r = 0; r < 7; ++r) y(r) = 10 + 2 * x(r, 0) - x(r, 1) + 3 * x(r, 0) * x(r, 0);
  y(4) += 0.1, y(5) -= 0.1;  // spread at the centre: the pure error
  const Fit fit = doe::fit(x, y, {"a", "b"}, ModelKind::main, 0.05);
  ASSERT_EQ(fit.terms.back().name, "Ct Pt");
  EXPECT_NEAR(fit.coefficients.back().coef, -3.0, 1e-9);  // centre mean - corner-fitted mean
  EXPECT_LT(fit.coefficients.back().p, 0.05);
  EXPECT_THROW(doe::fit(x.topRows(3), y.head(3), {"a", "b"}, ModelKind::interactions), InputError);
  // A response that never changes has nothing to fit; an exact fit (to rounding) has p ~ 0.
  EXPECT_THROW(doe::fit(x, Eigen::VectorXd::Constant(7, 5.0), {"a", "b"}, ModelKind::main), InputError);
  const Eigen::VectorXd exact =
      3.0 + 2.0 * x.col(0).array() - x.col(1).array() + (x.col(0).array() == 0.0).cast<double>();
  const Fit perfect = doe::fit(x, exact, {"a", "b"}, ModelKind::main);
  EXPECT_LT(perfect.coefficients[1].p, 1e-10);
}

}  // namespace
}  // namespace bushel::doe

namespace bushel::doe {
namespace {

TEST(Desirability, GoalsAndTheBestCompromise) {
  const ResponseGoal t = parse_goal("target:10:8:14");
  EXPECT_DOUBLE_EQ(desirability(t, 10.0), 1.0);
  EXPECT_DOUBLE_EQ(desirability(t, 9.0), 0.5);
  EXPECT_DOUBLE_EQ(desirability(t, 12.5), 0.375);
  EXPECT_DOUBLE_EQ(desirability(t, 7.0), 0.0);
  const ResponseGoal lo = parse_goal("minimize:2:6");
  EXPECT_DOUBLE_EQ(desirability(lo, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(desirability(lo, 5.0), 0.25);
  const ResponseGoal hi = parse_goal("maximize:0:4");
  EXPECT_DOUBLE_EQ(desirability(hi, 3.0), 0.75);
  EXPECT_THROW(parse_goal("target:10:12:14"), InputError);
  EXPECT_THROW(parse_goal("minimise:2:6"), InputError);
  // y1 = a (target 0.5 on [0, 1]), y2 = a + b (maximised up to 1.5): the best compromise is
  // a = 0.5 with b = 1, both fully desirable.
  Eigen::MatrixXd x(5, 2);
  x << -1, -1, 1, -1, -1, 1, 1, 1, 0, 0;
  Eigen::VectorXd y1 = x.col(0), y2 = x.col(0) + x.col(1);
  y1(4) += 1e-3, y2(4) -= 1e-3;  // an error estimate for the fits
  const std::vector<Fit> fits{fit(x, y1, {"a", "b"}, ModelKind::main), fit(x, y2, {"a", "b"}, ModelKind::main)};
  const Compromise c = maximize_desirability(fits, {parse_goal("target:0.5:0:1"), parse_goal("maximize:0:1.5")});
  EXPECT_GT(c.composite, 0.999);
  EXPECT_NEAR(c.coded(0), 0.5, 2e-3);
  EXPECT_NEAR(c.coded(1), 1.0, 2e-3);
}

}  // namespace
}  // namespace bushel::doe
