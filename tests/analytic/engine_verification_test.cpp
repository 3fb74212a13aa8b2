// The checks of `bushel verify` (docs/physics.md section 7) in their quick form; the tolerances
// are stated with each check in src/experiments/verification.cpp.
#include <gtest/gtest.h>

#include "bushel/experiments/verification.hpp"

namespace bushel::verification {
namespace {

void expect_all_pass(const std::vector<CheckResult>& results) {
  ASSERT_FALSE(results.empty());
  for (const auto& r : results) {
    EXPECT_TRUE(r.pass) << r.check << ": expected " << r.expected << ", measured " << r.measured << " (error "
                        << r.error() << ", tolerance " << r.tolerance << ")";
  }
}

const Options quick{true};

TEST(EngineVerification, Restitution) { expect_all_pass(restitution(quick)); }
TEST(EngineVerification, HertzContactTime) { expect_all_pass(hertz_contact_time(quick)); }
TEST(EngineVerification, EnergyConservation) { expect_all_pass(energy_conservation(quick)); }
TEST(EngineVerification, ObliqueImpact) { expect_all_pass(oblique_impact(quick)); }
TEST(EngineVerification, Incline) { expect_all_pass(incline(quick)); }
TEST(EngineVerification, RollingFriction) { expect_all_pass(rolling_friction(quick)); }
TEST(EngineVerification, ClumpFreeRotation) { expect_all_pass(clump_free_rotation(quick)); }
TEST(EngineVerification, AtRestStaysAtRest) { expect_all_pass(rest(quick)); }
TEST(GeometryVerification, MeshContactsMatchThePlane) { expect_all_pass(mesh_contact(quick)); }
TEST(GeometryVerification, GateTurnsExactly) { expect_all_pass(gate_turn(quick)); }
TEST(GeometryVerification, ServoLidHoldsPressure) { expect_all_pass(servo_hold(quick)); }

}  // namespace
}  // namespace bushel::verification
