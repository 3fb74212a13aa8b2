#pragma once
// Broad phase (docs/physics.md section 5, docs/engine.md): a uniform cell grid and a Verlet
// half list of sphere element pairs within r_i + r_j + m_i + m_j, m_i each element's margin
// (half the skin, or wider for a fast element), rebuilt only when some element has moved past
// its margin since the last build. Elements of the same body never pair.
//
// Each pair owns `history_size` values of contact history (tangential displacement, rolling
// spring). They are keyed by the pair's stable identity (the two elements' stable ids), so
// a rebuild -- or a spatial sort that renumbers everything -- carries them over.

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "bushel/core/vec3.hpp"
#include "bushel/io/archive_fwd.hpp"

namespace bushel {

class NeighborList {
 public:
  /// `skin` [m] > 0; `history_size` values of history per pair.
  NeighborList(double skin, int history_size);

  /// Builds the pair list from element positions, radii, owners and stable ids, every element
  /// with the margin skin / 2; keeps the history of pairs that were in the previous list (by
  /// stable id) and zeroes new ones.
  void build(std::span<const Vec3> position, std::span<const double> radius, std::span<const std::uint32_t> owner,
             std::span<const std::uint32_t> stable_id);
  /// The same with a margin per element [m], each at least skin / 2: pairs within r_i + r_j +
  /// m_i + m_j are listed, and the list holds while every element stays within its margin of
  /// where it was (docs/engine.md, margins per element).
  void build(std::span<const Vec3> position, std::span<const double> radius, std::span<const std::uint32_t> owner,
             std::span<const std::uint32_t> stable_id, std::span<const double> margin);

  /// True when the list was never built, or some element has moved past its margin: `excess`
  /// is the largest of excess2 over the elements.
  bool needs_rebuild(double excess) const { return builds_ == 0 || excess > 0.0; }
  /// An element's squared displacement since the build less its squared margin [m2]: positive
  /// once it has moved past the margin; infinite for an element that was not in the build.
  double excess2(std::size_t element, double displacement2) const {
    return element < margin_.size() ? displacement2 - margin_[element] * margin_[element]
                                    : std::numeric_limits<double>::infinity();
  }
  /// An element's margin at the last build [m] (skin / 2 for one that was not in it).
  double margin(std::size_t element) const { return element < margin_.size() ? margin_[element] : 0.5 * skin_; }
  /// Squared distance of an element from where it was at the last build [m2]; infinite for an
  /// element that was not in it.
  double displacement2(std::size_t element, const Vec3& position) const {
    return element < reference_.size() ? norm2(position - reference_[element])
                                       : std::numeric_limits<double>::infinity();
  }

  std::size_t pairs() const { return first_.size(); }
  std::uint32_t first(std::size_t p) const { return first_[p]; }
  std::uint32_t second(std::size_t p) const { return second_[p]; }
  /// All first and second elements, and all history, for hot loops.
  std::span<const std::uint32_t> firsts() const { return first_; }
  std::span<const std::uint32_t> seconds() const { return second_; }
  std::span<double> all_history() { return history_; }
  /// History values of pair p (history_size doubles).
  double* history(std::size_t p) { return history_.data() + p * static_cast<std::size_t>(history_size_); }
  int history_size() const { return history_size_; }
  double skin() const { return skin_; }
  /// Sets the skin [m] > 0 that the next build uses (the current list keeps its own until then:
  /// call it just before build).
  void set_skin(double skin);
  std::size_t builds() const { return builds_; }

  /// Pairs are stored grouped by their first element: those of element i are the
  /// contiguous indices [begin_of(i), begin_of(i + 1)), so one thread can sum their forces on
  /// i without sharing it.
  std::size_t begin_of(std::size_t element) const { return first_start_[element]; }

  /// The whole list, for a checkpoint; `load` restores it exactly (throws InputError on a
  /// truncated archive).
  void save(io::BinaryWriter& out) const;
  /// `version` 1: a list without margins (each element's is half the skin); 2: with them;
  /// 3: with the elements' ids at the build instead of each pair's stable identity; 4: without
  /// an index of the pairs by second element (which earlier versions kept).
  void load(io::BinaryReader& in, std::uint32_t version);

 private:
  /// The old list's history of each new pair (given by its first elements' ranges `start` and
  /// its second elements, over elements with ids `stable_id`) into `history`.
  void carry_history(std::span<const std::uint32_t> stable_id, std::span<const std::uint32_t> start,
                     std::span<const std::uint32_t> second, std::span<double> history) const;
  /// The stable identity of old pair o: min id << 32 | max id.
  std::uint64_t old_key(std::size_t o) const;

  double skin_;
  int history_size_;
  std::size_t builds_ = 0;
  std::vector<Vec3> reference_;  // positions at the last build
  std::vector<double> margin_;   // each element's margin at the last build [m]
  std::vector<std::uint32_t> first_, second_;
  std::vector<double> history_;
  std::vector<std::uint32_t> first_start_;   // CSR over first elements
  std::vector<std::uint32_t> ids_at_build_;  // the elements' stable ids at the last build
  std::vector<std::uint64_t> loaded_keys_;   // each pair's stable identity, from a checkpoint of version 1 or 2
                                             // (which did not save ids_at_build_), until the next build
};

}  // namespace bushel
