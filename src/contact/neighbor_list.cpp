#include "bushel/contact/neighbor_list.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "bushel/core/parallel.hpp"
#include "bushel/io/binary_archive.hpp"
#include "partner_scan.hpp"

namespace bushel {
namespace {

std::uint64_t pair_key(std::uint32_t a, std::uint32_t b) {
  return a < b ? (std::uint64_t{a} << 32 | b) : (std::uint64_t{b} << 32 | a);
}

// The pairs of a search in element order, each element's partners from its block's list
// merged with the extra pairs it is first of: the pairs of element i are [start[i],
// start[i + 1]).
void flatten(const PartnerBlocks& partners, std::size_t n, std::vector<std::uint32_t>& start,
             std::vector<std::uint32_t>& first, std::vector<std::uint32_t>& second) {
  start.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) start[i + 1] = partners.count[i];
  for (const std::uint64_t e : partners.extra) ++start[(e >> 32) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  first.resize(start[n]);
  second.resize(start[n]);
  auto extra = partners.extra.begin();
  for (std::size_t b = 0; b < partners.block.size(); ++b) {
    const std::uint32_t* from = partners.block[b].data();  // the block's partners, in element order
    for (std::size_t i = b * partner_block; i < std::min(n, (b + 1) * partner_block); ++i) {
      const std::uint32_t* const from_end = from + partners.count[i];
      for (std::size_t p = start[i]; p < start[i + 1]; ++p) {
        const bool take_extra = extra != partners.extra.end() && (*extra >> 32) == i &&
                                (from == from_end || static_cast<std::uint32_t>(*extra) < *from);
        const std::uint32_t j = take_extra ? static_cast<std::uint32_t>(*extra++) : *from++;
        first[p] = static_cast<std::uint32_t>(i);
        second[p] = j;
      }
    }
  }
}

}  // namespace

NeighborList::NeighborList(double skin, int history_size) : skin_(skin), history_size_(history_size) {
  if (!(skin > 0.0)) throw std::invalid_argument("NeighborList: skin must be positive");
  if (history_size < 0) throw std::invalid_argument("NeighborList: negative history size");
}

void NeighborList::set_skin(double skin) {
  if (!(skin > 0.0)) throw std::invalid_argument("NeighborList: skin must be positive");
  skin_ = skin;
}

void NeighborList::build(std::span<const Vec3> position, std::span<const double> radius,
                         std::span<const std::uint32_t> owner, std::span<const std::uint32_t> stable_id) {
  const std::vector<double> margin(position.size(), 0.5 * skin_);
  build(position, radius, owner, stable_id, margin);
}

void NeighborList::build(std::span<const Vec3> position, std::span<const double> radius,
                         std::span<const std::uint32_t> owner, std::span<const std::uint32_t> stable_id,
                         std::span<const double> margin) {
  const std::size_t n = position.size();
  if (margin.size() != n ||
      !std::all_of(margin.begin(), margin.end(), [&](double m) { return m >= 0.5 * skin_ && std::isfinite(m); })) {
    throw std::invalid_argument("NeighborList: a finite margin of at least half the skin per element expected");
  }
  std::vector<std::uint32_t> start, first, second;
  {
    PartnerBlocks partners;  // (scratch: freed before the histories are made)
    find_partners(position, radius, owner, margin, skin_, partners);
    flatten(partners, n, start, first, second);
  }
  const std::size_t n_pairs = first.size();
  margin_.assign(margin.begin(), margin.end());
  std::vector<double> history(n_pairs * static_cast<std::size_t>(history_size_), 0.0);
  if (history_size_ > 0 && !first_.empty()) carry_history(stable_id, start, second, history);
  ids_at_build_.assign(stable_id.begin(), stable_id.end());
  std::vector<std::uint64_t>().swap(loaded_keys_);
  first_ = std::move(first);
  second_ = std::move(second);
  history_ = std::move(history);
  first_start_ = std::move(start);
  reference_.assign(position.begin(), position.end());
  ++builds_;
}

std::uint64_t NeighborList::old_key(std::size_t o) const {
  return loaded_keys_.empty() ? pair_key(ids_at_build_[first_[o]], ids_at_build_[second_[o]]) : loaded_keys_[o];
}

void NeighborList::carry_history(std::span<const std::uint32_t> stable_id, std::span<const std::uint32_t> start,
                                 std::span<const std::uint32_t> second, std::span<double> history) const {
  // The elements keep their indices from build to build unless something renumbered them (a
  // spatial sort, bodies added or removed), and both lists are sorted by (i, j): then each
  // element's old and new partners are merged in one pass (also after a restart: a checkpoint
  // keeps the ids). Otherwise (and after loading a list of version 1 or 2, which kept keys
  // instead of ids) each pair is looked up by its stable identity. Both carry the same values
  // over.
  const auto h = static_cast<std::size_t>(history_size_);
  const auto sn = static_cast<std::ptrdiff_t>(stable_id.size());
  if (std::equal(stable_id.begin(), stable_id.end(), ids_at_build_.begin(), ids_at_build_.end())) {
#pragma omp parallel for schedule(static) if (sn > parallel_threshold)
    for (std::ptrdiff_t si = 0; si < sn; ++si) {
      const auto i = static_cast<std::size_t>(si);
      std::size_t o = first_start_[i];
      const std::size_t o_end = first_start_[i + 1];
      for (std::size_t p = start[i]; p < start[i + 1] && o < o_end; ++p) {
        while (o < o_end && second_[o] < second[p]) ++o;
        if (o < o_end && second_[o] == second[p]) std::copy_n(history_.data() + o * h, h, history.data() + p * h);
      }
    }
    return;
  }
  // Only the old pairs whose history is not zero need carrying over: those in contact (the
  // others' was zeroed when their contact ended), about half the list in a packed bed and few
  // in a flow. Their keys with their slots, sorted in one contiguous array, make each new
  // pair's lookup a binary search in a compact array.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> carried;
  for (std::size_t o = 0; o < first_.size(); ++o) {
    const double* old = history_.data() + o * h;
    if (std::any_of(old, old + h, [](double v) { return v != 0.0; }))
      carried.emplace_back(old_key(o), static_cast<std::uint32_t>(o));
  }
  if (carried.empty()) return;
  std::sort(carried.begin(), carried.end());
#pragma omp parallel for schedule(static) if (sn > parallel_threshold)
  for (std::ptrdiff_t si = 0; si < sn; ++si) {
    const auto i = static_cast<std::size_t>(si);
    for (std::size_t p = start[i]; p < start[i + 1]; ++p) {
      const std::uint64_t key = pair_key(stable_id[i], stable_id[second[p]]);
      const auto it = std::lower_bound(carried.begin(), carried.end(), std::pair{key, std::uint32_t{0}});
      if (it != carried.end() && it->first == key) {
        std::copy_n(history_.data() + std::size_t{it->second} * h, h, history.data() + p * h);
      }
    }
  }
}

void NeighborList::save(io::BinaryWriter& out) const {
  out.put(skin_);
  out.put(history_size_);
  out.put(static_cast<std::uint64_t>(builds_));
  out.put(reference_);
  out.put(margin_);
  out.put(first_);
  out.put(second_);
  out.put(history_);
  out.put(first_start_);
  out.put(ids_at_build_);
}

void NeighborList::load(io::BinaryReader& in, std::uint32_t version) {
  in.get(skin_);
  in.get(history_size_);
  builds_ = static_cast<std::size_t>(in.get<std::uint64_t>());
  in.get(reference_);
  if (version >= 2) {
    in.get(margin_);
  } else {
    margin_.assign(reference_.size(), 0.5 * skin_);
  }
  if (margin_.size() != reference_.size()) in.damaged("a neighbour list with margins for another number of elements");
  if (!std::all_of(margin_.begin(), margin_.end(), [](double m) { return m >= 0.0 && std::isfinite(m); })) {
    in.damaged("a neighbour list margin that is negative or not finite");
  }
  in.get(first_);
  in.get(second_);
  loaded_keys_.clear();
  if (version <= 2) in.get(loaded_keys_);  // (earlier formats kept each pair's stable identity)
  in.get(history_);
  in.get(first_start_);
  if (version <= 3) {  // (earlier formats kept an index of the pairs by second element)
    std::vector<std::uint32_t> second_start, as_second;
    in.get(second_start), in.get(as_second);
  }
  ids_at_build_.clear();
  if (version >= 3) in.get(ids_at_build_);
  const bool keyed = version >= 3 ? ids_at_build_.size() == reference_.size() : loaded_keys_.size() == first_.size();
  const bool built = !first_start_.empty();  // (a list saved before its first build is empty)
  const bool histories = history_.size() == first_.size() * static_cast<std::size_t>(std::max(history_size_, 0));
  if (!histories ||
      (built && (!keyed || first_start_.size() != reference_.size() + 1 || second_.size() != first_.size()))) {
    in.damaged("a neighbour list whose arrays do not fit together");
  }
  const auto below = [](const std::vector<std::uint32_t>& v, std::size_t n) {
    return std::all_of(v.begin(), v.end(), [n](std::uint32_t x) { return x < n; });
  };
  const auto ranges = [&](const std::vector<std::uint32_t>& start) {  // CSR offsets: rising, ending at the pairs
    return start.empty() ||
           (std::is_sorted(start.begin(), start.end()) && start.front() == 0 && start.back() == first_.size());
  };
  if (!below(first_, reference_.size()) || !below(second_, reference_.size()) || !ranges(first_start_)) {
    in.damaged("a neighbour list with an element or pair index out of range");
  }
}

}  // namespace bushel
