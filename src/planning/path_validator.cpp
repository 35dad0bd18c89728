#include "uavip/planning/path_validator.h"

#include "uavip/core/geometry.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace uavip::planning {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Segments are checked in pieces of at most this length [m].
constexpr double kPieceLength = 0.5;
/// Tolerance of the clearance test [m].
constexpr double kTolerance = 1e-9;

}  // namespace

/// kd-tree over the cloud, stored in float relative to `offset` (keeps precision
/// for large coordinates); exact distances use the double copy.
struct PathValidator::Index {
  PointList points;
  Vec3 offset{Vec3::Zero()};
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud;
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  double pad{1e-3};  ///< slack added to search radii for the float kd-tree [m]

  pcl::PointXYZ toPcl(const Vec3& p) const {
    const Vec3 q = p - offset;
    return {static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z())};
  }

  /// Indices of the points within `radius` of c (plus the float slack).
  std::vector<int> within(const Vec3& c, double radius) const {
    std::vector<int> idx;
    std::vector<float> d2;
    tree.radiusSearch(toPcl(c), radius + pad, idx, d2);
    return idx;
  }

  /// Distance from c to its nearest point per the kd-tree (float precision).
  double approxNearest(const Vec3& c) const {
    std::vector<int> idx(1);
    std::vector<float> d2(1);
    if (tree.nearestKSearch(toPcl(c), 1, idx, d2) < 1) return kInf;
    return (points[static_cast<std::size_t>(idx[0])] - c).norm();
  }
};

PathValidator::PathValidator(const PointList& cloud, double required_clearance_m)
    : index_(std::make_unique<Index>()), required_clearance_m_(required_clearance_m) {
  index_->points = cloud;
  if (!cloud.empty()) {
    const Aabb box = boundingBox(cloud);
    index_->offset = 0.5 * (box.min + box.max);
    const double extent = (box.max - box.min).norm();
    index_->pad = 1e-3 + 1e-6 * extent;
    index_->cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    index_->cloud->points.reserve(cloud.size());
    for (const auto& p : cloud) index_->cloud->points.push_back(index_->toPcl(p));
    index_->cloud->width = static_cast<std::uint32_t>(cloud.size());
    index_->cloud->height = 1;
    index_->cloud->is_dense = true;
    index_->tree.setInputCloud(index_->cloud);
  }
}

PathValidator::~PathValidator() = default;
PathValidator::PathValidator(PathValidator&&) noexcept = default;
PathValidator& PathValidator::operator=(PathValidator&&) noexcept = default;

double PathValidator::clearance(const Vec3& p) const {
  if (!index_ || index_->points.empty()) return kInf;
  const double d0 = index_->approxNearest(p);
  double best = d0;
  for (int i : index_->within(p, d0)) {
    best = std::min(best, (index_->points[static_cast<std::size_t>(i)] - p).norm());
  }
  return best;
}

ValidationResult PathValidator::validate(const PointList& path) const {
  ValidationResult out;
  out.min_clearance_m = kInf;
  if (path.empty() || !index_ || index_->points.empty()) return out;
  const double req = required_clearance_m_;

  if (path.size() == 1) {
    const Vec3& p = path[0];
    const double d0 = index_->approxNearest(p);
    for (int i : index_->within(p, d0)) {
      const Vec3& q = index_->points[static_cast<std::size_t>(i)];
      const double d = (q - p).norm();
      if (d < out.min_clearance_m) {
        out.min_clearance_m = d;
        out.violation_point = q;
      }
    }
    out.collision_free = out.min_clearance_m >= req - kTolerance;
    if (out.collision_free) {
      out.violation_point = Vec3::Zero();
    } else {
      out.first_violation_segment = 0;
    }
    return out;
  }

  for (std::size_t s = 0; s + 1 < path.size(); ++s) {
    const Vec3& a = path[s];
    const Vec3& b = path[s + 1];
    const double len = (b - a).norm();
    const int pieces = std::max(1, static_cast<int>(std::ceil(len / kPieceLength)));
    double seg_min = kInf;
    Vec3 seg_point = Vec3::Zero();
    for (int k = 0; k < pieces; ++k) {
      const Vec3 pa = a + (b - a) * (static_cast<double>(k) / pieces);
      const Vec3 pb = a + (b - a) * (static_cast<double>(k + 1) / pieces);
      const Vec3 mid = 0.5 * (pa + pb);
      const double half = 0.5 * (pb - pa).norm();
      // Every point nearer to the piece than the mid-point's nearest neighbour lies
      // within d0 + half of the mid-point, so this search makes the minimum exact.
      const double d0 = index_->approxNearest(mid);
      for (int i : index_->within(mid, d0 + half)) {
        const Vec3& q = index_->points[static_cast<std::size_t>(i)];
        const double d = pointSegmentDistance(q, pa, pb);
        if (d < seg_min) {
          seg_min = d;
          seg_point = q;
        }
      }
    }
    out.min_clearance_m = std::min(out.min_clearance_m, seg_min);
    if (seg_min < req - kTolerance && out.first_violation_segment < 0) {
      out.collision_free = false;
      out.first_violation_segment = static_cast<int>(s);
      out.violation_point = seg_point;
    }
  }
  return out;
}

}  // namespace uavip::planning
