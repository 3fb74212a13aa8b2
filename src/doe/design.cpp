#include "bushel/doe/design.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>

#include "bushel/core/choice.hpp"
#include "bushel/core/input_error.hpp"

namespace bushel::doe {

namespace {

Design make(std::string kind, Eigen::MatrixXd coded, int centre_points) {
  Design d;
  d.kind = std::move(kind);
  const Eigen::Index base = coded.rows();
  d.coded = Eigen::MatrixXd::Zero(base + centre_points, coded.cols());
  d.coded.topRows(base) = coded;
  d.block.assign(static_cast<std::size_t>(d.coded.rows()), 1);
  d.centre.assign(static_cast<std::size_t>(d.coded.rows()), false);
  for (Eigen::Index r = base; r < d.coded.rows(); ++r) d.centre[static_cast<std::size_t>(r)] = true;
  d.run_order.resize(static_cast<std::size_t>(d.coded.rows()));
  std::iota(d.run_order.begin(), d.run_order.end(), 1);
  return d;
}

void require_factors(int factors, int lo, int hi, const char* design) {
  if (factors < lo || factors > hi) {
    throw InputError(fmt::format("a {} design takes {} to {} factors, got {}", design, lo, hi, factors))
        .with_key("factors");
  }
}

// Full two-level factorial in Yates order: factor 0 alternates fastest.
Eigen::MatrixXd full_factorial(int k) {
  const Eigen::Index n = Eigen::Index{1} << k;
  Eigen::MatrixXd x(n, k);
  for (Eigen::Index r = 0; r < n; ++r) {
    for (int f = 0; f < k; ++f) x(r, f) = ((r >> f) & 1) != 0 ? 1.0 : -1.0;
  }
  return x;
}

}  // namespace

Design plackett_burman(int factors, int runs) {
  // First rows of Plackett and Burman (1946); the other rows are cyclic shifts.
  static const std::map<int, std::string> generator{
      {12, "++-+++---+-"},
      {20, "++--++++-+-+----++-"},
      {24, "+++++-+-++--++--+-+----"},
  };
  const auto it = generator.find(runs);
  if (it == generator.end()) {
    throw InputError(fmt::format("Plackett-Burman designs here have 12, 20 or 24 runs, got {}", runs)).with_key("runs");
  }
  require_factors(factors, 2, runs - 1, "Plackett-Burman");
  const std::string& g = it->second;
  const int m = runs - 1;
  Eigen::MatrixXd x(runs, factors);
  for (int r = 0; r < runs; ++r) {
    for (int f = 0; f < factors; ++f) {
      // Column f is the generator down the runs, shifted by f (Minitab's arrangement).
      x(r, f) = r == m ? -1.0 : (g[static_cast<std::size_t>((r - f + m) % m)] == '+' ? 1.0 : -1.0);
    }
  }
  return make("plackett-burman", x, 0);
}

Design factorial(int factors, int fraction, int centre, const std::vector<std::string>& generators) {
  require_factors(factors, 2, 15, "two-level factorial");
  if (fraction < 0 || factors - fraction < 2) {
    throw InputError(fmt::format("expected a fraction p with k - p >= 2, got k {} p {}", factors, fraction))
        .with_key("fraction");
  }
  if (centre < 0) throw InputError("expected centre points >= 0").with_key("center");
  std::vector<std::string> gens = generators;
  if (gens.empty() && fraction > 0) {
    // Minimum-aberration generators (as tabulated in Montgomery, Design and Analysis of
    // Experiments, for two-level fractional factorials).
    static const std::map<std::pair<int, int>, std::vector<std::string>> standard{
        {{3, 1}, {"C=AB"}},
        {{4, 1}, {"D=ABC"}},
        {{5, 1}, {"E=ABCD"}},
        {{5, 2}, {"D=AB", "E=AC"}},
        {{6, 1}, {"F=ABCDE"}},
        {{6, 2}, {"E=ABC", "F=BCD"}},
        {{6, 3}, {"D=AB", "E=AC", "F=BC"}},
        {{7, 1}, {"G=ABCDEF"}},
        {{7, 2}, {"F=ABCD", "G=ABDE"}},
        {{7, 3}, {"E=ABC", "F=BCD", "G=ACD"}},
        {{7, 4}, {"D=AB", "E=AC", "F=BC", "G=ABC"}},
        {{8, 4}, {"E=BCD", "F=ACD", "G=ABC", "H=ABD"}},
    };
    const auto it = standard.find({factors, fraction});
    if (it == standard.end()) {
      throw InputError(fmt::format("no standard generators for 2^({}-{}); give them, e.g. E=ABCD", factors, fraction))
          .with_key("generators");
    }
    gens = it->second;
  }
  if (static_cast<int>(gens.size()) != fraction) {
    throw InputError(
        fmt::format("expected {} generators for 2^({}-{}), got {}", fraction, factors, fraction, gens.size()))
        .with_key("generators");
  }
  const int base = factors - fraction;
  Eigen::MatrixXd x(Eigen::Index{1} << base, factors);
  x.leftCols(base) = full_factorial(base);
  for (int g = 0; g < fraction; ++g) {
    const std::string& text = gens[static_cast<std::size_t>(g)];
    const int target = base + g;
    const auto eq = text.find('=');
    bool ok = eq == 1 && text[0] == static_cast<char>('A' + target) && eq + 1 < text.size();
    Eigen::VectorXd column = Eigen::VectorXd::Ones(x.rows());
    for (std::size_t c = eq + 1; ok && c < text.size(); ++c) {
      const int f = text[c] - 'A';
      ok = f >= 0 && f < base;
      if (ok) column = column.cwiseProduct(x.col(f));
    }
    if (!ok) {
      throw InputError(fmt::format("expected the generator of factor {} over factors A to {}, e.g. {}=ABC; got '{}'",
                                   static_cast<char>('A' + target), static_cast<char>('A' + base - 1),
                                   static_cast<char>('A' + target), text))
          .with_key("generators");
    }
    x.col(target) = column;
  }
  return make(fraction > 0 ? "fractional factorial" : "factorial", x, centre);
}

CcdType parse_ccd_type(const std::string& text) {
  return parse_choice<CcdType>(
      text,
      {{"circumscribed", CcdType::circumscribed}, {"face", CcdType::face_centred}, {"inscribed", CcdType::inscribed}});
}

Design central_composite(int factors, CcdType type, int centre, int blocks) {
  require_factors(factors, 2, 10, "central composite");
  if (blocks != 1 && blocks != 2) throw InputError("expected 1 or 2 blocks").with_key("blocks");
  if (centre < 0) throw InputError("expected centre points >= 0").with_key("center");
  const Eigen::MatrixXd cube = full_factorial(factors);
  const double alpha = std::pow(static_cast<double>(cube.rows()), 0.25);
  const double axial = type == CcdType::face_centred ? 1.0 : type == CcdType::circumscribed ? alpha : 1.0;
  const double scale = type == CcdType::inscribed ? 1.0 / alpha : 1.0;
  const Eigen::Index nf = cube.rows(), na = 2 * factors;
  const int centre_total = centre * blocks;
  Design d = make("ccd", Eigen::MatrixXd::Zero(nf + na, factors), centre_total);
  d.coded.topRows(nf) = cube * scale;
  for (int f = 0; f < factors; ++f) {
    d.coded(nf + 2 * f, f) = -axial;
    d.coded(nf + 2 * f + 1, f) = axial;
  }
  if (blocks == 2) {  // block 1: cube + its centre points; block 2: axial + its centre points
    const Eigen::Index total = d.coded.rows();
    Eigen::MatrixXd ordered(total, factors);
    ordered.topRows(nf) = d.coded.topRows(nf);
    ordered.middleRows(nf, centre) = Eigen::MatrixXd::Zero(centre, factors);
    ordered.middleRows(nf + centre, na) = d.coded.middleRows(nf, na);
    ordered.bottomRows(centre) = Eigen::MatrixXd::Zero(centre, factors);
    d.coded = ordered;
    for (Eigen::Index r = 0; r < total; ++r) {
      const auto i = static_cast<std::size_t>(r);
      d.block[i] = r < nf + centre ? 1 : 2;
      d.centre[i] = (r >= nf && r < nf + centre) || r >= nf + centre + na;
    }
  }
  return d;
}

Design box_behnken(int factors, int centre) {
  require_factors(factors, 3, 5, "Box-Behnken");
  if (centre < 0) throw InputError("expected centre points >= 0").with_key("center");
  std::vector<Eigen::VectorXd> rows;
  for (int i = 0; i < factors; ++i) {
    for (int j = i + 1; j < factors; ++j) {
      for (const double a : {-1.0, 1.0}) {
        for (const double b : {-1.0, 1.0}) {
          Eigen::VectorXd r = Eigen::VectorXd::Zero(factors);
          r(i) = a, r(j) = b;
          rows.push_back(r);
        }
      }
    }
  }
  Eigen::MatrixXd x(static_cast<Eigen::Index>(rows.size()), factors);
  for (std::size_t r = 0; r < rows.size(); ++r) x.row(static_cast<Eigen::Index>(r)) = rows[r].transpose();
  return make("box-behnken", x, centre);
}

Design latin_hypercube(int factors, int runs, std::uint64_t seed) {
  require_factors(factors, 1, 1000, "Latin hypercube");
  if (runs < 2) throw InputError(fmt::format("expected at least 2 runs, got {}", runs)).with_key("runs");
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::MatrixXd x(runs, factors);
  std::vector<int> strata(static_cast<std::size_t>(runs));
  for (int f = 0; f < factors; ++f) {
    std::iota(strata.begin(), strata.end(), 0);
    std::shuffle(strata.begin(), strata.end(), rng);
    for (int r = 0; r < runs; ++r) {
      x(r, f) = -1.0 + 2.0 * (strata[static_cast<std::size_t>(r)] + u(rng)) / runs;
    }
  }
  return make("latin hypercube", x, 0);
}

void randomize(Design& d, std::uint64_t seed) {
  std::vector<int> order(static_cast<std::size_t>(d.runs()));
  std::iota(order.begin(), order.end(), 0);
  std::mt19937_64 rng(seed);
  // Within each block (blocks are run one after the other).
  auto begin = order.begin();
  while (begin != order.end()) {
    const int block = d.block[static_cast<std::size_t>(*begin)];
    auto end = std::find_if(begin, order.end(), [&](int r) { return d.block[static_cast<std::size_t>(r)] != block; });
    std::shuffle(begin, end, rng);
    begin = end;
  }
  for (std::size_t position = 0; position < order.size(); ++position) {
    d.run_order[static_cast<std::size_t>(order[position])] = static_cast<int>(position) + 1;
  }
}

int point_type(const Design& d, Eigen::Index r) {
  if (d.centre[static_cast<std::size_t>(r)]) return 0;
  int nonzero = 0;
  for (Eigen::Index c = 0; c < d.coded.cols(); ++c) nonzero += d.coded(r, c) != 0.0 ? 1 : 0;
  if (d.kind == "ccd" && nonzero == 1) return -1;
  if (d.kind == "box-behnken") return 2;
  return 1;
}

std::string design_csv(const Design& d, const std::vector<Factor>& factors) {
  if (factors.size() != static_cast<std::size_t>(d.coded.cols())) {
    throw InputError(
        fmt::format("expected {} factors (one per column of the design), got {}", d.coded.cols(), factors.size()));
  }
  std::string csv = "std_order,run_order,center_pt,block";
  for (const Factor& f : factors) csv += "," + f.name;
  csv += "\n";
  std::vector<Eigen::Index> by_run(static_cast<std::size_t>(d.runs()));
  for (Eigen::Index r = 0; r < d.runs(); ++r)
    by_run[static_cast<std::size_t>(d.run_order[static_cast<std::size_t>(r)] - 1)] = r;
  for (const Eigen::Index r : by_run) {
    csv += fmt::format("{},{},{},{}", r + 1, d.run_order[static_cast<std::size_t>(r)], point_type(d, r),
                       d.block[static_cast<std::size_t>(r)]);
    for (std::size_t f = 0; f < factors.size(); ++f) {
      csv += fmt::format(",{:.6g}", factors[f].decode(d.coded(r, static_cast<Eigen::Index>(f))));
    }
    csv += "\n";
  }
  return csv;
}

}  // namespace bushel::doe
