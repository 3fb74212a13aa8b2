// Design generators against their defining properties and against the study's own designs
// (data/pb_*: Minitab's 12-run Plackett-Burman for 6 factors; data/rsm_*: a face-centred
// central composite design in 2 blocks with 3 centre points each), in standard order.

#include "bushel/doe/design.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>

#include "bushel/core/input_error.hpp"
#include "bushel/doe/factor_table.hpp"

namespace bushel::doe {
namespace {

// The table's factor columns coded from their ranges, rows in standard order.
Eigen::MatrixXd study_design(const std::string& file, const std::vector<std::string>& factors) {
  const FactorTable t = read_factor_table(std::string(BUSHEL_DATA_DIR) + "/" + file, factors, "std_order");
  Eigen::MatrixXd x(t.coded.rows(), t.coded.cols());
  for (Eigen::Index r = 0; r < t.coded.rows(); ++r)
    x.row(static_cast<Eigen::Index>(t.response(r)) - 1) = t.coded.row(r);
  return x;
}

void expect_orthogonal_balanced(const Eigen::MatrixXd& x) {
  const Eigen::MatrixXd gram = x.transpose() * x;
  EXPECT_TRUE(gram.isApprox(x.rows() * Eigen::MatrixXd::Identity(x.cols(), x.cols()), 1e-12));
  EXPECT_LT(x.colwise().sum().cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Designs, PlackettBurmanIsOrthogonalAndMatchesTheStudy) {
  for (const int runs : {12, 20, 24}) {
    SCOPED_TRACE(runs);
    expect_orthogonal_balanced(plackett_burman(runs - 1, runs).coded);
  }
  const Design pb = plackett_burman(6, 12);
  EXPECT_EQ(pb.coded,
            study_design("pb_5sphere_large_table3_9.csv", {"fr_ww", "fr_ws", "fs_ww", "fs_ws", "e_ww", "e_ws"}));
  EXPECT_THROW(plackett_burman(12, 12), InputError);
  EXPECT_THROW(plackett_burman(5, 16), InputError);
}

TEST(Designs, FactorialsAndTheirDefiningRelations) {
  const Design full = factorial(3, 0, 4);
  EXPECT_EQ(full.runs(), 12);
  expect_orthogonal_balanced(full.coded.topRows(8));
  EXPECT_EQ(std::count(full.centre.begin(), full.centre.end(), true), 4);
  EXPECT_EQ(full.coded.row(1), (Eigen::RowVector3d{1, -1, -1}));  // Yates order: A fastest
  // 2^(5-1) with E = ABCD: I = ABCDE on every run; resolution V: 2-factor interactions
  // orthogonal to the main effects and to each other.
  const Design half = factorial(5, 1);
  EXPECT_EQ(half.runs(), 16);
  Eigen::MatrixXd model(16, 15);
  int c = 0;
  for (int i = 0; i < 5; ++i) model.col(c++) = half.coded.col(i);
  for (int i = 0; i < 5; ++i) {
    for (int j = i + 1; j < 5; ++j) model.col(c++) = half.coded.col(i).cwiseProduct(half.coded.col(j));
  }
  expect_orthogonal_balanced(model);
  for (Eigen::Index r = 0; r < 16; ++r) EXPECT_EQ(half.coded.row(r).prod(), 1.0);
  EXPECT_EQ(factorial(7, 3).runs(), 16);
  EXPECT_THROW(factorial(5, 1, 0, {"E=ABCF"}), InputError);
  EXPECT_THROW(factorial(9, 3), InputError);  // no standard generators: give them
}

TEST(Designs, CentralCompositeMatchesTheStudysResponseSurfaceDesign) {
  const Design ccd = central_composite(4, CcdType::face_centred, 3, 2);
  EXPECT_EQ(ccd.runs(), 30);
  const Eigen::MatrixXd study = study_design("rsm_5sphere_large_table3_10.csv", {"fs_ww", "fr_ww", "e_ww", "fs_ws"});
  EXPECT_LT((ccd.coded - study).cwiseAbs().maxCoeff(), 1e-12) << ccd.coded << "\n\n" << study;
  EXPECT_EQ(ccd.block[15], 1);
  EXPECT_EQ(ccd.block[19], 2);
  // Rotatable: axial distance (2^k)^(1/4) = 2 for k = 4; inscribed: inside the cube.
  EXPECT_DOUBLE_EQ(central_composite(4, CcdType::circumscribed).coded.maxCoeff(), 2.0);
  EXPECT_DOUBLE_EQ(central_composite(4, CcdType::inscribed).coded.cwiseAbs().maxCoeff(), 1.0);
  EXPECT_DOUBLE_EQ(central_composite(4, CcdType::inscribed).coded(0, 0), -0.5);
  EXPECT_THROW(parse_ccd_type("faced"), InputError);
}

TEST(Designs, BoxBehnkenAndLatinHypercube) {
  const Design bb = box_behnken(4, 3);
  EXPECT_EQ(bb.runs(), 27);
  for (Eigen::Index r = 0; r < 24; ++r) EXPECT_EQ((bb.coded.row(r).array() != 0.0).count(), 2);
  EXPECT_LT(bb.coded.colwise().sum().cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_THROW(box_behnken(6), InputError);

  const Design lhs = latin_hypercube(3, 10, 42);
  for (int f = 0; f < 3; ++f) {  // one run in each tenth of every factor's range
    std::set<int> strata;
    for (Eigen::Index r = 0; r < 10; ++r) strata.insert(static_cast<int>(std::floor((lhs.coded(r, f) + 1.0) * 5.0)));
    EXPECT_EQ(strata.size(), 10u);
  }
  EXPECT_EQ(latin_hypercube(3, 10, 42).coded, lhs.coded);
  EXPECT_NE(latin_hypercube(3, 10, 43).coded, lhs.coded);
}

TEST(Designs, RandomRunOrderIsAReproduciblePermutationWithinBlocks) {
  Design d = central_composite(3, CcdType::face_centred, 2, 2);
  randomize(d, 7);
  std::vector<int> sorted = d.run_order;
  std::sort(sorted.begin(), sorted.end());
  for (int i = 0; i < d.runs(); ++i) EXPECT_EQ(sorted[static_cast<std::size_t>(i)], i + 1);
  for (int r = 0; r < d.runs(); ++r) {  // block 1 (8 cube + 2 centre runs) runs first
    const auto i = static_cast<std::size_t>(r);
    EXPECT_EQ(d.run_order[i] <= 10, d.block[i] == 1) << r;
  }
  Design again = central_composite(3, CcdType::face_centred, 2, 2);
  randomize(again, 7);
  EXPECT_EQ(again.run_order, d.run_order);
}

}  // namespace
}  // namespace bushel::doe
