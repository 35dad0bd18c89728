#include "uavip/core/neighbour_index.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <flann/flann.hpp>
#include <limits>
#include <numeric>
#include <string>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/parallel.h"
#include "uavip/core/text.h"

namespace uavip {

namespace {

using FlannTree = flann::Index<flann::L2_Simple<float>>;

/// Exact search, results sorted by distance: KdTreeFLANN's nearestKSearch.
const flann::SearchParams kExact(-1, 0.0f);

}  // namespace

/// The points in one FLANN tree, or, from kSplitPoints on, in two: the halves below
/// and from the median of the longest axis, built at once on two threads (a tree's
/// build is serial). A query searches its own
/// half and the other only when the split plane is nearer than the k-th neighbour
/// found; a point across the plane is never nearer than the plane, in float too
/// (rounding is monotone), so the neighbours and distances are the one tree's (ties
/// aside: the own half's come first).
struct NeighbourIndex::Tree {
  static constexpr std::size_t kSplitPoints = std::size_t{1} << 18;

  /// One tree over some of the points: their float copies (relative to the origin)
  /// and where they are in the cloud.
  struct Part {
    std::vector<float> xyz;
    std::vector<int> cloud_index;  ///< empty when the part is cloud[offset, offset + size)
    int offset{0};
    std::unique_ptr<FlannTree> index;

    std::size_t size() const { return xyz.size() / 3; }
    int toCloud(int local) const {
      return cloud_index.empty() ? offset + local : cloud_index[static_cast<std::size_t>(local)];
    }
    void build() {
      index = std::make_unique<FlannTree>(flann::Matrix<float>(xyz.data(), size(), 3),
                                          flann::KDTreeSingleIndexParams(15));
      index->buildIndex();
    }
    /// Up to k points strictly nearer to f than √bound2, the nearest first; local indices.
    int nearerThan(const float* f, int k, float bound2, std::vector<int>& idx,
                   std::vector<float>& d2) const {
      flann::Matrix<float> query(const_cast<float*>(f), 1, 3);
      std::vector<std::vector<int>> i(1);
      std::vector<std::vector<float>> d(1);
      flann::SearchParams params(-1, 0.0f, true);
      params.max_neighbors = k;
      index->radiusSearch(query, i, d, bound2, params);
      idx = std::move(i[0]);
      d2 = std::move(d[0]);
      return static_cast<int>(idx.size());
    }
    /// The min(k, size()) nearest of float point f, sorted; local indices.
    int knn(const float* f, int k, int* idx, float* d2) const {
      const int found =
          static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(k), size()));
      flann::Matrix<float> query(const_cast<float*>(f), 1, 3);
      flann::Matrix<int> i(idx, 1, static_cast<std::size_t>(found));
      flann::Matrix<float> d(d2, 1, static_cast<std::size_t>(found));
      index->knnSearch(query, i, d, static_cast<std::size_t>(found), kExact);
      return found;
    }
  };

  std::vector<Part> parts;  ///< one, or two: coordinate `axis` < split, and the rest
  int axis{0};
  float split{0.0f};
  std::vector<std::uint8_t> part_of;    ///< each cloud point's part (two parts)
  std::vector<std::uint32_t> local_of;  ///< its index there

  /// Float copy of cloud point i.
  const float* stored(std::size_t i) const {
    if (parts.size() == 1) return parts[0].xyz.data() + 3 * i;
    return parts[part_of[i]].xyz.data() + 3 * std::size_t{local_of[i]};
  }
  std::size_t ownPart(const float* f) const { return parts.size() == 1 || f[axis] < split ? 0 : 1; }
  /// Squared float distance from f to the split plane.
  float planeDistance2(const float* f) const {
    const float gap = f[axis] - split;
    return gap * gap;
  }

  /// The k nearest points of f over both parts (k ≤ the cloud's size), sorted, cloud
  /// indices; the own part's first among equal distances.
  void knn(const float* f, int k, int* idx, float* d2) const {
    const std::size_t own = ownPart(f);
    const int found = parts[own].knn(f, k, idx, d2);
    finish(f, k, own, found, idx, d2);
  }

  /// Turns the `found` nearest of f in part `own` (local indices, sorted) into the k
  /// nearest over both parts (cloud indices): the other part is searched only when
  /// the split plane is nearer than the k-th found.
  void finish(const float* f, int k, std::size_t own, int found, int* idx, float* d2) const {
    const Part& a = parts[own];
    if (parts.size() == 1 || (found == k && d2[k - 1] <= planeDistance2(f))) {
      if (parts.size() > 1)
        for (int j = 0; j < found; ++j) idx[j] = a.toCloud(idx[j]);
      return;
    }
    const Part& b = parts[1 - own];
    std::vector<int> ai(idx, idx + found);
    std::vector<float> ad(d2, d2 + found);
    std::vector<int> bi;
    std::vector<float> bd;
    int other = 0;
    if (found < k) {
      bi.resize(static_cast<std::size_t>(k));
      bd.resize(static_cast<std::size_t>(k));
      other = b.knn(f, k, bi.data(), bd.data());
    } else {  // only what is nearer than the k-th found: a bounded search
      other = b.nearerThan(f, k, d2[k - 1], bi, bd);
    }
    std::size_t x = 0, y = 0;
    const auto nx = static_cast<std::size_t>(found), ny = static_cast<std::size_t>(other);
    for (int j = 0; j < k && (x < nx || y < ny); ++j) {
      if (y >= ny || (x < nx && ad[x] <= bd[y])) {
        idx[j] = a.toCloud(ai[x]);
        d2[j] = ad[x++];
      } else {
        idx[j] = b.toCloud(bi[y]);
        d2[j] = bd[y++];
      }
    }
  }
};

