#include "bushel/analysis/compressibility.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "bushel/core/input_error.hpp"
#include "temp_dir_test.hpp"

namespace bushel {
namespace {

TEST(Compressibility, WpackingFormInKilopascals) {
  const Compressibility m = Compressibility::wpacking(0.3, 2.0, 0.01, 13.0);
  // D - D_o = a P + b sqrt(P) + c P MC with P = 100 kPa: 30 + 20 + 13 = 63 kg/m3.
  EXPECT_NEAR(m.density(100e3, 770.0), 833.0, 1e-12);
  EXPECT_EQ(m.density(0.0, 770.0), 770.0);
  EXPECT_THROW(Compressibility::wpacking(0.3, 2.0, 0.01, 120.0), InputError);
  EXPECT_THROW(m.density(-1.0, 770.0), InputError);
}

TEST(Compressibility, TableIsMonotoneThroughItsPoints) {
  // Levels of a compression run: 0, 7, 21, 34, 48, 69, 103, 138 kPa.
  const std::vector<double> p{0, 7e3, 21e3, 34e3, 48e3, 69e3, 103e3, 138e3};
  const std::vector<double> r{1.0, 1.012, 1.030, 1.041, 1.050, 1.060, 1.071, 1.078};
  const Compressibility m = Compressibility::table(p, r, Extrapolation::error, "levels");
  for (std::size_t i = 0; i < p.size(); ++i) EXPECT_NEAR(m.density(p[i], 800.0), 800.0 * r[i], 1e-9);
  double last = 0.0;
  for (double q = 0.0; q <= 138e3; q += 50.0) {  // no overshoot between the levels
    const double d = m.density(q, 800.0);
    EXPECT_GE(d, last - 1e-12) << q;
    last = d;
  }
  // A flat stretch stays flat (Fritsch-Carlson: no wiggle next to a plateau).
  const Compressibility flat =
      Compressibility::table({0, 10e3, 20e3, 30e3}, {1.0, 1.05, 1.05, 1.1}, Extrapolation::error, "flat");
  for (double q = 10e3; q <= 20e3; q += 500.0) EXPECT_NEAR(flat.density(q, 1.0), 1.05, 1e-12) << q;
}

TEST(Compressibility, BeyondTheTable) {
  const std::vector<double> p{0, 10e3, 20e3};
  const std::vector<double> r{1.0, 1.02, 1.03};
  try {
    (void)Compressibility::table(p, r, Extrapolation::error, "levels.csv").density(25e3, 800.0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("levels.csv"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("25 kPa"), std::string::npos) << e.what();
  }
  EXPECT_NEAR(Compressibility::table(p, r, Extrapolation::hold, "t").density(40e3, 800.0), 824.0, 1e-9);
  EXPECT_NEAR(Compressibility::table(p, r, Extrapolation::linear, "t").density(30e3, 800.0), 832.0, 1e-9);
  EXPECT_THROW(Compressibility::table({5e3, 10e3}, {1.0, 1.1}, Extrapolation::error, "t"), InputError);
  EXPECT_THROW(Compressibility::table({0, 10e3, 10e3}, {1.0, 1.1, 1.2}, Extrapolation::error, "t"), InputError);
  EXPECT_THROW(parse_extrapolation("clamp"), InputError);
}

class CompressibilityFile : public TempDirTest {};

TEST_F(CompressibilityFile, ReadsUnitsAndNamesBadCells) {
  const std::string good = path("levels.csv");
  std::ofstream(good) << "pressure,bulk_density\n0kPa,800kg/m3\n7kPa,810kg/m3\n21kPa,824kg/m3\n";
  const Compressibility m = Compressibility::read_csv(good, Extrapolation::error);
  EXPECT_NEAR(m.density(7e3, 760.0), 760.0 * 810.0 / 800.0, 1e-9);
  const std::string bad = path("bad.csv");
  std::ofstream(bad) << "pressure,bulk_density\n0kPa,800kg/m3\n7,810kg/m3\n";
  try {
    (void)Compressibility::read_csv(bad, Extrapolation::error);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.key(), "pressure");
  }
  const std::string ratios = path("ratios.csv");
  std::ofstream(ratios) << "pressure,packing_ratio\n0Pa,1\n0.1MPa,1.05\n";
  EXPECT_NEAR(Compressibility::read_csv(ratios, Extrapolation::error).density(100e3, 780.0), 819.0, 1e-9);
}

}  // namespace
}  // namespace bushel
