#include "uavip/coverage/structure_views.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <queue>
#include <utility>

#include "uavip/core/error.h"
#include "uavip/core/math.h"
#include "uavip/core/voxel_key.h"

namespace uavip::coverage {

namespace {

/// A candidate pose, the seed it looks at, and its direction: the candidates of one
/// seed and direction (one per distance factor, nearest first) share `direction`.
struct Candidate {
  ViewPose pose;
  Vec3 target;
  std::size_t direction{0};
};

/// Viewing directions at a seed with normal n: n (and −n when two-sided), each also
/// tilted toward +z and −z by each tilt (about the horizontal axis n × z; about x when
/// n is vertical).
std::vector<Vec3> viewingDirections(const Vec3& n, bool two_sided,
                                    const std::vector<double>& tilts_deg) {
  Vec3 up = Vec3::UnitZ() - n.z() * n;  // the part of +z across n
  if (up.norm() < 1e-6) up = Vec3::UnitX() - n.x() * n;
  up.normalize();
  std::vector<Vec3> dirs;
  for (const double sign : {1.0, -1.0}) {
    if (sign < 0.0 && !two_sided) break;
    const Vec3 m = sign * n;
    dirs.push_back(m);
    for (const double tilt : tilts_deg) {
      const double t = tilt * kDegToRad;
      dirs.push_back((std::cos(t) * m + std::sin(t) * up).normalized());
      dirs.push_back((std::cos(t) * m - std::sin(t) * up).normalized());
    }
  }
  return dirs;
}

/// Seeds: one point per seed cell (the centroid of the cell's points), with the
/// normal of the structure point nearest to it.
std::vector<Candidate> makeCandidates(const PointList& points, const std::vector<Vec3>& normals,
                                      const std::vector<char>& two_sided,
                                      const StructureViewOptions& o, std::size_t& seeds) {
  const double spacing = o.seed_spacing_m > 0.0 ? o.seed_spacing_m : o.standoff_m / 3.0;
  const VoxelKeyer keyer = VoxelKeyer::forPoints(points, spacing, "structure seed spacing");
  // Per cell, the point nearest to the cell's centroid stands for it (its own normal).
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    keyed[i] = {keyer.key(points[i]), static_cast<std::uint32_t>(i)};
  std::sort(keyed.begin(), keyed.end());
  std::vector<Candidate> out;
  seeds = 0;
  std::size_t directions = 0;
  for (std::size_t b = 0; b < keyed.size();) {
    std::size_t e = b;
    Vec3 sum = Vec3::Zero();
    for (; e < keyed.size() && keyed[e].first == keyed[b].first; ++e)
      sum += points[keyed[e].second];
    const Vec3 centroid = sum / static_cast<double>(e - b);
    std::uint32_t best = keyed[b].second;
    for (std::size_t j = b; j < e; ++j) {
      if ((points[keyed[j].second] - centroid).squaredNorm() <
          (points[best] - centroid).squaredNorm())
        best = keyed[j].second;
    }
    ++seeds;
    const Vec3& p = points[best];
    const bool both = !two_sided.empty() && two_sided[best] != 0;
    for (const Vec3& dir : viewingDirections(normals[best], both, o.tilts_deg)) {
      for (const double factor : o.distance_factors) {
        const Vec3 c = p + factor * o.standoff_m * dir;
        out.push_back({lookAt(c, p), p, directions});
      }
      ++directions;
    }
    b = e;
  }
  return out;
}

/// Lazy greedy set cover: photos in order of choice until `needed` points are covered.
std::vector<std::size_t> greedyCover(const std::vector<std::vector<std::uint32_t>>& sets,
                                     std::size_t n_points, std::size_t needed,
                                     std::vector<int>& count) {
  std::vector<char> covered(n_points, 0);
  count.assign(n_points, 0);
  // Max-heap on (gain, −index): equal gains go to the lower index.
  std::priority_queue<std::pair<std::size_t, std::int64_t>> heap;
  for (std::size_t i = 0; i < sets.size(); ++i)
    if (!sets[i].empty()) heap.push({sets[i].size(), -static_cast<std::int64_t>(i)});
  std::vector<std::size_t> chosen;
  std::size_t done = 0;
  while (done < needed && !heap.empty()) {
    const auto [stale_gain, neg] = heap.top();
    heap.pop();
    const auto i = static_cast<std::size_t>(-neg);
    std::size_t gain = 0;
    for (const auto p : sets[i]) gain += covered[p] == 0;
    if (gain == 0) continue;
    if (!heap.empty() && gain < heap.top().first) {  // stale: push back with its true gain
      heap.push({gain, neg});
      continue;
    }
    chosen.push_back(i);
    for (const auto p : sets[i]) {
      done += covered[p] == 0;
      covered[p] = 1;
      ++count[p];
    }
  }
  return chosen;
}

/// Removes, latest first, every chosen photo whose points all have another photo.
std::vector<std::size_t> pruneRedundant(const std::vector<std::vector<std::uint32_t>>& sets,
                                        const std::vector<std::size_t>& chosen,
                                        std::vector<int>& count) {
  std::vector<char> keep(chosen.size(), 1);
  for (std::size_t k = chosen.size(); k-- > 0;) {
    const auto& s = sets[chosen[k]];
    if (std::all_of(s.begin(), s.end(), [&](std::uint32_t p) { return count[p] >= 2; })) {
      keep[k] = 0;
      for (const auto p : s) --count[p];
    }
  }
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < chosen.size(); ++k)
    if (keep[k]) out.push_back(chosen[k]);
  return out;
}

}  // namespace