namespace {

/// q − origin in float.
std::array<float, 3> toFloat(const Vec3& q, const Vec3& origin) {
  const Vec3 d = q - origin;
  return {static_cast<float>(d.x()), static_cast<float>(d.y()), static_cast<float>(d.z())};
}

Vec3 minCorner(const PointList& cloud) {
  if (cloud.empty()) throw InputError("neighbour index: the cloud is empty");
  return boundingBox(cloud).min;
}

}  // namespace

NeighbourIndex::NeighbourIndex(const PointList& cloud) : NeighbourIndex(cloud, minCorner(cloud)) {}

NeighbourIndex::NeighbourIndex(const PointList& cloud, const Vec3& origin)
    : cloud_(cloud), origin_(origin), tree_(std::make_unique<Tree>()) {
  if (cloud.empty()) throw InputError("neighbour index: the cloud is empty");
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!cloud[i].allFinite()) {
      throw InputError("neighbour index: point " + std::to_string(i) +
                       " is not finite: " + formatRawPoint(cloud[i]));
    }
  }
  if (!origin.allFinite()) throw InputError("neighbour index: the origin is not finite");
  if (cloud.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw InputError("neighbour index: cloud has " + std::to_string(cloud.size()) +
                     " points, more than the 2^31 - 1 a kd-tree index holds");
  }
  const std::size_t n = cloud.size();
  Tree& t = *tree_;
  const auto whole = [&] {
    t.parts.clear();
    t.parts.resize(1);
    t.part_of = {};
    t.parts[0].xyz.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto f = toFloat(cloud[i], origin);
      std::copy(f.begin(), f.end(), t.parts[0].xyz.begin() + static_cast<std::ptrdiff_t>(3 * i));
    }
    t.parts[0].build();
  };
  if (n < Tree::kSplitPoints) {
    whole();
    return;
  }
  // Two halves at the median of the longest axis (in float: the frame queries use).
  const Aabb box = boundingBox(cloud);
  (box.max - box.min).maxCoeff(&t.axis);
  const auto axis = static_cast<std::size_t>(t.axis);
  {
    std::vector<float> along(n);
    for (std::size_t i = 0; i < n; ++i) along[i] = toFloat(cloud[i], origin)[axis];
    std::nth_element(along.begin(), along.begin() + static_cast<std::ptrdiff_t>(n / 2),
                     along.end());
    t.split = along[n / 2];
  }
  t.part_of.resize(n);
  std::size_t changes = 0;  // 1: each part is a run of the cloud (a cloud sorted on the axis)
  for (std::size_t i = 0; i < n; ++i) {
    t.part_of[i] = static_cast<std::uint8_t>(toFloat(cloud[i], origin)[axis] < t.split ? 0 : 1);
    changes += i > 0 && t.part_of[i] != t.part_of[i - 1];
  }
  const auto below = static_cast<std::size_t>(std::count(t.part_of.begin(), t.part_of.end(), 0));
  if (below == 0) {  // half the points or more share the lowest value
    whole();
    return;
  }
  t.parts.resize(2);
  t.parts[0].xyz.reserve(3 * below);
  t.parts[1].xyz.reserve(3 * (n - below));
  t.local_of.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    Tree::Part& p = t.parts[t.part_of[i]];
    t.local_of[i] = static_cast<std::uint32_t>(p.size());
    if (p.size() == 0) p.offset = static_cast<int>(i);
    if (changes > 1) p.cloud_index.push_back(static_cast<int>(i));
    const auto f = toFloat(cloud[i], origin);
    p.xyz.insert(p.xyz.end(), f.begin(), f.end());
  }
  parallelFor(2, hardwareThreads(), [&](std::size_t part, std::size_t) { t.parts[part].build(); });
}

