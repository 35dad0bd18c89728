#include "uavip/perception/obstacle_clusterer.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/perception/euclidean_clusters.h"

namespace uavip::perception {
namespace {

/// Lexicographic (x, y, z) order, used to break ties between clusters.
bool lexLess(const Vec3& a, const Vec3& b) {
  if (a.x() != b.x()) return a.x() < b.x();
  if (a.y() != b.y()) return a.y() < b.y();
  return a.z() < b.z();
}

Obstacle makeObstacle(const PointList& points, std::vector<int> idx) {
  std::sort(idx.begin(), idx.end());
  Obstacle o;
  o.points.reserve(idx.size());
  for (const auto i : idx) o.points.push_back(points[static_cast<std::size_t>(i)]);
  const Aabb box = boundingBox(o.points);
  o.aabb_min = box.min;
  o.aabb_max = box.max;
  return o;
}

Vec3 smallestPoint(const PointList& points) {
  return *std::min_element(points.begin(), points.end(), lexLess);
}

}  // namespace

void ClusterOptions::validate(const std::string& where) const { table().check(*this, where); }

const params::Table<ClusterOptions>& ClusterOptions::table() {
  static const params::Table<ClusterOptions> t = [] {
    params::Table<ClusterOptions> p;
    p.add("obstacle_tolerance_m", &ClusterOptions::tolerance_m,
          "neighbour distance that joins points into one obstacle (§II-E's r)")
        .unitIs("m")
        .positive()
        .mayBeAuto();
    p.add("obstacle_min_points", &ClusterOptions::min_points,
          "smaller clusters are merged into one residual obstacle, never dropped")
        .atLeast(1);
    return p;
  }();
  return t;
}

std::vector<Obstacle> clusterObstacles(const PointList& points, const ClusterOptions& options) {
  options.validate();
  if (points.empty()) return {};
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      throw InputError("perception: obstacle point " + std::to_string(i) + " is not finite");
    }
  }

  std::vector<int> all(points.size());
  std::iota(all.begin(), all.end(), 0);
  const std::vector<std::vector<int>> clusters =
      euclideanClusters(points, all, options.tolerance_m);

  std::vector<Obstacle> obstacles;
  std::vector<int> residual;
  for (const auto& c : clusters) {
    if (static_cast<int>(c.size()) < options.min_points) {
      residual.insert(residual.end(), c.begin(), c.end());
    } else {
      obstacles.push_back(makeObstacle(points, c));
    }
  }
  if (!residual.empty()) obstacles.push_back(makeObstacle(points, std::move(residual)));

  // Largest first; equal sizes by their lexicographically smallest point.
  std::vector<std::pair<Vec3, std::size_t>> keys;
  keys.reserve(obstacles.size());
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    keys.emplace_back(smallestPoint(obstacles[i].points), i);
  }
  std::vector<std::size_t> order(obstacles.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const auto na = obstacles[a].points.size();
    const auto nb = obstacles[b].points.size();
    if (na != nb) return na > nb;
    if (lexLess(keys[a].first, keys[b].first)) return true;
    if (lexLess(keys[b].first, keys[a].first)) return false;
    return a < b;
  });
  std::vector<Obstacle> sorted;
  sorted.reserve(obstacles.size());
  for (const auto i : order) {
    sorted.push_back(std::move(obstacles[i]));
    sorted.back().id = static_cast<int>(sorted.size()) - 1;
  }
  return sorted;
}

}  // namespace uavip::perception
