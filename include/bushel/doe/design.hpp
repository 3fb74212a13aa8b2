#pragma once
// Experimental designs in coded units (-1 low, +1 high), with the run bookkeeping the analysis
// and the campaigns need: standard order, a randomised run order from a seed, centre-point
// flags and blocks.

#include <Eigen/Dense>
#include <cstdint>
#include <string>
#include <vector>

#include "bushel/doe/factor_table.hpp"

namespace bushel::doe {

struct Design {
  std::string kind;            ///< "plackett-burman", "factorial", "ccd", ...
  Eigen::MatrixXd coded;       ///< runs x factors, in standard order
  std::vector<int> block;      ///< per run, from 1
  std::vector<bool> centre;    ///< per run: a centre point
  std::vector<int> run_order;  ///< per run (standard order index): its position when run, from 1
  int runs() const { return static_cast<int>(coded.rows()); }
};

/// Plackett-Burman screening design of `runs` = 12, 20 or 24 runs for up to runs - 1 factors
/// (the cyclic generators of Plackett and Burman 1946; last run all low).
Design plackett_burman(int factors, int runs);

/// Two-level factorial of 2^(k - p) runs: the full factorial of the first k - p factors in
/// standard (Yates) order, each further factor defined by a generator over them, e.g.
/// {"E=ABCD"} (letters A, B, ... name the factors in order). With no generators given for a
/// fraction, standard minimum-aberration ones are used where known. Plus `centre` centre points.
Design factorial(int factors, int fraction = 0, int centre = 0, const std::vector<std::string>& generators = {});

enum class CcdType {
  circumscribed,  ///< axial points at +-alpha, alpha = (factorial runs)^(1/4) (rotatable)
  face_centred,   ///< axial points on the faces, alpha = 1
  inscribed,      ///< the circumscribed design scaled into the cube (factorial at +-1/alpha)
};
/// "circumscribed", "face", "inscribed"; InputError with a did-you-mean otherwise.
CcdType parse_ccd_type(const std::string& text);
/// Central composite design: a full factorial, 2k axial points, `centre` centre points per
/// block; with blocks = 2 the factorial and the axial part are blocks 1 and 2.
Design central_composite(int factors, CcdType type, int centre = 6, int blocks = 1);

/// Box-Behnken design for 3 to 5 factors: every pair of factors at +-1 with the others at
/// their centre, plus `centre` centre points.
Design box_behnken(int factors, int centre = 3);

/// Latin hypercube of `runs` runs in [-1, 1]: each factor's range cut into `runs` equal
/// strata, one run in each, at a random place; random pairing from `seed`.
Design latin_hypercube(int factors, int runs, std::uint64_t seed);

/// Sets a random run order from `seed` (a shuffle, reproducible); without it, run order =
/// standard order.
void randomize(Design& design, std::uint64_t seed);

/// Minitab's point type of a run: 1 corner, 0 centre, -1 axial, 2 edge (Box-Behnken).
int point_type(const Design& design, Eigen::Index run);

/// The design as the table `bushel doe design` writes and `bushel doe run` reads: columns
/// std_order, run_order, center_pt, block and the factors (physical units, 6 digits), one
/// row per run in run order. `factors` (one per column of the design) decode the levels.
std::string design_csv(const Design& design, const std::vector<Factor>& factors);

}  // namespace bushel::doe
