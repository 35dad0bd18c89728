#include "uavip/core/neighbour_index.h"

#include <algorithm>
#include <array>
#include <flann/flann.hpp>
#include <limits>
#include <string>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/text.h"

namespace uavip {

struct NeighbourIndex::Tree {
  std::vector<float> xyz;  ///< 3 floats per point, relative to origin_
  std::unique_ptr<flann::Index<flann::L2_Simple<float>>> index;
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
  tree_->xyz.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto f = toFloat(cloud[i], origin);
    std::copy(f.begin(), f.end(), tree_->xyz.begin() + static_cast<std::ptrdiff_t>(3 * i));
  }
  tree_->index = std::make_unique<flann::Index<flann::L2_Simple<float>>>(
      flann::Matrix<float>(tree_->xyz.data(), n, 3), flann::KDTreeSingleIndexParams(15));
  tree_->index->buildIndex();
}

NeighbourIndex::~NeighbourIndex() = default;

void NeighbourIndex::nearest(std::size_t first, std::size_t count, int k, int* indices,
                             float* squared_m2) const {
  if (count == 0) return;
  const auto kk = static_cast<std::size_t>(k);
  flann::Matrix<float> queries(tree_->xyz.data() + 3 * first, count, 3);
  flann::Matrix<int> idx(indices, count, kk);
  flann::Matrix<float> dst(squared_m2, count, kk);
  flann::SearchParams params(-1, 0.0f);  // exact and sorted, as KdTreeFLANN's nearestKSearch
  tree_->index->knnSearch(queries, idx, dst, kk, params);
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
  auto f = toFloat(q, origin_);
  int index = -1;
  float d2 = 0.0f;
  flann::Matrix<float> query(f.data(), 1, 3);
  flann::Matrix<int> idx(&index, 1, 1);
  flann::Matrix<float> dst(&d2, 1, 1);
  tree_->index->knnSearch(query, idx, dst, 1, flann::SearchParams(-1, 0.0f));
  if (squared_m2 != nullptr) *squared_m2 = d2;
  return index;
}

void NeighbourIndex::within(const Vec3& q, double radius, std::vector<int>& indices,
                            std::vector<float>& squared_m2, bool sorted) const {
  auto f = toFloat(q, origin_);
  flann::Matrix<float> query(f.data(), 1, 3);
  std::vector<std::vector<int>> idx(1);
  std::vector<std::vector<float>> dst(1);
  flann::SearchParams params(-1, 0.0f, sorted);
  params.max_neighbors = -1;  // all of them
  tree_->index->radiusSearch(query, idx, dst, static_cast<float>(radius * radius), params);
  indices = std::move(idx[0]);
  squared_m2 = std::move(dst[0]);
}

}  // namespace uavip
