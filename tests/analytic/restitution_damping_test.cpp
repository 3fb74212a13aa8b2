#include <gtest/gtest.h>

#include "bushel/contact/restitution_damping.hpp"

namespace bushel {
namespace {

TEST(RestitutionDamping, EdemFactorIsExactWithoutTheClamp) {
  // The dimensionless impact reproduces the linear-theory result the EDEM factor rests on.
  for (const double e : {0.1, 0.3, 0.5, 0.7, 0.9}) {
    EXPECT_NEAR(hertz_restitution(edem_damping_factor(e), false), e, 2e-4) << e;
  }
}

TEST(RestitutionDamping, ClampingRaisesTheReboundOfTheEdemFactor) {
  EXPECT_NEAR(hertz_restitution(edem_damping_factor(0.1), true), 0.253, 0.003);
  EXPECT_NEAR(hertz_restitution(edem_damping_factor(0.5), true), 0.550, 0.003);
}

TEST(RestitutionDamping, InverseRestoresTheRequestedRestitution) {
  double previous = 1e9;
  for (const double e : {0.05, 0.1, 0.3, 0.5, 0.7, 0.9}) {
    const double gamma = damping_for_restitution(e);
    EXPECT_NEAR(hertz_restitution(gamma, true), e, 2e-4) << e;
    EXPECT_GE(gamma, edem_damping_factor(e)) << e;
    EXPECT_LT(gamma, previous);  // less damping for livelier contacts
    previous = gamma;
  }
  EXPECT_EQ(damping_for_restitution(1.0), 0.0);
  EXPECT_THROW(damping_for_restitution(0.0), std::invalid_argument);
}

}  // namespace
}  // namespace bushel
