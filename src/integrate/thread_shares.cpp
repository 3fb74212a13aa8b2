#include "bushel/integrate/thread_shares.hpp"

#include <algorithm>
#include <cmath>

namespace bushel {

bool ThreadShares::split(std::size_t n_chunks, int team) {
  const auto t_n = static_cast<std::size_t>(std::max(team, 1));
  if (share_.size() != t_n) {
    share_.assign(t_n, 1.0 / static_cast<double>(t_n));
    busy_.assign(t_n, 0.0);
    steps_ = 0;
  }
  std::vector<std::uint32_t>& bounds = next_;  // (kept: no allocation per step)
  bounds.assign(t_n + 1, 0);
  const auto n = static_cast<double>(n_chunks);
  double cumulative = 0.0;
  for (std::size_t t = 0; t + 1 < t_n; ++t) {
    cumulative += share_[t];
    bounds[t + 1] = static_cast<std::uint32_t>(std::clamp(std::round(cumulative * n), 0.0, n));
  }
  bounds[t_n] = static_cast<std::uint32_t>(n_chunks);
  if (bounds == bounds_) return false;
  bounds_.swap(bounds);
  return true;
}

void ThreadShares::balance() {
  if (++steps_ < balance_steps) return;
  const std::size_t t_n = share_.size();
  std::vector<double> rate(t_n, 0.0);
  double total = 0.0;
  for (std::size_t t = 0; t < t_n; ++t) {
    const double chunks = bounds_[t + 1] - bounds_[t];
    if (!(busy_[t] > 0.0) || chunks == 0.0) {
      rate[t] = -1.0;  // (nothing to go by)
    } else {
      rate[t] = chunks / busy_[t];
      total += rate[t];
    }
  }
  std::fill(busy_.begin(), busy_.end(), 0.0);
  steps_ = 0;
  if (std::any_of(rate.begin(), rate.end(), [](double r) { return r < 0.0; }) || !(total > 0.0)) return;
  std::vector<double> share(t_n);
  double moved = 0.0, old_cumulative = 0.0, new_cumulative = 0.0;
  for (std::size_t t = 0; t < t_n; ++t) {
    share[t] = 0.5 * (share_[t] + rate[t] / total);
    old_cumulative += share_[t], new_cumulative += share[t];
    moved = std::max(moved, std::abs(new_cumulative - old_cumulative));
  }
  if (moved >= least_move) share_ = std::move(share);
}

}  // namespace bushel
