// The contact stage's blocks of chunks per thread (ThreadShares), with made-up timings: equal
// until measured, then sized so that the threads finish together, whether the threads differ
// in speed or the chunks in cost, without swinging; small moves are not made.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <vector>

#include "bushel/integrate/thread_shares.hpp"

namespace bushel {
namespace {

// One step of a loop over chunks of cost `cost` (seconds each) by threads that run at
// `speed` (chunks of cost 1 per second): each thread's busy seconds; then the balance.
std::vector<double> step(ThreadShares& s, const std::vector<double>& cost, const std::vector<double>& speed) {
  s.split(cost.size(), static_cast<int>(speed.size()));
  std::vector<double> seconds(speed.size());
  for (std::size_t t = 0; t < speed.size(); ++t) {
    const auto b = s.bounds();
    seconds[t] = std::accumulate(cost.begin() + b[t], cost.begin() + b[t + 1], 0.0) / speed[t];
    s.add_busy(static_cast<int>(t), seconds[t]);
  }
  s.balance();
  return seconds;
}

// The time of the slowest thread over the mean, after `steps` steps.
double imbalance(ThreadShares& s, const std::vector<double>& cost, const std::vector<double>& speed, int steps) {
  std::vector<double> seconds;
  for (int k = 0; k < steps; ++k) seconds = step(s, cost, speed);
  const double mean = std::accumulate(seconds.begin(), seconds.end(), 0.0) / static_cast<double>(seconds.size());
  return *std::max_element(seconds.begin(), seconds.end()) / mean;
}

TEST(ThreadShares, EqualUntilMeasured) {
  ThreadShares s;
  EXPECT_TRUE(s.split(100, 2));
  EXPECT_EQ(std::vector<std::uint32_t>(s.bounds().begin(), s.bounds().end()), (std::vector<std::uint32_t>{0, 50, 100}));
  EXPECT_FALSE(s.split(100, 2));  // (the same blocks)
  EXPECT_TRUE(s.split(101, 2));   // (a new list: other chunks)
  EXPECT_TRUE(s.split(101, 3));
  EXPECT_EQ(std::vector<std::uint32_t>(s.bounds().begin(), s.bounds().end()),
            (std::vector<std::uint32_t>{0, 34, 67, 101}));
}

TEST(ThreadShares, HalfWayToTheMeasuredRates) {
  // Thread 0 takes 2 s for its 50 chunks, thread 1 1 s: rates 25 and 50 chunks/s, so
  // thread 0's share goes half-way from 1/2 to 1/3.
  ThreadShares s;
  s.split(100, 2);
  for (int k = 0; k < ThreadShares::balance_steps; ++k) {
    s.add_busy(0, 2.0 / ThreadShares::balance_steps);
    s.add_busy(1, 1.0 / ThreadShares::balance_steps);
    s.balance();
  }
  EXPECT_DOUBLE_EQ(s.shares()[0], 0.5 * (0.5 + 1.0 / 3.0));
  EXPECT_TRUE(s.split(100, 2));
  EXPECT_EQ(s.bounds()[1], 42u);
}

TEST(ThreadShares, ThreadsOfDifferentSpeedFinishTogether) {
  ThreadShares s;
  const std::vector<double> cost(400, 1.0);
  EXPECT_NEAR(imbalance(s, cost, {0.5, 1.0}, 1), 4.0 / 3.0, 1e-12);  // equal blocks first
  EXPECT_LT(imbalance(s, cost, {0.5, 1.0}, 12 * ThreadShares::balance_steps), 1.02);
  EXPECT_NEAR(s.shares()[0], 1.0 / 3.0, 0.01);
}

TEST(ThreadShares, CostlyChunksAtOneEndSettle) {
  // The first quarter of the chunks (elements along the floor, with their wall contacts)
  // costs 4 times the rest: equal blocks leave thread 1 idle most of the time.
  std::vector<double> cost(400, 1.0);
  std::fill(cost.begin(), cost.begin() + 100, 4.0);
  ThreadShares s;
  EXPECT_GT(imbalance(s, cost, {1.0, 1.0, 1.0}, 1), 1.5);
  EXPECT_LT(imbalance(s, cost, {1.0, 1.0, 1.0}, 20 * ThreadShares::balance_steps), 1.03);
  // and stays there: later balances move no boundary by more than a chunk or two
  const std::vector<std::uint32_t> settled(s.bounds().begin(), s.bounds().end());
  imbalance(s, cost, {1.0, 1.0, 1.0}, 10 * ThreadShares::balance_steps);
  for (std::size_t t = 0; t < settled.size(); ++t) EXPECT_NEAR(s.bounds()[t], settled[t], 2.0) << t;
}

TEST(ThreadShares, SmallMovesAreNotMadeAndANewTeamStartsEqual) {
  ThreadShares s;
  const std::vector<double> cost(1000, 1.0);
  imbalance(s, cost, {1.0, 1.004}, 4 * ThreadShares::balance_steps);  // (a move of 0.1 %)
  EXPECT_EQ(s.shares()[0], 0.5);
  imbalance(s, cost, {1.0, 2.0}, 4 * ThreadShares::balance_steps);
  EXPECT_LT(s.shares()[0], 0.4);
  s.split(1000, 1);
  s.split(1000, 2);
  EXPECT_EQ(s.shares()[0], 0.5);
}

}  // namespace
}  // namespace bushel
