#include "coefficients.hpp"

#include <utility>

namespace bushel::engine {

PairCoefficientTable make_coefficients(const ContactTable& table, const std::vector<ParticleType>& types,
                                       const std::vector<Part>& parts) {
  std::vector<Species> species;
  std::vector<const Material*> materials;
  for (const auto& t : types) {
    species.push_back({t.name, t.material.name});
    materials.push_back(&t.material);
  }
  for (const auto& w : parts) {
    species.push_back({w.name, w.material.name});
    materials.push_back(&w.material);
  }
  const DenseContactTable dense = table.resolve(species);
  const std::size_t n = species.size();
  std::vector<PairCoefficients> c(n * n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j)
      c[i * n + j] = make_pair_coefficients(*materials[i], *materials[j], dense(i, j));
  }
  return PairCoefficientTable(n, std::move(c));
}

}  // namespace bushel::engine
