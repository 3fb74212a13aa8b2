#include "bushel/integrate/thread_governor.hpp"

#include <algorithm>
#include <limits>
#include <utility>

#include <fmt/format.h>

namespace bushel {

std::string ThreadStatus::describe() const {
  if (!adaptive) return fmt::format("threads {}", threads);
  if (max_over_chosen <= 0.0) return fmt::format("threads {} of {} (measuring)", threads, max);
  if (threads == max) return fmt::format("threads {} of {}", threads, max);
  return fmt::format("threads {} of {} ({} were {:.2f}x slower)", threads, max, max, max_over_chosen);
}

ThreadGovernor::ThreadGovernor(int max, bool adaptive) : max_(std::max(1, max)), adaptive_(adaptive && max_ > 1) {
  chosen_ = max_;
  if (!adaptive_) {
    window_ = {max_, std::numeric_limits<double>::infinity()};
    return;
  }
  for (int t = max_; t >= 1; t /= 2) candidates_.push_back(t);
  if (candidates_.back() != 1) candidates_.push_back(1);
  window_ = {max_, warm_up_seconds};
}

void ThreadGovernor::start_probe() {
  phase_ = Phase::probe;
  order_ = {chosen_};
  for (const int t : candidates_) {
    if (t != chosen_) order_.push_back(t);
  }
  order_.push_back(chosen_);
  trial_.assign(order_.size(), 0.0);
  next_ = 0;
  window_ = {order_[0], probe_seconds};
}

void ThreadGovernor::choose() {
  // seconds per step of each team in this trial; the chosen team's two windows averaged
  std::vector<std::pair<int, double>> measured;
  for (std::size_t k = 1; k + 1 < order_.size(); ++k) measured.emplace_back(order_[k], trial_[k]);
  measured.emplace_back(chosen_, 0.5 * (trial_.front() + trial_.back()));
  std::sort(measured.begin(), measured.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  double fastest = measured[0].second;
  for (const auto& m : measured) fastest = std::min(fastest, m.second);
  std::size_t pick = 0;  // the most threads within fewer_gain of the fastest
  while (measured[pick].second > fewer_gain * fastest) ++pick;
  interval_ = measured[pick].first == chosen_ ? std::min(2.0 * interval_, last_interval) : first_interval;
  chosen_ = measured[pick].first;
  chosen_rate_ = measured[pick].second;
  max_over_chosen_ = measured[0].second / chosen_rate_;
  since_trial_ = 0.0;
  phase_ = Phase::run;
  window_ = {chosen_, check_seconds};
}

const ThreadGovernor::Window& ThreadGovernor::finished(std::uint64_t steps, double seconds) {
  if (!adaptive_) return window_;
  const double per_step = seconds / static_cast<double>(std::max<std::uint64_t>(1, steps));
  switch (phase_) {
    case Phase::warm_up:
      start_probe();
      break;
    case Phase::probe:
      trial_[next_++] = per_step;
      if (next_ == order_.size()) {
        choose();
      } else {
        window_ = {order_[next_], probe_seconds};
      }
      break;
    case Phase::run:
      since_trial_ += seconds;
      if (per_step > slower_by * chosen_rate_) {
        interval_ = first_interval;
        start_probe();
      } else if (since_trial_ >= interval_) {
        start_probe();
      } else {
        window_ = {chosen_, check_seconds};
      }
      break;
  }
  return window_;
}

ThreadStatus ThreadGovernor::status() const {
  return {.threads = max_over_chosen_ > 0.0 || !adaptive_ ? chosen_ : window_.threads,
          .max = max_,
          .adaptive = adaptive_,
          .max_over_chosen = max_over_chosen_};
}

}  // namespace bushel
