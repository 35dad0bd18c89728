#include "uavip/preprocess/neighbour_index.h"

#include <algorithm>
#include <flann/flann.hpp>
#include <limits>
#include <string>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/text.h"

namespace uavip::preprocess {

struct NeighbourIndex::Tree {
  std::vector<float> xyz;  ///< 3 floats per point, relative to the cloud's min corner
  std::unique_ptr<flann::Index<flann::L2_Simple<float>>> index;
};

NeighbourIndex::NeighbourIndex(const PointList& cloud)
    : cloud_(cloud), tree_(std::make_unique<Tree>()) {
  if (cloud.empty()) throw InputError("neighbour index: the cloud is empty");
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (!cloud[i].allFinite()) {
      throw InputError("neighbour index: point " + std::to_string(i) +
                       " is not finite: " + formatRawPoint(cloud[i]));
    }
  }
  if (cloud.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw InputError("neighbour index: cloud has " + std::to_string(cloud.size()) +
                     " points, more than the 2^31 - 1 a kd-tree index holds");
  }
  const std::size_t n = cloud.size();
  const Vec3 origin = boundingBox(cloud).min;
  tree_->xyz.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 q = cloud[i] - origin;
    tree_->xyz[3 * i] = static_cast<float>(q.x());
    tree_->xyz[3 * i + 1] = static_cast<float>(q.y());
    tree_->xyz[3 * i + 2] = static_cast<float>(q.z());
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

}  // namespace uavip::preprocess
