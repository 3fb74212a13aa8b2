#pragma once
// Samples (time, value) over a trailing time window: one sample at or before the window's
// start is kept, so that the samples always span the whole window once it has passed (a flow
// rate over the last 50 ms, whether a value has been stable for 50 ms).

#include <cstddef>
#include <vector>

namespace bushel {

struct SampleWindow {
  std::vector<double> time;   ///< [s], ascending
  std::vector<double> value;  ///< the samples' values

  /// Adds a sample at t [s] and drops those older than needed for a window of `window` [s].
  void add(double t, double v, double window) {
    time.push_back(t);
    value.push_back(v);
    std::size_t drop = 0;
    while (time.size() - drop > 2 && time[drop + 1] <= t - window) ++drop;
    time.erase(time.begin(), time.begin() + static_cast<std::ptrdiff_t>(drop));
    value.erase(value.begin(), value.begin() + static_cast<std::ptrdiff_t>(drop));
  }

  /// The mean rate of change over the samples kept [value/s]: 0 until two times differ.
  [[nodiscard]] double slope() const {
    const double span = time.empty() ? 0.0 : time.back() - time.front();
    return span > 0.0 ? (value.back() - value.front()) / span : 0.0;
  }
};

}  // namespace bushel
