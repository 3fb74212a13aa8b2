#pragma once
// The thread count of a run, chosen from what the machine gives while it runs
// (docs/engine.md, "Threads on a busy machine").
//
// Each step has several parallel loops, each ending in a barrier. When another program holds
// a core, a thread that waits at a barrier for one the scheduler set aside loses more than
// the second core gains: 2 threads then run at about 0.5 of 1 thread (bench/results/
// wait-policy.md). The governor times windows of steps at each candidate team size (all the
// threads, half, ..., 1), keeps the fastest, runs with it, and measures again now and then,
// and at once when the chosen team slows down by more than a third. A trial begins and ends
// with the chosen team, whose two windows are averaged, so that a machine that changes during
// the trial favours no team size and the slower teams get one window each. The results are the
// same bits at any team size, so the choice changes only the speed.

#include <cstdint>
#include <string>
#include <vector>

namespace bushel {

/// How many threads a simulation's parallel loops use.
struct ThreadPolicy {
  int max = 0;            ///< most threads; 0 = OpenMP's default (OMP_NUM_THREADS or the cores)
  bool adaptive = false;  ///< false: always max; true: the fastest of max, max/2, ..., 1 as measured
};

/// What the governor is doing, for the progress line.
struct ThreadStatus {
  int threads = 1;        ///< team size of the steps now
  int max = 1;            ///< most threads allowed
  bool adaptive = false;  ///< chosen by measuring
  /// Time per step with all max threads over the time with `threads`, at the last measurement
  /// [-]: above 1 when fewer threads were faster (a busy core); 0 before any measurement.
  double max_over_chosen = 0.0;
  std::string describe() const;  ///< e.g. "threads 1 of 2 (2 were 1.62x slower)"
};

/// The decision logic, apart from any clock, so that it can be tested with made-up timings.
/// A window is a stretch of steps with one team size, ended at the first step boundary after
/// its time; the caller then reports how many steps ran in how much engine time and gets the
/// next window.
class ThreadGovernor {
 public:
  struct Window {
    int threads = 1;
    double seconds = 0.0;  ///< engine time to run [s]; infinite: never ends
  };

  /// `max` threads at most (>= 1); adaptive false: one endless window of max threads.
  ThreadGovernor(int max, bool adaptive);

  const Window& window() const { return window_; }
  /// The current window ran `steps` (>= 1) steps in `seconds` [s] of engine time; returns
  /// the next window.
  const Window& finished(std::uint64_t steps, double seconds);
  ThreadStatus status() const;

  // Tuning, in wall seconds [s], chosen so that measuring costs about 1 % of a run.
  static constexpr double warm_up_seconds = 0.05;  ///< first steps, not measured (lists, caches)
  static constexpr double probe_seconds = 0.08;    ///< one candidate's trial window
  static constexpr double check_seconds = 0.25;    ///< a window of the chosen team between trials
  static constexpr double first_interval = 3.0;    ///< between trials, doubled while the choice holds
  static constexpr double last_interval = 48.0;    ///< the longest time between trials
  static constexpr double slower_by = 4.0 / 3.0;   ///< a chosen team this much slower: measure again
  static constexpr double fewer_gain = 1.05;       ///< fewer threads are kept only if this much faster

 private:
  enum class Phase { warm_up, probe, run };
  void start_probe();
  void choose();

  int max_;
  bool adaptive_;
  Phase phase_ = Phase::warm_up;
  Window window_;
  std::vector<int> candidates_;  ///< team sizes: max, max/2, ..., 1
  std::vector<int> order_;       ///< this trial's windows: chosen, the others, chosen
  std::vector<double> trial_;    ///< [window of order_]: seconds per step measured [s]
  std::size_t next_ = 0;         ///< window of order_ being run
  int chosen_ = 1;
  double chosen_rate_ = 0.0;  ///< seconds per step of the chosen team in its trial [s]
  double max_over_chosen_ = 0.0;
  double interval_ = first_interval;  ///< engine seconds between trials [s]
  double since_trial_ = 0.0;          ///< engine seconds run since the last trial [s]
};

}  // namespace bushel
