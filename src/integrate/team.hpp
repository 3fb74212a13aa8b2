#pragma once
// The team size of the steps (thread_governor.hpp) with the engine's clock: only the time
// spent inside Simulation::step counts, so that a run's output between steps does not
// weigh on the choice.

#include <chrono>
#include <cstdint>
#include <optional>

#include "bushel/integrate/thread_governor.hpp"

namespace bushel::engine {

class Team {
 public:
  explicit Team(ThreadPolicy policy) : policy_(policy) {}

  /// Before a call's steps: sets OpenMP's thread count for them (the governor's, made on the
  /// first call, when OpenMP's default is known), remembering the caller's.
  void enter();
  /// Before each step: closes a window that has run its time and opens the next (a clock
  /// read per step only where the governor measures: some 25 ns against a step's 1 ms).
  void before_step() {
    if (!measuring_) return;
    const Clock::time_point now = Clock::now();
    seconds_ += std::chrono::duration<double>(now - mark_).count();
    mark_ = now;
    if (steps_ > 0 && seconds_ >= governor_->window().seconds) next_window();
    ++steps_;
  }
  /// After a call's steps: gives the caller its thread count back.
  void leave();
  ThreadStatus status() const;

 private:
  using Clock = std::chrono::steady_clock;
  void next_window();
  void apply(int threads) const;

  ThreadPolicy policy_;
  std::optional<ThreadGovernor> governor_;
  bool measuring_ = false;   ///< the governor chooses (adaptive, more than one thread)
  std::uint64_t steps_ = 0;  ///< steps of the window so far
  double seconds_ = 0.0;     ///< engine time of the window so far [s]
  Clock::time_point mark_;   ///< since when seconds_ is not yet counted
  int outer_ = 0;            ///< the caller's OpenMP thread count
};

}  // namespace bushel::engine
