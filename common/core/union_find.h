#pragma once
// Disjoint sets over 0..n-1 (union-find with path halving; Tarjan and van
// Leeuwen 1984). A set's root is always its smallest element, so that the
// roots, and whatever is numbered by them, do not depend on the order of
// the joins.
#include <algorithm>
#include <numeric>
#include <vector>

namespace gp {

class UnionFind {
 public:
  explicit UnionFind(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }

  // The root (smallest element) of v's set.
  int find(int v) {
    while (parent_[static_cast<size_t>(v)] != v) {
      parent_[static_cast<size_t>(v)] = parent_[static_cast<size_t>(parent_[static_cast<size_t>(v)])];
      v = parent_[static_cast<size_t>(v)];
    }
    return v;
  }

  // Joins the sets of a and b; false when they were one already.
  bool unite(int a, int b) {
    const int ra = find(a), rb = find(b);
    if (ra == rb) return false;
    parent_[static_cast<size_t>(std::max(ra, rb))] = std::min(ra, rb);
    return true;
  }

  size_t size() const { return parent_.size(); }

 private:
  std::vector<int> parent_;
};

}  // namespace gp
