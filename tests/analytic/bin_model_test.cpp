// The bin model against closed forms: Janssen's profile for a constant density, the
// hydrostatic limit, M = D_o V without compaction (volumes of cylinder, cones and hopper),
// second-order convergence with depth-dependent density, and the units the trade uses.

#include "bushel/analysis/bin_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bushel/analysis/grain_trade.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/units/units.hpp"

namespace bushel {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double deg = pi / 180.0;

BinSpec farm_bin() {  // a 30 ft bin filled to 24 ft
  BinSpec s;
  s.diameter = 9.144;
  s.grain_height = 7.315;
  s.lateral_ratio = 0.5;
  s.wall_friction = 0.3;
  s.layers = 400;
  return s;
}

TEST(BinModel, ConstantDensityFollowsJanssensClosedForm) {
  const BinSpec s = farm_bin();
  const double d0 = units::parse("60lb/bu", units::dim::density);
  const BinResult r = fill_bin(s, Compressibility::none(), d0);
  const double gamma = d0 * s.gravity, rh = 0.25 * s.diameter, k_mu = s.lateral_ratio * s.wall_friction;
  ASSERT_EQ(r.levels.size(), static_cast<std::size_t>(s.layers) + 1);
  for (const BinLevel& l : r.levels) {
    const double closed = gamma * rh / k_mu * (1.0 - std::exp(-k_mu * l.depth / rh));
    EXPECT_NEAR(l.pressure, closed, 1e-11 * gamma * s.grain_height) << l.depth;
  }
  // Less than the hydrostatic pressure: the wall carries part of the weight.
  EXPECT_LT(r.bottom_pressure(), gamma * s.grain_height);
  EXPECT_NEAR(r.mass, d0 * pi * 0.25 * s.diameter * s.diameter * s.grain_height, 1e-12 * r.mass);
  EXPECT_NEAR(r.packing_ratio(), 1.0, 1e-13);
}

TEST(BinModel, NoWallFrictionIsHydrostatic) {
  BinSpec s = farm_bin();
  s.wall_friction = 0.0;
  const BinResult r = fill_bin(s, Compressibility::none(), 780.0);
  EXPECT_NEAR(r.bottom_pressure(), 780.0 * s.gravity * s.grain_height, 1e-9 * r.bottom_pressure());
}

TEST(BinModel, WithoutCompactionMassIsInitialDensityTimesVolume) {
  // Peaked surcharge and a hopper: cylinder + cone above + frustum below, exactly.
  BinSpec s = farm_bin();
  s.surcharge = Surcharge::peaked;
  s.repose_angle = 25 * deg;
  s.hopper_angle = 40 * deg;
  s.outlet_diameter = 0.4;
  const double d0 = 772.0;
  const BinResult r = fill_bin(s, Compressibility::wpacking(0.0, 0.0, 0.0, 12.0), d0);
  const double R = 0.5 * s.diameter, ro = 0.5 * s.outlet_diameter;
  const double cone = pi * R * R * R * std::tan(s.repose_angle) / 3.0;
  const double h = (R - ro) * std::tan(s.hopper_angle);
  const double frustum = pi * h * (R * R + R * ro + ro * ro) / 3.0;
  const double volume = pi * R * R * s.grain_height + cone + frustum;
  EXPECT_NEAR(r.volume, volume, 1e-12 * volume);
  EXPECT_NEAR(r.mass, d0 * volume, 1e-12 * d0 * volume);
  // The surcharge loads the eave with its weight spread over the section: gamma h_c / 3.
  bool eave_seen = false;
  for (const BinLevel& l : r.levels) {
    if (l.depth != 0.0) continue;
    eave_seen = true;
    EXPECT_NEAR(l.pressure, d0 * s.gravity * R * std::tan(s.repose_angle) / 3.0, 1e-9 * l.pressure);
  }
  EXPECT_TRUE(eave_seen);
  // An inverted cone takes away what a peaked one adds.
  s.surcharge = Surcharge::inverted;
  const BinResult inv = fill_bin(s, Compressibility::none(), d0);
  EXPECT_NEAR(inv.volume, volume - 2.0 * cone, 1e-12 * volume);
}

TEST(BinModel, FinerLayersConvergeAtSecondOrder) {
  // WPACKING-form compaction (illustrative coefficients): the density grows with depth.
  const Compressibility m = Compressibility::wpacking(0.35, 0.0, 0.01, 12.0);
  BinSpec s = farm_bin();
  double masses[4];
  for (int k = 0; k < 4; ++k) {
    s.layers = 25 << k;
    masses[k] = fill_bin(s, m, 772.0).mass;
  }
  const double e1 = std::abs(masses[1] - masses[0]), e2 = std::abs(masses[2] - masses[1]),
               e3 = std::abs(masses[3] - masses[2]);
  EXPECT_GT(e1 / e2, 3.5);  // halving the layer halves the error twice (order 2)
  EXPECT_GT(e2 / e3, 3.5);
  EXPECT_LT(e3 / masses[3], 1e-6);
  // With the sqrt(P) term the density is not smooth at the surface (D - D_o ~ sqrt(z)), and
  // the order drops; the default 2,000 layers are still within 1e-6 of 32,000.
  const Compressibility rough = Compressibility::wpacking(0.35, 3.0, 0.01, 12.0);
  BinSpec fine = farm_bin();
  fine.layers = 2000;
  const double m_default = fill_bin(fine, rough, 772.0).mass;
  fine.layers = 4000;
  const double m_double = fill_bin(fine, rough, 772.0).mass;
  fine.layers = 32000;
  const double m_fine = fill_bin(fine, rough, 772.0).mass;
  EXPECT_LT(std::abs(m_default - m_fine), 1e-6 * m_fine);
  EXPECT_LT(std::abs(m_double - m_fine), 0.6 * std::abs(m_default - m_fine));  // still converging
  const BinResult r = fill_bin(s, m, 772.0);
  EXPECT_GT(r.packing_ratio(), 1.0);
  for (std::size_t i = 1; i < r.levels.size(); ++i) {
    EXPECT_GE(r.levels[i].pressure, r.levels[i - 1].pressure);
    EXPECT_GE(r.levels[i].density, r.levels[i - 1].density);
  }
}

TEST(BinModel, TradeUnitsRoundTrip) {
  const double lb_bu = units::parse("1lb/bu", units::dim::density);
  EXPECT_NEAR(lb_bu, 12.8718, 1e-4);  // docs/wheat.md: 1 lb/bu = 12.8719 kg/m3
  EXPECT_NEAR(units::parse("60lb/bu", units::dim::density) / lb_bu, 60.0, 1e-12);
  const double bushel = units::parse("1bu", units::dim::volume);
  EXPECT_NEAR(units::parse("1000bu", units::dim::volume) / bushel, 1000.0, 1e-9);
  // A standard bushel of wheat is 60 lb: test weight x one bushel of volume.
  const StandardBushel& wheat = standard_bushel("wheat");
  EXPECT_NEAR(wheat.test_weight() * bushel, wheat.mass(), 1e-12 * wheat.mass());
}

TEST(BinModel, JakyRatioAndBadSpecs) {
  EXPECT_NEAR(jaky_lateral_ratio(30 * deg), 0.5, 1e-15);
  EXPECT_THROW(jaky_lateral_ratio(0.0), InputError);
  BinSpec s = farm_bin();
  s.diameter = -1.0;
  EXPECT_THROW(validate(s), InputError);
  s = farm_bin();
  s.hopper_angle = 45 * deg;
  s.outlet_diameter = 10.0;
  try {
    validate(s);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "outlet_diameter");
  }
  s = farm_bin();
  s.surcharge = Surcharge::inverted;
  s.repose_angle = 70 * deg;  // the cone would be deeper than the grain
  EXPECT_THROW(fill_bin(s, Compressibility::none(), 780.0), InputError);
  EXPECT_THROW(parse_surcharge("peaky"), InputError);
}

}  // namespace
}  // namespace bushel
