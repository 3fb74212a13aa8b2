#include "bushel/doe/regression.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "bushel/core/choice.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/doe/distributions.hpp"

namespace bushel::doe {

ModelKind parse_model(const std::string& text) {
  return parse_choice<ModelKind>(
      text,
      {{"main", ModelKind::main}, {"interactions", ModelKind::interactions}, {"quadratic", ModelKind::quadratic}});
}

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

bool is_centre(const Eigen::VectorXd& x) { return x.cwiseAbs().maxCoeff() < 1e-9; }

double Term_value(const Term& t, const Eigen::VectorXd& x, bool centre) {
  if (t.centre_indicator) return centre ? 1.0 : 0.0;
  if (t.block >= 0) return 0.0;  // (filled per run by model_matrix)
  double v = 1.0;
  for (const int f : t.factors) v *= x(f);
  return v;
}

// Which group a term belongs to in the ANOVA table (Minitab's grouping).
std::string group_of(const Term& t) {
  if (t.centre_indicator) return "Curvature";
  if (t.block >= 0) return "Blocks";
  if (t.factors.size() == 1) return "Linear";
  if (t.factors.size() == 2) return t.factors[0] == t.factors[1] ? "Square" : "2-Way Interaction";
  return "Constant";
}

// `block_of[r]`: run r's block as an index 0..n_blocks-1 (empty: no blocks).
Eigen::MatrixXd model_matrix(const std::vector<Term>& terms, const Eigen::MatrixXd& coded,
                             const std::vector<int>& block_of, int n_blocks) {
  Eigen::MatrixXd x(coded.rows(), static_cast<Eigen::Index>(terms.size()));
  for (Eigen::Index r = 0; r < coded.rows(); ++r) {
    const Eigen::VectorXd row = coded.row(r).transpose();
    const bool centre = is_centre(row);
    for (std::size_t c = 0; c < terms.size(); ++c) {
      const Term& t = terms[c];
      double v = Term_value(t, row, centre);
      if (t.block >= 0) {
        const int b = block_of[static_cast<std::size_t>(r)];
        v = b == t.block ? 1.0 : b == n_blocks - 1 ? -1.0 : 0.0;
      }
      x(r, static_cast<Eigen::Index>(c)) = v;
    }
  }
  return x;
}

// Residual sum of squares of a least-squares fit (QR with column pivoting; rank checked).
double residual_ss(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, Eigen::Index* rank = nullptr) {
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(x);
  if (rank != nullptr) *rank = qr.rank();
  const Eigen::VectorXd b = qr.solve(y);
  return (y - x * b).squaredNorm();
}

}  // namespace

double Term::value(const Eigen::VectorXd& coded) const { return Term_value(*this, coded, false); }

double Fit::predict(const Eigen::VectorXd& coded) const {
  double y = 0.0;
  for (std::size_t c = 0; c < terms.size(); ++c) y += beta(static_cast<Eigen::Index>(c)) * terms[c].value(coded);
  return y;
}

Eigen::VectorXd Fit::gradient(const Eigen::VectorXd& coded) const {
  Eigen::VectorXd g = Eigen::VectorXd::Zero(coded.size());
  for (std::size_t c = 0; c < terms.size(); ++c) {
    const Term& t = terms[c];
    if (t.centre_indicator || t.block >= 0) continue;
    for (std::size_t k = 0; k < t.factors.size(); ++k) {  // d/dx_f of the product
      double rest = 1.0;
      for (std::size_t m = 0; m < t.factors.size(); ++m) {
        if (m != k) rest *= coded(t.factors[m]);
      }
      g(t.factors[k]) += beta(static_cast<Eigen::Index>(c)) * rest;
    }
  }
  return g;
}

double Fit::prediction_half_width(const Eigen::VectorXd& coded, double a) const {
  Eigen::VectorXd row(static_cast<Eigen::Index>(terms.size()));
  for (std::size_t c = 0; c < terms.size(); ++c) row(static_cast<Eigen::Index>(c)) = terms[c].value(coded);
  const double leverage = row.dot(xtx_inverse * row);
  return t_critical(a, error_df) * s * std::sqrt(1.0 + leverage);
}

