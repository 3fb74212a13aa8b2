// Same input, same result, whatever the thread count (no loop races: each writes only its own
// slots and sums in a fixed order, so a fixed scene's final state hashes the same): a pour of
// clumps and spheres large enough that every parallel loop really runs on several threads,
// hashed bit for bit at 1 and 2 threads.
#include <gtest/gtest.h>

#include <cstring>

#include "bushel/core/input_error.hpp"
#include "bushel/experiments/pour_scene.hpp"
#include "bushel/io/binary_archive.hpp"

#ifdef BUSHEL_HAVE_OPENMP
#include <omp.h>
#endif

namespace bushel {
namespace {

std::uint64_t fnv1a(std::uint64_t h, const void* data, std::size_t n) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  return h;
}

PourSpec bed_spec() {
  PourSpec spec;
  spec.count = 1200;  // 6000 sphere elements: above the parallel threshold
  spec.particle = "large_5s";
  spec.solid_fraction = 0.35;
  spec.initial_speed = 0.5;  // collisions from the first steps
  return spec;
}

// The state after `steps` steps, hashed. An adaptive policy's run goes on, 10 steps at a time,
// until its first trial has run (it is timed in wall seconds, so on a slow or shared core it
// takes more steps), and `ran` gets the steps taken.
std::uint64_t run_and_hash(int threads, std::uint64_t steps, ThreadPolicy policy = {}, std::uint64_t* ran = nullptr) {
#ifdef BUSHEL_HAVE_OPENMP
  omp_set_num_threads(threads);
#else
  (void)threads;
#endif
  PourSpec spec = bed_spec();
  spec.threads = policy;
  PourScene scene = make_pour_scene(spec);
  std::size_t contacts_seen = 0;  // summed over sampled steps: the run must really collide
  const auto trial_pending = [&] { return policy.adaptive && scene.simulation.threads().max_over_chosen == 0.0; };
  std::uint64_t k = 0;
  for (; k < steps || (trial_pending() && k < 200 * steps); k += 10) {
    scene.simulation.step(10);
    contacts_seen += scene.simulation.contacts();
  }
  if (ran != nullptr) *ran = k;
  const auto& p = scene.simulation.particles();
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t b = 0; b < p.bodies(); ++b) {
    // Hash in stable-id order, so the check does not depend on the sort order either.
    h = fnv1a(h, &p.body_id[b], sizeof(std::uint32_t));
    h = fnv1a(h, &p.position[b], sizeof(Vec3));
    h = fnv1a(h, &p.velocity[b], sizeof(Vec3));
    h = fnv1a(h, &p.orientation[b], sizeof(Quat));
    h = fnv1a(h, &p.angular_velocity[b], sizeof(Vec3));
  }
  // and the diagnostics summed across threads: the unbalanced force's contact force sums
  const double unbalanced = scene.simulation.unbalanced_force_ratio();
  EXPECT_GT(unbalanced, 0.0);
  h = fnv1a(h, &unbalanced, sizeof(double));
  EXPECT_GT(contacts_seen, 300u);
  EXPECT_GT(scene.simulation.neighbors().builds(), 10u);
  if (policy.adaptive) {  // a trial ran: steps at 2 threads, then at 1, then at 2 again
    EXPECT_GT(scene.simulation.threads().max_over_chosen, 0.0) << scene.simulation.threads().describe();
  }
  return h;
}

TEST(Determinism, SameStateAtOneAndTwoThreads) {
  const std::uint64_t steps = 1500;  // enough for many contacts, rebuilds and a spatial sort
  const std::uint64_t one = run_and_hash(1, steps);
  const std::uint64_t two = run_and_hash(2, steps);
  EXPECT_EQ(one, two);
  EXPECT_EQ(run_and_hash(2, steps), two);  // and the same again
}

TEST(Determinism, SameStateWhenTheTeamChangesMidRun) {
  // The thread governor switches between 2 and 1 threads between steps while it measures
  // (thread_governor.hpp): the steps come out the same bits as on a fixed team.
  std::uint64_t steps = 0;
  const std::uint64_t adaptive = run_and_hash(1, 1500, {.max = 2, .adaptive = true}, &steps);
  EXPECT_EQ(adaptive, run_and_hash(1, steps));
}

TEST(Determinism, TheUnbalancedForceComesBackFromASavedState) {
  // The contact force sums are in the state's section engine.diagnostics: a simulation built
  // again reads the same ratio to the bit before it takes a step, and without that section
  // (a default) it still loads, with the ratio unknown until the next step.
  PourScene a = make_pour_scene(bed_spec());
  a.simulation.step(300);
  io::BinaryWriter out;
  a.simulation.save_state(out);
  const std::string bytes = out.bytes();
  PourScene b = make_pour_scene(bed_spec());
  io::BinaryReader in(bytes, "state");
  b.simulation.load_state(io::SectionTable(in));
  EXPECT_TRUE(in.done());
  EXPECT_EQ(b.simulation.unbalanced_force_ratio(), a.simulation.unbalanced_force_ratio());
  EXPECT_GT(a.simulation.unbalanced_force_ratio(), 0.0);

  const std::string without = bytes.substr(0, bytes.find(std::string("engine.diagnostics")) - 8);
  PourScene c = make_pour_scene(bed_spec());
  io::BinaryReader in_c(without, "state");
  c.simulation.load_state(io::SectionTable(in_c));
  EXPECT_EQ(c.simulation.steps(), a.simulation.steps());
  c.simulation.step(1);
  b.simulation.step(1);
  EXPECT_EQ(c.simulation.particles().position, b.simulation.particles().position);
}

TEST(Determinism, AStateOfAnotherRollingModelIsRefused) {
  // Its contacts' histories have another length (cdt keeps 3 values a pair, epsd 6): read
  // with the other model's stride they would be read out of bounds.
  PourScene a = make_pour_scene(bed_spec());
  a.simulation.step(20);
  io::BinaryWriter out;
  a.simulation.save_state(out);
  PourSpec other = bed_spec();
  other.rolling = "epsd";
  PourScene b = make_pour_scene(other);
  io::BinaryReader in(out.bytes(), "state");
  try {
    b.simulation.load_state(io::SectionTable(in));
    FAIL() << "loaded a state of another rolling model";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rolling model"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace bushel
