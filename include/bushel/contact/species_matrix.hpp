#pragma once
// A dense matrix over contact species (particle types, then walls), resolved once before a
// run so that the hot loop finds a pair's values by two indices, never by name.

#include <cstddef>
#include <utility>
#include <vector>

namespace bushel {

template <class T>
class SpeciesMatrix {
 public:
  SpeciesMatrix() = default;
  /// `entries` row-major, n x n.
  SpeciesMatrix(std::size_t n, std::vector<T> entries) : n_(n), entries_(std::move(entries)) {}
  const T& operator()(std::size_t i, std::size_t j) const { return entries_[i * n_ + j]; }
  std::size_t size() const { return n_; }

 private:
  std::size_t n_ = 0;
  std::vector<T> entries_;
};

}  // namespace bushel