Fit fit(const Eigen::MatrixXd& coded, const Eigen::VectorXd& y, const std::vector<std::string>& factors,
        ModelKind model, double alpha, const std::vector<int>& blocks) {
  const auto k = static_cast<int>(factors.size());
  if (coded.cols() != k || coded.rows() != y.size()) throw InputError("expected one coded column per factor");
  Fit out;
  out.factors = factors;
  out.alpha = alpha;
  out.runs = static_cast<int>(y.size());
  std::vector<Term>& terms = out.terms;
  terms.push_back({"Constant", {}});
  for (int i = 0; i < k; ++i) terms.push_back({factors[static_cast<std::size_t>(i)], {i}});
  if (model == ModelKind::quadratic) {
    for (int i = 0; i < k; ++i) {
      const auto& n = factors[static_cast<std::size_t>(i)];
      terms.push_back({n + "*" + n, {i, i}});
    }
  }
  if (model != ModelKind::main) {
    for (int i = 0; i < k; ++i) {
      for (int j = i + 1; j < k; ++j) {
        terms.push_back({factors[static_cast<std::size_t>(i)] + "*" + factors[static_cast<std::size_t>(j)], {i, j}});
      }
    }
  }
  // Blocks, sorted by label as Minitab lists them; the last is the one coded -1.
  std::vector<int> labels(blocks.begin(), blocks.end()), block_of;
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  if (!blocks.empty() && static_cast<Eigen::Index>(blocks.size()) != y.size()) {
    throw InputError("expected one block label per run");
  }
  for (const int b : blocks) {
    block_of.push_back(static_cast<int>(std::lower_bound(labels.begin(), labels.end(), b) - labels.begin()));
  }
  const int n_blocks = static_cast<int>(labels.size());
  for (int b = 0; b + 1 < n_blocks; ++b) {
    Term t{fmt::format("Block {}", labels[static_cast<std::size_t>(b)]), {}};
    t.block = b;
    terms.push_back(t);
  }
  // Curvature: a two-level design with centre points, fitted without squares.
  int centres = 0, corners = 0;
  for (Eigen::Index r = 0; r < coded.rows(); ++r) {
    const Eigen::VectorXd row = coded.row(r).transpose();
    if (is_centre(row)) ++centres;
    if ((row.cwiseAbs().array() - 1.0).abs().maxCoeff() < 1e-9) ++corners;
  }
  if (model != ModelKind::quadratic && centres > 0 && corners > 0) terms.push_back({"Ct Pt", {}, true});

  const Eigen::MatrixXd x = model_matrix(terms, coded, block_of, n_blocks);
  const auto p = static_cast<int>(terms.size());
  if (out.runs <= p) {
    throw InputError(fmt::format("{} runs cannot fit a model of {} terms with an error estimate", out.runs, p));
  }
  Eigen::Index rank = 0;
  const double sse = residual_ss(x, y, &rank);
  if (rank < p)
    throw InputError(fmt::format("the design cannot estimate all {} terms of this model (rank {})", p, rank));
  out.xtx_inverse = (x.transpose() * x).inverse();
  out.beta = out.xtx_inverse * (x.transpose() * y);
  out.error_df = out.runs - p;
  const double mse = sse / out.error_df;
  out.s = std::sqrt(mse);
  const double mean = y.mean();
  const double sst = (y.array() - mean).square().sum();
  if (!(sst > 0.0)) throw InputError(fmt::format("the response is {} in every run: there is nothing to fit", mean));
  out.r2 = 1.0 - sse / sst;
  out.r2_adjusted = 1.0 - (sse / out.error_df) / (sst / (out.runs - 1));
  // PRESS: each run's residual as if it had been left out, e / (1 - h).
  const Eigen::VectorXd residual = y - x * out.beta;
  double press = 0.0;
  for (Eigen::Index r = 0; r < x.rows(); ++r) {
    const double h = x.row(r).dot(out.xtx_inverse * x.row(r).transpose());
    press += std::pow(residual(r) / (1.0 - h), 2);
  }
  out.r2_predicted = 1.0 - press / sst;

  for (int c = 0; c < p; ++c) {
    const Term& t = terms[static_cast<std::size_t>(c)];
    Coefficient co;
    co.term = t.name;
    co.coef = out.beta(c);
    co.se = std::sqrt(mse * out.xtx_inverse(c, c));
    co.t = co.coef / co.se;
    co.p = t_two_sided_p(co.t, out.error_df);
    const bool linear_or_interaction =
        !t.centre_indicator && t.block < 0 &&
        (t.factors.size() == 1 || (t.factors.size() == 2 && t.factors[0] != t.factors[1]));
    co.effect = linear_or_interaction ? 2.0 * co.coef : nan;
    co.significant = c > 0 && co.p < alpha;
    out.coefficients.push_back(co);
  }

  // ANOVA: the model, each group of terms by its adjusted sum of squares (the rise in the
  // residual when the group is left out), the error split into lack of fit and pure error.
  auto row = [&](const std::string& source, double df, double ss, bool test) {
    AnovaRow a{source, df, ss, df > 0 ? ss / df : nan, nan, nan};
    if (test && df > 0) {
      a.f = a.ms / mse;
      a.p = f_upper_p(a.f, df, out.error_df);
    }
    out.anova.push_back(a);
  };
  row("Model", p - 1, sst - sse, true);
  for (const char* group : {"Blocks", "Linear", "Square", "2-Way Interaction", "Curvature"}) {
    std::vector<Eigen::Index> keep;
    for (int c = 0; c < p; ++c) {
      if (group_of(terms[static_cast<std::size_t>(c)]) != group) keep.push_back(c);
    }
    if (static_cast<int>(keep.size()) == p) continue;
    Eigen::MatrixXd reduced(x.rows(), static_cast<Eigen::Index>(keep.size()));
    for (std::size_t c = 0; c < keep.size(); ++c) reduced.col(static_cast<Eigen::Index>(c)) = x.col(keep[c]);
    row(std::string("  ") + group, p - static_cast<int>(keep.size()), residual_ss(reduced, y) - sse, true);
  }
  row("Error", out.error_df, sse, false);
  // Pure error: spread among runs at the same settings.
  std::map<std::vector<long long>, std::vector<double>> groups;
  for (Eigen::Index r = 0; r < coded.rows(); ++r) {
    std::vector<long long> key;
    for (Eigen::Index c = 0; c < coded.cols(); ++c) key.push_back(std::llround(coded(r, c) * 1e6));
    groups[key].push_back(y(r));
  }
  double ss_pe = 0.0;
  int df_pe = 0;
  for (const auto& [key, values] : groups) {
    double m = 0.0;
    for (const double v : values) m += v / static_cast<double>(values.size());
    for (const double v : values) ss_pe += (v - m) * (v - m);
    df_pe += static_cast<int>(values.size()) - 1;
  }
  const int df_lof = out.error_df - df_pe;
  if (df_pe > 0 && df_lof > 0) {
    AnovaRow lof{"  Lack-of-Fit", static_cast<double>(df_lof), sse - ss_pe, (sse - ss_pe) / df_lof, nan, nan};
    lof.f = lof.ms / (ss_pe / df_pe);
    lof.p = f_upper_p(lof.f, df_lof, df_pe);
    out.anova.push_back(lof);
    out.anova.push_back({"  Pure Error", static_cast<double>(df_pe), ss_pe, ss_pe / df_pe, nan, nan});
  }
  out.anova.push_back({"Total", static_cast<double>(out.runs - 1), sst, nan, nan, nan});
  return out;
}

