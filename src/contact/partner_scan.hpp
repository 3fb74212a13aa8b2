#pragma once
// The neighbour list's search (docs/engine.md, the neighbour list): every element's partners
// j > i within r_i + r_j + m_i + m_j, m the elements' margins, by a uniform cell grid.
//
// Most elements have the narrow margin, half the skin: they are found by a scan of the 27
// cells around each element in a grid of cells 2 r_max + skin wide, the hot path. The few
// elements with a wider margin (moving fast when the list was built) are left out of that
// grid; each of them scans the narrow elements' grid as far as its own reach, and a grid of
// the wide elements for its wide partners.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "bushel/core/vec3.hpp"

namespace bushel {

/// A build's scratch: the partners of each element, in one list per block of partner_block
/// elements (fewer allocations than one per element), and their counts; and the pairs that
/// wide elements found with lower narrow ones.
inline constexpr std::size_t partner_block = 256;
struct PartnerBlocks {
  std::vector<std::vector<std::uint32_t>> block;  ///< [block]: its elements' partners, in element order
  std::vector<std::uint32_t> count;               ///< [element]: its partners in its block's list
  std::vector<std::uint64_t> extra;               ///< more pairs, first << 32 | second, sorted
};

/// Partners of every element into `partners`: per element i, the partners j > i in its block's
/// list, sorted, and their count; the pairs (j, i), j < i, that wide elements i found with
/// narrow j in `partners.extra`, sorted. `margin` [m] per element, each at least skin / 2 (an
/// element with skin / 2 exactly is narrow).
void find_partners(std::span<const Vec3> position, std::span<const double> radius, std::span<const std::uint32_t> owner,
                   std::span<const double> margin, double skin, PartnerBlocks& partners);

}  // namespace bushel