void StructureViewOptions::validate(const std::string& where) const {
  requireThat(std::isfinite(standoff_m) && standoff_m > 0.0, where, "standoff_m", "> 0 and finite",
              standoff_m);
  require(!distance_factors.empty(), where,
          "distance_factors: give at least one (1 = the standoff)");
  for (std::size_t i = 0; i < distance_factors.size(); ++i) {
    const double f = distance_factors[i];
    requireThat(std::isfinite(f) && f >= 1.0 && f <= 3.0, where, "distance_factors", "in [1, 3]",
                f);
    if (i > 0)
      requireThat(f > distance_factors[i - 1], where, "distance_factors",
                  "ascending (nearest first)", f);
  }
  for (const double t : tilts_deg)
    requireThat(std::isfinite(t) && t > 0.0 && t < 90.0, where, "tilts_deg", "in (0, 90)", t);
  requireThat(std::isfinite(seed_spacing_m) && seed_spacing_m >= 0.0, where, "seed_spacing_m",
              ">= 0 (0 = standoff / 3)", seed_spacing_m);
  requireThat(target_coverage > 0.0 && target_coverage <= 1.0, where, "target_coverage",
              "in (0, 1]", target_coverage);
  requireThat(threads >= 1, where, "threads", ">= 1", threads);
  criteria.validate(where + ".criteria");
}

ViewPose lookAt(const Vec3& position, const Vec3& target) {
  const Vec3 d = target - position;
  const double horizontal = std::hypot(d.x(), d.y());
  ViewPose pose;
  pose.position = position;
  pose.yaw_deg = horizontal > 1e-9 ? std::atan2(d.y(), d.x()) * kRadToDeg : 0.0;
  pose.pitch_deg = std::atan2(d.z(), horizontal) * kRadToDeg;
  return pose;
}

StructureViews selectStructureViews(const PointList& points, const std::vector<Vec3>& normals,
                                    const std::vector<char>& two_sided, const CameraModel& camera,
                                    const LineOfSight* los, const ViewpointFree& is_free,
                                    const StructureViewOptions& options) {
  options.validate();
  require(normals.size() == points.size(), "structure_views",
          "one normal per point: " + std::to_string(points.size()) + " points, " +
              std::to_string(normals.size()) + " normals");
  require(two_sided.empty() || two_sided.size() == points.size(), "structure_views",
          "one two-sided flag per point or none: " + std::to_string(points.size()) + " points, " +
              std::to_string(two_sided.size()) + " flags");
  StructureViews out;
  out.points = points.size();
  if (points.empty()) return out;
  const std::vector<Candidate> all = makeCandidates(points, normals, two_sided, options, out.seeds);
  out.candidates = all.size();
  // Per seed and direction the nearest free candidate: a farther one stands in only
  // where the nearer ones are not free.
  std::vector<Candidate> usable;
  for (const Candidate& c : all) {
    if (!usable.empty() && usable.back().direction == c.direction) continue;
    const double pitch = c.pose.pitch_deg;
    if (pitch < options.gimbal.pitch_min_deg || pitch > options.gimbal.pitch_max_deg) continue;
    if (is_free && !is_free(c.pose.position)) continue;
    usable.push_back(c);
  }
  out.free_candidates = usable.size();
  std::vector<ViewPose> poses;
  poses.reserve(usable.size());
  for (const auto& c : usable) poses.push_back(c.pose);
  const auto sets = imagedByView(points, normals, poses, camera, options.criteria, los,
                                 options.threads, two_sided.empty() ? nullptr : &two_sided);
  std::vector<char> seen(points.size(), 0);
  for (const auto& s : sets)
    for (const auto p : s) seen[p] = 1;
  for (const char s : seen) out.imageable += s != 0;
  const auto needed = static_cast<std::size_t>(
      std::ceil(options.target_coverage * static_cast<double>(out.imageable)));
  std::vector<int> count;
  const auto chosen = pruneRedundant(sets, greedyCover(sets, points.size(), needed, count), count);
  for (const int c : count) out.covered += c > 0;
  for (const auto i : chosen) {
    out.views.push_back(usable[i].pose);
    out.targets.push_back(usable[i].target);
  }
  return out;
}

}  // namespace uavip::coverage
