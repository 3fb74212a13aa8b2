// The rolling sub-models on single contacts, against their equations (rolling_models.hpp):
// where bushel's EDEM-style CDT and LIGGGHTS's CDT agree and where they differ.

#include <gtest/gtest.h>

#include "bushel/contact/contact_model.hpp"
#include "bushel/contact/rolling_models.hpp"

namespace bushel {
namespace {

// Two spheres of radii 2 and 1 mm side by side along x, 10 um overlap.
RollingInput contact(const Vec3& omega_i, const Vec3& omega_j) {
  const double ri = 2e-3, rj = 1e-3, overlap = 1e-5;
  const double s_n = 1e5;  // [N/m]
  return {.normal = {1, 0, 0},
          .omega_i = omega_i,
          .omega_j = omega_j,
          .arm_i = ri - 0.5 * overlap,
          .arm_j = rj - 0.5 * overlap,
          .r_star = ri * rj / (ri + rj),
          .normal_force = 2.0 / 3.0 * s_n * overlap + 0.1,  // (elastic plus some damping)
          .normal_stiffness = s_n,
          .overlap = overlap,
          .mu_r = 0.05,
          .inertia_r = 0.0,
          .dt = 1e-6};
}

TEST(LiggghtsCdt, OpposesTheRelativeSpinWithTheEffectiveRadius) {
  const RollingInput in = contact({0, 0, 3}, {0, 0, -1});
  Vec3 unused;
  const RollingOutput out = LiggghtsCdtRolling::torque(in, unused);
  const double magnitude = in.mu_r * (2.0 / 3.0 * in.normal_stiffness * in.overlap) * in.r_star;
  EXPECT_NEAR(out.torque_i.z, -magnitude, 1e-15);
  EXPECT_NEAR(out.torque_j.z, magnitude, 1e-15);
  EXPECT_EQ(out.torque_i.x, 0.0);
  EXPECT_EQ(out.cdt_i, 0.0);
  EXPECT_EQ(out.cdt_j, 0.0);
}

TEST(LiggghtsCdt, LeavesTwistingAndEqualSpinsAlone) {
  Vec3 unused;
  // Spin about the normal is twisting, not rolling: the torque's normal part is removed.
  const RollingOutput twist = LiggghtsCdtRolling::torque(contact({4, 0, 0}, {0, 0, 0}), unused);
  EXPECT_NEAR(norm(twist.torque_i), 0.0, 1e-18);
  // Both bodies spinning alike (a pair carried round together): no relative spin, no torque,
  // where bushel's CDT resists each body's own spin.
  const RollingInput same = contact({0, 2, 0}, {0, 2, 0});
  EXPECT_EQ(norm(LiggghtsCdtRolling::torque(same, unused).torque_i), 0.0);
  const RollingOutput edem = CdtRolling::torque(same, unused);
  EXPECT_DOUBLE_EQ(edem.cdt_i, same.mu_r * same.normal_force * same.arm_i);
  EXPECT_DOUBLE_EQ(edem.cdt_j, same.mu_r * same.normal_force * same.arm_j);
}

TEST(RollingRegistry, KnowsEveryModelByName) {
  for (const char* name : {"cdt", "epsd", "liggghts_cdt", "none"}) EXPECT_EQ(name_of(rolling_model(name)), name);
  EXPECT_EQ(history_size(rolling_model("liggghts_cdt")), 3);
  EXPECT_EQ(history_size(rolling_model("epsd")), 6);
}

}  // namespace
}  // namespace bushel
