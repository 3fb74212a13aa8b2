// The gather stage: the contact stage's sums onto bodies and parts, in a fixed order (the same
// bits for any thread count).

#include <algorithm>

#include "bushel/core/parallel.hpp"
#include "stages.hpp"

namespace bushel::engine {

void sum_part_reactions(PartCandidates& pc, std::span<Part> parts, StepDiagnostics& d) {
  // Fixed blocks of candidates, summed in order: the same sums for any thread count, without
  // a serial pass over every candidate.
  const std::size_t n_w = parts.size(), n_c = pc.part.size();
  d.part_force_sum = 0.0;
  d.part_contacts = 0;
  if (n_w == 0) return;
  constexpr std::size_t blocks = 64;
  const std::size_t per_block = (n_c + blocks - 1) / blocks;
  pc.partial.assign(3 * blocks * n_w, Vec3{});  // force, torque, (touches, sum of |force|, touching)
  const auto nk = static_cast<std::ptrdiff_t>(blocks);
#pragma omp parallel for schedule(static) if (static_cast <std::ptrdiff_t>(n_c) > parallel_threshold)
  for (std::ptrdiff_t sk = 0; sk < nk; ++sk) {
    const auto k = static_cast<std::size_t>(sk);
    Vec3* out = pc.partial.data() + 3 * k * n_w;
    for (std::size_t c = k * per_block; c < std::min(n_c, (k + 1) * per_block); ++c) {
      const std::uint32_t w = pc.part[c];
      out[3 * w] += pc.reaction[2 * c];
      out[3 * w + 1] += pc.reaction[2 * c + 1];
      out[3 * w + 2].x += pc.touches[c];
      out[3 * w + 2].y += norm(pc.reaction[2 * c]);
      out[3 * w + 2].z += pc.touches[c] > 0 ? 1.0 : 0.0;
    }
  }
  for (std::size_t w = 0; w < n_w; ++w) {
    Vec3 f, t;
    double touches = 0.0;
    for (std::size_t k = 0; k < blocks; ++k) {
      const Vec3* block = pc.partial.data() + 3 * (k * n_w + w);
      f += block[0];
      t += block[1];
      touches += block[2].x;
      d.part_force_sum += block[2].y;
      d.part_contacts += static_cast<std::size_t>(block[2].z);
    }
    parts[w].force = f;
    parts[w].torque = t;
    parts[w].touches = static_cast<std::size_t>(touches);
  }
}

void gather(const ParticleSystem& ps, ContactSums& sums, const Vec3& gravity) {
  // The contact stage finished most bodies at its chunks' ends; the deferred ones (a body
  // across two threads' chunks, or whose elements take shares as second from another thread) are
  // taken here from their elements' kept own sums, in the same order. An element's shares as
  // second are its entry where the contact stage summed them directly, else its pair slots
  // summed in pair order.
  const auto second = [&sums](std::uint32_t s) {
    if (sums.second_direct[s]) return sums.element[s];
    ElementSums from_slots;
    for (std::size_t k = sums.slots_of[s]; k < sums.slots_of[s + 1]; ++k) {
      if (!sums.pair_active[sums.slot_pair[k]]) continue;  // (as the contact stage: only pairs that touch)
      from_slots.force -= sums.pair_force[k];
      from_slots.torque += sums.pair_torque_j[k];
      from_slots.cdt += sums.pair_cdt_j[k];
    }
    return from_slots;
  };
  // Each body once, from the entry of its first element (a body's deferred elements are all of
  // its elements, in order).
  const std::span<const std::uint32_t> deferred = sums.deferred;
  const auto nd = static_cast<std::ptrdiff_t>(deferred.size());
#pragma omp parallel for schedule(static) if (nd > parallel_threshold / 4)
  for (std::ptrdiff_t sk = 0; sk < nd; ++sk) {
    const auto k = static_cast<std::size_t>(sk);
    const std::uint32_t s0 = deferred[k], b = ps.owner[s0];
    if (s0 != ps.first_sphere[b]) continue;
    const auto own = [&sums, k, s0](std::uint32_t s) -> const ElementSums& { return sums.deferred_own[k + s - s0]; };
    const std::uint32_t n = ps.sphere_count[b];
    put_totals(sums.element, s0, n, body_totals(ps.mass(b) * gravity, s0, n, own, second));
  }
}

namespace {

// v reordered to `order` (new index -> old); an old index past its end (an element added
// since the last step) gives zero.
template <class T>
void reorder(std::vector<T>& v, std::span<const std::uint32_t> order) {
  std::vector<T> out(order.size());
  for (std::size_t s = 0; s < out.size(); ++s) out[s] = order[s] < v.size() ? v[order[s]] : T{};
  v = std::move(out);
}

}  // namespace

void permute_body_sums(ContactSums& sums, std::span<const std::uint32_t> sphere_order) {
  reorder(sums.element, sphere_order);
}

double unbalanced_force_ratio(const ParticleSystem& ps, const ContactSums& sums, const StepDiagnostics& d) {
  const std::size_t n = ps.bodies(), touching = d.contacts + d.part_contacts;
  if (n == 0) return 0.0;
  double net = 0.0;  // (in body order: the same sum for any thread count)
  for (std::size_t b = 0; b < n; ++b) net += has_sums(ps, sums, b) ? norm(body_force(ps, sums, b)) : 0.0;
  const double contact = d.pair_force_sum + d.part_force_sum;
  if (touching == 0 || !(contact > 0.0)) return net > 0.0 ? 1.0 : 0.0;
  return (net / static_cast<double>(n)) / (contact / static_cast<double>(touching));
}

}  // namespace bushel::engine
