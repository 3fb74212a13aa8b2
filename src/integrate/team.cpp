#include "team.hpp"

#ifdef BUSHEL_HAVE_OPENMP
#include <omp.h>
#endif

namespace bushel::engine {
namespace {

int openmp_threads() {
#ifdef BUSHEL_HAVE_OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

}  // namespace

void Team::apply(int threads) const {
#ifdef BUSHEL_HAVE_OPENMP
  // Without a policy the caller's setting stands (tests and tools set it themselves).
  if (policy_.max > 0 || policy_.adaptive) omp_set_num_threads(threads);
#else
  (void)threads;
#endif
}

void Team::enter() {
  outer_ = openmp_threads();
  if (!governor_) {
    governor_.emplace(policy_.max > 0 ? policy_.max : outer_, policy_.adaptive);
    measuring_ = governor_->status().adaptive;
  }
  apply(governor_->window().threads);
  mark_ = Clock::now();
}

void Team::next_window() {
  apply(governor_->finished(steps_, seconds_).threads);
  steps_ = 0;
  seconds_ = 0.0;
}

void Team::leave() {
  if (measuring_) seconds_ += std::chrono::duration<double>(Clock::now() - mark_).count();
  apply(outer_);
}

ThreadStatus Team::status() const {
  if (governor_) return governor_->status();
  const int max = policy_.max > 0 ? policy_.max : openmp_threads();
  return {.threads = max, .max = max, .adaptive = policy_.adaptive && max > 1};
}

}  // namespace bushel::engine
