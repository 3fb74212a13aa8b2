#pragma once
// The probability distributions behind the regression statistics (t tests on coefficients, F
// tests in the ANOVA table, prediction intervals), from the regularized incomplete beta
// function evaluated by its continued fraction (modified Lentz).

namespace bushel::doe {

/// Regularized incomplete beta I_x(a, b) for a, b > 0 and x in [0, 1].
double incomplete_beta(double a, double b, double x);
/// Two-sided p-value of Student's t with `df` degrees of freedom: P(|T| >= |t|).
double t_two_sided_p(double t, double df);
/// Upper-tail p-value of Fisher's F(df1, df2): P(F >= f).
double f_upper_p(double f, double df1, double df2);
/// The t with P(|T| >= t) = alpha (two-sided critical value), alpha in (0, 1).
double t_critical(double alpha, double df);

}  // namespace bushel::doe