Eigen::VectorXd solve_for_target(const Fit& f, double target, double limit, Eigen::VectorXd start,
                                 const std::vector<bool>& fixed) {
  const auto k = static_cast<Eigen::Index>(f.factors.size());
  Eigen::VectorXd x = start.size() == k ? std::move(start) : Eigen::VectorXd::Zero(k);
  auto free_only = [&](Eigen::VectorXd g) {
    for (Eigen::Index i = 0; i < k && static_cast<std::size_t>(i) < fixed.size(); ++i) {
      if (fixed[static_cast<std::size_t>(i)]) g(i) = 0.0;
    }
    return g;
  };
  // Projected Gauss-Newton on r(x) = predict - target: the least-norm step along the
  // gradient, clipped to the region; a step that does not reduce |r| is halved.
  for (int it = 0; it < 500; ++it) {
    const double r = f.predict(x) - target;
    if (std::abs(r) < 1e-10 * std::max(1.0, std::abs(target))) return x;
    const Eigen::VectorXd g = free_only(f.gradient(x));
    const double g2 = g.squaredNorm();
    if (g2 == 0.0) break;
    double step = 1.0;
    Eigen::VectorXd next = x;
    for (int h = 0; h < 40; ++h, step *= 0.5) {
      next = (x - step * r / g2 * g).cwiseMax(-limit).cwiseMin(limit);
      for (Eigen::Index i = 0; i < k && static_cast<std::size_t>(i) < fixed.size(); ++i) {
        if (fixed[static_cast<std::size_t>(i)]) next(i) = x(i);  // (a fixed factor may lie outside)
      }
      if (std::abs(f.predict(next) - target) < std::abs(r)) break;
    }
    if ((next - x).norm() < 1e-14) break;
    x = next;
  }
  const double reached = f.predict(x);
  if (std::abs(reached - target) > 1e-6 * std::max(1.0, std::abs(target))) {
    throw InputError(fmt::format("the model does not reach {} within the design region; the closest it gets is {}",
                                 target, reached));
  }
  return x;
}

}  // namespace bushel::doe
