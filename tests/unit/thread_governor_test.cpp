// The thread governor's choices against made-up machines: a step takes `cost(threads)`
// seconds, and the governor must settle on the fastest team, follow a change of load, and
// spend little of a run measuring the slower team.
#include "bushel/integrate/thread_governor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <vector>

namespace bushel {
namespace {

using Cost = std::function<double(int threads)>;  // seconds per step [s]

// Runs the current window on `cost` as the engine would (steps until its time has passed);
// returns its steps and adds them to `steps` per team size.
double run_window(ThreadGovernor& g, const Cost& cost, std::map<int, double>& steps) {
  const ThreadGovernor::Window w = g.window();
  const double n = std::max(1.0, std::ceil(w.seconds / cost(w.threads)));
  steps[w.threads] += n;
  g.finished(static_cast<std::uint64_t>(n), n * cost(w.threads));
  return n * cost(w.threads);
}

// Runs the governor for `seconds` of engine time on `cost`; returns the steps run per team size.
std::map<int, double> run(ThreadGovernor& g, const Cost& cost, double seconds) {
  std::map<int, double> steps;
  for (double t = 0.0; t < seconds;) t += run_window(g, cost, steps);
  return steps;
}

Cost machine(std::map<int, double> per_step) {
  return [per_step](int threads) { return per_step.at(threads); };
}

TEST(ThreadGovernor, FixedNeverMeasures) {
  ThreadGovernor g(2, false);
  EXPECT_EQ(g.window().threads, 2);
  EXPECT_EQ(g.window().seconds, std::numeric_limits<double>::infinity());
  EXPECT_EQ(g.finished(1000, 1.0).threads, 2);
  EXPECT_EQ(g.status().describe(), "threads 2");
  // one thread allowed: nothing to choose
  ThreadGovernor one(1, true);
  EXPECT_FALSE(one.status().adaptive);
  EXPECT_EQ(one.window().threads, 1);
}

TEST(ThreadGovernor, KeepsAllThreadsOnFreeCores) {
  ThreadGovernor g(2, true);
  EXPECT_EQ(g.status().describe(), "threads 2 of 2 (measuring)");
  const auto steps = run(g, machine({{2, 1e-3}, {1, 1.8e-3}}), 600.0);
  EXPECT_EQ(g.status().threads, 2);
  EXPECT_NEAR(g.status().max_over_chosen, 1.0, 1e-12);
  EXPECT_EQ(g.status().describe(), "threads 2 of 2");
  // the trials at 1 thread cost under 1 % of the run's steps
  EXPECT_LT(steps.at(1) / steps.at(2), 0.01);
}

TEST(ThreadGovernor, DropsToOneThreadWhenACoreIsBusy) {
  ThreadGovernor g(2, true);
  const auto steps = run(g, machine({{2, 1.67e-3}, {1, 1e-3}}), 600.0);
  EXPECT_EQ(g.status().threads, 1);
  EXPECT_NEAR(g.status().max_over_chosen, 1.67, 1e-9);
  EXPECT_EQ(g.status().describe(), "threads 1 of 2 (2 were 1.67x slower)");
  // as fast as one thread but for the trials: at least 0.99 of its steps in the same time
  const double all = steps.at(1) + steps.at(2);
  EXPECT_GT(all / (600.0 / 1e-3), 0.99);
}

TEST(ThreadGovernor, PrefersMoreThreadsWithinFivePercent) {
  ThreadGovernor g(2, true);
  run(g, machine({{2, 1.00e-3}, {1, 0.97e-3}}), 10.0);
  EXPECT_EQ(g.status().threads, 2);
  ThreadGovernor h(2, true);
  run(h, machine({{2, 1.00e-3}, {1, 0.90e-3}}), 10.0);
  EXPECT_EQ(h.status().threads, 1);
}

TEST(ThreadGovernor, FollowsTheLoad) {
  // Free cores, then a busy one: the chosen team slows by more than a third, which starts a
  // trial at once; then free again: the next periodic trial (within first_interval, as the
  // choice changed) returns to both threads.
  double now = 0.0;
  bool busy = false;
  ThreadGovernor g(2, true);
  auto cost = [&](int threads) { return busy ? (threads == 2 ? 1.67e-3 : 1e-3) : (threads == 2 ? 1e-3 : 1.8e-3); };
  std::map<int, double> steps;
  auto advance = [&](double seconds) {
    for (const double end = now + seconds; now < end;) now += run_window(g, cost, steps);
  };
  advance(200.0);
  EXPECT_EQ(g.status().threads, 2);
  busy = true;
  advance(1.0);  // a check window and a trial
  EXPECT_EQ(g.status().threads, 1);
  busy = false;
  advance(ThreadGovernor::first_interval + 1.0);
  EXPECT_EQ(g.status().threads, 2);
}

TEST(ThreadGovernor, TriesHalvesOnManyCores) {
  // 8 threads with others busy: 4 is the fastest, and is the one kept.
  ThreadGovernor g(8, true);
  run(g, machine({{8, 2.0e-3}, {4, 1.0e-3}, {2, 1.5e-3}, {1, 2.6e-3}}), 30.0);
  EXPECT_EQ(g.status().threads, 4);
  EXPECT_EQ(g.status().max, 8);
  // an odd maximum still ends its candidates at 1
  ThreadGovernor h(3, true);
  run(h, machine({{3, 2.0e-3}, {1, 1.0e-3}}), 10.0);
  EXPECT_EQ(h.status().threads, 1);
}

TEST(ThreadGovernor, ATrialBeginsAndEndsWithTheChosenTeam) {
  // The first trial: 2 (the default), 1, 2. Once 1 is chosen: 1, 2, 1, so that a busy
  // machine pays for one window of the slow team per trial.
  ThreadGovernor g(2, true);
  EXPECT_EQ(g.window().seconds, ThreadGovernor::warm_up_seconds);
  std::vector<int> teams;
  for (const double seconds : {0.05, 0.5, 0.08, 0.5}) teams.push_back(g.finished(10, seconds).threads);
  EXPECT_EQ(teams, (std::vector<int>{2, 1, 2, 1}));
  EXPECT_EQ(g.status().threads, 1);
  EXPECT_EQ(g.window().seconds, ThreadGovernor::check_seconds);
  g.finished(31, ThreadGovernor::check_seconds);  // 8 ms a step, as in the trial
  EXPECT_EQ(g.window().threads, 1);
  EXPECT_EQ(g.window().seconds, ThreadGovernor::check_seconds);
  // a check window a third slower than the trial: a new trial at once, beginning with 1
  EXPECT_EQ(g.finished(10, 0.2).threads, 1);
  EXPECT_EQ(g.window().seconds, ThreadGovernor::probe_seconds);
  EXPECT_EQ(g.finished(10, 0.08).threads, 2);
  EXPECT_EQ(g.finished(10, 0.5).threads, 1);
}

}  // namespace
}  // namespace bushel