NeighbourIndex::~NeighbourIndex() = default;

void NeighbourIndex::nearest(std::size_t first, std::size_t count, int k, int* indices,
                             float* squared_m2) const {
  if (count == 0) return;
  const auto kk = static_cast<std::size_t>(k);
  if (tree_->parts.size() == 1) {  // one batch for FLANN
    flann::Matrix<float> queries(const_cast<float*>(tree_->stored(first)), count, 3);
    flann::Matrix<int> idx(indices, count, kk);
    flann::Matrix<float> dst(squared_m2, count, kk);
    tree_->parts[0].index->knnSearch(queries, idx, dst, kk, kExact);
    return;
  }
  // Runs of points stored one after another in one part go to FLANN in one batch; a
  // row whose k-th neighbour lies beyond the split plane is searched again over both.
  const Tree& t = *tree_;
  for (std::size_t r = 0; r < count;) {
    const std::size_t i = first + r;
    const Tree::Part& p = t.parts[t.part_of[i]];
    std::size_t end = r + 1;
    while (end < count && t.part_of[first + end] == t.part_of[i] &&
           t.local_of[first + end] == t.local_of[i] + (end - r))
      ++end;
    int* idx_rows = indices + r * kk;
    float* d2_rows = squared_m2 + r * kk;
    if (p.size() >= kk) {
      flann::Matrix<float> queries(const_cast<float*>(t.stored(i)), end - r, 3);
      flann::Matrix<int> idx(idx_rows, end - r, kk);
      flann::Matrix<float> dst(d2_rows, end - r, kk);
      p.index->knnSearch(queries, idx, dst, kk, kExact);
    }
    for (std::size_t row = r; row < end; ++row) {
      const float* f = t.stored(first + row);
      if (p.size() >= kk)
        t.finish(f, k, t.part_of[i], k, indices + row * kk, squared_m2 + row * kk);
      else
        t.knn(f, k, indices + row * kk, squared_m2 + row * kk);
    }
    r = end;
  }
}

void NeighbourIndex::nearest(std::size_t i, int k, std::vector<int>& indices,
                             std::vector<float>& squared_m2) const {
  const int found =
      static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(k), cloud_.size()));
  indices.resize(static_cast<std::size_t>(found));
  squared_m2.resize(static_cast<std::size_t>(found));
  nearest(i, 1, found, indices.data(), squared_m2.data());
}

int NeighbourIndex::nearestTo(const Vec3& q, float* squared_m2) const {
  const auto f = toFloat(q, origin_);
  int index = -1;
  float d2 = 0.0f;
  tree_->knn(f.data(), 1, &index, &d2);
  if (squared_m2 != nullptr) *squared_m2 = d2;
  return index;
}

void NeighbourIndex::within(const Vec3& q, double radius, std::vector<int>& indices,
                            std::vector<float>& squared_m2, bool sorted) const {
  const auto f = toFloat(q, origin_);
  const auto radius2 = static_cast<float>(radius * radius);
  flann::Matrix<float> query(const_cast<float*>(f.data()), 1, 3);
  flann::SearchParams params(-1, 0.0f, sorted);
  params.max_neighbors = -1;  // all of them
  indices.clear();
  squared_m2.clear();
  const std::size_t own = tree_->ownPart(f.data());
  // The own part, then the other when the ball reaches across the split plane.
  for (const std::size_t part : {own, 1 - own}) {
    if (part >= tree_->parts.size()) break;
    if (part != own && tree_->planeDistance2(f.data()) > radius2) break;
    const Tree::Part& p = tree_->parts[part];
    std::vector<std::vector<int>> idx(1);
    std::vector<std::vector<float>> dst(1);
    p.index->radiusSearch(query, idx, dst, radius2, params);
    for (std::size_t j = 0; j < idx[0].size(); ++j) {
      indices.push_back(p.toCloud(idx[0][j]));
      squared_m2.push_back(dst[0][j]);
    }
  }
  if (sorted && tree_->parts.size() > 1) {  // merge the parts' sorted runs, stably
    std::vector<std::size_t> order(indices.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t x, std::size_t y) { return squared_m2[x] < squared_m2[y]; });
    std::vector<int> i2(order.size());
    std::vector<float> d2(order.size());
    for (std::size_t j = 0; j < order.size(); ++j) {
      i2[j] = indices[order[j]];
      d2[j] = squared_m2[order[j]];
    }
    indices = std::move(i2);
    squared_m2 = std::move(d2);
  }
}

}  // namespace uavip
