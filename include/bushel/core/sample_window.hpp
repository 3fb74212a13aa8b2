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
};

}  // namespace bushel
