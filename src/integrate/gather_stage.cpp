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
  // Per element: its own sums, then the sum of its shares as second element in pair order,
  // which the contact stage kept (direct) or which is summed here from the pair slots in the
  // same order; the second-element accumulators are zeroed for the next step. The body's
  // totals take its first element's own sums (read before), which the next contact stage
  // zeroes again: no per-body arrays.
  const auto nb = static_cast<std::ptrdiff_t>(ps.bodies());
  const Vec3 g = gravity;  // (a copy: through the reference it is reloaded after every store)
#pragma omp parallel for schedule(static) if (parallel_work(ps))
  for (std::ptrdiff_t sb = 0; sb < nb; ++sb) {
    const auto b = static_cast<std::size_t>(sb);
    Vec3 f = ps.mass(b) * g, t;
    double cdt = 0.0;
    for (std::uint32_t s = ps.first_sphere[b]; s < ps.first_sphere[b] + ps.sphere_count[b]; ++s) {
      f += sums.own[s].force;
      t += sums.own[s].torque;
      cdt += sums.own[s].cdt;
      if (sums.second_direct[s]) {
        ElementSums& second = sums.second[s];
        f += second.force;
        t += second.torque;
        cdt += second.cdt;
        second = {};
        continue;
      }
      Vec3 f_second, t_second;
      double cdt_second = 0.0;
      for (std::size_t k = sums.slots_of[s]; k < sums.slots_of[s + 1]; ++k) {
        if (!sums.pair_active[sums.slot_pair[k]]) continue;  // (as the contact stage: only pairs that touch)
        f_second -= sums.pair_force[k];
        t_second += sums.pair_torque_j[k];
        cdt_second += sums.pair_cdt_j[k];
      }
      f += f_second;
      t += t_second;
      cdt += cdt_second;
    }
    const std::uint32_t s0 = ps.first_sphere[b];
    sums.own[s0] = {.force = f, .torque = t, .cdt = cdt};
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
  reorder(sums.own, sphere_order);
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
