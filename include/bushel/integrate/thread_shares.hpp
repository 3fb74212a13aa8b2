#pragma once
// How the contact stage's chunks are shared among its threads (docs/engine.md, "Threads on a
// busy machine"). Each thread takes a contiguous block of the chunks, in order; the blocks are
// sized by what each thread was measured to get through, so that the threads reach the end of
// the loop together although chunks differ in cost (a run of elements along the walls, with
// their part contacts, costs more than one inside the bed) and cores differ in speed (one that
// the machine gives to another program for a while). Which thread computes a chunk changes no
// bit of the results, only where its second-element shares are summed.

#include <cstdint>
#include <span>
#include <vector>

namespace bushel {

class ThreadShares {
 public:
  /// Steps between two balances, and the least move of a block boundary, as a fraction of
  /// the chunks, that is made (smaller ones are not worth finding the direct sums again).
  static constexpr int balance_steps = 32;
  static constexpr double least_move = 0.005;

  /// Splits n_chunks among `team` threads by their shares (equal until measured, and again
  /// when the team size changes); returns whether the blocks differ from the last split.
  bool split(std::size_t n_chunks, int team);
  /// Block boundaries of the last split: thread t takes chunks [bounds()[t], bounds()[t + 1]).
  std::span<const std::uint32_t> bounds() const { return bounds_; }
  /// Each thread's fraction of the chunks (summing to 1).
  std::span<const double> shares() const { return share_; }
  /// Thread t spent `seconds` on its block this step. Threads call it at once, each for its own t.
  void add_busy(int t, double seconds) { busy_[static_cast<std::size_t>(t)] += seconds; }
  /// After each step: every balance_steps steps, moves each share half-way towards the
  /// thread's rate (chunks per busy second) over the sum of the rates, so that a mix of costly
  /// and cheap chunks settles instead of swinging.
  void balance();

 private:
  std::vector<double> share_;
  std::vector<std::uint32_t> bounds_, next_;  // next_: the split being made
  std::vector<double> busy_;                  // seconds per thread since the last balance
  int steps_ = 0;
};

}  // namespace bushel
