// hipfai — union-find over the integers 0..n-1 (connected pieces of meshes and FE bodies).
#pragma once

#include <cstddef>
#include <numeric>
#include <vector>

namespace hipfai {

class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n = 0) { reset(n); }

  // Makes 0..n-1 singletons again, keeping the storage (for a loop over many small sets).
  void reset(std::size_t n) {
    parent_.resize(n);
    std::iota(parent_.begin(), parent_.end(), std::size_t{0});
  }

  // The representative of i's set.
  std::size_t find(std::size_t i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];  // path halving keeps the trees shallow
    return i;
  }

  // Joins the sets of a and b (b's representative stays one).
  void unite(std::size_t a, std::size_t b) { parent_[find(a)] = find(b); }

 private:
  std::vector<std::size_t> parent_;
};

}  // namespace hipfai
