#pragma once
/// \file
/// Union–find over indices 0 … n−1 (path halving); joining keeps the lower index as
/// the root, so a group is led by its earliest member whatever the join order.
/// Used by tiling's part merge and structure coverage's photo groups.

#include <algorithm>
#include <cstddef>
#include <numeric>
#include <vector>

namespace uavip {

/// Disjoint sets of indices; find() returns a set's lowest index.
struct UnionFind {
  std::vector<std::size_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  std::size_t find(std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the earliest leads
  }
};

}  // namespace uavip
